//! Shadow rays: whether a light reaches a surface point, and how much of it.
//!
//! A shadow ray runs from the (offset) surface point towards the light and asks an any-hit
//! query, which may stop at the first blocker. In a scene with transparent surfaces it asks
//! for the nearest hit instead and continues through each transparent surface it meets,
//! filtered by its kt (a colour: red glass casts a red shadow), as POV-Ray does; refraction of the
//! shadow ray itself is ignored (no
//! caustics).
//!
//! Who answers the query is the shadow method (`ShadowSpec`), and every method gives the
//! same answer, bit for bit:
//! - `any-hit`: the scene's accelerator (the BVH by default);
//! - `cache`: the last blocker found for the same light at the same depth of the ray tree
//!   is tested first (ray coherence: neighbouring points are usually shadowed by the same
//!   object); only in scenes without transparent surfaces, where one hit settles the answer;
//! - `light-buffer`: a light buffer per light (`light_buffer.rs`): a cube of directions
//!   around a point or spot light, one orthographic grid across a directional light's
//!   direction; lights whose buffer would pass the memory budget keep the accelerator;
//! - `both`: the light buffer, then the cache;
//! - `auto`: what is predicted to pay in a render: today `any-hit` (measured in
//!   docs/shadows.md: `both` beats the BVH on single rays, but renders send any-hit
//!   shadow rays in packets, which beat both on every SPD scene).

use super::light_buffer::{BufferParams, LightBuffer, LightBufferInfo};
use crate::accel::{Bvh, Hit, HitSearch, PacketQuery, QueryMode, PACKET_MAX};
pub use crate::choices::{ShadowMethod, ShadowSpec};
use crate::geometry::{SurfacePoint, Uv};
use crate::light::{Light, LightSample};
use crate::math::robust::offset_ray_origin;
use crate::math::{Color, Ray, TraceRay, Vec3};
use crate::scene::{PreparedScene, Scene};
use crate::stats::Stats;
use arrayvec::ArrayVec;
use std::cell::RefCell;

/// Upper bound on transparent surfaces one shadow ray passes through.
const MAX_SHADOW_SEGMENTS: u32 = 64;
/// The light buffers' memory budget when none is given, in MiB (for all lights).
pub(super) const DEFAULT_LIGHT_BUFFER_BUDGET_MIB: u32 = 256;

/// What a shadow method's settings mean for the light buffers.
impl ShadowSpec {
    /// The resolution a buffer over `primitives` gets.
    pub fn resolution(&self, primitives: usize) -> u32 {
        match self.res {
            0 => LightBuffer::auto_resolution(primitives),
            r => r,
        }
    }

    fn budget_bytes(&self) -> u64 {
        let mib = match self.budget_mib {
            0 => DEFAULT_LIGHT_BUFFER_BUDGET_MIB,
            m => m,
        };
        mib as u64 * 1024 * 1024
    }
}

/// The shadow-ray machinery of one render: the method and, per light, its buffer.
pub struct Shadows<'a> {
    scene: &'a PreparedScene<'a>,
    spec: ShadowSpec,
    /// Per light; None where the accelerator answers.
    buffers: Vec<Option<LightBuffer>>,
    /// Per light, why it has no buffer although the method asked for one.
    pub unbuilt: Vec<Option<String>>,
}

