//! Truncated cones between two points with a radius at each end; equal radii make a
//! cylinder (NFF's `c` entity). Open by default, with optional end caps.
//!
//! The ray is moved into a frame where the axis is +z from the base; the side is the
//! quadric x² + y² = (r_base + k·z)², solved in f64 because rays nearly parallel to the
//! side make its leading coefficient cancel.

use super::{ShapeHit, SurfacePoint, Uv};
use crate::math::robust::gamma;
use crate::math::{Aabb, Frame, Ray, Vec2, Vec3};
use glam::DVec3;
use std::f32::consts::PI;

/// A truncated cone, or a cylinder when both radii are equal; `new` checks the parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// Centre of the base disc.
    pub base: Vec3,
    /// Radius at the base (zero makes a pointed cone).
    pub base_radius: f32,
    /// Centre of the apex disc.
    pub apex: Vec3,
    /// Radius at the apex (zero makes a pointed cone).
    pub apex_radius: f32,
    /// Whether the two end discs are part of the surface (NFF cones are open).
    pub capped: bool,
    frame: Frame,
    height: f32,
}

// Which part a hit is on, carried in `ShapeHit::u`.
const SIDE: f32 = 0.0;
const BASE_CAP: f32 = 1.0;
const APEX_CAP: f32 = 2.0;

/// What `Cone::intersect` computes with, for the tests that repeat its operations in SIMD
/// lanes (`accel/bvh/simd8/cones.rs`): the frame's axes and base in f32, where the ray is
/// moved into the frame, and the rest in the f64 of the quadric.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ConeTerms {
    /// Centre of the base disc, the frame's origin.
    pub base: Vec3,
    /// The frame whose z axis runs from the base to the apex.
    pub frame: Frame,
    /// Distance from base to apex.
    pub height: f64,
    /// Radius at the base.
    pub base_radius: f64,
    /// Radius at the apex.
    pub apex_radius: f64,
    /// The radius's change per unit of height.
    pub slope: f64,
    /// Whether the end discs are part of the surface.
    pub capped: bool,
}

impl ConeTerms {
    /// The value `intersect` gives `ShapeHit::u` for a hit on the side, the base cap and
    /// the apex cap.
    pub(crate) const PARTS: [f32; 3] = [SIDE, BASE_CAP, APEX_CAP];
}

impl Cone {
    /// `None` when base and apex coincide or a radius is negative or not finite.
    pub fn new(
        base: Vec3,
        base_radius: f32,
        apex: Vec3,
        apex_radius: f32,
        capped: bool,
    ) -> Option<Self> {
        let axis = apex - base;
        let height = axis.length();
        let ok = |r: f32| r.is_finite() && r >= 0.0;
        if !(height > 0.0 && height.is_finite() && ok(base_radius) && ok(apex_radius)) {
            return None;
        }
        if base_radius == 0.0 && apex_radius == 0.0 {
            return None;
        }
        Some(Cone {
            base,
            base_radius,
            apex,
            apex_radius,
            capped,
            frame: Frame::from_z(axis / height),
            height,
        })
    }

    /// A cylinder from `base` to `top`; `None` for the same reasons as `new`.
    pub fn cylinder(base: Vec3, top: Vec3, radius: f32, capped: bool) -> Option<Self> {
        Cone::new(base, radius, top, radius, capped)
    }

    /// The terms of `intersect`'s arithmetic.
    pub(crate) fn terms(&self) -> ConeTerms {
        ConeTerms {
            base: self.base,
            frame: self.frame,
            height: self.height as f64,
            base_radius: self.base_radius as f64,
            apex_radius: self.apex_radius as f64,
            slope: self.slope(),
            capped: self.capped,
        }
    }

    fn slope(&self) -> f64 {
        (self.apex_radius as f64 - self.base_radius as f64) / self.height as f64
    }

    fn local_ray(&self, ray: &Ray) -> (DVec3, DVec3) {
        let o = self.frame.to_local(ray.origin - self.base).as_dvec3();
        let d = self.frame.to_local(ray.dir).as_dvec3();
        (o, d)
    }

    /// Nearest hit with `0 < t < t_max`; `u` tells the side from the caps.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let (o, d) = self.local_ray(ray);
        let (h, rb, k) = (self.height as f64, self.base_radius as f64, self.slope());
        let mut best: Option<(f64, f32)> = None;
        // Bounds are checked on the f32 distance the caller gets: an f64 root just below
        // t_max can round up to it, and accelerators rely on hits being strictly nearer.
        let mut consider = |t: f64, part: f32| {
            let reported = t as f32;
            if reported > 0.0 && reported < t_max && best.is_none_or(|(b, _)| t < b) {
                best = Some((t, part));
            }
        };

