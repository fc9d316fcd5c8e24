//! The watertight ray–triangle test of Woop, Benthin and Wald (JCGT 2013).
//!
//! The ray is sheared so it runs along +z from the origin; the triangle is projected
//! the same way and the 2D edge functions decide containment. Edges shared by two
//! triangles are evaluated identically from both sides, so no ray slips through a closed
//! mesh; exact zeros are re-evaluated in f64 for the same reason.

use super::triangle_lanes::t_rounding_bound;
use crate::math::{TraceRay, Vec3};

/// A hit of the watertight triangle test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Distance along the ray.
    pub t: f32,
    /// Barycentric weights of the second and third vertex (the first is 1 − b1 − b2).
    pub b1: f32,
    /// Barycentric weight of the third vertex.
    pub b2: f32,
}

/// The watertight test of one triangle given by its corners: the hit with `0 < t < t_max`, from
/// either side.
#[inline(always)]
pub fn intersect_triangle(
    ray: &TraceRay,
    v0: Vec3,
    v1: Vec3,
    v2: Vec3,
    t_max: f32,
) -> Option<TriangleHit> {
    // Masked indices into padded arrays: the compiler sees them in bounds, so a component
    // chosen at run time costs a load, where glam's `Vec3[i]` is a three-way branch (12 %
    // of all instructions on the bunny, by callgrind). The values are the same.
    let (kx, ky, kz) = (ray.kx & 3, ray.ky & 3, ray.kz & 3);
    let s = ray.shear;
    let padded = |v: Vec3| [v.x, v.y, v.z, 0.0];
    let a = padded(v0 - ray.ray.origin);
    let b = padded(v1 - ray.ray.origin);
    let c = padded(v2 - ray.ray.origin);

    let ax = a[kx] - s.x * a[kz];
    let ay = a[ky] - s.y * a[kz];
    let bx = b[kx] - s.x * b[kz];
    let by = b[ky] - s.y * b[kz];
    let cx = c[kx] - s.x * c[kz];
    let cy = c[ky] - s.y * c[kz];

    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        u = (cx as f64 * by as f64 - cy as f64 * bx as f64) as f32;
        v = (ax as f64 * cy as f64 - ay as f64 * cx as f64) as f32;
        w = (bx as f64 * ay as f64 - by as f64 * ax as f64) as f32;
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let az = s.z * a[kz];
    let bz = s.z * b[kz];
    let cz = s.z * c[kz];
    let t_scaled = u * az + v * bz + w * cz;
    // Compare before dividing: the sign of det decides which way the inequalities go.
    if det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det) {
        return None;
    }
    if det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det) {
        return None;
    }
    let inv = 1.0 / det;
    let t = t_scaled * inv;
    if t >= t_max {
        return None;
    }
    // Reject hits whose distance is not provably positive (pbrt-v4's bound on the rounding
    // of everything above): a ray leaving this triangle must not find it again at t ≈ 0.
    let delta_t = t_rounding_bound([ax, bx, cx], [ay, by, cy], [az, bz, cz], [u, v, w], inv);
    if t <= delta_t {
        return None;
    }
    Some(TriangleHit {
        t,
        b1: v * inv,
        b2: w * inv,
    })
}
