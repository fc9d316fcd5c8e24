//! The watertight triangle test in SIMD lanes, written once over `FloatLanes`: each lane a
//! triangle and a ray (either of them broadcast), lane by lane `intersect_triangle`'s
//! operations in its order (no fused multiply-add), so every width gives its values bit for
//! bit. Its instances: four triangles against one ray (`TrianglePack::hits`, glam's `Vec4`),
//! eight against one ray (two packs at once in the 8-wide walk), and one triangle against
//! eight or sixteen rays of a packet (`accel/bvh/simd8/per_ray.rs`); pbrt-v4's bound on the
//! rounding of t (`t_rounding_bound`) serves the scalar test too.
//!
//! A lane is left *undecided*, for the scalar test to decide, where an edge function is an
//! exact zero (the scalar test re-evaluates those in f64) or a value is not finite.

use super::triangle_pack::DecidedHit;
use crate::math::lanes::FloatLanes;
use crate::math::robust::gamma;

/// pbrt-v4's bound on the rounding of the watertight test's t, from the sheared vertices'
/// x, y and z (a lane per triangle), the edge functions and 1 / det: a hit at a distance
/// not above it is not provably in front of the ray. The one statement of the bound: the
/// scalar test takes it with one lane (`f32`).
#[inline(always)]
pub(crate) fn t_rounding_bound<L: FloatLanes>(
    x: [L; 3],
    y: [L; 3],
    z: [L; 3],
    edges: [L; 3],
    inv: L,
) -> L {
    let (max_x, max_y, max_z) = (L::abs_max(x), L::abs_max(y), L::abs_max(z));
    let gamma = |n| L::splat(gamma(n));
    let delta_z = gamma(3) * max_z;
    let delta_x = gamma(5) * (max_x + max_z);
    let delta_y = gamma(5) * (max_y + max_z);
    let delta_e = L::splat(2.0) * (gamma(2) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    let max_e = L::abs_max(edges);
    L::splat(3.0) * (gamma(3) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv.abs()
}

/// The edge functions, determinant, scaled distance and sheared vertex coordinates (`x[i]`,
/// `y[i]`, `z[i]` for vertex i) of the lanes, as `intersect_triangle` computes them.
pub(crate) struct Sheared<L> {
    x: [L; 3],
    y: [L; 3],
    z: [L; 3],
    u: L,
    v: L,
    w: L,
    det: L,
    t_scaled: L,
}

impl<L: FloatLanes> Sheared<L> {
    /// The lanes' triangles `[a, b, c]`, their vertices relative to the ray's origin with
    /// the axes in the ray's permutation (`kx`, `ky`, `kz`), sheared by `shear`.
    #[inline(always)]
    pub(crate) fn new([a, b, c]: [[L; 3]; 3], [sx, sy, sz]: [L; 3]) -> Sheared<L> {
        let ax = a[0] - sx * a[2];
        let ay = a[1] - sy * a[2];
        let bx = b[0] - sx * b[2];
        let by = b[1] - sy * b[2];
        let cx = c[0] - sx * c[2];
        let cy = c[1] - sy * c[2];
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        let az = sz * a[2];
        let bz = sz * b[2];
        let cz = sz * c[2];
        Sheared {
            x: [ax, bx, cx],
            y: [ay, by, cy],
            z: [az, bz, cz],
            det: u + v + w,
            t_scaled: u * az + v * bz + w * cz,
            u,
            v,
            w,
        }
    }

    /// The lanes the scalar test rejects at bound `t_max` on the comparisons that need no
    /// exact zero re-evaluated, and those with an exact zero edge function (only the scalar
    /// test can decide them), as bits.
    #[inline(always)]
    pub(crate) fn rejected(&self, t_max: L) -> (u32, u32) {
        let zero = L::splat(0.0);
        let (u, v, w, det, t_scaled) = (self.u, self.v, self.w, self.det, self.t_scaled);
        let exact_zero = u.eq(zero) | v.eq(zero) | w.eq(zero);
        let outside =
            (u.lt(zero) | v.lt(zero) | w.lt(zero)) & (u.gt(zero) | v.gt(zero) | w.gt(zero));
        let bound = t_max * det;
        let behind_or_beyond = (det.lt(zero) & (t_scaled.ge(zero) | t_scaled.lt(bound)))
            | (det.gt(zero) & (t_scaled.le(zero) | t_scaled.gt(bound)));
        // A zero determinant rejects in the scalar test too.
        let rejected = outside | behind_or_beyond | det.eq(zero);
        (L::bits(rejected), L::bits(exact_zero))
    }

    /// The whole test of the lanes of `lanes` (bits) at bound `t_max`: each lane's hit is
    /// the one `intersect_triangle` reports at that bound, bit for bit (the division
    /// included), except the lanes in `undecided`.
    #[inline(always)]
    pub(crate) fn hits(&self, t_max: L, lanes: u32) -> LaneHits<L> {
        let (rejected, exact_zero) = self.rejected(t_max);
        let undecided = exact_zero & lanes;
        let open = !rejected & !exact_zero & lanes;
        if open == 0 {
            return LaneHits::none(undecided);
        }
        let inv = L::splat(1.0) / self.det;
        let t = self.t_scaled * inv;
        let edges = [self.u, self.v, self.w];
        let delta_t = t_rounding_bound(self.x, self.y, self.z, edges, inv);
        let infinity = L::splat(f32::INFINITY);
        let finite = L::bits(t.abs().lt(infinity)) & L::bits(delta_t.abs().lt(infinity));
        let within = L::bits(t.lt(t_max) & t.gt(delta_t));
        LaneHits {
            hit: open & within & finite,
            undecided: undecided | (open & !finite),
            t,
            t_scaled: self.t_scaled,
            det: self.det,
            b1: self.v * inv,
            b2: self.w * inv,
        }
    }
}

/// What a pass of the test found, lane by lane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LaneHits<L> {
    /// Lanes hit at the bound the test was given.
    pub hit: u32,
    /// Lanes only the scalar test can decide.
    pub undecided: u32,
    t: L,
    t_scaled: L,
    det: L,
    b1: L,
    b2: L,
}

impl<L: FloatLanes> LaneHits<L> {
    #[inline(always)]
    fn none(undecided: u32) -> LaneHits<L> {
        let zero = L::splat(0.0);
        LaneHits {
            hit: 0,
            undecided,
            t: zero,
            t_scaled: zero,
            det: zero,
            b1: zero,
            b2: zero,
        }
    }

    /// Lane `lane`'s values (a lane of `hit`), for `DecidedHit::within`.
    #[inline(always)]
    pub(crate) fn decided(&self, lane: usize) -> DecidedHit {
        DecidedHit {
            det: self.det.to_array()[lane],
            t_scaled: self.t_scaled.to_array()[lane],
            t: self.t.to_array()[lane],
            b1: self.b1.to_array()[lane],
            b2: self.b2.to_array()[lane],
        }
    }

    /// `keep` of every lane hit and its values, lowest lane first (the values stored once).
    #[inline(always)]
    pub(crate) fn each_hit(&self, mut keep: impl FnMut(usize, &DecidedHit)) {
        let mut hit = self.hit;
        if hit == 0 {
            return;
        }
        let (det, t_scaled, t) = (
            self.det.to_array(),
            self.t_scaled.to_array(),
            self.t.to_array(),
        );
        let (b1, b2) = (self.b1.to_array(), self.b2.to_array());
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
            keep(j, &decided);
        }
    }
}
