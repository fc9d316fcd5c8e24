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
//! A vertex is three steps, `arrive` (the hit, the emission seen, the BSDF),
//! `light_queries` (the light samples and their shadow rays) and `leave` (the unblocked
//! light, then the BSDF's direction and Russian roulette), which a single path takes in
//! turn and a packet of paths takes breadth first with its queries batched
//! (`trace_camera_packet`): the same operations on every path either way.
//!
//! Random numbers come from `math::hash::Stream`: dimension 0 and 1 place the sample in
//! its pixel, then each vertex draws `DIMS_PER_VERTEX` numbers of its own, so a sample is a
//! pure function of (pixel, sample index, seed) whatever the thread, tile or order.
//!
//! Transparent surfaces block shadow rays here (light through glass is found by BSDF
//! sampling, as caustics), and the η² scaling of radiance across a refraction is left out:
//! a path that enters a closed object leaves it again and the factors cancel.

use super::emitters::Emitters;
use super::CameraPacket;
use crate::accel::{Hit, PACKET_MAX};
use crate::choices::Strategy;
use crate::math::hash::Stream;
use crate::math::robust::{gamma, offset_ray_origin};
use crate::math::{Color, Ray, Vec3};
use crate::options::RenderOptions;
use crate::scene::PreparedScene;
use crate::shading::{Bsdf, BsdfSample, Material, MaterialLobes, Texture};
use crate::stats::Stats;
use arrayvec::ArrayVec;
use std::f32::consts::PI;

/// Vertices after which Russian roulette may end a path (the camera's hit is vertex 1).
pub const RR_DEPTH: u32 = 3;
/// The first dimension of vertex 1's numbers; 0 and 1 are the position in the pixel.
const FIRST_VERTEX_DIM: u32 = 2;
/// Numbers each vertex draws: emitter choice, point on it (2), lobe choice, direction in
/// it (2), Russian roulette.
const DIMS_PER_VERTEX: u32 = 7;

/// A path tracer over one prepared scene.
pub struct PathTracer<'a> {
    pub(super) scene: &'a PreparedScene<'a>,
    emitters: Emitters,
    /// Per material, its BSDF's part that no hit changes, where its coefficients and
    /// colour are the same all over it (`uniform_lobes`); `None` for the others.
    lobes: Vec<Option<MaterialLobes>>,
    pub(super) max_depth: u32,
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

/// The part of `Bsdf::new` that no hit on `material` changes, where its coefficients are
/// the same at every uv (no metallic-roughness texture; an emissive texture changes only
/// the emission, which the BSDF does not read) and its colour is one colour: `Bsdf::new`
/// then makes the same `MaterialLobes` at every hit, so making it once changes no bit.
fn uniform_lobes(material: &Material) -> Option<MaterialLobes> {
    let Texture::Solid(color) = material.color else {
        return None;
    };
    material
        .metal_rough
        .is_none()
        .then(|| MaterialLobes::new(&material.coefficients(), color))
}

impl<'a> PathTracer<'a> {
    /// The path tracer for `scene` with the depth and strategy of `options`.
    pub fn new(scene: &'a PreparedScene<'a>, options: &RenderOptions) -> Self {
        PathTracer {
            scene,
            emitters: Emitters::new(scene.scene),
            lobes: scene.scene.materials.iter().map(uniform_lobes).collect(),
            max_depth: options.max_depth,
            strategy: options.path_strategy,
        }
    }

    /// The numbers of dimension `k` of vertex `depth`.
    #[inline]
    fn dim(depth: u32, k: u32) -> u32 {
        FIRST_VERTEX_DIM + (depth - 1) * DIMS_PER_VERTEX + k
    }

    /// Radiance along a camera ray; `stream` holds the sample's random numbers.
    pub fn trace_camera_ray(&self, ray: &Ray, stream: &Stream, stats: &mut Stats) -> Color {
        stats.primary_rays += 1;
        let mut path = Path::new(*ray);
        LIGHT_QUERIES.with_borrow_mut(|lights| {
            for depth in 1..=self.max_depth {
                let s = self.scene;
                let hit =
                    s.intersector
                        .intersect(&s.scene.geometry, &path.ray, f32::INFINITY, stats);
                let Some(vertex) = self.arrive(&mut path, hit, depth, stats) else {
                    break;
                };
                lights.clear();
                self.light_queries(&vertex, depth, stream, lights);
                for q in lights.iter_mut() {
                    q.blocked = self.blocked(q, stats);
                }
                if !self.leave(&mut path, &vertex, lights, depth, stream, stats) {
                    break;
                }
            }
        });
        path.finish()
    }

