//! The single-ray leaf test of the 8-wide walk: the two triangle packs of a leaf (eight
//! triangles) go through the first pass of the watertight test in one AVX2 pass instead of
//! two 4-wide ones.
//!
//! Lanes 0..4 hold the first pack and lanes 4..8 the second, each row loaded as the two
//! packs' 128-bit rows side by side. Lane by lane the pass computes what
//! `TrianglePack::hits` computes (the same operations in the same order, the division
//! included, no fused multiply-add), so its values are the 4-wide pass's bit for bit
//! (unit-tested below). The lanes are then handled by `HitSearch::take_pack_lanes`, as
//! `HitSearch::test_pack` handles them, the first pack's before the second's: hits, ties,
//! statistics and any-hit exits are those of two `test_pack` calls.

use super::super::leaves::PACKED;
use super::super::traverse::LeafQuery;
use crate::accel::query::HitSearch;
#[cfg(test)]
use crate::geometry::DecidedHit;
use crate::geometry::{LaneHits, PackRay, ShapeKind, Sheared, TrianglePack};
use crate::math::lanes::{F32x8, FloatLanes};
use crate::stats::Stats;

/// A ray's `PackRay` constants, broadcast across eight lanes.
pub(in crate::accel::bvh) struct PairRay {
    origin: [F32x8; 3],
    shear: [F32x8; 3],
    axes: [usize; 3],
}

impl PairRay {
    /// Only where the CPU has AVX2 (see `math::lanes`).
    #[target_feature(enable = "avx2,popcnt")]
    #[inline]
    pub(in crate::accel::bvh) fn new(ray: &PackRay) -> PairRay {
        PairRay {
            origin: ray.origin().map(F32x8::splat),
            shear: ray.shear().map(F32x8::splat),
            axes: ray.axes(),
        }
    }
}

/// What `pair_hits` found: `PackHits` for two packs, the first's in lanes 0..4.
type PairHits = LaneHits<F32x8>;

/// Pack `half`'s (0 or 1) lanes of `bits`, numbered as `PackHits` numbers them (bit k for
/// the pack's lane k).
#[inline(always)]
fn half_of(bits: u32, half: usize) -> u32 {
    (bits >> (4 * half)) & 0xf
}

/// `TrianglePack::hits` of `first` (lanes 0..4) and `second` (lanes 4..8) at bound `t_max`
/// in one pass: each lane's hit and values are those the 4-wide pass gives the lane's
/// pack, bit for bit.
#[target_feature(enable = "avx2,popcnt")]
#[inline]
pub(in crate::accel::bvh) fn pair_hits(
    first: &TrianglePack,
    second: &TrianglePack,
    ray: &PairRay,
    t_max: f32,
) -> PairHits {
    let (p, q) = (first.lanes_by_vertex(), second.lanes_by_vertex());
    // `TrianglePack::sheared`: vertices relative to the origin, permuted and sheared; the
    // first pack's four lanes low, the second's high.
    let [kx, ky, kz] = ray.axes;
    let rel = |i: usize| {
        let row = |axis: usize| F32x8::from_halves(p[i][axis], q[i][axis]);
        let o = &ray.origin;
        [row(kx) - o[0], row(ky) - o[1], row(kz) - o[2]]
    };
    let sheared = Sheared::new([rel(0), rel(1), rel(2)], ray.shear);
    let lanes = lane_mask(first) | lane_mask(second) << 4;
    sheared.hits(F32x8::splat(t_max), lanes)
}

/// The lanes of `pack` that hold a triangle.
#[inline(always)]
fn lane_mask(pack: &TrianglePack) -> u32 {
    (1u32 << pack.len()) - 1
}

/// Tests a leaf for one ray as `LeafQuery::test` does, its packs two at a time through
/// `pair_hits` (an odd last pack, and leaves of primitives, as `LeafQuery::test` tests
/// them); true when the query is answered.
#[target_feature(enable = "avx2,popcnt")]
#[inline]
pub(in crate::accel::bvh) fn test_leaf(
    leaves: &LeafQuery<'_>,
    first: u32,
    count: u32,
    search: &mut HitSearch,
    stats: &mut Stats,
) -> bool {
    if count & PACKED == 0 {
        if let Some(answered) =
            super::spheres::test_sphere_leaf(leaves, first, count, search, stats)
        {
            return answered;
        }
        return leaves.test(first, count, search, stats);
    }
    let packs = &leaves.packs[first as usize..(first + (count & !PACKED)) as usize];
    let mut pairs = packs.chunks_exact(2);
    for pair in &mut pairs {
        if test_pair(&pair[0], &pair[1], leaves, search, stats) {
            return true;
        }
    }
    match pairs.remainder() {
        [last] => search.test_pack(last, leaves.pack_ray, leaves.ray, stats),
        _ => false,
    }
}

