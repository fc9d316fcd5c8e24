//! The packet kernels of `simd8.rs` with AVX-512: sixteen rays per step instead of eight,
//! and comparisons straight into mask registers. Lane by lane the same operations in the
//! same order as the AVX2 kernels (no fused multiply-add), so every answer is bit-identical
//! to theirs and to each ray's own test; the walk, the node test and the leaves around
//! them are shared (`x86::traverse_packet16`).

use super::x86::Packet8;
use super::{PacketSearch, RaySoa, TrianglePack, Wide8Node};
use crate::geometry::{DecidedHit, ShapeHit, ShapeKind, Sphere};
use crate::math::robust::gamma;
use crate::stats::Stats;
use std::arch::x86_64::*;

/// Sixteen lanes of a packet array (one value per ray), from ray `at`.
#[target_feature(enable = "avx2,popcnt,avx512f")]
#[inline]
fn load(v: &[f32; 64], at: usize) -> __m512 {
    debug_assert!(at + 16 <= 64);
    // SAFETY: `at + 16 <= 64` (the callers' groups); unaligned load.
    unsafe { _mm512_loadu_ps(v.as_ptr().add(at)) }
}

/// The sixteen lanes of `v`, for the scalar steps after a kernel.
#[target_feature(enable = "avx2,popcnt,avx512f")]
#[inline]
fn store(v: __m512) -> [f32; 16] {
    let mut out = [0.0f32; 16];
    // SAFETY: `out` holds sixteen f32s; unaligned store.
    unsafe { _mm512_storeu_ps(out.as_mut_ptr(), v) };
    out
}

/// `x86::rays_entering` sixteen rays per step: the rays of `rays_in` whose own box test
/// enters child `lane` of `node` before their bound.
#[target_feature(enable = "avx2,popcnt,avx512f")]
#[inline]
pub(super) fn rays_entering(
    packet: &Packet8,
    node: &Wide8Node,
    lane: usize,
    rays_in: u64,
    soa: &RaySoa,
    bound: &[f32; 64],
) -> u64 {
    // Written out rather than mapped through a closure, which one build left as a call
    // per child (balls 8 % slower).
    let (b, n, f) = (&node.bounds, packet.near, packet.far);
    let near = [
        _mm512_set1_ps(b[n[0]][lane]),
        _mm512_set1_ps(b[n[1]][lane]),
        _mm512_set1_ps(b[n[2]][lane]),
    ];
    let far = [
        _mm512_set1_ps(b[f[0]][lane]),
        _mm512_set1_ps(b[f[1]][lane]),
        _mm512_set1_ps(b[f[2]][lane]),
    ];
    let exit_scale = _mm512_set1_ps(crate::accel::CULL_SLACK);
    let mut out = 0u64;
    for group in 0..4 {
        let at = 16 * group;
        let wanted = (rays_in >> at) as u16;
        if wanted == 0 {
            continue;
        }
        let mut enter = _mm512_setzero_ps();
        let mut exit = load(bound, at);
        for axis in 0..3 {
            let o = load(&soa.origin[axis], at);
            let inv = load(&soa.inv_dir[axis], at);
            let t_near = _mm512_mul_ps(_mm512_sub_ps(near[axis], o), inv);
            let t_far = _mm512_mul_ps(_mm512_sub_ps(far[axis], o), inv);
            // As `_mm256_max_ps`/`_mm256_min_ps`: a NaN first operand yields the second.
            enter = _mm512_max_ps(t_near, enter);
            exit = _mm512_min_ps(t_far, exit);
        }
        let hit =
            _mm512_mask_cmp_ps_mask::<_CMP_LE_OQ>(wanted, enter, _mm512_mul_ps(exit, exit_scale));
        out |= u64::from(hit) << at;
    }
    out
}