    /// Radiance along a packet of camera rays (at most `PACKET_MAX`), `streams[i]` ray i's
    /// random numbers: `colors[i]` is exactly what `trace_camera_ray` gives ray i. The
    /// paths go breadth first, a packet per depth: the rays of the paths still alive find
    /// their hits together, and so do their shadow rays. The camera rays and the first
    /// vertices' shadow rays are coherent and walk as packets; after a bounce the rays
    /// point every way, and the packet query answers them one by one.
    /// `rays_of[i]` gains the rays of path i after its camera ray.
    pub fn trace_camera_packet(&self, packet: CameraPacket<'_>, stats: &mut Stats) {
        let (rays, streams) = (packet.rays, packet.streams);
        let (colors, rays_of) = (packet.colors, packet.rays_of);
        let n = rays.len();
        debug_assert!(n <= PACKET_MAX && streams.len() == n && colors.len() >= n);
        stats.primary_rays += n as u64;
        let s = self.scene;
        let geometry = &s.scene.geometry;
        let mut paths: ArrayVec<Path, PACKET_MAX> = rays.iter().map(|&r| Path::new(r)).collect();
        // The lanes whose paths go on, in lane order.
        let mut alive: ArrayVec<u8, PACKET_MAX> = (0..n as u8).collect();
        let mut vertices: ArrayVec<(u8, Vertex), PACKET_MAX> = ArrayVec::new();
        // Every vertex's light samples, one after the other; `spans[v]` are vertex v's.
        let mut lights: Vec<LightQuery> = Vec::new();
        let mut spans: ArrayVec<std::ops::Range<usize>, PACKET_MAX> = ArrayVec::new();
        for depth in 1..=self.max_depth {
            if alive.is_empty() {
                break;
            }
            let ray_of: ArrayVec<Ray, PACKET_MAX> =
                alive.iter().map(|&i| paths[usize::from(i)].ray).collect();
            let mut hits = [None; PACKET_MAX];
            let m = ray_of.len();
            s.intersector
                .intersect_packet(geometry, &ray_of, f32::INFINITY, &mut hits[..m], stats);
            vertices.clear();
            lights.clear();
            spans.clear();
            for (&i, &hit) in alive.iter().zip(&hits[..m]) {
                let lane = usize::from(i);
                if let Some(v) = self.arrive(&mut paths[lane], hit, depth, stats) {
                    let first = lights.len();
                    self.light_queries(&v, depth, &streams[lane], &mut lights);
                    rays_of[lane] += (lights.len() - first) as u32;
                    spans.push(first..lights.len());
                    vertices.push((i, v));
                }
            }
            // The shadow rays of every vertex, in lane order, in packets of PACKET_MAX.
            for chunk in lights.chunks_mut(PACKET_MAX) {
                let c = chunk.len();
                let shadow: ArrayVec<Ray, PACKET_MAX> =
                    chunk.iter().map(|q| Ray::new(q.origin, q.dir)).collect();
                let t_max: ArrayVec<f32, PACKET_MAX> = chunk.iter().map(|q| q.t_max).collect();
                let mut blocked = [false; PACKET_MAX];
                stats.shadow_query(c as u64, |stats| {
                    s.intersector.occluded_packet(
                        geometry,
                        &shadow,
                        &t_max,
                        &mut blocked[..c],
                        stats,
                    )
                });
                for (q, &b) in chunk.iter_mut().zip(&blocked[..c]) {
                    q.blocked = b;
                }
            }
            alive.clear();
            for ((i, v), span) in vertices.iter().zip(&spans) {
                let lane = usize::from(*i);
                let path = &mut paths[lane];
                let queries = &lights[span.clone()];
                if self.leave(path, v, queries, depth, &streams[lane], stats) {
                    alive.push(*i);
                    rays_of[lane] += 1;
                }
            }
        }
        for (c, path) in colors.iter_mut().zip(&paths) {
            *c = path.finish();
        }
    }

    /// Whether the shadow ray of `q` is blocked; counted as a shadow ray with its tests
    /// and visits.
    #[inline(always)]
    pub(super) fn blocked(&self, q: &LightQuery, stats: &mut Stats) -> bool {
        let s = self.scene;
        let ray = Ray::new(q.origin, q.dir);
        stats.shadow_query(1, |stats| {
            (s.intersector).occluded(&s.scene.geometry, &ray, q.t_max, stats)
        })
    }

