//! Path tracing (Kajiya 1986): one random walk per sample from the camera, scattering by
//! the `Bsdf` of each hit, with next-event estimation at every non-mirror vertex.
//!
//! Light reaches a path two ways, and multiple importance sampling (Veach and Guibas
//! 1995, power heuristic β = 2) weighs them against each other for area lights: a light
//! sample (a point on an emitter, then a shadow ray) and the BSDF sample that happens to
//! hit an emitter. Point, spot and directional lights are deltas: only light samples find
//! them. A Whitted light's colour is the irradiance it gives a surface facing it, with no
//! falloff (`light.rs`); the path tracer takes it as π × that, so that direct light on a
//! white Lambertian surface (f = 1/π) gives exactly Whitted's kd·C·cos θ·colour.
//!
//! After `RR_DEPTH` vertices a path survives with probability min(max(throughput), 0.95),
//! its weight divided by that (Russian roulette); no path has more than `max_depth`
//! segments (the camera ray is the first, so 1 sees emitters only and 2 adds direct light).
//! Rays that leave the scene see the background as radiance from every direction.
//!
//! Random numbers come from `math::hash::Stream`: dimension 0 and 1 place the sample in
//! its pixel, then each vertex draws `DIMS_PER_VERTEX` numbers of its own, so a sample is a
//! pure function of (pixel, sample index, seed) whatever the thread, tile or order.
//!
//! Transparent surfaces block shadow rays here (light through glass is found by BSDF
//! sampling, as caustics), and the η² scaling of radiance across a refraction is left out:
//! a path that enters a closed object leaves it again and the factors cancel.

use super::emitters::Emitters;
use crate::math::hash::Stream;
use crate::math::robust::{gamma, offset_ray_origin};
use crate::math::{Color, Ray, Vec3};
use crate::options::RenderOptions;
use crate::scene::PreparedScene;
use crate::shading::Bsdf;
use crate::stats::Stats;
use serde::{Deserialize, Serialize};
use std::f32::consts::PI;

/// Vertices after which Russian roulette may end a path (the camera's hit is vertex 1).
pub const RR_DEPTH: u32 = 3;
/// The first dimension of vertex 1's numbers; 0 and 1 are the position in the pixel.
const FIRST_VERTEX_DIM: u32 = 2;
/// Numbers each vertex draws: emitter choice, point on it (2), lobe choice, direction in
/// it (2), Russian roulette.
const DIMS_PER_VERTEX: u32 = 7;

/// Which estimator of area light reaches the film: both weighted by MIS (the default), or
/// one alone (for tests: all three converge to the same image, at different noise).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Strategy {
    /// Light samples and BSDF samples, weighted by the power heuristic.
    #[default]
    Mis,
    /// Light samples only; BSDF samples that hit a sampled emitter add nothing.
    LightOnly,
    /// BSDF samples only; no light samples of area lights (delta lights keep theirs).
    BsdfOnly,
}

named_kinds! {
    Strategy, "path strategy" {
        Mis => "mis",
        LightOnly => "light-only",
        BsdfOnly => "bsdf-only",
    }
}

/// A path tracer over one prepared scene.
pub struct PathTracer<'a> {
    scene: &'a PreparedScene<'a>,
    emitters: Emitters,
    max_depth: u32,
    strategy: Strategy,
}

/// The power heuristic's weight of a sample drawn with density `a` against another
/// strategy's density `b` for the same direction.
#[inline]
fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 && (a2 + b2).is_finite() {
        a2 / (a2 + b2)
    } else if a > b {
        1.0
    } else {
        0.0
    }
}

impl<'a> PathTracer<'a> {
    /// The path tracer for `scene` with the depth and strategy of `options`.
    pub fn new(scene: &'a PreparedScene<'a>, options: &RenderOptions) -> Self {
        PathTracer {
            scene,
            emitters: Emitters::new(scene.scene),
            max_depth: options.max_depth,
            strategy: options.path_strategy,
        }
    }

    /// The numbers of dimension `k` of vertex `depth`.
    #[inline]
    fn dim(depth: u32, k: u32) -> u32 {
        FIRST_VERTEX_DIM + (depth - 1) * DIMS_PER_VERTEX + k
    }

    /// Whether a shadow ray from `origin` (already offset off its surface) along `dir` is
    /// blocked before `distance`; counted as a shadow ray with its tests and visits.
    fn blocked(&self, origin: Vec3, dir: Vec3, distance: f32, stats: &mut Stats) -> bool {
        stats.shadow_rays += 1;
        let (tests, nodes) = (stats.primitive_tests, stats.node_visits);
        let s = self.scene;
        let blocked =
            s.intersector
                .occluded(&s.scene.geometry, &Ray::new(origin, dir), distance, stats);
        stats.shadow_tests += stats.primitive_tests - tests;
        stats.shadow_node_visits += stats.node_visits - nodes;
        blocked
    }

    /// Radiance along a camera ray; `stream` holds the sample's random numbers.
    pub fn trace_camera_ray(&self, ray: &Ray, stream: &Stream, stats: &mut Stats) -> Color {
        stats.primary_rays += 1;
        let c = self.trace(*ray, stream, stats);
        // One NaN would poison a pixel's mean for ever in a progressive render.
        if c.is_finite() {
            c
        } else {
            Color::ZERO
        }
    }

