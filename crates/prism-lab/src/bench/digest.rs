//! What a method answered, in one number per ray kind, so the bench can tell a method that
//! finds other hits from one that is merely slower: an order-independent sum of a hash of
//! (ray index, primitive, distance) over the primary hits, and of the indices of the
//! blocked shadow rays. Computed in a pass of its own, outside the timed ones.

use super::rays::ShadowRay;
use prism::accel::SceneIntersector;
use prism::geometry::Geometry;
use prism::math::Ray;
use prism::stats::Stats;
use rayon::prelude::*;
use serde::Serialize;

/// Hits and their fingerprint for one ray kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct HitDigest {
    /// Rays that hit (or were blocked).
    pub hits: usize,
    /// The sum of one hash per ray of its index and answer, so the same answers give the
    /// same number whatever order the rays were traced in.
    pub fingerprint: u64,
}

impl HitDigest {
    fn add(self, other: HitDigest) -> HitDigest {
        HitDigest {
            hits: self.hits + other.hits,
            fingerprint: self.fingerprint.wrapping_add(other.fingerprint),
        }
    }
}

/// SplitMix64's finaliser: a well-mixed 64-bit hash of `x`.
fn mix(mut x: u64) -> u64 {
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// The nearest hit of every ray: which primitive, at exactly which distance.
pub(super) fn primary(
    intersector: &SceneIntersector,
    geometry: &Geometry,
    rays: &[Ray],
) -> HitDigest {
    digest(rays, |i, ray, stats| {
        let hit = intersector.intersect(geometry, ray, f32::INFINITY, stats)?;
        Some(mix(mix(i as u64)
            ^ (u64::from(hit.prim) << 32)
            ^ u64::from(hit.t.to_bits())))
    })
}

/// Which shadow rays are blocked.
pub(super) fn shadow(
    intersector: &SceneIntersector,
    geometry: &Geometry,
    rays: &[ShadowRay],
) -> HitDigest {
    digest(rays, |i, s, stats| {
        intersector
            .occluded(geometry, &s.ray, s.t_max, stats)
            .then(|| mix(i as u64))
    })
}

/// The digest of `rays`, `answer(i, ray)` the hash of ray i's answer where it hit (or was
/// blocked), in parallel.
fn digest<T: Sync>(
    rays: &[T],
    answer: impl Fn(usize, &T, &mut Stats) -> Option<u64> + Sync,
) -> HitDigest {
    rays.par_iter()
        .enumerate()
        .map(|(i, ray)| {
            let mut stats = Stats::default();
            match answer(i, ray, &mut stats) {
                Some(fingerprint) => HitDigest {
                    hits: 1,
                    fingerprint,
                },
                None => HitDigest::default(),
            }
        })
        .reduce(HitDigest::default, HitDigest::add)
}