    /// A path's ray at `depth` arrives at `hit`: the background on a miss, the emission
    /// it sees, and the vertex it scatters from (None when the path ends here).
    #[inline(always)]
    pub(super) fn arrive(
        &self,
        path: &mut Path,
        hit: Option<Hit>,
        depth: u32,
        stats: &mut Stats,
    ) -> Option<Vertex> {
        let scene = self.scene.scene;
        let geometry = &scene.geometry;
        let ray = &path.ray;
        let Some(hit) = hit else {
            path.radiance += path.throughput * scene.background;
            return None;
        };
        if depth == 1 {
            stats.primary_hits += 1;
        }
        let prim = &geometry.primitives[hit.prim as usize];
        let material = &scene.materials[prim.material as usize];
        let mut sp = geometry.surface_with(hit.prim, ray, &hit.shape_hit(), material.uv_need());
        crate::shading::normal_map::apply(material, geometry, hit.prim, &mut sp);
        let (entering, ng, ns) = sp.facing(ray.dir);
        let wo = -ray.dir;
        let k = material.coefficients_at(sp.uv);

        // Emission, seen from its front side.
        if entering && k.is_emissive() {
            let pdf_light = self.emitters.pdf_area(hit.prim);
            let weight = if path.prev_delta || pdf_light <= 0.0 {
                1.0
            } else {
                match self.strategy {
                    Strategy::Mis => {
                        let cos_l = wo.dot(ng);
                        let pdf_light = pdf_light * hit.t * hit.t / cos_l;
                        power_heuristic(path.prev_pdf, pdf_light)
                    }
                    Strategy::LightOnly => 0.0,
                    Strategy::BsdfOnly => 1.0,
                }
            };
            path.radiance += path.throughput * k.emission * weight;
        }
        if depth == self.max_depth {
            return None;
        }
        let bsdf = match &self.lobes[prim.material as usize] {
            Some(lobes) => lobes.at(&k, wo, ns, ng, entering),
            None => Bsdf::new(&k, material.color_at(sp.uv, sp.p), wo, ns, ng, entering),
        };
        Some(Vertex {
            p: sp.p,
            p_error: sp.p_error,
            bsdf,
        })
    }

