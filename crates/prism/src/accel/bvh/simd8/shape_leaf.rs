//! The single-ray test of a leaf of spheres and cones in the 8-wide walk: the leaf's spheres
//! through one pass of eight lanes (`spheres.rs`) and its cones through passes of four
//! (`cones.rs`) instead of one `intersect` call each; its other primitives are tested one by
//! one in their turn. Scenes of spheres and cylinders (SPD's shells, lattice, rings, balls)
//! meet such leaves on every reflected and refracted ray, which the packet walks answer one
//! ray at a time once the rays point every way.
//!
//! Each lane's result is the scalar test's bit for bit. The leaf is then gone through in
//! order: a hit from a pass is kept through `HitSearch::keep_within` at the tie rule's bound
//! for its id, another primitive is tested as the scalar loop tests it, and every test is
//! counted as that loop counts it (up to the one that answers an any-hit query), so hits,
//! ties, statistics and early exits are those of `LeafQuery::test`.

use super::super::traverse::LeafQuery;
use super::cones::{cone_lanes, ConeLanes};
use super::spheres::{sphere_hits, LANES};
use crate::accel::query::HitSearch;
use crate::geometry::{ConeTerms, Shape, ShapeHit, ShapeKind};
use crate::stats::Stats;
use arrayvec::ArrayVec;
use std::arch::x86_64::*;

/// The fewest spheres a pass is made for: a scalar test that misses stops before its
/// square root and division, which the pass always makes, so for two or three spheres the
/// pass cost as much as it saved (SPD balls and rings 1-3 % slower; shells, whose rays
/// meet 90 spheres each, 12 % faster either way).
const MIN_SPHERES: u32 = 4;

/// The fewest cones a pass is made for: as for spheres, a scalar test that misses the side
/// stops before its square root and divisions, and a pass makes them for all four lanes
/// once one lane needs them (SPD rings rendered 0.55 s with passes from two cones, 0.52 s
/// from four, as fast as from three or five within the noise).
const MIN_CONES: u32 = 4;