    fn trace(&self, mut ray: Ray, stream: &Stream, stats: &mut Stats) -> Color {
        let scene = self.scene.scene;
        let geometry = &scene.geometry;
        let mut radiance = Color::ZERO;
        let mut throughput = Color::ONE;
        // The camera ray is a delta "sample": what it sees counts fully.
        let mut prev_delta = true;
        let mut prev_pdf = 0.0f32;
        for depth in 1..=self.max_depth {
            let Some(hit) =
                (self.scene.intersector).intersect(geometry, &ray, f32::INFINITY, stats)
            else {
                radiance += throughput * scene.background;
                break;
            };
            if depth == 1 {
                stats.primary_hits += 1;
            }
            let prim = &geometry.primitives[hit.prim as usize];
            let material = &scene.materials[prim.material as usize];
            let sp = geometry.surface_with(hit.prim, &ray, &hit.shape_hit(), material.uv_need());
            let entering = ray.dir.dot(sp.ng) < 0.0;
            let (ng, ns) = if entering {
                (sp.ng, sp.ns)
            } else {
                (-sp.ng, -sp.ns)
            };
            let wo = -ray.dir;

            // Emission, seen from its front side.
            if entering && material.is_emissive() {
                let pdf_light = self.emitters.pdf_area(hit.prim);
                let weight = if prev_delta || pdf_light <= 0.0 {
                    1.0
                } else {
                    match self.strategy {
                        Strategy::Mis => {
                            let cos_l = wo.dot(ng);
                            let pdf_light = pdf_light * hit.t * hit.t / cos_l;
                            power_heuristic(prev_pdf, pdf_light)
                        }
                        Strategy::LightOnly => 0.0,
                        Strategy::BsdfOnly => 1.0,
                    }
                };
                radiance += throughput * material.emission * weight;
            }
            if depth == self.max_depth {
                break;
            }

            let color = material.color_at(sp.uv, sp.p);
            let bsdf = Bsdf::new(material, color, wo, ns, ng, entering);
            if bsdf.has_smooth_lobe() {
                radiance += throughput * self.direct(&bsdf, &sp, ng, depth, stream, stats);
            }

            let Some(s) = bsdf.sample(
                stream.uniform(Self::dim(depth, 3)),
                stream.uniform(Self::dim(depth, 4)),
                stream.uniform(Self::dim(depth, 5)),
            ) else {
                break;
            };
            throughput *= s.weight;
            if throughput.max_element() <= 0.0 {
                break;
            }
            prev_delta = s.delta;
            prev_pdf = s.pdf;
            if depth >= RR_DEPTH {
                let survive = throughput.max_element().min(0.95);
                if stream.uniform(Self::dim(depth, 6)) >= survive {
                    break;
                }
                throughput /= survive;
            }
            if s.transmitted {
                stats.refracted_rays += 1;
            } else {
                stats.reflected_rays += 1;
            }
            ray = Ray::new(offset_ray_origin(sp.p, sp.p_error, ng, s.wi), s.wi);
        }
        radiance
    }

    /// Light samples at one vertex: every delta light, and one point on an area light.
    fn direct(
        &self,
        bsdf: &Bsdf,
        sp: &crate::geometry::SurfacePoint,
        ng: Vec3,
        depth: u32,
        stream: &Stream,
        stats: &mut Stats,
    ) -> Color {
        let scene = self.scene.scene;
        let mut sum = Color::ZERO;
        for light in &scene.lights {
            let Some(ls) = light.sample(sp.p) else {
                continue;
            };
            let wi = ls.to_light;
            if ng.dot(wi) <= 0.0 {
                continue;
            }
            let f = bsdf.eval(wi);
            if f.max_element() <= 0.0 {
                continue;
            }
            let origin = offset_ray_origin(sp.p, sp.p_error, ng, wi);
            if !self.blocked(origin, wi, ls.distance, stats) {
                sum += f * bsdf.cos(wi) * (PI * ls.color);
            }
        }

        if self.strategy == Strategy::BsdfOnly || self.emitters.is_empty() {
            return sum;
        }
        let Some(e) = self.emitters.sample(
            scene,
            stream.uniform(Self::dim(depth, 0)),
            stream.uniform(Self::dim(depth, 1)),
            stream.uniform(Self::dim(depth, 2)),
        ) else {
            return sum;
        };
        let to_light = e.p - sp.p;
        let Some(wi) = to_light.try_normalize() else {
            return sum;
        };
        let cos_l = -wi.dot(e.n);
        if cos_l <= 0.0 || ng.dot(wi) <= 0.0 {
            return sum;
        }
        let f = bsdf.eval(wi);
        if f.max_element() <= 0.0 {
            return sum;
        }
        // Both ends leave their surfaces; the shadow ray stops short of the light by a
        // few ulps of its length, so it cannot find the light itself.
        let origin = offset_ray_origin(sp.p, sp.p_error, ng, wi);
        let target = offset_ray_origin(e.p, e.p_error, e.n, -wi);
        let span = target - origin;
        let distance = span.length();
        if distance.is_nan() || distance <= 0.0 || span.dot(wi) <= 0.0 {
            return sum;
        }
        let dir = span / distance;
        if self.blocked(origin, dir, distance * (1.0 - gamma(16)), stats) {
            return sum;
        }
        let d2 = to_light.length_squared();
        let pdf_light = e.pdf_area * d2 / cos_l;
        let weight = match self.strategy {
            Strategy::Mis => power_heuristic(pdf_light, bsdf.pdf(wi)),
            _ => 1.0,
        };
        sum + f * bsdf.cos(wi) * e.radiance * (weight / pdf_light)
    }
}
