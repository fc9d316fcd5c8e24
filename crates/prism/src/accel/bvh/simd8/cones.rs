//! `Cone::intersect` in four lanes: one cone against four rays of a packet, the cone kernel
//! of both packet walks (AVX2 and AVX-512).
//! SPD's lattice and rings are mostly cylinders; tested one ray and one cone at a time,
//! their tests were a quarter to two fifths of a render (`perf`), most of it the latency of
//! one test's chain of f64 steps.
//!
//! Lane by lane the pass makes the operations of `Cone::intersect` in the same order (the
//! ray moved into the cone's frame in f32, the quadric and the caps in f64, no fused
//! multiply-add), so each lane's distance and part are the scalar test's bit for bit
//! (unit-tested below). The f64 steps take four lanes of AVX2: with AVX-512 eight lanes
//! would not go faster, as its dividers and square roots are no wider.

use super::{PacketSearch, RaySoa};
use crate::geometry::{Cone, ConeTerms, ShapeHit, ShapeKind};
use crate::stats::Stats;
use std::arch::x86_64::*;

/// A cone's terms (`ConeTerms`) broadcast across four lanes.
pub(super) struct ConeLanes {
    base: [__m128; 3],
    /// The frame's axes x, y and z, each by its three components.
    axes: [[__m128; 3]; 3],
    height: __m256d,
    base_radius: __m256d,
    apex_radius: __m256d,
    slope: __m256d,
    /// All ones where the cone is capped.
    capped: __m256d,
}

impl ConeLanes {
    /// One cone's terms in every lane.
    #[target_feature(enable = "avx2,popcnt")]
    #[inline]
    pub(super) fn splat(c: &ConeTerms) -> ConeLanes {
        let vector = |v: glam::Vec3| v.to_array().map(|x| _mm_set1_ps(x));
        ConeLanes {
            base: vector(c.base),
            axes: [vector(c.frame.x), vector(c.frame.y), vector(c.frame.z)],
            height: _mm256_set1_pd(c.height),
            base_radius: _mm256_set1_pd(c.base_radius),
            apex_radius: _mm256_set1_pd(c.apex_radius),
            slope: _mm256_set1_pd(c.slope),
            capped: _mm256_set1_pd(lane_mask(c.capped)),
        }
    }
}

/// A lane of a mask: all ones where `set`.
fn lane_mask(set: bool) -> f64 {
    if set {
        f64::from_bits(u64::MAX)
    } else {
        0.0
    }
}

/// What a pass found: the lanes hit before the bound (a bit each), and in every lane the
/// distance and the part (`ShapeHit::t` and `u` as `Cone::intersect` gives them).
pub(super) struct ConeHits {
    pub hit: u32,
    pub t: [f32; 4],
    pub part: [f32; 4],
}