impl<'a> Shadows<'a> {
    /// Builds what `spec` needs for `scene`'s lights.
    pub fn new(scene: &'a PreparedScene<'a>, spec: ShadowSpec) -> Shadows<'a> {
        let lights = &scene.scene.lights;
        let mut buffers = Vec::with_capacity(lights.len());
        let mut unbuilt = Vec::with_capacity(lights.len());
        let geometry = &scene.scene.geometry;
        let res = spec.resolution(geometry.primitives.len());
        // The budget is shared out among the lights.
        let params = BufferParams {
            res,
            budget_bytes: spec.budget_bytes() / lights.len().max(1) as u64,
        };
        for light in lights {
            let built = spec.method.uses_light_buffer().then(|| match *light {
                Light::Point { position, .. } | Light::Spot { position, .. } => {
                    LightBuffer::build(&scene.intersector, position, &params)
                }
                // Its shadow rays' direction, as `Light::sample` gives it.
                Light::Directional { direction, .. } => {
                    LightBuffer::build_directional(&scene.intersector, -direction, &params)
                }
            });
            let (buffer, why) = match built {
                None => (None, None),
                Some(Ok(b)) => (Some(b), None),
                Some(Err(why)) => (
                    None,
                    Some(format!("{why}: its shadow rays use the accelerator")),
                ),
            };
            buffers.push(buffer);
            unbuilt.push(why);
        }
        Shadows {
            scene,
            spec,
            buffers,
            unbuilt,
        }
    }

    /// Whether anything blocks `ray` (from a surface towards the scene's `light`-th light,
    /// at `depth` of the ray tree) before `t_max`: the any-hit answer, by this method.
    pub fn blocked(
        &self,
        light: usize,
        depth: u32,
        ray: &Ray,
        t_max: f32,
        stats: &mut Stats,
    ) -> bool {
        let query = self.query(light);
        if self.spec.method.uses_cache() {
            cached_any_hit(&query, light, depth, ray, t_max, stats)
        } else {
            query.any(ray, t_max, stats).is_some()
        }
    }

    /// Who answers the queries of the scene's `light`-th light.
    fn query(&self, light: usize) -> Query<'_> {
        let buffer = self.buffers.get(light).and_then(Option::as_ref);
        Query {
            scene: self.scene,
            buffer: buffer.zip(self.scene.intersector.accel.as_bvh()),
        }
    }

    /// The light buffers' figures, per light (None where a light has none).
    pub fn buffer_info(&self) -> Vec<Option<LightBufferInfo>> {
        self.buffers
            .iter()
            .map(|b| b.as_ref().map(LightBuffer::info))
            .collect()
    }

    /// For a packet of shadow rays towards the scene's `index`-th light, in a scene with
    /// transparent surfaces: the fraction of the light that reaches each ray's origin,
    /// `distances[i]` away, exactly as `visibility` finds it. The walk through transparent
    /// surfaces goes breadth first: the rays still walking after each surface go on as one
    /// packet (they leave the same glass towards the same light, so they stay coherent),
    /// each step a nearest-hit packet (the light buffer's where the light has one; the
    /// cache, which remembers blockers, has no part in it, as in `visibility`). An any-hit
    /// packet would have to be traced again through the transparent surfaces (on SPD gears
    /// that made the render 20 % slower).
    /// `segments[i]` gains ray i's continuation rays, which `stats` counts too.
    pub(super) fn transmittance_packet(
        &self,
        index: usize,
        rays: &[Ray],
        distances: &[f32],
        visibility: &mut [Color],
        segments: &mut [u32],
        stats: &mut Stats,
    ) {
        let scene = self.scene;
        let (geometry, accel) = (&scene.scene.geometry, &scene.intersector);
        let n = rays.len();
        stats.shadow_query(n as u64, |stats| {
            // The rays still walking after the first segment: which of the packet's, their
            // next segment and what is left of their distance (the first segment is the
            // packet's own rays, not copied).
            let mut walking: ArrayVec<usize, PACKET_MAX> = ArrayVec::new();
            let mut segment_rays: ArrayVec<Ray, PACKET_MAX> = ArrayVec::new();
            let mut remaining: ArrayVec<f32, PACKET_MAX> = ArrayVec::new();
            let mut atten = [Color::ONE; PACKET_MAX];
            let mut hits = [None; PACKET_MAX];
            for segment in 0..MAX_SHADOW_SEGMENTS {
                let (these, bounds) = if segment == 0 {
                    (rays, distances)
                } else {
                    (&segment_rays[..], &remaining[..])
                };
                let m = these.len();
                if m == 0 {
                    break;
                }
                if segment > 0 {
                    stats.shadow_continuations += m as u64;
                    for &i in &walking {
                        segments[i] += 1;
                    }
                }
                let hits = &mut hits[..m];
                match self.query(index).buffer {
                    Some((b, _)) => b.nearest_packet(geometry, accel, these, bounds, hits, stats),
                    None => {
                        let packet = PacketQuery::new(geometry, these, bounds, QueryMode::Nearest);
                        accel.query_packet(&packet, hits, stats)
                    }
                }
                // Each ray's step, as `transmittance` takes it; the rays that go on are
                // gathered in `next` (the segment's rays are still borrowed) and form the next
                // segment's packet.
                let mut next = ArrayVec::<(usize, Ray, f32), PACKET_MAX>::new();
                for k in 0..m {
                    let i = if segment == 0 { k } else { walking[k] };
                    match step(scene.scene, &these[k], bounds[k], hits[k], &mut atten[i]) {
                        Step::Ends(seen) => visibility[i] = seen,
                        Step::GoesOn(ray, left) => next.push((i, ray, left)),
                    }
                }
                walking.clear();
                segment_rays.clear();
                remaining.clear();
                for (i, ray, left) in next {
                    walking.push(i);
                    segment_rays.push(ray);
                    remaining.push(left);
                }
            }
            // Rays that crossed `MAX_SHADOW_SEGMENTS` surfaces see nothing, as in the walk.
            for &i in &walking {
                visibility[i] = Color::ZERO;
            }
        })
    }

    /// Whether each of a packet of shadow rays (at most `PACKET_MAX`) towards the scene's
    /// `index`-th light, from hits at `depth` of the ray tree, is blocked: ray i from its
    /// offset surface point towards the light, `distances[i]` away; counted as the shadow
    /// rays. The rays walk as one any-hit packet (from the light buffer's cells where the
    /// light has one); with the cache, the blocker remembered for this light and depth is
    /// tried on every ray first, and the rest walk. For a scene without transparent
    /// surfaces (`transmittance_packet` serves the others): a ray that is not blocked sees
    /// the light, one that is sees nothing, as `visibility` says.
    pub fn blocked_packet(
        &self,
        index: usize,
        depth: u32,
        rays: &[Ray],
        distances: &[f32],
        blocked: &mut [bool],
        stats: &mut Stats,
    ) {
        let n = rays.len();
        let scene = self.scene;
        let (geometry, accel) = (&scene.scene.geometry, &scene.intersector);
        stats.shadow_query(n as u64, |stats| {
            let answers = if self.spec.method.uses_cache() {
                self.cached_packet(index, depth, rays, distances, stats)
            } else if self.query(index).buffer.is_some() {
                let mut answers = [None; PACKET_MAX];
                self.any_hit_packet(index, rays, distances, &mut answers[..n], stats);
                answers
            } else {
                // Which blocker does not matter here: planes are tested only where the
                // accelerator found nothing.
                accel.occluded_packet(geometry, rays, distances, blocked, stats);
                return;
            };
            for (b, answer) in blocked.iter_mut().zip(&answers[..n]) {
                *b = answer.is_some();
            }
        })
    }

    /// The any-hit answers of a packet towards the `index`-th light: its light buffer's
    /// where it has one, the accelerator's otherwise.
    fn any_hit_packet(
        &self,
        index: usize,
        rays: &[Ray],
        distances: &[f32],
        answers: &mut [Option<Hit>],
        stats: &mut Stats,
    ) {
        let scene = self.scene;
        let (geometry, accel) = (&scene.scene.geometry, &scene.intersector);
        match self.query(index).buffer {
            Some((b, _)) => b.any_hit_packet(geometry, accel, rays, distances, answers, stats),
            None => {
                let packet = PacketQuery::new(geometry, rays, distances, QueryMode::Any);
                accel.query_packet(&packet, answers, stats)
            }
        }
    }

    /// `blocked_packet` with the shadow cache: the blocker remembered for this light and
    /// depth is tried on every ray of the packet, the rays it does not block walk as one
    /// packet, and what is remembered afterwards is what single rays in the packet's order
    /// would leave: the last ray's blocker, or nothing where the last ray is not blocked.
    /// (Between the packet's rays it does not change, as it would ray by ray: the same
    /// answers, a few more or fewer cache hits.) Returns each ray's blocker.
    fn cached_packet(
        &self,
        index: usize,
        depth: u32,
        rays: &[Ray],
        distances: &[f32],
        stats: &mut Stats,
    ) -> [Option<Hit>; PACKET_MAX] {
        let n = rays.len();
        let geometry = &self.scene.scene.geometry;
        let (slot, remembered) = remembered_blocker(index, depth);
        let mut answers = [None; PACKET_MAX];
        let mut open: ArrayVec<u8, PACKET_MAX> = ArrayVec::new();
        for (i, (ray, &t_max)) in rays.iter().zip(distances).enumerate() {
            if let Some(prim) = remembered {
                let mut search = HitSearch::new(t_max, QueryMode::Any);
                if search.test(geometry, &TraceRay::new(*ray), prim, stats) {
                    stats.shadow_cache_hits += 1;
                    answers[i] = search.best();
                    continue;
                }
            }
            open.push(i as u8);
        }
        if open.len() == n {
            self.any_hit_packet(index, rays, distances, &mut answers[..n], stats);
        } else if !open.is_empty() {
            let group: ArrayVec<Ray, PACKET_MAX> =
                open.iter().map(|&i| rays[usize::from(i)]).collect();
            let bounds: ArrayVec<f32, PACKET_MAX> =
                open.iter().map(|&i| distances[usize::from(i)]).collect();
            let mut found = [None; PACKET_MAX];
            let found = &mut found[..open.len()];
            self.any_hit_packet(index, &group, &bounds, found, stats);
            for (&i, &hit) in open.iter().zip(found.iter()) {
                answers[usize::from(i)] = hit;
            }
        }
        let remember = answers[..n]
            .last()
            .copied()
            .flatten()
            .map_or(u32::MAX, |h| h.prim);
        if remember != u32::MAX || remembered.is_some() {
            remember_blocker(slot, remember);
        }
        answers
    }

    /// The fraction of light `light` (the scene's `index`-th) that reaches surface point
    /// `sp`, whose geometric normal faces the light as `ng`, from a ray at `depth` of the ray
    /// tree: one shadow ray, counted in `stats`.
    pub(super) fn visibility(
        &self,
        index: usize,
        depth: u32,
        sp: &SurfacePoint,
        ng: Vec3,
        light: &LightSample,
        stats: &mut Stats,
    ) -> Color {
        let scene = self.scene;
        let origin = offset_ray_origin(sp.p, sp.p_error, ng, light.to_light);
        let query = self.query(index);
        stats.shadow_query(1, |stats| {
            if scene.has_transmissive {
                transmittance(&query, origin, light.to_light, light.distance, stats)
            } else {
                let ray = Ray::new(origin, light.to_light);
                if self.blocked(index, depth, &ray, light.distance, stats) {
                    Color::ZERO
                } else {
                    Color::ONE
                }
            }
        })
    }
}

