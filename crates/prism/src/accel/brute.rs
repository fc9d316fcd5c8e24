//! Brute force: test every primitive. Slow and obviously right, the oracle for the others.

use super::query::HitSearch;
use super::Method;
use super::{Accel, AccelInfo, Hit, RayQuery};
use crate::choices::{Key, Keyed};
use crate::geometry::Geometry;
use crate::stats::Stats;

/// Brute force has no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BruteForceOptions;

impl Keyed for BruteForceOptions {
    const NAME: &'static str = "brute-force";
    const SUMMARY: &'static str = "test every primitive: the reference";
    const KEYS: &'static [Key<Self>] = &[];
}

impl Method for BruteForceOptions {
    fn build(&self, _geometry: &Geometry, prims: Vec<u32>) -> Box<dyn Accel> {
        Box::new(BruteForce::new(prims))
    }
}

/// The primitives in a list, tested one by one.
pub struct BruteForce {
    prims: Vec<u32>,
}

impl BruteForce {
    /// The list of `prims`, tested in this order.
    pub fn new(prims: Vec<u32>) -> Self {
        BruteForce { prims }
    }
}

impl Accel for BruteForce {
    #[inline(always)]
    fn query(&self, query: &RayQuery, stats: &mut Stats) -> Option<Hit> {
        let mut search = HitSearch::new(query.t_max, query.mode);
        for &prim in &self.prims {
            if search.test(query.geometry, query.ray, prim, stats) {
                break;
            }
        }
        search.best()
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
