//! Front-to-back kd-tree walk (the standard recursive-stack algorithm of Jansen, Arvo and
//! Kirk as in pbrt): at each split descend into the child on the ray origin's side with the
//! part of the ray before the plane, and push the other child with the part after it.

use super::{KdTree, MAX_DEPTH};
use crate::accel::cells::{plane_crossing, CellSearch};
use crate::accel::stack::TraversalStack;
use crate::accel::{Accel, AccelInfo, Hit, RayQuery};
use crate::stats::Stats;

impl Accel for KdTree {
    #[inline(always)]
    fn query(&self, query: &RayQuery, stats: &mut Stats) -> Option<Hit> {
        let ray = query.ray;
        let (mut t_near, mut t_far) =
            CellSearch::enter(query, self.nodes.is_empty(), &self.bounds, stats)?;
        let mut search = CellSearch::new(query);
        // Far children still to search: (node, t where the ray enters it, t where it leaves).
        let mut stack = TraversalStack::<(u32, f32, f32), MAX_DEPTH>::new();
        let mut current = 0usize;
        loop {
            let node = self.nodes[current];
            if node.is_leaf() {
                let (first, count) = node.prims();
                let prims = &self.refs[first..first + count];
                if search.search_cell(query.geometry, ray, prims, t_far, stats) {
                    return search.hits.best();
                }
                // Next pushed child that starts before the best hit so far.
                loop {
                    let Some((n, a, b)) = stack.pop() else {
                        return search.hits.best();
                    };
                    if a <= search.hits.t_max() {
                        (current, t_near, t_far) = (n as usize, a, b);
                        break;
                    }
                }
                stats.node_visits += 1;
                continue;
            }
            let axis = node.axis();
            let split = node.split();
            let t_split = plane_crossing(ray, axis, split);
            let o = ray.ray.origin[axis];
            let below_first = o < split || (o == split && ray.ray.dir[axis] <= 0.0);
            let (first, second) = if below_first {
                (current + 1, node.above())
            } else {
                (node.above(), current + 1)
            };
            if t_split > t_far || t_split <= 0.0 {
                current = first;
            } else if t_split < t_near {
                current = second;
            } else {
                stack.push((second as u32, t_split, t_far));
                current = first;
                t_far = t_split;
            }
            stats.node_visits += 1;
        }
    }

    fn info(&self) -> AccelInfo {
        self.info()
    }
}