/// One shadow query, answered by the light's buffer or by the accelerator.
struct Query<'a> {
    scene: &'a PreparedScene<'a>,
    /// The light's buffer and the BVH it was built over.
    buffer: Option<(&'a LightBuffer, &'a Bvh)>,
}

impl Query<'_> {
    fn any(&self, ray: &Ray, t_max: f32, stats: &mut Stats) -> Option<Hit> {
        let geometry = &self.scene.scene.geometry;
        match self.buffer {
            Some((b, bvh)) => {
                stats.light_buffer_queries += 1;
                let accel = &self.scene.intersector;
                b.any_hit(geometry, accel, bvh, ray, t_max, None, stats)
            }
            None => self.scene.intersector.any_hit(geometry, ray, t_max, stats),
        }
    }

    fn nearest(&self, ray: &Ray, t_max: f32, stats: &mut Stats) -> Option<Hit> {
        let geometry = &self.scene.scene.geometry;
        match self.buffer {
            Some((b, bvh)) => {
                stats.light_buffer_queries += 1;
                let accel = &self.scene.intersector;
                b.nearest(geometry, accel, bvh, ray, t_max, stats)
            }
            None => self
                .scene
                .intersector
                .intersect(geometry, ray, t_max, stats),
        }
    }
}

thread_local! {
    /// The shadow cache of this worker: per (light, depth), the last blocker found, or
    /// u32::MAX. Cleared at the start of every tile or row (`begin_piece`), so what a
    /// piece of work counts does not depend on which thread ran what before it.
    static CACHE: RefCell<Vec<u32>> = const { RefCell::new(Vec::new()) };
}