/// `Cone::intersect` of `cone` in four lanes, each a ray (`origin`, `dir`) at its bound in
/// `t_max`: lane by lane its operations in its order.
#[target_feature(enable = "avx2,popcnt")]
#[inline]
pub(super) fn cone_lanes(
    cone: &ConeLanes,
    origin: [__m128; 3],
    dir: [__m128; 3],
    t_max: __m128,
) -> ConeHits {
    // The ray in the cone's frame, in f32 as `Frame::to_local` (`Vec3::dot` sums x, y,
    // then z), then widened.
    let dot = |v: &[__m128; 3], axis: &[__m128; 3]| {
        _mm_add_ps(
            _mm_add_ps(_mm_mul_ps(v[0], axis[0]), _mm_mul_ps(v[1], axis[1])),
            _mm_mul_ps(v[2], axis[2]),
        )
    };
    let v = [0, 1, 2].map(|a| _mm_sub_ps(origin[a], cone.base[a]));
    let local = |v: &[__m128; 3]| cone.axes.map(|axis| _mm256_cvtps_pd(dot(v, &axis)));
    let [ox, oy, oz] = local(&v);
    let [dx, dy, dz] = local(&dir);

    let (add, sub, mul, div) = (_mm256_add_pd, _mm256_sub_pd, _mm256_mul_pd, _mm256_div_pd);
    let splat = _mm256_set1_pd;
    let (and, zero) = (_mm256_and_pd, _mm256_setzero_pd());
    let (h, rb, k) = (cone.height, cone.base_radius, cone.slope);
    let ro = add(rb, mul(k, oz));
    let a = sub(add(mul(dx, dx), mul(dy, dy)), mul(mul(mul(k, k), dz), dz));
    let b = mul(
        splat(2.0),
        sub(add(mul(ox, dx), mul(oy, dy)), mul(mul(k, ro), dz)),
    );
    let c = sub(add(mul(ox, ox), mul(oy, oy)), mul(ro, ro));
    let on_side = |t: __m256d| {
        let z = add(oz, mul(t, dz));
        and(
            _mm256_cmp_pd::<_CMP_LE_OQ>(zero, z),
            _mm256_cmp_pd::<_CMP_LE_OQ>(z, h),
        )
    };
    // `consider` of each candidate in the scalar order: kept if its f32 distance lies
    // within (0, t_max) and it is strictly nearer than the one kept so far. The f32
    // comparisons are made on the values widened back, which is exact.
    let t_max = _mm256_cvtps_pd(t_max);
    let [side, base_cap, apex_cap] = ConeTerms::PARTS.map(|p| splat(f64::from(p)));
    let (mut best, mut part) = (splat(f64::INFINITY), zero);
    let mut consider = |t: __m256d, candidate: __m256d, p: __m256d| {
        let reported = _mm256_cvtps_pd(_mm256_cvtpd_ps(t));
        let within = and(
            _mm256_cmp_pd::<_CMP_GT_OQ>(reported, zero),
            _mm256_cmp_pd::<_CMP_LT_OQ>(reported, t_max),
        );
        let keep = and(and(candidate, within), _mm256_cmp_pd::<_CMP_LT_OQ>(t, best));
        best = _mm256_blendv_pd(best, t, keep);
        part = _mm256_blendv_pd(part, p, keep);
    };
    // Each kind of candidate only where some lane has one: most tests miss the side
    // (no real root) and SPD's cylinders have no caps, and the scalar test skips those
    // divisions and square roots too.
    let any = |mask: __m256d| _mm256_movemask_pd(mask) != 0;
    // `a != 0.0` holds for NaN as well (unordered), as in the scalar test.
    let quadratic = _mm256_cmp_pd::<_CMP_NEQ_UQ>(a, zero);
    let disc = sub(mul(b, b), mul(mul(splat(4.0), a), c));
    let roots = and(quadratic, _mm256_cmp_pd::<_CMP_GE_OQ>(disc, zero));
    if any(roots) {
        // -0.5 * (b + copysign(sqrt(disc), b))
        let sign = splat(-0.0);
        let root = _mm256_sqrt_pd(disc);
        let signed_root = _mm256_or_pd(_mm256_andnot_pd(sign, root), and(sign, b));
        let q = mul(splat(-0.5), add(b, signed_root));
        let (t1, t2) = (div(q, a), div(c, q));
        consider(t1, and(roots, on_side(t1)), side);
        consider(t2, and(roots, on_side(t2)), side);
    }
    // A leading coefficient of exactly zero leaves a linear equation.
    let linear = and(
        _mm256_cmp_pd::<_CMP_EQ_OQ>(a, zero),
        _mm256_cmp_pd::<_CMP_NEQ_UQ>(b, zero),
    );
    if any(linear) {
        let t = div(_mm256_xor_pd(c, splat(-0.0)), b);
        consider(t, and(linear, on_side(t)), side);
    }
    let caps = and(cone.capped, _mm256_cmp_pd::<_CMP_NEQ_UQ>(dz, zero));
    if any(caps) {
        for (z, r, p) in [(zero, rb, base_cap), (h, cone.apex_radius, apex_cap)] {
            let t = div(sub(z, oz), dz);
            let (x, y) = (add(ox, mul(t, dx)), add(oy, mul(t, dy)));
            let inside = _mm256_cmp_pd::<_CMP_LE_OQ>(add(mul(x, x), mul(y, y)), mul(r, r));
            consider(t, and(caps, inside), p);
        }
    }
    // A kept distance is finite (its f32 lies below t_max), so +∞ marks the lanes that
    // kept none.
    let hit = _mm256_cmp_pd::<_CMP_LT_OQ>(best, splat(f64::INFINITY));
    let mut out = ConeHits {
        hit: _mm256_movemask_pd(hit) as u32,
        t: [0.0; 4],
        part: [0.0; 4],
    };
    // SAFETY: each array holds four f32s; unaligned stores.
    unsafe {
        _mm_storeu_ps(out.t.as_mut_ptr(), _mm256_cvtpd_ps(best));
        _mm_storeu_ps(out.part.as_mut_ptr(), _mm256_cvtpd_ps(part));
    }
    out
}

