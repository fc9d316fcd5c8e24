//! Shadow rays: whether a light reaches a surface point, and how much of it.
//!
//! A shadow ray runs from the (offset) surface point towards the light and asks the
//! accelerator's any-hit query, which may stop at the first blocker. In a scene with
//! transparent surfaces it asks for the nearest hit instead and continues through each
//! transparent surface it meets, attenuated by its kt, as POV-Ray does; refraction of the
//! shadow ray itself is ignored (no caustics).
//!
//! This is where the lecture's shadow-ray accelerations belong when they come: a light
//! buffer (per light, the candidate blockers in each direction) and a shadow cache (the
//! last blocker found for each light, tried first).

use crate::geometry::SurfacePoint;
use crate::light::LightSample;
use crate::math::robust::offset_ray_origin;
use crate::math::{Ray, Vec3};
use crate::scene::PreparedScene;
use crate::stats::Stats;

/// Upper bound on transparent surfaces one shadow ray passes through.
const MAX_SHADOW_SEGMENTS: u32 = 64;

/// The fraction of light `light` that reaches surface point `sp`, whose geometric normal
/// faces the light as `ng`: one shadow ray, counted in `stats`.
pub(super) fn visibility(
    scene: &PreparedScene,
    sp: &SurfacePoint,
    ng: Vec3,
    light: &LightSample,
    stats: &mut Stats,
) -> f32 {
    stats.shadow_rays += 1;
    let origin = offset_ray_origin(sp.p, sp.p_error, ng, light.to_light);
    transmittance(scene, origin, light.to_light, light.distance, stats)
}

/// Fraction of a light's radiance that reaches `origin` along `dir` within `distance`:
/// 0 behind an opaque surface, the product of kt over the transparent ones otherwise.
fn transmittance(
    s: &PreparedScene,
    origin: Vec3,
    dir: Vec3,
    distance: f32,
    stats: &mut Stats,
) -> f32 {
    let geometry = &s.scene.geometry;
    if !s.has_transmissive {
        let blocked = s
            .intersector
            .occluded(geometry, &Ray::new(origin, dir), distance, stats);
        return if blocked { 0.0 } else { 1.0 };
    }
    let mut atten = 1.0;
    let mut origin = origin;
    let mut remaining = distance;
    for segment in 0..MAX_SHADOW_SEGMENTS {
        if segment > 0 {
            stats.shadow_continuations += 1;
        }
        let ray = Ray::new(origin, dir);
        let Some(hit) = s.intersector.intersect(geometry, &ray, remaining, stats) else {
            return atten;
        };
        let prim = &geometry.primitives[hit.prim as usize];
        let kt = s.scene.materials[prim.material as usize].transmit;
        atten *= kt;
        if atten <= 0.0 {
            return 0.0;
        }
        let sp = geometry.surface(hit.prim, &ray, &hit.shape_hit());
        let next = offset_ray_origin(sp.p, sp.p_error, sp.ng, dir);
        remaining -= (next - origin).dot(dir);
        origin = next;
        if remaining <= 0.0 {
            return atten;
        }
    }
    0.0
}