/// Depths the cache keeps apart (deeper rays share the last slot).
const CACHE_DEPTHS: usize = 8;

/// Forgets every remembered blocker of this thread: called when a worker starts a tile or
/// a row.
pub fn begin_piece() {
    CACHE.with(|c| c.borrow_mut().clear());
}

/// An any-hit query that first tries the blocker last found for this light and depth.
fn cached_any_hit(
    query: &Query,
    light: usize,
    depth: u32,
    ray: &Ray,
    t_max: f32,
    stats: &mut Stats,
) -> bool {
    let (slot, remembered) = remembered_blocker(light, depth);
    let geometry = &query.scene.scene.geometry;
    let answer = match query.buffer {
        // The buffer asks the remembered blocker first.
        Some((b, bvh)) => {
            stats.light_buffer_queries += 1;
            let accel = &query.scene.intersector;
            b.any_hit(geometry, accel, bvh, ray, t_max, remembered, stats)
        }
        None => {
            if let Some(prim) = remembered {
                // The accelerators' own counted test: one hit settles an any-hit query.
                let mut search = HitSearch::new(t_max, QueryMode::Any);
                if search.test(geometry, &TraceRay::new(*ray), prim, stats) {
                    stats.shadow_cache_hits += 1;
                    return true;
                }
            }
            query.any(ray, t_max, stats)
        }
    };
    // Remember the blocker; after an unblocked ray, nothing: shadows come in runs, and a
    // point in light is usually followed by another, for which a remembered blocker would
    // be one wasted test (3 to 4 % hits on SPD tree, teapot and tetra).
    let remember = answer.map_or(u32::MAX, |hit| hit.prim);
    if remember != u32::MAX || remembered.is_some() {
        remember_blocker(slot, remember);
    }
    answer.is_some()
}