/// Tests the leaf `prims[first .. first + count]` of at most eight primitives when it holds
/// `MIN_SPHERES` spheres or `MIN_CONES` cones: those in passes, the others one by one as
/// `LeafQuery::test` tests them, all in leaf order. `None` (nothing tested, nothing
/// counted) for any other leaf; Some(true) when the query is answered. Never inlined, so
/// that the walks over triangle packs keep their code as it was.
#[target_feature(enable = "avx2,popcnt")]
#[inline(never)]
pub(in crate::accel::bvh) fn test_shape_leaf(
    leaves: &LeafQuery<'_>,
    first: u32,
    count: u32,
    search: &mut HitSearch,
    stats: &mut Stats,
) -> Option<bool> {
    let n = count as usize;
    // Smaller leaves cannot hold enough of either: not even their shapes are read.
    if !(MIN_SPHERES.min(MIN_CONES) as usize..=LANES).contains(&n) {
        return None;
    }
    let ids = &leaves.prims[first as usize..][..n];
    // The spheres' centres and radii in the lanes of their places in the leaf (other
    // lanes stay zero and are masked off); the cones' places.
    let mut rows = [[0.0f32; LANES]; 4];
    let (mut spheres, mut cones) = (0u32, 0u32);
    for (k, &prim) in ids.iter().enumerate() {
        match &leaves.geometry.primitives[prim as usize].shape {
            Shape::Sphere(s) => {
                rows[0][k] = s.center.x;
                rows[1][k] = s.center.y;
                rows[2][k] = s.center.z;
                rows[3][k] = s.radius;
                spheres |= 1 << k;
            }
            Shape::Cone(_) => cones |= 1 << k,
            _ => {}
        }
    }
    if spheres.count_ones() < MIN_SPHERES {
        spheres = 0;
    }
    if cones.count_ones() < MIN_CONES {
        cones = 0;
    }
    if spheres == 0 && cones == 0 {
        return None;
    }
    // At the loosest bound the search will give any of them: bounds only shrink, and each
    // hit is held to its own bound when its turn comes.
    let bound = search.nested_limit();
    let (mut hit, mut t, mut part) = (0u32, [0.0f32; LANES], [0.0f32; LANES]);
    if spheres != 0 {
        let (sphere_hit, sphere_t) = sphere_hits(&rows, leaves, bound);
        hit |= sphere_hit & spheres;
        t = sphere_t;
    }
    if cones != 0 {
        cone_hits(ids, cones, leaves, bound, (&mut hit, &mut t, &mut part));
    }
    for (k, &prim) in ids.iter().enumerate() {
        let answered = if (spheres | cones) & (1 << k) != 0 {
            let kind = if spheres & (1 << k) != 0 {
                ShapeKind::Sphere
            } else {
                ShapeKind::Cone
            };
            stats.count_test(kind);
            let shape_hit = ShapeHit {
                t: t[k],
                u: part[k],
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

/// `Cone::intersect` of the cones at the places `cones` of the leaf `ids` against the
/// leaf's ray at bound `t_max`, four at a time: each one's hit bit, distance and part
/// written into its place.
#[target_feature(enable = "avx2,popcnt")]
#[inline]
fn cone_hits(
    ids: &[u32],
    cones: u32,
    leaves: &LeafQuery<'_>,
    t_max: f32,
    (hit, t, part): (&mut u32, &mut [f32; LANES], &mut [f32; LANES]),
) {
    let ray = &leaves.ray.ray;
    let origin = ray.origin.to_array().map(|v| _mm_set1_ps(v));
    let dir = ray.dir.to_array().map(|v| _mm_set1_ps(v));
    let bound = _mm_set1_ps(t_max);
    let terms = |k: usize| match &leaves.geometry.primitives[ids[k] as usize].shape {
        Shape::Cone(c) => c.terms(),
        _ => unreachable!("a cone at each place of `cones`"),
    };
    let mut left = cones;
    while left != 0 {
        // The next four cones (or fewer), in leaf order.
        let (mut group, mut places) =
            (ArrayVec::<ConeTerms, 4>::new(), ArrayVec::<usize, 4>::new());
        while left != 0 && !group.is_full() {
            let k = left.trailing_zeros() as usize;
            left &= left - 1;
            group.push(terms(k));
            places.push(k);
        }
        let found = cone_lanes(&ConeLanes::new(&group), origin, dir, bound);
        for (lane, &k) in places.iter().enumerate() {
            *hit |= (found.hit >> lane & 1) << k;
            t[k] = found.t[lane];
            part[k] = found.part[lane];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::{Hit, QueryMode};
    use crate::geometry::{AaBox, Cone, Geometry, PackRay, Sphere};
    use crate::math::hash::uniform;
    use crate::math::{Ray, TraceRay, Vec3};

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

    /// Six cones between the spheres' centres, as SPD lattice's and rings' cylinders join
    /// their balls: cylinders and cones, open and capped, one a copy of another (a tie).
    fn cones(case: u64, scale: f32, s: &[Sphere]) -> Vec<Cone> {
        let mut c: Vec<Cone> = (0..6u64)
            .map(|k| {
                let (a, b) = (s[k as usize].center, s[(k as usize + 3) % 8].center);
                let r = 0.1 * scale * (1.0 + k as f32 * 0.3);
                let apex_radius = if (case + k).is_multiple_of(3) {
                    0.5 * r
                } else {
                    r
                };
                let b = if a == b { a + Vec3::Y * scale } else { b };
                Cone::new(a, r, b, apex_radius, (case + k).is_multiple_of(2)).expect("a cone")
            })
            .collect();
        c[(case % 5) as usize + 1] = c[0];
        c
    }

    /// A ray for `case`: toward a sphere's centre, grazing one (along a tangent, so the
    /// discriminant is about zero), from inside one, axis-parallel, along or across a
    /// cone's axis, or anywhere.
    fn ray(case: u64, scale: f32, s: &[Sphere], c: &[Cone]) -> Option<TraceRay> {
        let target = s[(case / 8 % 8) as usize];
        let cone = c[(case / 8 % 6) as usize];
        let origin = point(case * 64 + 40, 3.0 * scale);
        let (origin, dir) = match case % 8 {
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
                d[(case / 8 % 3) as usize] = if case % 16 < 8 { 1.0 } else { -1.0 };
                (
                    target.center - d * 2.0 * scale + point(case * 64 + 43, 0.1 * target.radius),
                    d,
                )
            }
            4 => (origin, (cone.base + cone.apex) * 0.5 - origin),
            // Along the cone's axis, into its caps when it has them.
            5 => (
                cone.base - (cone.apex - cone.base),
                cone.apex - cone.base + point(case * 64 + 45, 1e-3 * scale),
            ),
            _ => (origin, point(case * 64 + 44, 1.0)),
        };
        let dir = dir.normalize_or_zero();
        (dir != Vec3::ZERO).then(|| TraceRay::new(Ray::new(origin, dir)))
    }

    /// The leaf test gives what `LeafQuery::test` gives primitive by primitive: answer,
    /// best hit, bound and statistics, for leaves of two to eight primitives in a shuffled
    /// order: spheres only, spheres with a box and a cone, cones with a sphere and a box,
    /// and cones only (leaves with too few of both must be declined); both query modes,
    /// with no prior hit, a far one, and one tying the leaf's first hit with a lower or a
    /// higher id; at three scales.
    #[test]
    fn the_leaf_passes_are_the_scalar_loop() {
        if !super::super::available() {
            eprintln!("skipped: this CPU lacks AVX2, so the 8-wide path is never taken");
            return;
        }
        let (mut hits, mut answered, mut ties, mut mixed, mut cone_hits) = (0, 0, 0, 0, 0);
        for scale in [1e-3f32, 1.0, 1e3] {
            for case in 0..3000u64 {
                let s = spheres(case, scale);
                let c = cones(case, scale, &s);
                let mut geometry = Geometry::default();
                for sphere in &s {
                    geometry.add(Shape::Sphere(*sphere), 0);
                }
                // A box, id 8, then the cones, ids 9 to 14.
                let a = s[0].center;
                geometry.add(Shape::from(AaBox::new(a, a + Vec3::splat(0.3 * scale))), 0);
                for cone in &c {
                    geometry.add(Shape::from(*cone), 0);
                }
                let Some(ray) = ray(case, scale, &s, &c) else {
                    continue;
                };
                let n = 2 + (case % 7) as u32;
                // Ids in a shuffled order, as leaves hold them after a build.
                let shift = (case / 3 % 8) as u32;
                let mut prims: Vec<u32> = (0..8).map(|k| (k * 5 + shift) % 8).collect();
                match case % 4 {
                    // Spheres with the box and a cone.
                    1 => {
                        prims[(case / 21 % 3) as usize] = 8;
                        prims[(1 + case / 63 % 7) as usize] = 9 + (case / 7 % 6) as u32;
                    }
                    // Cones, with a sphere and the box among them.
                    2 => {
                        for (k, p) in prims.iter_mut().enumerate() {
                            if k as u64 != case / 4 % 8 {
                                *p = 9 + ((k as u64 + case) % 6) as u32;
                            }
                        }
                        prims[(case / 32 % 8) as usize] = 8;
                    }
                    // Cones only.
                    3 => {
                        for (k, p) in prims.iter_mut().enumerate() {
                            *p = 9 + ((k as u64 * 5 + case) % 6) as u32;
                        }
                    }
                    _ => {}
                }
                let pack_ray = PackRay::new(&ray);
                let leaves = LeafQuery {
                    prims: &prims,
                    packs: &[],
                    geometry: &geometry,
                    ray: &ray,
                    pack_ray: &pack_ray,
                };
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
                            unsafe { test_shape_leaf(&leaves, 0, n, &mut wide, &mut wide_stats) };
                        let at = format!("scale {scale} case {case} n {n} {mode:?} {prior:?}");
                        let leaf = &prims[..n as usize];
                        let count = |ids: std::ops::Range<u32>| {
                            leaf.iter().filter(|p| ids.contains(p)).count() as u32
                        };
                        let (in_spheres, in_cones) = (count(0..8), count(9..15));
                        if in_spheres < MIN_SPHERES && in_cones < MIN_CONES {
                            assert_eq!(got, None, "{at}");
                            continue;
                        }
                        mixed += u32::from(in_spheres > 0 && in_cones > 0);
                        assert_eq!(got, Some(want), "{at}");
                        let key = |h: Option<Hit>| h.map(|h| (h.prim, h.t.to_bits(), h.u));
                        assert_eq!(key(wide.best()), key(scalar.best()), "{at}");
                        assert_eq!(wide.t_max().to_bits(), scalar.t_max().to_bits(), "{at}");
                        assert_eq!(wide_stats, scalar_stats, "{at}");
                        let best = scalar.best().filter(|b| b.prim < 1_000);
                        hits += u32::from(best.is_some());
                        cone_hits += u32::from(best.is_some_and(|b| (9..15).contains(&b.prim)));
                        answered += u32::from(want);
                        ties += u32::from(prior.is_some_and(|p| {
                            scalar.best().is_some_and(|b| b.t == p.1 && b.prim != p.0)
                        }));
                    }
                }
            }
        }
        assert!(
            hits > 10_000 && cone_hits > 3_000 && answered > 3_000 && ties > 500 && mixed > 3_000,
            "{hits} hits ({cone_hits} on cones), {answered} answered, {ties} ties won, \
             {mixed} mixed leaves"
        );
    }

    /// A leaf with fewer than `MIN_SPHERES` spheres and `MIN_CONES` cones is left to the
    /// scalar loop, untested and uncounted; one with enough is taken, a plane among them
    /// included.
    #[test]
    fn leaves_of_few_spheres_and_cones_are_left_alone() {
        if !super::super::available() {
            eprintln!("skipped: this CPU lacks AVX2, so the 8-wide path is never taken");
            return;
        }
        let mut geometry = Geometry::default();
        let floor = crate::geometry::Plane::new(Vec3::NEG_Y, Vec3::Y).expect("a plane");
        geometry.add(Shape::from(floor), 0);
        for k in 0..MIN_SPHERES {
            let centre = Vec3::new(k as f32, 0.0, 0.0);
            geometry.add(Shape::Sphere(Sphere::new(centre, 1.0)), 0);
        }
        let post = |x: f32| {
            let base = Vec3::new(x, -1.0, 3.0);
            Cone::cylinder(base, base + Vec3::Y * 2.0, 0.5, false).expect("a cylinder")
        };
        // Behind the spheres, ids MIN_SPHERES + 1 onwards.
        for k in 0..MIN_CONES {
            geometry.add(Shape::from(post(k as f32)), 0);
        }
        let ray = TraceRay::new(Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z));
        let pack_ray = PackRay::new(&ray);
        let prims: Vec<u32> = (0..=MIN_SPHERES + MIN_CONES).collect();
        let leaves = LeafQuery {
            prims: &prims,
            packs: &[],
            geometry: &geometry,
            ray: &ray,
            pack_ray: &pack_ray,
        };
        let test = |first: u32, count: u32| {
            let mut search = HitSearch::new(f32::INFINITY, QueryMode::Nearest);
            let mut stats = Stats::default();
            // SAFETY: AVX2 was detected above.
            let got = unsafe { test_shape_leaf(&leaves, first, count, &mut search, &mut stats) };
            (got, search.best().map(|h| h.prim), stats.primitive_tests)
        };
        // One sphere short, with and without the plane.
        assert_eq!(test(0, MIN_SPHERES), (None, None, 0));
        assert_eq!(test(2, MIN_SPHERES - 1), (None, None, 0));
        // One cone short, after the last sphere.
        assert_eq!(test(MIN_SPHERES, MIN_CONES), (None, None, 0));
        // Enough spheres, with and without the plane: the first sphere (id 1) is the
        // nearest.
        let count = u64::from(MIN_SPHERES);
        assert_eq!(test(0, MIN_SPHERES + 1), (Some(false), Some(1), count + 1));
        assert_eq!(test(1, MIN_SPHERES), (Some(false), Some(1), count));
        // Enough cones, with and without the last sphere (which the ray misses): the
        // first cone is the nearest.
        let cones = u64::from(MIN_CONES);
        let first_cone = MIN_SPHERES + 1;
        assert_eq!(
            test(MIN_SPHERES, MIN_CONES + 1),
            (Some(false), Some(first_cone), cones + 1)
        );
        assert_eq!(
            test(first_cone, MIN_CONES),
            (Some(false), Some(first_cone), cones)
        );
    }
}
