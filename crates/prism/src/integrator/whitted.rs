//! Whitted ray tracing (Whitted 1980), step by step:
//!
//! TraceRay(R, depth): find the nearest hit; on a miss return the background. For every
//! light, cast a shadow ray and keep only lights it reaches; add the local illumination
//! from those. If depth < max depth, trace the reflected and the refracted ray. Result:
//! I = Le + Ia·ka·C + Σ (Id + Is) + wr·I_R + wt·I_T, with (wr, wt) from the material
//! (constant, or split by Fresnel reflectance). Shadow rays are `shadow.rs`: those that
//! meet a transparent surface continue through it, filtered by its kt (a colour), as
//! POV-Ray does. Weights are colours too: red glass passes red light only.

use super::shadow::Shadows;
use crate::accel::Hit;
use crate::math::robust::offset_ray_origin;
use crate::math::{Color, Ray};
use crate::options::RenderOptions;
use crate::scene::PreparedScene;
use crate::shading::optics::{reflect, refract};
use crate::stats::Stats;

/// Whitted's recursive ray tracer over one prepared scene: local shading with shadow rays, plus the
/// reflected and refracted rays, to a depth and weight limit.
pub struct Whitted<'a> {
    scene: &'a PreparedScene<'a>,
    shadows: Shadows<'a>,
    max_depth: u32,
    min_weight: f32,
    spd_rules: bool,
}

impl<'a> Whitted<'a> {
    /// The integrator for `scene` with the depth, weight and shadow settings of `options`; builds
    /// light buffers when the shadow method asks for them.
    pub fn new(scene: &'a PreparedScene<'a>, options: &RenderOptions) -> Self {
        Whitted {
            scene,
            shadows: Shadows::new(scene, options.shadows),
            max_depth: options.max_depth,
            min_weight: options.min_weight,
            spd_rules: options.spd_rules,
        }
    }

    /// Whether a secondary ray of weight `w` (in its parent) is traced. `present` says the
    /// material has the term at all (kr or kt > 0), which is all SPD's rules ask. Rays the
    /// static limit would trace but adaptive depth control drops are counted. A coloured
    /// weight counts by its largest channel: the most the ray can change any channel.
    fn spawns(&self, present: bool, w: Color, weight: Color, stats: &mut Stats) -> bool {
        if self.spd_rules {
            return present;
        }
        if w.max_element() <= 0.0 {
            return false;
        }
        if (weight * w).max_element() >= self.min_weight {
            true
        } else {
            stats.pruned_rays += 1;
            false
        }
    }

    /// The shadow-ray machinery this render built (light buffers and why some lights have
    /// none), for reports.
    pub fn shadows(&self) -> &Shadows<'a> {
        &self.shadows
    }

    /// Radiance along a camera ray (depth 1).
    pub fn trace_camera_ray(&self, ray: &Ray, stats: &mut Stats) -> Color {
        stats.primary_rays += 1;
        self.trace(ray, 1, Color::ONE, stats)
    }

    fn nearest(&self, ray: &Ray, t_max: f32, stats: &mut Stats) -> Option<Hit> {
        let s = self.scene;
        s.intersector
            .intersect(&s.scene.geometry, ray, t_max, stats)
    }

    /// `weight` is the product of reflection and transmission weights from the eye to this
    /// ray, per channel: what its radiance is worth in the pixel (for adaptive depth
    /// control).
    pub fn trace(&self, ray: &Ray, depth: u32, weight: Color, stats: &mut Stats) -> Color {
        let scene = self.scene.scene;
        let Some(hit) = self.nearest(ray, f32::INFINITY, stats) else {
            return scene.background;
        };
        if depth == 1 {
            stats.primary_hits += 1;
        }
        let prim = &scene.geometry.primitives[hit.prim as usize];
        let material = &scene.materials[prim.material as usize];
        let sp = scene.geometry.surface(hit.prim, ray, &hit.shape_hit());

        // Face the normals towards the incoming ray; `entering` says which side it came from.
        let entering = ray.dir.dot(sp.ng) < 0.0;
        let (ng, ns) = if entering {
            (sp.ng, sp.ns)
        } else {
            (-sp.ng, -sp.ns)
        };
        let to_eye = -ray.dir;
        let color = material.color_at(sp.uv, sp.p);

        // Local illumination.
        let mut radiance = material.ambient * color * scene.ambient;
        // An area light shows its own radiance; Whitted's shadow rays do not sample it
        // (the path tracer does).
        if entering && material.is_emissive() {
            radiance += material.emission;
        }
        for (index, light) in scene.lights.iter().enumerate() {
            let Some(ls) = light.sample(sp.p) else {
                continue;
            };
            // A light behind the surface contributes nothing: no shadow ray (SPD rule 10).
            if ng.dot(ls.to_light) <= 0.0 {
                continue;
            }
            let visibility = self.shadows.visibility(index, depth, &sp, ng, &ls, stats);
            if visibility.max_element() <= 0.0 {
                continue;
            }
            let diffuse = material.diffuse * ns.dot(ls.to_light).max(0.0) * color;
            let highlight = material.highlight_term(ns, ls.to_light, to_eye);
            radiance += visibility * ls.color * (diffuse + Color::splat(highlight));
        }

        if depth >= self.max_depth {
            return radiance;
        }

        // Recursive terms. η_io = η_incident / η_transmitted; the outside is vacuum.
        let eta = if entering {
            1.0 / material.ior
        } else {
            material.ior
        };
        let cos_i = to_eye.dot(ns).clamp(0.0, 1.0);
        let w = material.specular_weights(cos_i, eta);
        if w.total_internal_reflection {
            stats.total_internal_reflections += 1;
        }
        let transmissive = material.is_transmissive();
        let has_specular = material.reflect > 0.0 || transmissive;
        let w_reflect = Color::splat(w.reflect);
        if self.spawns(has_specular, w_reflect, weight, stats) {
            let mut dir = reflect(ray.dir, ns);
            // An interpolated normal can mirror the ray below the true surface; use the
            // geometric normal there instead.
            if dir.dot(ng) <= 0.0 {
                dir = reflect(ray.dir, ng);
            }
            let origin = offset_ray_origin(sp.p, sp.p_error, ng, dir);
            stats.reflected_rays += 1;
            let r = self.trace(&Ray::new(origin, dir), depth + 1, weight * w_reflect, stats);
            radiance += w.reflect * r;
        }
        if !w.total_internal_reflection && self.spawns(transmissive, w.transmit, weight, stats) {
            if let Some(dir) = refract(ray.dir, ns, eta) {
                let origin = offset_ray_origin(sp.p, sp.p_error, ng, dir);
                stats.refracted_rays += 1;
                let t = self.trace(
                    &Ray::new(origin, dir),
                    depth + 1,
                    weight * w.transmit,
                    stats,
                );
                radiance += w.transmit * t;
            }
        }
        radiance
    }
}