/// This thread's cache slot for `light` at `depth`, and the blocker it remembers.
fn remembered_blocker(light: usize, depth: u32) -> (usize, Option<u32>) {
    let slot = light * CACHE_DEPTHS + (depth as usize).min(CACHE_DEPTHS) - 1;
    let prim = CACHE.with(|c| c.borrow().get(slot).copied().unwrap_or(u32::MAX));
    (slot, (prim != u32::MAX).then_some(prim))
}

/// Sets this thread's cache `slot` to `prim` (u32::MAX for nothing).
fn remember_blocker(slot: usize, prim: u32) {
    CACHE.with(|c| {
        let mut c = c.borrow_mut();
        if c.len() <= slot {
            c.resize(slot + 1, u32::MAX);
        }
        c[slot] = prim;
    });
}

/// Fraction of a light's radiance, per channel, that reaches `origin` along `dir` within
/// `distance`: 0 behind an opaque surface, the product of kt (a colour) over the
/// transparent ones otherwise. `Shadows::transmittance_packet` takes the same steps for a
/// packet.
fn transmittance(
    query: &Query,
    origin: Vec3,
    dir: Vec3,
    distance: f32,
    stats: &mut Stats,
) -> Color {
    let mut atten = Color::ONE;
    let mut ray = Ray::new(origin, dir);
    let mut remaining = distance;
    for segment in 0..MAX_SHADOW_SEGMENTS {
        if segment > 0 {
            stats.shadow_continuations += 1;
        }
        let hit = query.nearest(&ray, remaining, stats);
        match step(query.scene.scene, &ray, remaining, hit, &mut atten) {
            Step::Ends(seen) => return seen,
            Step::GoesOn(next, left) => (ray, remaining) = (next, left),
        }
    }
    Color::ZERO
}

/// Where a shadow ray's walk through transparent surfaces stands after one segment.
enum Step {
    /// The walk is over: this much of the light is seen.
    Ends(Color),
    /// It goes on along this ray, with this distance left to the light.
    GoesOn(Ray, f32),
}

/// One segment of the walk: `ray` met `hit` (its nearest surface within `remaining`, or
/// none), and `atten` is what the surfaces before it let through.
#[inline(always)]
fn step(scene: &Scene, ray: &Ray, remaining: f32, hit: Option<Hit>, atten: &mut Color) -> Step {
    let Some(hit) = hit else {
        return Step::Ends(*atten);
    };
    let geometry = &scene.geometry;
    let prim = &geometry.primitives[hit.prim as usize];
    *atten *= scene.materials[prim.material as usize].transmit;
    if atten.max_element() <= 0.0 {
        return Step::Ends(Color::ZERO);
    }
    let sp = geometry.surface_with(hit.prim, ray, &hit.shape_hit(), Uv::Skip);
    let next = offset_ray_origin(sp.p, sp.p_error, sp.ng, ray.dir);
    let left = remaining - (next - ray.origin).dot(ray.dir);
    if left <= 0.0 {
        return Step::Ends(*atten);
    }
    Step::GoesOn(Ray::new(next, ray.dir), left)
}