        let ro = rb + k * o.z;
        let a = d.x * d.x + d.y * d.y - k * k * d.z * d.z;
        let b = 2.0 * (o.x * d.x + o.y * d.y - k * ro * d.z);
        let c = o.x * o.x + o.y * o.y - ro * ro;
        let on_side = |t: f64| {
            let z = o.z + t * d.z;
            (0.0..=h).contains(&z)
        };
        if a != 0.0 {
            let disc = b * b - 4.0 * a * c;
            if disc >= 0.0 {
                let q = -0.5 * (b + disc.sqrt().copysign(b));
                for t in [q / a, c / q] {
                    if on_side(t) {
                        consider(t, SIDE);
                    }
                }
            }
        } else if b != 0.0 {
            let t = -c / b;
            if on_side(t) {
                consider(t, SIDE);
            }
        }

        if self.capped && d.z != 0.0 {
            for (z, r, part) in [(0.0, rb, BASE_CAP), (h, self.apex_radius as f64, APEX_CAP)] {
                let t = (z - o.z) / d.z;
                let (x, y) = (o.x + t * d.x, o.y + t * d.y);
                if x * x + y * y <= r * r {
                    consider(t, part);
                }
            }
        }
        best.map(|(t, part)| ShapeHit {
            t: t as f32,
            u: part,
            v: 0.0,
        })
    }

    /// The point, normals and uv of a hit that `intersect` found, on the side or a cap.
    pub fn surface(&self, ray: &Ray, hit: &ShapeHit) -> SurfacePoint {
        self.surface_with(ray, hit, Uv::Compute)
    }

    /// `surface`, with the uv parameters only if `uv` asks for them (else zero).
    pub fn surface_with(&self, ray: &Ray, hit: &ShapeHit, uv: Uv) -> SurfacePoint {
        let (o, d) = self.local_ray(ray);
        let local = o + hit.t as f64 * d;
        let h = self.height as f64;
        let (mut l, n_local, uv) = if hit.u == SIDE {
            let z = local.z.clamp(0.0, h);
            let r = self.base_radius as f64 + self.slope() * z;
            let radial = glam::DVec2::new(local.x, local.y)
                .try_normalize()
                .unwrap_or(glam::DVec2::X);
            let n = DVec3::new(radial.x, radial.y, -self.slope()).normalize();
            let uv = match uv {
                Uv::Compute => {
                    let phi = radial.y.atan2(radial.x) as f32;
                    Vec2::new(0.5 + phi / (2.0 * PI), (z / h) as f32)
                }
                Uv::Skip => Vec2::ZERO,
            };
            (DVec3::new(radial.x * r, radial.y * r, z), n, uv)
        } else {
            let top = hit.u == APEX_CAP;
            let z = if top { h } else { 0.0 };
            let r = if top {
                self.apex_radius
            } else {
                self.base_radius
            } as f64;
            let uv = Vec2::new(
                (0.5 + 0.5 * local.x / r.max(f64::MIN_POSITIVE)) as f32,
                (0.5 + 0.5 * local.y / r.max(f64::MIN_POSITIVE)) as f32,
            );
            (
                DVec3::new(local.x, local.y, z),
                DVec3::new(0.0, 0.0, if top { 1.0 } else { -1.0 }),
                uv,
            )
        };
        if !l.is_finite() {
            l = DVec3::ZERO;
        }
        let local_p = l.as_vec3();
        let p = self.base + self.frame.to_world(local_p);
        let n = self.frame.to_world(n_local.as_vec3()).normalize();
        let scale = self.base.abs() + Vec3::splat(local_p.abs().max_element());
        SurfacePoint::flat(p, gamma(12) * scale, n, uv)
    }

    /// A box around both end discs.
    pub fn bounds(&self) -> Aabb {
        // Exact box of the two end discs: a disc of radius r with unit normal a extends
        // r·sqrt(1 − a_i²) along axis i.
        let a = self.frame.z;
        let e = (Vec3::ONE - a * a).max(Vec3::ZERO).map(f32::sqrt);
        let disc = |c: Vec3, r: f32| Aabb::new(c - r * e, c + r * e);
        disc(self.base, self.base_radius).union(&disc(self.apex, self.apex_radius))
    }
}
