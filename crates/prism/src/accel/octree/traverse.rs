//! Front-to-back octree walk. In a cell spanning `[t0, t1]` of the ray, the three midplanes
//! are crossed at known parameters; sorting the crossings that fall inside the span gives
//! the octants the ray visits, in order (the idea behind Revelles et al.'s parametric
//! traversal, here with an explicit sort of at most three values). The octants are pushed
//! far to near, each with its own span, so the nearest is searched first.

use super::{octant, Octree, MAX_DEPTH};
use crate::accel::cells::{plane_crossing, CellSearch};
use crate::accel::stack::TraversalStack;
use crate::accel::{Accel, AccelInfo, Hit, RayQuery};
use crate::math::Aabb;
use crate::stats::Stats;

/// Each level pops one entry and pushes at most four.
const STACK: usize = 3 * MAX_DEPTH + 4;

impl Accel for Octree {
    #[inline(always)]
    fn query(&self, query: &RayQuery, stats: &mut Stats) -> Option<Hit> {
        let ray = query.ray;
        let (t0, t1) = CellSearch::enter(query, self.nodes.is_empty(), &self.bounds, stats)?;
        let mut search = CellSearch::new(query);
        // Octants still to search: (node, its box, the ray's span in it).
        let mut stack = TraversalStack::<(u32, Aabb, f32, f32), STACK>::new();
        stack.push((0, self.bounds, t0, t1));
        let (o, d) = (ray.ray.origin, ray.ray.dir);
        while let Some((index, bounds, t0, t1)) = stack.pop() {
            if t0 > search.hits.t_max() {
                continue;
            }
            stats.node_visits += 1;
            let node = self.nodes[index as usize];
            if node.is_leaf() {
                let prims = &self.refs[node.first as usize..(node.first + node.count) as usize];
                if search.search_cell(query.geometry, ray, prims, t1, stats) {
                    return search.hits.best();
                }
                continue;
            }
            let mid = bounds.center();
            let mut child = 0usize;
            let mut crossings = [(f32::INFINITY, 0usize); 3];
            let mut count = 0;
            for k in 0..3 {
                let t = plane_crossing(ray, k, mid[k]);
                // Which side of the midplane the ray is on at t0.
                let high = if t.is_finite() && d[k] > 0.0 {
                    t <= t0
                } else if t.is_finite() && d[k] < 0.0 {
                    t > t0
                } else {
                    o[k] >= mid[k]
                };
                child |= (high as usize) << k;
                if t.is_finite() && t > t0 && t < t1 {
                    crossings[count] = (t, k);
                    count += 1;
                }
            }
            crossings[..count].sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
            // Octants in ray order with their spans; pushed in reverse so the first pops
            // first.
            let mut order = [(0usize, 0.0f32, 0.0f32); 4];
            let mut start = t0;
            for (i, &(t, k)) in crossings[..count].iter().enumerate() {
                order[i] = (child, start, t);
                child ^= 1 << k;
                start = t;
            }
            order[count] = (child, start, t1);
            for &(c, a, b) in order[..=count].iter().rev() {
                stack.push((node.first + c as u32, octant(&bounds, c), a, b));
            }
        }
        search.hits.best()
    }

    fn info(&self) -> AccelInfo {
        self.info()
    }
}
