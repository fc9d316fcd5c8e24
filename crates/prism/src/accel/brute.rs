//! Brute force: test every primitive. Slow and obviously right, the oracle for the others.

use super::{Accel, AccelInfo, Hit};
use crate::geometry::Geometry;
use crate::math::TraceRay;
use crate::stats::Stats;

pub struct BruteForce {
    prims: Vec<u32>,
}

impl BruteForce {
    pub fn new(prims: Vec<u32>) -> Self {
        BruteForce { prims }
    }
}

impl Accel for BruteForce {
    fn intersect(
        &self,
        geometry: &Geometry,
        ray: &TraceRay,
        mut t_max: f32,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let mut best = None;
        for &prim in &self.prims {
            if let Some(h) = geometry.intersect_counted(prim, ray, t_max, stats) {
                t_max = h.t;
                best = Some(Hit {
                    t: h.t,
                    prim,
                    u: h.u,
                    v: h.v,
                });
            }
        }
        best
    }

    fn occluded(&self, geometry: &Geometry, ray: &TraceRay, t_max: f32, stats: &mut Stats) -> bool {
        for &prim in &self.prims {
            if geometry
                .intersect_counted(prim, ray, t_max, stats)
                .is_some()
            {
                return true;
            }
        }
        false
    }

    fn info(&self) -> AccelInfo {
        let n = self.prims.len();
        AccelInfo {
            method: "brute force".into(),
            primitives: n,
            nodes: 1,
            leaves: 1,
            depth: 1,
            max_leaf_size: n,
            mean_leaf_size: n as f64,
            sah_cost: Some(n as f64),
            memory_bytes: n * 4,
        }
    }
}