/// `x86::test_triangle` sixteen rays per step: triangle `lane` of `pack` against the rays
/// of `rays`, which share the axis permutation `k`.
#[target_feature(enable = "avx2,popcnt,avx512f")]
#[inline]
pub(super) fn test_triangle(
    pack: &TrianglePack,
    lane: usize,
    k: [usize; 3],
    rays: u64,
    soa: &RaySoa,
    search: &mut PacketSearch,
) {
    let v = pack.lanes_by_vertex();
    let vertex = |i: usize| k.map(|axis| _mm512_set1_ps(v[i][axis][lane]));
    let (pa, pb, pc) = (vertex(0), vertex(1), vertex(2));
    let zero = _mm512_setzero_ps();
    let splat = |x: f32| _mm512_set1_ps(x);
    let (add, sub, mul) = (_mm512_add_ps, _mm512_sub_ps, _mm512_mul_ps);
    let eq = |x| _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(x, zero);
    let lt = |x| _mm512_cmp_ps_mask::<_CMP_LT_OQ>(x, zero);
    let gt = |x| _mm512_cmp_ps_mask::<_CMP_GT_OQ>(x, zero);
    let less = |x, y| _mm512_cmp_ps_mask::<_CMP_LT_OQ>(x, y);
    let greater = |x, y| _mm512_cmp_ps_mask::<_CMP_GT_OQ>(x, y);
    let abs = _mm512_abs_ps;
    let abs_max = |x: [__m512; 3]| _mm512_max_ps(_mm512_max_ps(abs(x[0]), abs(x[1])), abs(x[2]));
    let prim = pack.ids[lane];
    for group in 0..4 {
        let at = 16 * group;
        let wanted = (rays >> at) as u16;
        if wanted == 0 {
            continue;
        }
        let o = k.map(|axis| load(&soa.origin[axis], at));
        let (sx, sy, sz) = (
            load(&soa.shear[0], at),
            load(&soa.shear[1], at),
            load(&soa.shear[2], at),
        );
        let rel = |p: &[__m512; 3]| [0, 1, 2].map(|a| sub(p[a], o[a]));
        let (a, b, c) = (rel(&pa), rel(&pb), rel(&pc));
        let sheared = |p: &[__m512; 3]| (sub(p[0], mul(sx, p[2])), sub(p[1], mul(sy, p[2])));
        let (ax, ay) = sheared(&a);
        let (bx, by) = sheared(&b);
        let (cx, cy) = sheared(&c);
        let u = sub(mul(cx, by), mul(cy, bx));
        let v = sub(mul(ax, cy), mul(ay, cx));
        let w = sub(mul(bx, ay), mul(by, ax));
        let exact_zero = (eq(u) | eq(v) | eq(w)) & wanted;
        let outside = (lt(u) | lt(v) | lt(w)) & (gt(u) | gt(v) | gt(w));
        let det = add(add(u, v), w);
        let (az, bz, cz) = (mul(sz, a[2]), mul(sz, b[2]), mul(sz, c[2]));
        let t_scaled = add(add(mul(u, az), mul(v, bz)), mul(w, cz));
        let nested = load(&search.nested, at);
        let limit = mul(nested, det);
        let behind_or_beyond = (lt(det)
            & (_mm512_cmp_ps_mask::<_CMP_GE_OQ>(t_scaled, zero) | less(t_scaled, limit)))
            | (gt(det)
                & (_mm512_cmp_ps_mask::<_CMP_LE_OQ>(t_scaled, zero) | greater(t_scaled, limit)));
        let rejected = outside | behind_or_beyond | eq(det);
        let open = !rejected & !exact_zero & wanted;
        let mut undecided = u64::from(exact_zero);
        if open != 0 {
            // The division and pbrt-v4's bound on the rounding of t, as the scalar test.
            let inv = _mm512_div_ps(splat(1.0), det);
            let t = mul(t_scaled, inv);
            let (max_x, max_y, max_z) = (
                abs_max([ax, bx, cx]),
                abs_max([ay, by, cy]),
                abs_max([az, bz, cz]),
            );
            let delta_z = mul(splat(gamma(3)), max_z);
            let delta_x = mul(splat(gamma(5)), add(max_x, max_z));
            let delta_y = mul(splat(gamma(5)), add(max_y, max_z));
            let delta_e = mul(
                splat(2.0),
                add(
                    add(mul(mul(splat(gamma(2)), max_x), max_y), mul(delta_y, max_x)),
                    mul(delta_x, max_y),
                ),
            );
            let max_e = abs_max([u, v, w]);
            let delta_t = mul(
                mul(
                    splat(3.0),
                    add(
                        add(mul(mul(splat(gamma(3)), max_e), max_z), mul(delta_e, max_z)),
                        mul(delta_z, max_e),
                    ),
                ),
                abs(inv),
            );
            let infinity = splat(f32::INFINITY);
            let finite = less(abs(t), infinity) & less(abs(delta_t), infinity);
            let within = less(t, nested) & greater(t, delta_t);
            let mut hit = u64::from(open & finite & within);
            undecided |= u64::from(open & !finite);
            if hit != 0 {
                let (det, t_scaled, t) = (store(det), store(t_scaled), store(t));
                let (b1, b2) = (store(mul(v, inv)), store(mul(w, inv)));
                while hit != 0 {
                    let j = hit.trailing_zeros() as usize;
                    hit &= hit - 1;
                    let decided = DecidedHit {
                        det: det[j],
                        t_scaled: t_scaled[j],
                        t: t[j],
                        b1: b1[j],
                        b2: b2[j],
                    };
                    search.keep_decided(at + j, prim, &decided);
                }
            }
        }
        while undecided != 0 {
            let j = undecided.trailing_zeros() as usize;
            undecided &= undecided - 1;
            search.test_pack_lane(at + j, pack, lane, &soa.ray(at + j));
        }
    }
}

