//! Area lights for Whitted's tracer: the emitting triangles, meshes and spheres that the
//! path tracer samples (`Emitters`), each shading point lit by a fixed number of points on
//! them, one shadow ray each, so their shadows are soft (Cook, Porter & Carpenter 1984;
//! POV-Ray's `area_light`). The points are chosen by power, stratified over the emitters,
//! and placed by a hash of the shading point, so a render stays a pure function of scene,
//! options and seed.
//!
//! Each point is a point light whose colour makes the Whitted diffuse term, kd·C·(n·l)
//! times it, an unbiased estimate of the Lambert reflection kd·C/π of the emitters'
//! radiance: Le·cos θ_l / (π·d²·pdf·N) for a point at distance d seen at angle θ_l from its
//! normal, with density pdf per unit area, out of N. The direct light is then the path
//! tracer's (its first bounce) in expectation, up to the ambient term.

use super::emitters::Emitters;
use crate::light::LightSample;
use crate::math::hash::uniform;
use crate::math::robust::{gamma, offset_ray_origin};
use crate::math::Vec3;
use crate::scene::Scene;

/// Hash dimensions of an area light sample: the stratum jitter and the point on the emitter.
const DIM_STRATUM: u32 = 0;
const DIM_U1: u32 = 1;
const DIM_U2: u32 = 2;

/// The scene's emitters as Whitted's lights.
pub(super) struct AreaLights {
    emitters: Emitters,
    /// Points, and shadow rays, per shading point.
    samples: u32,
    seed: u64,
}

impl AreaLights {
    /// The area lights of `scene`, `samples` points per shading point; None when nothing
    /// emits that light samples can aim at, or `samples` is 0.
    pub(super) fn new(scene: &Scene, samples: u32, seed: u64) -> Option<AreaLights> {
        if samples == 0 {
            return None;
        }
        let emitters = Emitters::new(scene);
        (!emitters.is_empty()).then_some(AreaLights {
            emitters,
            samples,
            seed,
        })
    }

    /// Points per shading point.
    pub(super) fn samples(&self) -> u32 {
        self.samples
    }

    /// Point `k` (of `samples()`) seen from `p`, whose geometric normal `ng` faces the
    /// incoming ray: the light it sends, as a point light's sample. None when the point is
    /// behind the surface or faces away from it. The sample's distance stops short of the
    /// emitter, so that its shadow ray cannot find the emitter itself.
    pub(super) fn sample(&self, scene: &Scene, p: Vec3, ng: Vec3, k: u32) -> Option<LightSample> {
        // Keyed by the point: the same point gets the same samples whoever traces it.
        let (px, py) = (p.x.to_bits(), p.y.to_bits() ^ p.z.to_bits().rotate_left(16));
        let u = |dim| uniform(px, py, k, dim, self.seed);
        let n = self.samples as f32;
        let stratum = ((k as f32 + u(DIM_STRATUM)) / n).min(1.0 - f32::EPSILON / 2.0);
        let e = self.emitters.sample(scene, stratum, u(DIM_U1), u(DIM_U2))?;
        let to_light = e.p - p;
        let wi = to_light.try_normalize()?;
        let cos_l = -wi.dot(e.n);
        if cos_l <= 0.0 || ng.dot(wi) <= 0.0 {
            return None;
        }
        let target = offset_ray_origin(e.p, e.p_error, e.n, -wi);
        let distance = (target - p).dot(wi) * (1.0 - gamma(16));
        if distance.is_nan() || distance <= 0.0 {
            return None;
        }
        let d2 = to_light.length_squared();
        Some(LightSample {
            to_light: wi,
            distance,
            color: e.radiance * (cos_l / (std::f32::consts::PI * d2 * e.pdf_area * n)),
        })
    }
}
