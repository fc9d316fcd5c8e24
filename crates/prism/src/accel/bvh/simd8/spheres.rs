//! `Sphere::intersect` in eight lanes of AVX2: one ray against up to eight spheres (the
//! single-ray walk's leaves, `shape_leaf.rs`) or one sphere against eight rays (the AVX2
//! packets' sphere kernel, `x86::test_sphere`).
//!
//! Lane by lane the pass makes the operations of `Sphere::intersect` in the same order (no
//! fused multiply-add), so each lane's distance is the scalar test's bit for bit
//! (unit-tested in `shape_leaf.rs` and by the packet tests).

use super::super::traverse::LeafQuery;
use std::arch::x86_64::*;

/// The most spheres one pass takes.
pub(super) const LANES: usize = 8;

/// `Sphere::intersect` of the spheres in `rows` (centre x, y, z and radius, a lane each)
/// against the leaf's ray at bound `t_max`: the lanes hit (a bit each) and every lane's
/// distance.
#[target_feature(enable = "avx2,popcnt")]
#[inline]
pub(super) fn sphere_hits(
    rows: &[[f32; LANES]; 4],
    leaves: &LeafQuery<'_>,
    t_max: f32,
) -> (u32, [f32; 8]) {
    let load = |row: &[f32; LANES]| {
        // SAFETY: a row holds eight f32s; unaligned load.
        unsafe { _mm256_loadu_ps(row.as_ptr()) }
    };
    let ray = &leaves.ray.ray;
    let origin = ray.origin.to_array().map(|v| _mm256_set1_ps(v));
    let dir = ray.dir.to_array().map(|v| _mm256_set1_ps(v));
    let centre = [0, 1, 2].map(|a| load(&rows[a]));
    let radius = load(&rows[3]);
    let r2 = _mm256_mul_ps(radius, radius);
    let (hit, t) = sphere_lanes(origin, dir, centre, r2, _mm256_set1_ps(t_max));
    let mut ts = [0.0f32; LANES];
    // SAFETY: `ts` holds eight f32s; unaligned store.
    unsafe { _mm256_storeu_ps(ts.as_mut_ptr(), t) };
    (hit, ts)
}

/// `Sphere::intersect` in eight lanes, each a ray (`origin`, `dir`) and a sphere (`centre`,
/// squared radius `r2`), any of them broadcast: lane by lane its operations in its order
/// (`Vec3::dot` sums x, y, then z; no fused multiply-add), so each lane's distance is the
/// scalar test's bit for bit. Returns the lanes that hit before `t_max` (a bit each) and
/// every lane's distance. Shared by the single-ray leaf test (`shape_leaf.rs`) and the packets' sphere
/// kernel (`x86::test_sphere`).
#[target_feature(enable = "avx2,popcnt")]
#[inline]
pub(super) fn sphere_lanes(
    origin: [__m256; 3],
    dir: [__m256; 3],
    centre: [__m256; 3],
    r2: __m256,
    t_max: __m256,
) -> (u32, __m256) {
    let (add, sub, mul) = (_mm256_add_ps, _mm256_sub_ps, _mm256_mul_ps);
    let dot = |x: &[__m256; 3], y: &[__m256; 3]| {
        add(add(mul(x[0], y[0]), mul(x[1], y[1])), mul(x[2], y[2]))
    };
    let (zero, sign) = (_mm256_setzero_ps(), _mm256_set1_ps(-0.0));
    let f = [0, 1, 2].map(|a| sub(origin[a], centre[a]));
    let b = dot(&f, &dir);
    let l = [0, 1, 2].map(|a| sub(f[a], mul(b, dir[a])));
    let disc = sub(r2, dot(&l, &l));
    let c = sub(dot(&f, &f), r2);
    // -b - copysign(sqrt(disc), b)
    let root = _mm256_sqrt_ps(disc);
    let signed_root = _mm256_or_ps(_mm256_andnot_ps(sign, root), _mm256_and_ps(sign, b));
    let q = sub(_mm256_xor_ps(b, sign), signed_root);
    let t0 = _mm256_div_ps(c, q);
    let swap = _mm256_cmp_ps::<_CMP_GT_OQ>(t0, q);
    let (near, far) = (_mm256_blendv_ps(t0, q, swap), _mm256_blendv_ps(q, t0, swap));
    let near_ahead = _mm256_cmp_ps::<_CMP_GT_OQ>(near, zero);
    let t = _mm256_blendv_ps(far, near, near_ahead);
    // A negative discriminant misses (the scalar test returns before its square root).
    let hit = _mm256_and_ps(
        _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GT_OQ>(t, zero),
            _mm256_cmp_ps::<_CMP_LT_OQ>(t, t_max),
        ),
        _mm256_cmp_ps::<_CMP_NLT_UQ>(disc, zero),
    );
    (_mm256_movemask_ps(hit) as u32, t)
}
