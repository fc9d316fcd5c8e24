//! Spheres, with a numerically careful quadratic (Haines et al., Ray Tracing Gems ch. 7).

use super::{ShapeHit, SurfacePoint, Uv};
use crate::math::lanes::{axes, FloatLanes};
use crate::math::robust::gamma;
use crate::math::{Aabb, Ray, Vec2, Vec3};
use std::f32::consts::PI;

/// A sphere, solid or (inside out) the inner wall of a shell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius, positive.
    pub radius: f32,
    /// Normals point inwards: the inner wall of a hollow glass shell, or NFF's negative radius.
    pub inside_out: bool,
}

impl Sphere {
    /// A sphere whose normals point outwards.
    pub fn new(center: Vec3, radius: f32) -> Self {
        Sphere {
            center,
            radius,
            inside_out: false,
        }
    }

    /// Nearest hit with `0 < t < t_max`, from outside or inside.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let f = ray.origin - self.center;
        let b = f.dot(ray.dir);
        let r2 = self.radius * self.radius;
        // r² − |f − (f·d)d|² instead of b² − c: no catastrophic cancellation when the
        // sphere is small and far away.
        let l = f - b * ray.dir;
        let disc = r2 - l.length_squared();
        if disc < 0.0 {
            return None;
        }
        let c = f.length_squared() - r2;
        let q = -b - disc.sqrt().copysign(b);
        let (mut t0, mut t1) = (c / q, q);
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        let t = if t0 > 0.0 { t0 } else { t1 };
        (t > 0.0 && t < t_max).then_some(ShapeHit { t, u: 0.0, v: 0.0 })
    }

    /// The point, normals and uv (longitude, latitude) of a hit.
    pub fn surface(&self, ray: &Ray, hit: &ShapeHit) -> SurfacePoint {
        self.surface_with(ray, hit, Uv::Compute)
    }

    /// `surface`, with the uv parameters only if `uv` asks for them (else zero).
    pub fn surface_with(&self, ray: &Ray, hit: &ShapeHit, uv: Uv) -> SurfacePoint {
        // Re-project onto the sphere: the error is then a few ulps of |p|, not of t.
        let dir = (ray.at(hit.t) - self.center).normalize();
        let p = self.center + self.radius * dir;
        let p_error = gamma(5) * (self.center.abs() + (self.radius * dir).abs());
        let n = if self.inside_out { -dir } else { dir };
        // An arc tangent and an arc cosine: a fifth of a shadow ray's cost through glass,
        // so only for textures that read them.
        let uv = match uv {
            Uv::Compute => Vec2::new(
                0.5 + dir.z.atan2(dir.x) / (2.0 * PI),
                dir.y.clamp(-1.0, 1.0).acos() / PI,
            ),
            Uv::Skip => Vec2::ZERO,
        };
        SurfacePoint::flat(p, p_error, n, uv)
    }

    /// The cube around the sphere.
    pub fn bounds(&self) -> Aabb {
        let r = Vec3::splat(self.radius.abs());
        Aabb::new(self.center - r, self.center + r)
    }
}

/// `Sphere::intersect` in SIMD lanes, each a ray (`origin`, `dir`) and a sphere (`centre`,
/// squared radius `r2`), any of them broadcast: lane by lane its operations in its order
/// (`Vec3::dot` sums x, y, then z; no fused multiply-add), so each lane's distance is the
/// scalar test's bit for bit, where the scalar test reports a hit. Returns the lanes that
/// hit before `t_max` (bits) and every lane's distance. Shared by the 8-wide walk's leaves
/// of spheres and the packets' sphere kernel of every width.
#[inline(always)]
pub(crate) fn sphere_lanes<L: FloatLanes>(
    origin: [L; 3],
    dir: [L; 3],
    centre: [L; 3],
    r2: L,
    t_max: L,
) -> (u32, L) {
    let dot = |x: &[L; 3], y: &[L; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    let zero = L::splat(0.0);
    let f = axes(|a| origin[a] - centre[a]);
    let b = dot(&f, &dir);
    let l = axes(|a| f[a] - b * dir[a]);
    let disc = r2 - dot(&l, &l);
    let c = dot(&f, &f) - r2;
    let q = b.neg() - disc.sqrt().copysign(b);
    let t0 = c / q;
    let swap = t0.gt(q);
    let (near, far) = (L::select(swap, q, t0), L::select(swap, t0, q));
    let t = L::select(near.gt(zero), near, far);
    // A negative discriminant misses (the scalar test returns before its square root).
    let hit = t.gt(zero) & t.lt(t_max) & disc.not_lt(zero);
    (L::bits(hit), t)
}