/// `cone` (primitive `prim`) against the rays of `rays`, four per step, at each ray's
/// `nested` bound; a hit so found is kept if it holds at the ray's own bound for `prim`
/// (`PacketSearch::keep_shape_hit`), as the scalar test decides it. Shared by the AVX2 and
/// AVX-512 packet walks.
#[target_feature(enable = "avx2,popcnt")]
#[inline]
pub(super) fn test_cone(
    cone: &Cone,
    prim: u32,
    rays: u64,
    soa: &RaySoa,
    search: &mut PacketSearch,
    stats: &mut Stats,
) {
    stats.count_tests(ShapeKind::Cone, u64::from(rays.count_ones()));
    let lanes = ConeLanes::splat(&cone.terms());
    let load = |v: &[f32; 64], at: usize| {
        debug_assert!(at + 4 <= 64);
        // SAFETY: `at` is a multiple of four below 64; unaligned load.
        unsafe { _mm_loadu_ps(v.as_ptr().add(at)) }
    };
    let mut left = rays;
    while left != 0 {
        // The group of four rays holding the lowest one left.
        let at = (left.trailing_zeros() & !3) as usize;
        let wanted = (left >> at) & 0xf;
        left &= !(0xf << at);
        let origin = [0, 1, 2].map(|a| load(&soa.origin[a], at));
        let dir = [0, 1, 2].map(|a| load(&soa.dir[a], at));
        let found = cone_lanes(&lanes, origin, dir, load(&search.nested, at));
        let mut hit = wanted & u64::from(found.hit);
        while hit != 0 {
            let j = hit.trailing_zeros() as usize;
            hit &= hit - 1;
            let shape_hit = ShapeHit {
                t: found.t[j],
                u: found.part[j],
                v: 0.0,
            };
            search.keep_shape_hit(at + j, prim, shape_hit);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::hash::uniform;
    use crate::math::{Ray, Vec3};

    fn point(seed: u64, scale: f32) -> Vec3 {
        let c = |k| (uniform(seed as u32, (seed >> 32) as u32, 0, k, 31) * 2.0 - 1.0) * scale;
        Vec3::new(c(0), c(1), c(2))
    }

    /// A cone for `case`: cylinders (equal radii), cones narrowing and widening, pointed
    /// ones, capped and open, along an axis or any way.
    fn cone(case: u64, scale: f32) -> Cone {
        let u = |k: u32| uniform(case as u32, (case >> 32) as u32, 1, k, 32);
        let base = point(case * 8, scale);
        let axis = match case % 4 {
            0 => Vec3::Z,
            1 => Vec3::new(0.0, -1.0, 0.0),
            _ => point(case * 8 + 1, 1.0).normalize_or(Vec3::X),
        } * scale
            * (0.2 + u(0));
        let r = (0.05 + u(1)) * 0.5 * scale;
        let (rb, ra) = match case / 4 % 5 {
            0 | 1 => (r, r),
            2 => (r, 0.5 * r),
            3 => (0.0, r),
            _ => (r, 0.0),
        };
        Cone::new(base, rb, base + axis, ra, (case / 20).is_multiple_of(2)).expect("a cone")
    }

    /// A ray for `case` toward `c`: at its middle, along its axis, across it, grazing its
    /// side, from inside, or anywhere.
    fn ray(case: u64, c: &Cone, scale: f32) -> Ray {
        let t = c.terms();
        let mid = (c.base + c.apex) * 0.5;
        let origin = mid + point(case * 16 + 2, 3.0 * scale);
        let (origin, dir) = match case % 7 {
            0 => (origin, mid - origin),
            // Along the axis from off either end, into the caps when it has them.
            1 => (
                mid - t.frame.z * 3.0 * scale + point(case * 16 + 5, 0.1 * scale),
                t.frame.z,
            ),
            2 => (
                mid + t.frame.z * 3.0 * scale + point(case * 16 + 6, 0.1 * scale),
                -t.frame.z,
            ),
            // Perpendicular to the axis: the caps' division by zero.
            3 => (mid + t.frame.x * 4.0 * scale, -t.frame.x),
            // Tangent to the side at the middle.
            4 => {
                let radius = (t.base_radius + t.apex_radius) as f32 * 0.5;
                (
                    mid + t.frame.x * radius - t.frame.y * 3.0 * scale,
                    t.frame.y,
                )
            }
            5 => (mid, point(case * 16 + 3, 1.0)),
            _ => (origin, point(case * 16 + 4, 1.0)),
        };
        Ray::new(origin, dir.normalize_or(Vec3::Y))
    }

    fn lanes(v: [f32; 4]) -> __m128 {
        // SAFETY: four f32s; unaligned load (SSE is part of x86-64).
        unsafe { _mm_loadu_ps(v.as_ptr()) }
    }

    /// Rays parallel to a cone's side (a leading coefficient of exactly zero, the scalar
    /// test's linear branch) and along a cylinder's axis (no side hit at all): the lanes
    /// agree with the scalar test there too, and the linear branch does find hits.
    #[test]
    #[cfg_attr(
        not(prism_host_avx2),
        ignore = "this CPU lacks AVX2: the 8-wide kernels never run here"
    )]
    fn lanes_take_the_linear_branch_as_the_scalar_test() {
        if super::super::skipped_without_avx2() {
            return;
        }
        let mut linear_hits = 0;
        for scale in [1e-3f32, 1.0, 1e3] {
            // Slope -1: radius `scale` at the base, a point at the apex, axis +z, so a
            // direction with |x| = |z| (and y = 0) runs parallel to a side line.
            let cone = Cone::new(Vec3::ZERO, scale, Vec3::Z * scale, 0.0, true).expect("a cone");
            let cylinder =
                Cone::cylinder(Vec3::ZERO, Vec3::Z * scale, scale, false).expect("a cylinder");
            for case in 0..400u64 {
                let o = point(case * 16 + 7, 2.0 * scale);
                let s = std::f32::consts::FRAC_1_SQRT_2;
                let dirs = [
                    Vec3::new(s, 0.0, s),
                    Vec3::new(-s, 0.0, s),
                    Vec3::new(s, 0.0, -s),
                    Vec3::Z,
                ];
                for c in [&cone, &cylinder] {
                    let rays = dirs.map(|d| Ray::new(o, d));
                    let row =
                        |f: fn(&Ray) -> Vec3, a: usize| lanes(rays.each_ref().map(|r| f(r)[a]));
                    // SAFETY: AVX2 was detected above.
                    let got = unsafe {
                        cone_lanes(
                            &ConeLanes::splat(&c.terms()),
                            [0, 1, 2].map(|a| row(|r| r.origin, a)),
                            [0, 1, 2].map(|a| row(|r| r.dir, a)),
                            lanes([f32::INFINITY; 4]),
                        )
                    };
                    for (lane, r) in rays.iter().enumerate() {
                        let want = c.intersect(r, f32::INFINITY);
                        let at = format!("scale {scale} case {case} lane {lane}: {c:?} {r:?}");
                        assert_eq!(got.hit >> lane & 1 == 1, want.is_some(), "{at}");
                        if let Some(w) = want {
                            assert_eq!(got.t[lane].to_bits(), w.t.to_bits(), "{at}");
                            assert_eq!(got.part[lane], w.u, "{at}");
                            linear_hits +=
                                u32::from(lane < 3 && w.u == 0.0 && std::ptr::eq(c, &cone));
                        }
                    }
                }
            }
        }
        assert!(
            linear_hits > 100,
            "{linear_hits} hits on the side through the linear branch"
        );
    }

    /// Every lane is `Cone::intersect` bit for bit: one cone against four rays, at three
    /// scales and several bounds.
    #[test]
    #[cfg_attr(
        not(prism_host_avx2),
        ignore = "this CPU lacks AVX2: the 8-wide kernels never run here"
    )]
    fn lanes_are_the_scalar_test() {
        if super::super::skipped_without_avx2() {
            return;
        }
        let (mut hits, mut caps, mut misses) = (0, 0, 0);
        for scale in [1e-3f32, 1.0, 1e3] {
            for case in 0..4000u64 {
                let c = cone(case, scale);
                let rays: Vec<Ray> = (0..4).map(|k| ray(case * 4 + k, &c, scale)).collect();
                let bound = [f32::INFINITY, 3.0 * scale, 0.5 * scale][(case % 3) as usize];
                let bounds = [bound, f32::INFINITY, bound, 1e-3 * scale];
                let row =
                    |f: fn(&Ray) -> Vec3, a: usize| lanes([0, 1, 2, 3].map(|k| f(&rays[k])[a]));
                // SAFETY: AVX2 was detected above.
                let got = unsafe {
                    cone_lanes(
                        &ConeLanes::splat(&c.terms()),
                        [0, 1, 2].map(|a| row(|r| r.origin, a)),
                        [0, 1, 2].map(|a| row(|r| r.dir, a)),
                        lanes(bounds),
                    )
                };
                for (lane, r) in rays.iter().enumerate() {
                    let want = c.intersect(r, bounds[lane]);
                    let at = format!("scale {scale} case {case} lane {lane}: {c:?} {r:?}");
                    assert_eq!(got.hit >> lane & 1 == 1, want.is_some(), "{at}");
                    match want {
                        Some(w) => {
                            assert_eq!(got.t[lane].to_bits(), w.t.to_bits(), "{at}");
                            assert_eq!(got.part[lane], w.u, "{at}");
                            *(if w.u != 0.0 { &mut caps } else { &mut hits }) += 1;
                        }
                        None => misses += 1,
                    }
                }
            }
        }
        assert!(
            hits > 10_000 && caps > 2_000 && misses > 10_000,
            "{hits} side hits, {caps} cap hits, {misses} misses"
        );
    }
}
