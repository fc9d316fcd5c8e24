//! The single-ray test of a leaf of spheres in the 8-wide walk: up to eight spheres through
//! one AVX2 pass instead of one `Sphere::intersect` call each (the leaf's other primitives,
//! such as the cylinders between SPD lattice's balls, tested one by one in their turn).
//! Scenes of spheres (SPD's shells, lattice, balls) meet such leaves on every reflected and
//! refracted ray, which the packet walks answer one ray at a time once the rays point every
//! way.
//!
//! Lane by lane the pass makes the operations of `Sphere::intersect` in the same order (no
//! fused multiply-add), so each lane's distance is the scalar test's bit for bit
//! (unit-tested below). The leaf is then gone through in order: a sphere's hit is kept
//! through `HitSearch::keep_within` at the tie rule's bound for its id, another primitive
//! is tested as the scalar loop tests it, and every test is counted as that loop counts it
//! (up to the one that answers an any-hit query), so hits, ties, statistics and early exits
//! are those of `LeafQuery::test`.

use super::super::traverse::LeafQuery;
use crate::accel::query::HitSearch;
use crate::geometry::{sphere_lanes, Shape, ShapeHit, ShapeKind};
use crate::math::lanes::{F32x8, FloatLanes};
use crate::stats::Stats;

/// The most spheres one pass takes.
const LANES: usize = 8;

/// The fewest spheres a pass is made for: a scalar test that misses stops before its
/// square root and division, which the pass always makes, so for two or three spheres the
/// pass cost as much as it saved (SPD balls and rings 1-3 % slower; shells, whose rays
/// meet 90 spheres each, 12 % faster either way).
const MIN_SPHERES: u32 = 4;

/// Tests the leaf `prims[first .. first + count]` when it holds `MIN_SPHERES` to eight
/// spheres among at most eight primitives: the spheres in one pass, the others one by one as
/// `LeafQuery::test` tests them, all in leaf order. `None` (nothing tested, nothing
/// counted) for any other leaf; Some(true) when the query is answered. Never inlined, so
/// that the walks over triangle packs keep their code as it was.
#[target_feature(enable = "avx2,popcnt")]
#[inline(never)]
pub(in crate::accel::bvh) fn test_sphere_leaf(
    leaves: &LeafQuery<'_>,
    first: u32,
    count: u32,
    search: &mut HitSearch,
    stats: &mut Stats,
) -> Option<bool> {
    let n = count as usize;
    // Smaller leaves cannot hold enough spheres: not even their shapes are read.
    if !(MIN_SPHERES as usize..=LANES).contains(&n) {
        return None;
    }
    let ids = &leaves.prims[first as usize..][..n];
    // The spheres' centres and radii in the lanes of their places in the leaf; other
    // lanes stay zero and are masked off.
    let mut rows = [[0.0f32; LANES]; 4];
    let mut spheres = 0u32;
    for (k, &prim) in ids.iter().enumerate() {
        if let Shape::Sphere(s) = &leaves.geometry.primitives[prim as usize].shape {
            rows[0][k] = s.center.x;
            rows[1][k] = s.center.y;
            rows[2][k] = s.center.z;
            rows[3][k] = s.radius;
            spheres |= 1 << k;
        }
    }
    if spheres.count_ones() < MIN_SPHERES {
        return None;
    }
    // At the loosest bound the search will give any of them: bounds only shrink, and each
    // hit is held to its own bound when its turn comes.
    let (hit, t) = sphere_hits(&rows, leaves, search.nested_limit());
    let hit = hit & spheres;
    for (k, &prim) in ids.iter().enumerate() {
        let answered = if spheres & (1 << k) != 0 {
            stats.count_test(ShapeKind::Sphere);
            let shape_hit = ShapeHit {
                t: t[k],
                u: 0.0,
                v: 0.0,
            };
            hit & (1 << k) != 0 && search.keep_within(prim, shape_hit)
        } else {
            search.test(leaves.geometry, leaves.ray, prim, stats)
        };
        if answered {
            return Some(true);
        }
    }
    Some(false)
}