/// `HitSearch::test_pack` of `first`, then of `second` unless that answered the query,
/// with the first pass of both made at once; true when the query is answered.
#[target_feature(enable = "avx2,popcnt")]
#[inline]
fn test_pair(
    first: &TrianglePack,
    second: &TrianglePack,
    leaves: &LeafQuery<'_>,
    search: &mut HitSearch,
    stats: &mut Stats,
) -> bool {
    stats.count_tests(ShapeKind::Triangle, first.len() as u64);
    // The ray's constants broadcast here, from memory, rather than once per walk: held
    // in registers through the walk they crowded its box tests (primary rays slower).
    let ray = &PairRay::new(leaves.pack_ray);
    // Both packs at the bound the first one gets: the bound only shrinks as the first
    // pack's hits are kept, and `take_pack_lanes` holds each lane to the search's bound
    // for it when it comes to the lane, so the second pack's answers are unchanged.
    let hits = pair_hits(first, second, ray, search.nested_limit());
    let (hit, undecided) = (half_of(hits.hit, 0), half_of(hits.undecided, 0));
    if search.take_pack_lanes(first, hit, undecided, |k| hits.decided(k), leaves.ray) {
        return true;
    }
    stats.count_tests(ShapeKind::Triangle, second.len() as u64);
    let (hit, undecided) = (half_of(hits.hit, 1), half_of(hits.undecided, 1));
    search.take_pack_lanes(second, hit, undecided, |k| hits.decided(4 + k), leaves.ray)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::{Hit, QueryMode};
    use crate::geometry::{intersect_triangle, Geometry};
    use crate::math::hash::uniform;
    use crate::math::robust::{next_down, next_up};
    use crate::math::{Ray, TraceRay, Vec3};

    fn point(seed: u64, scale: f32) -> Vec3 {
        let c = |k| (uniform(seed as u32, 0, 0, k, 11) * 2.0 - 1.0) * scale;
        Vec3::new(c(0), c(1), c(2))
    }

    /// A point of a small grid (steps of a quarter of `scale`), where axis-parallel rays
    /// through vertices give exact zero edge functions.
    fn grid_point(seed: u64, scale: f32) -> Vec3 {
        let c = |k| (uniform(seed as u32, 0, 0, k, 12) * 8.0).floor() * 0.25 * scale;
        Vec3::new(c(0), c(1), c(2))
    }

    /// Eight triangles for case `case`: random ones, fans around a shared vertex, grid
    /// triangles, or random ones among which some are degenerate (two equal vertices,
    /// three equal vertices, three collinear points).
    fn triangles(case: u64, scale: f32) -> Vec<[Vec3; 3]> {
        (0..8u64)
            .map(|k| {
                let s = case * 64 + k * 4;
                let mut t = [point(s, scale), point(s + 1, scale), point(s + 2, scale)];
                match case % 5 {
                    1 => t[0] = point(case * 64 + 60, scale),
                    2 => t = [0, 1, 2].map(|i| grid_point(s + i, scale)),
                    3 if k % 4 == 0 => t[1] = t[0],
                    3 if k % 4 == 1 => t = [t[0]; 3],
                    3 if k % 4 == 2 => t[2] = t[0] + (t[1] - t[0]) * 0.5,
                    _ => {}
                }
                t
            })
            .collect()
    }

    /// A ray for case `case`: toward a triangle's centre (jittered), through a vertex or
    /// an edge's midpoint, axis-parallel through a vertex, or from close to a triangle's
    /// plane.
    fn ray(case: u64, scale: f32, tris: &[[Vec3; 3]]) -> Option<TraceRay> {
        let [a, b, c] = tris[(case / 5 % 8) as usize];
        let origin = point(case * 64 + 50, 2.0 * scale);
        let (origin, dir) = match case % 8 {
            // Axis-parallel through a vertex, from either side.
            0 | 1 => {
                let axis = (case / 8 % 3) as usize;
                let sign = if case.is_multiple_of(8) { 1.0 } else { -1.0 };
                let mut d = Vec3::ZERO;
                d[axis] = sign;
                (a - d * 3.0 * scale, d)
            }
            2 => (origin, a - origin),
            // From close to the triangle's plane, across it: the hit's distance is about
            // its error bound (pbrt's delta_t), and that comparison decides.
            6 => {
                let normal = (b - a).cross(c - a).normalize_or_zero() * scale;
                // 1e-2 to 1e-8 of the scale away, spread evenly in the exponent.
                let exponent = -2.0 - 6.0 * uniform(case as u32, 0, 0, 0, 13);
                let from = (a + b + c) / 3.0 - normal * 10f32.powf(exponent);
                (from, normal + point(case * 64 + 52, 0.3 * scale))
            }
            3 => (origin, (b + c) * 0.5 - origin),
            4 => {
                // Axis-parallel, keeping the dominant component of a random direction.
                let dir = (a + b + c) / 3.0 - origin;
                let k = dir.abs().max_position();
                let mut d = Vec3::ZERO;
                d[k] = dir[k];
                (origin, d)
            }
            _ => (
                origin,
                (a + b + c) / 3.0 + point(case * 64 + 51, 0.3 * scale) - origin,
            ),
        };
        (dir != Vec3::ZERO).then(|| TraceRay::new(Ray::new(origin, dir)))
    }

    fn packs(tris: &[[Vec3; 3]], lens: [usize; 2]) -> [TrianglePack; 2] {
        let ids = |from: usize, n: usize| (from..from + n).map(|k| (tris[k], k as u32));
        let first: Vec<_> = ids(0, lens[0]).collect();
        let second: Vec<_> = ids(4, lens[1]).collect();
        [TrianglePack::new(&first), TrianglePack::new(&second)]
    }

    fn bits(d: &DecidedHit) -> [u32; 5] {
        [d.det, d.t_scaled, d.t, d.b1, d.b2].map(f32::to_bits)
    }

    /// Lane by lane, the 8-wide pass finds what two 4-wide `hits` calls find, bit for bit
    /// (the lanes hit, the lanes undecided, and the hit lanes' values), on random
    /// triangles, fans, grid and degenerate triangles, rays through vertices and edges and
    /// axis-parallel rays, at three scales and several bounds (around the hits too).
    #[test]
    #[cfg_attr(
        not(prism_host_avx2),
        ignore = "this CPU lacks AVX2: the 8-wide kernels never run here"
    )]
    fn the_pair_pass_is_two_four_wide_passes() {
        if super::super::skipped_without_avx2() {
            return;
        }
        let (mut hit, mut undecided, mut compared) = (0, 0, 0);
        for scale in [1e-3f32, 1.0, 1e3] {
            for case in 0..12_000u64 {
                let tris = triangles(case, scale);
                let Some(ray) = ray(case, scale, &tris) else {
                    continue;
                };
                let lens = [1 + (case % 4) as usize, 1 + (case / 4 % 4) as usize];
                let [first, second] = packs(&tris, lens);
                let pack_ray = PackRay::new(&ray);
                // SAFETY: AVX2 was detected above.
                let pair_ray = unsafe { PairRay::new(&pack_ray) };
                let mut bounds = vec![f32::INFINITY, 1.1, 1.0, 0.9, 0.5];
                let loosest = first.hits(&pack_ray, f32::INFINITY);
                if loosest.hit != 0 {
                    let t = loosest.decided(loosest.hit.trailing_zeros() as usize).t;
                    bounds.extend([t, next_up(t), next_down(t)]);
                }
                for t_max in bounds {
                    let four = [first.hits(&pack_ray, t_max), second.hits(&pack_ray, t_max)];
                    // SAFETY: AVX2 was detected above.
                    let eight = unsafe { pair_hits(&first, &second, &pair_ray, t_max) };
                    let at = format!("scale {scale} case {case} t_max {t_max}");
                    assert_eq!(eight.hit, four[0].hit | four[1].hit << 4, "hit, {at}");
                    let four_undecided = four[0].undecided | four[1].undecided << 4;
                    assert_eq!(eight.undecided, four_undecided, "undecided, {at}");
                    hit += eight.hit.count_ones();
                    undecided += eight.undecided.count_ones();
                    compared += lens[0] + lens[1];
                    let mut lanes = eight.hit;
                    while lanes != 0 {
                        let lane = lanes.trailing_zeros() as usize;
                        lanes &= lanes - 1;
                        let got = eight.decided(lane);
                        let want = four[lane / 4].decided(lane % 4);
                        assert_eq!(bits(&got), bits(&want), "lane {lane}, {at}");
                    }
                }
            }
        }
        // The workload must exercise both kinds of lane the pass hands on.
        assert!(
            hit > 40_000 && undecided > 80_000,
            "{hit} hit and {undecided} undecided of {compared} lanes"
        );
    }

    /// The 8-wide leaf test gives what `LeafQuery::test` gives, answer, bound and
    /// statistics alike, on leaves of one to five packs (an odd last pack included), for
    /// both query modes, with no hit yet, a far hit, and a hit tying one of the leaf's
    /// triangles with a lower or higher id (the tie rule); duplicate triangles across the
    /// packs make ties inside the leaf too.
    #[test]
    #[cfg_attr(
        not(prism_host_avx2),
        ignore = "this CPU lacks AVX2: the 8-wide kernels never run here"
    )]
    fn the_pair_leaf_test_is_the_four_wide_leaf_test() {
        if super::super::skipped_without_avx2() {
            return;
        }
        let geometry = Geometry::default();
        let (mut answered, mut ties) = (0, 0);
        for scale in [1e-3f32, 1.0, 1e3] {
            for case in 0..1500u64 {
                let mut tris = triangles(case, scale);
                tris.extend(triangles(case + 100_000, scale));
                tris.extend(triangles(case + 200_000, scale));
                // A copy of a triangle further on, with a higher id: a tie inside the leaf.
                tris[(5 + case % 12) as usize] = tris[(case % 5) as usize];
                let Some(ray) = ray(case, scale, &tris) else {
                    continue;
                };
                let n = 1 + (case % 5) as usize;
                let last = 1 + (case / 5 % 4) as usize;
                let packs: Vec<TrianglePack> = (0..n)
                    .map(|p| {
                        let len = if p + 1 == n { last } else { 4 };
                        let lane = |k: usize| (tris[4 * p + k], (10 * (4 * p + k)) as u32);
                        TrianglePack::new(&(0..len).map(lane).collect::<Vec<_>>())
                    })
                    .collect();
                let pack_ray = PackRay::new(&ray);
                let leaves = LeafQuery {
                    prims: &[],
                    packs: &packs,
                    geometry: &geometry,
                    ray: &ray,
                    pack_ray: &pack_ray,
                };
                // A hit of the leaf, for priors that tie with it.
                let leaf_hit = tris[..4 * n].iter().enumerate().find_map(|(k, v)| {
                    intersect_triangle(&ray, v[0], v[1], v[2], f32::INFINITY)
                        .map(|h| (10 * k as u32, h.t))
                });
                let mut priors = vec![None, Some((1_000_000, 0.6))];
                if let Some((prim, t)) = leaf_hit {
                    priors.extend([Some((prim + 5, t)), Some((prim.saturating_sub(5), t))]);
                }
                for mode in [QueryMode::Nearest, QueryMode::Any] {
                    for prior in &priors {
                        let start = || {
                            let mut search = HitSearch::new(f32::INFINITY, mode);
                            if let Some((prim, t)) = *prior {
                                let hit = Hit {
                                    t,
                                    prim,
                                    u: 0.1,
                                    v: 0.2,
                                };
                                search.offer(hit);
                            }
                            search
                        };
                        let (mut four, mut eight) = (start(), start());
                        let (mut four_stats, mut eight_stats) =
                            (Stats::default(), Stats::default());
                        let count = PACKED | n as u32;
                        let four_answer = leaves.test(0, count, &mut four, &mut four_stats);
                        // SAFETY: AVX2 was detected above.
                        let eight_answer =
                            unsafe { test_leaf(&leaves, 0, count, &mut eight, &mut eight_stats) };
                        let at = format!("scale {scale} case {case} {mode:?} {prior:?}");
                        assert_eq!(eight_answer, four_answer, "{at}");
                        let key =
                            |h: Option<Hit>| h.map(|h| (h.prim, [h.t, h.u, h.v].map(f32::to_bits)));
                        assert_eq!(key(eight.best()), key(four.best()), "{at}");
                        assert_eq!(eight.t_max().to_bits(), four.t_max().to_bits(), "{at}");
                        assert_eq!(eight_stats, four_stats, "{at}");
                        answered += u32::from(four_answer);
                        // The prior's tie with a leaf hit, won by the leaf's lower id.
                        ties += u32::from(prior.is_some_and(|p| {
                            four.best().is_some_and(|b| b.t == p.1 && b.prim != p.0)
                        }));
                    }
                }
            }
        }
        assert!(
            answered > 3000 && ties > 500,
            "{answered} answered, {ties} ties won"
        );
    }
}