    /// The light samples at a vertex, appended to `out`, each a shadow ray and what it
    /// adds unblocked: every delta light, and one point on an area light (none at a
    /// vertex of delta lobes only).
    #[inline(always)]
    pub(super) fn light_queries(
        &self,
        v: &Vertex,
        depth: u32,
        stream: &Stream,
        out: &mut Vec<LightQuery>,
    ) {
        if !v.bsdf.has_smooth_lobe() {
            return;
        }
        let (bsdf, ng) = (&v.bsdf, v.bsdf.ng());
        let scene = self.scene.scene;
        for light in &scene.lights {
            let Some(ls) = light.sample(v.p) else {
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
            out.push(LightQuery {
                origin: offset_ray_origin(v.p, v.p_error, ng, wi),
                dir: wi,
                t_max: ls.distance,
                value: f * bsdf.cos(wi) * (PI * ls.color),
                blocked: false,
            });
        }

        if self.strategy == Strategy::BsdfOnly || self.emitters.is_empty() {
            return;
        }
        let Some(e) = self.emitters.sample(
            scene,
            stream.uniform(Self::dim(depth, 0)),
            stream.uniform(Self::dim(depth, 1)),
            stream.uniform(Self::dim(depth, 2)),
        ) else {
            return;
        };
        let to_light = e.p - v.p;
        let Some(wi) = to_light.try_normalize() else {
            return;
        };
        let cos_l = -wi.dot(e.n);
        if cos_l <= 0.0 || ng.dot(wi) <= 0.0 {
            return;
        }
        let f = bsdf.eval(wi);
        if f.max_element() <= 0.0 {
            return;
        }
        // Both ends leave their surfaces; the shadow ray stops short of the light by a
        // few ulps of its length, so it cannot find the light itself.
        let origin = offset_ray_origin(v.p, v.p_error, ng, wi);
        let target = offset_ray_origin(e.p, e.p_error, e.n, -wi);
        let span = target - origin;
        let distance = span.length();
        if distance.is_nan() || distance <= 0.0 || span.dot(wi) <= 0.0 {
            return;
        }
        let d2 = to_light.length_squared();
        let pdf_light = e.pdf_area * d2 / cos_l;
        let weight = match self.strategy {
            Strategy::Mis => power_heuristic(pdf_light, bsdf.pdf(wi)),
            _ => 1.0,
        };
        out.push(LightQuery {
            origin,
            dir: span / distance,
            t_max: distance * (1.0 - gamma(16)),
            value: f * bsdf.cos(wi) * e.radiance * (weight / pdf_light),
            blocked: false,
        });
    }

    /// The path leaves vertex `v` at `depth`: the light its unblocked light samples
    /// (`lights`, answered) add, then a direction drawn from its BSDF and Russian
    /// roulette. False when the path ends here.
    #[inline(always)]
    pub(super) fn leave(
        &self,
        path: &mut Path,
        v: &Vertex,
        lights: &[LightQuery],
        depth: u32,
        stream: &Stream,
        stats: &mut Stats,
    ) -> bool {
        Self::add_light(path, v, lights);
        let [u_lobe, u1, u2] = Self::bsdf_numbers(depth, stream);
        let sample = v.bsdf.sample(u_lobe, u1, u2);
        Self::scatter(path, v, sample, depth, stream, stats)
    }

    /// `leave`'s first step: the light of the unblocked light samples at `v`.
    #[inline(always)]
    pub(super) fn add_light(path: &mut Path, v: &Vertex, lights: &[LightQuery]) {
        if v.bsdf.has_smooth_lobe() {
            // Summed in the order the samples were drawn: delta lights, then the area light.
            let mut sum = Color::ZERO;
            for q in lights.iter().filter(|q| !q.blocked) {
                sum += q.value;
            }
            path.radiance += path.throughput * sum;
        }
    }

    /// The numbers vertex `depth` draws its BSDF sample with: the lobe's, then the
    /// direction's two.
    #[inline(always)]
    pub(super) fn bsdf_numbers(depth: u32, stream: &Stream) -> [f32; 3] {
        [
            stream.uniform(Self::dim(depth, 3)),
            stream.uniform(Self::dim(depth, 4)),
            stream.uniform(Self::dim(depth, 5)),
        ]
    }

    /// `leave`'s last step, with the BSDF's sample drawn (`None`: the path ends): the
    /// throughput, Russian roulette and the next ray. False when the path ends here.
    #[inline(always)]
    pub(super) fn scatter(
        path: &mut Path,
        v: &Vertex,
        sample: Option<BsdfSample>,
        depth: u32,
        stream: &Stream,
        stats: &mut Stats,
    ) -> bool {
        let Some(s) = sample else {
            return false;
        };
        path.throughput *= s.weight;
        if path.throughput.max_element() <= 0.0 {
            return false;
        }
        path.prev_delta = s.delta;
        path.prev_pdf = s.pdf;
        if depth >= RR_DEPTH {
            let survive = path.throughput.max_element().min(0.95);
            if stream.uniform(Self::dim(depth, 6)) >= survive {
                return false;
            }
            path.throughput /= survive;
        }
        if s.transmitted {
            stats.refracted_rays += 1;
        } else {
            stats.reflected_rays += 1;
        }
        path.ray = Ray::new(offset_ray_origin(v.p, v.p_error, v.bsdf.ng(), s.wi), s.wi);
        true
    }
}

thread_local! {
    /// The light samples of the vertex a single path is at, kept per thread so that a
    /// path allocates nothing.
    static LIGHT_QUERIES: std::cell::RefCell<Vec<LightQuery>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// One path's state between its vertices.
pub(super) struct Path {
    /// The ray to follow next.
    pub(super) ray: Ray,
    radiance: Color,
    throughput: Color,
    /// The last scattering was a delta lobe (the camera ray counts as one): what it sees
    /// counts fully.
    prev_delta: bool,
    /// The density the last direction was drawn with.
    prev_pdf: f32,
}

impl Path {
    pub(super) fn new(ray: Ray) -> Path {
        Path {
            ray,
            radiance: Color::ZERO,
            throughput: Color::ONE,
            prev_delta: true,
            prev_pdf: 0.0,
        }
    }

    /// The path's radiance; a NaN would poison a pixel's mean for ever in a progressive
    /// render, so a path that made one gives nothing.
    pub(super) fn finish(&self) -> Color {
        if self.radiance.is_finite() {
            self.radiance
        } else {
            Color::ZERO
        }
    }
}

/// Where a path scatters: the point with its error bound, and the BSDF there, whose
/// geometric normal (`Bsdf::ng`, on the incoming side) the rays leaving it are offset
/// along. Only what the light samples and the bounce read after `arrive`: the wavefront
/// keeps a queue of them between its stages, where the surface point's own normals and
/// uv made a vertex a third larger.
pub(super) struct Vertex {
    p: Vec3,
    p_error: Vec3,
    pub(super) bsdf: Bsdf,
}

/// A light sample's shadow ray, the light it adds if nothing blocks it, and whether
/// something does (once asked).
#[derive(Clone, Copy)]
pub(super) struct LightQuery {
    pub(super) origin: Vec3,
    pub(super) dir: Vec3,
    pub(super) t_max: f32,
    value: Color,
    pub(super) blocked: bool,
}
