//! 3D-DDA (Amanatides & Woo 1987): step from cell to cell along the ray, always across the
//! nearest of the three next cell faces, testing each cell's primitives once per ray.

use super::Grid;
use crate::accel::cells::{plane_crossing, CellSearch};
use crate::accel::{Accel, AccelInfo, Hit, RayQuery};
use crate::stats::Stats;

impl Accel for Grid {
    #[inline(always)]
    fn query(&self, query: &RayQuery, stats: &mut Stats) -> Option<Hit> {
        let ray = query.ray;
        let (t_enter, t_exit) =
            CellSearch::enter(query, self.refs.is_empty(), &self.bounds, stats)?;
        let mut search = CellSearch::new(query);
        let (o, d) = (ray.ray.origin, ray.ray.dir);
        let entry = o + t_enter * d;
        let mut cell = [0u32; 3];
        let mut step = [0i32; 3];
        // Parameter at which the ray crosses the next cell face on each axis.
        let mut t_next = [f32::INFINITY; 3];
        for k in 0..3 {
            let f = ((entry[k] - self.bounds.min[k]) / self.cell_size[k]).floor();
            cell[k] = (f.max(0.0) as u32).min(self.res[k] - 1);
            if ray.inv_dir[k].is_finite() && d[k] > 0.0 {
                step[k] = 1;
                t_next[k] = plane_crossing(ray, k, self.plane(k, cell[k] + 1));
            } else if ray.inv_dir[k].is_finite() && d[k] < 0.0 {
                step[k] = -1;
                t_next[k] = plane_crossing(ray, k, self.plane(k, cell[k]));
            }
        }
        loop {
            stats.node_visits += 1;
            let axis = if t_next[0] <= t_next[1] && t_next[0] <= t_next[2] {
                0
            } else if t_next[1] <= t_next[2] {
                1
            } else {
                2
            };
            let cell_exit = t_next[axis].min(t_exit);
            if search.search_cell(query.geometry, ray, self.cell_prims(cell), cell_exit, stats) {
                return search.hits.best();
            }
            if t_next[axis] > t_exit.min(search.hits.t_max()) {
                return search.hits.best();
            }
            // Step across the face; leaving the grid ends the walk.
            let next = cell[axis] as i32 + step[axis];
            if next < 0 || next >= self.res[axis] as i32 {
                return search.hits.best();
            }
            cell[axis] = next as u32;
            let face = if step[axis] > 0 {
                next as u32 + 1
            } else {
                next as u32
            };
            t_next[axis] = plane_crossing(ray, axis, self.plane(axis, face));
        }
    }

    fn info(&self) -> AccelInfo {
        self.info()
    }
}