/// `Sphere::intersect` of the spheres in `rows` (centre x, y, z and radius, a lane each)
/// against the leaf's ray at bound `t_max`: the lanes hit (a bit each) and every lane's
/// distance.
#[target_feature(enable = "avx2,popcnt")]
#[inline]
fn sphere_hits(rows: &[[f32; LANES]; 4], leaves: &LeafQuery<'_>, t_max: f32) -> (u32, [f32; 8]) {
    let ray = &leaves.ray.ray;
    let origin = ray.origin.to_array().map(F32x8::splat);
    let dir = ray.dir.to_array().map(F32x8::splat);
    let centre = [0, 1, 2].map(|a| F32x8::load(&rows[a], 0));
    let radius = F32x8::load(&rows[3], 0);
    let (hit, t) = sphere_lanes(origin, dir, centre, radius * radius, F32x8::splat(t_max));
    (hit, t.to_array())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::{Hit, QueryMode};
    use crate::geometry::{AaBox, Cone, Geometry, PackRay, Sphere};
    use crate::math::hash::uniform;
    use crate::math::{Ray, TraceRay, Vec3};

    /// A leaf query over `prims` (no triangle packs) for `ray`.
    fn leaf_query<'a>(
        geometry: &'a Geometry,
        prims: &'a [u32],
        ray: &'a TraceRay,
        pack_ray: &'a PackRay,
    ) -> LeafQuery<'a> {
        LeafQuery {
            prims,
            packs: &[],
            geometry,
            ray,
            pack_ray,
        }
    }

    fn point(seed: u64, scale: f32) -> Vec3 {
        let c = |k| (uniform(seed as u32, (seed >> 32) as u32, 0, k, 21) * 2.0 - 1.0) * scale;
        Vec3::new(c(0), c(1), c(2))
    }

    /// Eight spheres for `case`, some overlapping, one a copy of another (a tie between
    /// two ids), one tiny beside big ones.
    fn spheres(case: u64, scale: f32) -> Vec<Sphere> {
        let mut s: Vec<Sphere> = (0..8u64)
            .map(|k| {
                let seed = case * 64 + k * 3;
                let radius = (0.05 + uniform(seed as u32, 1, 0, 0, 22)) * 0.5 * scale;
                Sphere::new(point(seed, scale), radius)
            })
            .collect();
        s[(1 + case % 7) as usize] = s[0];
        s[(case / 7 % 8) as usize].radius *= 1e-4;
        s
    }

    /// A ray for `case`: toward a sphere's centre, grazing one (along a tangent, so the
    /// discriminant is about zero), from inside one, axis-parallel, or anywhere.
    fn ray(case: u64, scale: f32, s: &[Sphere]) -> Option<TraceRay> {
        let target = s[(case / 6 % 8) as usize];
        let origin = point(case * 64 + 40, 3.0 * scale);
        let (origin, dir) = match case % 6 {
            0 => (origin, target.center - origin),
            1 => {
                // Through the point at the radius off the centre, perpendicular to it.
                let to = target.center - origin;
                let side = to.cross(Vec3::new(0.3, 1.0, -0.2)).normalize_or_zero();
                (origin, target.center + side * target.radius - origin)
            }
            2 => (
                target.center + point(case * 64 + 41, 0.2 * target.radius),
                point(case * 64 + 42, 1.0),
            ),
            3 => {
                let mut d = Vec3::ZERO;
                d[(case / 6 % 3) as usize] = if case % 12 < 6 { 1.0 } else { -1.0 };
                (
                    target.center - d * 2.0 * scale + point(case * 64 + 43, 0.1 * target.radius),
                    d,
                )
            }
            _ => (origin, point(case * 64 + 44, 1.0)),
        };
        let dir = dir.normalize_or_zero();
        (dir != Vec3::ZERO).then(|| TraceRay::new(Ray::new(origin, dir)))
    }

    /// The 8-wide sphere leaf test gives what `LeafQuery::test` gives sphere by sphere:
    /// answer, best hit, bound and statistics, for leaves of two to eight primitives in a
    /// shuffled order (a third with a box and a cone among the spheres; leaves of fewer
    /// than `MIN_SPHERES` spheres must be declined), both query modes, with no prior hit, a
    /// far one, and one tying a sphere's hit with a lower or a higher id; at three scales.
    #[test]
    #[cfg_attr(
        not(prism_host_avx2),
        ignore = "this CPU lacks AVX2: the 8-wide kernels never run here"
    )]
    fn the_sphere_leaf_pass_is_the_scalar_loop() {
        if super::super::skipped_without_avx2() {
            return;
        }
        let (mut hits, mut answered, mut ties, mut mixed) = (0, 0, 0, 0);
        for scale in [1e-3f32, 1.0, 1e3] {
            for case in 0..3000u64 {
                let s = spheres(case, scale);
                let mut geometry = Geometry::default();
                for sphere in &s {
                    geometry.add(Shape::Sphere(*sphere), 0);
                }
                // Two other shapes across the spheres, ids 8 and 9, for mixed leaves.
                let (a, b) = (s[0].center, s[(1 + case % 7) as usize].center);
                geometry.add(Shape::from(AaBox::new(a, a + Vec3::splat(0.3 * scale))), 0);
                let cone = Cone::new(
                    a,
                    0.2 * scale,
                    b + Vec3::X * scale,
                    0.1 * scale,
                    case % 2 == 0,
                );
                geometry.add(Shape::from(cone.expect("a cone")), 0);
                let Some(ray) = ray(case, scale, &s) else {
                    continue;
                };
                let n = 2 + (case % 7) as u32;
                // Ids in a shuffled order, as leaves hold them after a build.
                let shift = (case / 3 % 8) as u32;
                let mut prims: Vec<u32> = (0..8).map(|k| (k * 5 + shift) % 8).collect();
                // A third of the leaves mixed: the box and the cone among the spheres.
                if case % 3 == 1 {
                    prims[(case / 21 % 3) as usize] = 8;
                    prims[(1 + case / 63 % 7) as usize] = 9;
                }
                let pack_ray = PackRay::new(&ray);
                let leaves = leaf_query(&geometry, &prims, &ray, &pack_ray);
                let leaf_hit = prims[..n as usize]
                    .iter()
                    .find_map(|&p| geometry.intersect(p, &ray, f32::INFINITY).map(|h| (p, h.t)));
                let mut priors = vec![None, Some((1_000, 0.5 * scale))];
                if let Some((prim, t)) = leaf_hit {
                    priors.extend([Some((prim + 1, t)), Some((prim.saturating_sub(1), t))]);
                }
                for mode in [QueryMode::Nearest, QueryMode::Any] {
                    for prior in &priors {
                        let start = || {
                            let mut search = HitSearch::new(f32::INFINITY, mode);
                            if let Some((prim, t)) = *prior {
                                search.offer(Hit {
                                    t,
                                    prim,
                                    u: 0.0,
                                    v: 0.0,
                                });
                            }
                            search
                        };
                        let (mut scalar, mut wide) = (start(), start());
                        let (mut scalar_stats, mut wide_stats) =
                            (Stats::default(), Stats::default());
                        let want = leaves.test(0, n, &mut scalar, &mut scalar_stats);
                        // SAFETY: AVX2 was detected above.
                        let got =
                            unsafe { test_sphere_leaf(&leaves, 0, n, &mut wide, &mut wide_stats) };
                        let at = format!("scale {scale} case {case} n {n} {mode:?} {prior:?}");
                        let spheres = prims[..n as usize].iter().filter(|&&p| p < 8).count();
                        if spheres < MIN_SPHERES as usize {
                            assert_eq!(got, None, "{at}");
                            continue;
                        }
                        mixed += u32::from(spheres < n as usize);
                        assert_eq!(got, Some(want), "{at}");
                        let key = |h: Option<Hit>| h.map(|h| (h.prim, h.t.to_bits()));
                        assert_eq!(key(wide.best()), key(scalar.best()), "{at}");
                        assert_eq!(wide.t_max().to_bits(), scalar.t_max().to_bits(), "{at}");
                        assert_eq!(wide_stats, scalar_stats, "{at}");
                        hits += u32::from(scalar.best().is_some_and(|b| b.prim < 1_000));
                        answered += u32::from(want);
                        ties += u32::from(prior.is_some_and(|p| {
                            scalar.best().is_some_and(|b| b.t == p.1 && b.prim != p.0)
                        }));
                    }
                }
            }
        }
        assert!(
            hits > 10_000 && answered > 3_000 && ties > 500 && mixed > 3_000,
            "{hits} hits, {answered} answered, {ties} ties won, {mixed} mixed leaves"
        );
    }

    /// A leaf with fewer than `MIN_SPHERES` spheres is left to the scalar loop, untested
    /// and uncounted; one with enough is taken, a plane among them included.
    #[test]
    #[cfg_attr(
        not(prism_host_avx2),
        ignore = "this CPU lacks AVX2: the 8-wide kernels never run here"
    )]
    fn leaves_of_few_spheres_are_left_alone() {
        if super::super::skipped_without_avx2() {
            return;
        }
        let mut geometry = Geometry::default();
        let floor = crate::geometry::Plane::new(Vec3::NEG_Y, Vec3::Y).expect("a plane");
        geometry.add(Shape::from(floor), 0);
        for k in 0..MIN_SPHERES {
            let centre = Vec3::new(k as f32, 0.0, 0.0);
            geometry.add(Shape::Sphere(Sphere::new(centre, 1.0)), 0);
        }
        let ray = TraceRay::new(Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z));
        let pack_ray = PackRay::new(&ray);
        let prims: Vec<u32> = (0..=MIN_SPHERES).collect();
        let leaves = leaf_query(&geometry, &prims, &ray, &pack_ray);
        let test = |first: u32, count: u32| {
            let mut search = HitSearch::new(f32::INFINITY, QueryMode::Nearest);
            let mut stats = Stats::default();
            // SAFETY: AVX2 was detected above.
            let got = unsafe { test_sphere_leaf(&leaves, first, count, &mut search, &mut stats) };
            (got, search.best().map(|h| h.prim), stats.primitive_tests)
        };
        // One sphere short, with and without the plane.
        assert_eq!(test(0, MIN_SPHERES), (None, None, 0));
        assert_eq!(test(2, MIN_SPHERES - 1), (None, None, 0));
        // Enough, with and without the plane: the first sphere (id 1) is the nearest.
        let count = u64::from(MIN_SPHERES);
        assert_eq!(test(0, MIN_SPHERES + 1), (Some(false), Some(1), count + 1));
        assert_eq!(test(1, MIN_SPHERES), (Some(false), Some(1), count));
    }
}