/// `x86::test_sphere` sixteen rays per step: `sphere` (primitive `prim`) against the rays
/// of `rays`, lane by lane the operations of `Sphere::intersect`.
#[target_feature(enable = "avx2,popcnt,avx512f")]
#[inline]
pub(super) fn test_sphere(
    sphere: &Sphere,
    prim: u32,
    rays: u64,
    soa: &RaySoa,
    search: &mut PacketSearch,
    stats: &mut Stats,
) {
    stats.count_tests(ShapeKind::Sphere, u64::from(rays.count_ones()));
    let (add, sub, mul) = (_mm512_add_ps, _mm512_sub_ps, _mm512_mul_ps);
    let dot = |x: &[__m512; 3], y: &[__m512; 3]| {
        add(add(mul(x[0], y[0]), mul(x[1], y[1])), mul(x[2], y[2]))
    };
    // Sign-bit operations on the integer view (the float forms need AVX-512DQ).
    let bits = _mm512_castps_si512;
    let sign = _mm512_set1_epi32(i32::MIN);
    let centre = sphere.center.to_array().map(|v| _mm512_set1_ps(v));
    let r2 = _mm512_set1_ps(sphere.radius * sphere.radius);
    let zero = _mm512_setzero_ps();
    for group in 0..4 {
        let at = 16 * group;
        let wanted = (rays >> at) as u16;
        if wanted == 0 {
            continue;
        }
        let f = [0, 1, 2].map(|a| sub(load(&soa.origin[a], at), centre[a]));
        let d = [0, 1, 2].map(|a| load(&soa.dir[a], at));
        let b = dot(&f, &d);
        let l = [0, 1, 2].map(|a| sub(f[a], mul(b, d[a])));
        let disc = sub(r2, dot(&l, &l));
        let c = sub(dot(&f, &f), r2);
        // -b - copysign(sqrt(disc), b)
        let root = _mm512_sqrt_ps(disc);
        let signed_root = _mm512_castsi512_ps(_mm512_or_si512(
            _mm512_andnot_si512(sign, bits(root)),
            _mm512_and_si512(sign, bits(b)),
        ));
        let q = sub(
            _mm512_castsi512_ps(_mm512_xor_si512(bits(b), sign)),
            signed_root,
        );
        let t0 = _mm512_div_ps(c, q);
        let swap = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(t0, q);
        let (near, far) = (
            _mm512_mask_blend_ps(swap, t0, q),
            _mm512_mask_blend_ps(swap, q, t0),
        );
        let near_ahead = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(near, zero);
        let t = _mm512_mask_blend_ps(near_ahead, far, near);
        let nested = load(&search.nested, at);
        let hit = _mm512_cmp_ps_mask::<_CMP_GT_OQ>(t, zero)
            & _mm512_cmp_ps_mask::<_CMP_LT_OQ>(t, nested)
            & !_mm512_cmp_ps_mask::<_CMP_LT_OQ>(disc, zero);
        let mut hit = u64::from(hit & wanted);
        if hit != 0 {
            let ts = store(t);
            while hit != 0 {
                let j = hit.trailing_zeros() as usize;
                hit &= hit - 1;
                let shape_hit = ShapeHit {
                    t: ts[j],
                    u: 0.0,
                    v: 0.0,
                };
                search.keep_shape_hit(at + j, prim, shape_hit);
            }
        }
    }
}
