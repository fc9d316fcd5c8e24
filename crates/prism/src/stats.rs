//! Counters for the work a render does: rays by kind, intersection tests, node visits.
//!
//! Each worker owns a `Stats` and adds to it without atomics; the renderer sums them at the
//! end, so counting costs an increment and the totals do not depend on thread count.

use crate::geometry::ShapeKind;
use serde::Serialize;
use std::ops::AddAssign;

/// What one render (or one thread of it) did: rays by kind, tests, node visits and the shadow
/// methods' counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Stats {
    /// Camera rays.
    pub primary_rays: u64,
    /// Camera rays that hit something (SPD's "eye-hit rays").
    pub primary_hits: u64,
    /// One per (shading point, light) pair whose light is in front of the surface.
    pub shadow_rays: u64,
    /// Extra segments traced by shadow rays that pass through transparent surfaces.
    pub shadow_continuations: u64,
    /// Mirror-reflected rays traced.
    pub reflected_rays: u64,
    /// Refracted rays traced.
    pub refracted_rays: u64,
    /// Reflected or refracted rays not traced because their weight in the pixel fell below
    /// `min_weight` (adaptive depth control); each also saves its whole subtree.
    pub pruned_rays: u64,
    /// Shadow rays not cast because the light could change the pixel by less than
    /// `min_weight` whatever they found; the light gets through as much as the tested
    /// lights at the point do (adaptive shadow testing).
    pub pruned_shadow_rays: u64,
    /// Squares split by adaptive sampling.
    pub adaptive_splits: u64,
    /// Textured pixels that adaptive sampling gave the stratified pass.
    pub adaptive_stratified: u64,
    /// Refractions that turned into reflection because sin²θt > 1.
    pub total_internal_reflections: u64,
    /// Ray–primitive intersection tests.
    pub primitive_tests: u64,
    /// The same tests by shape kind, indexed by `ShapeKind as usize`.
    pub tests_by_kind: [u64; ShapeKind::COUNT],
    /// Acceleration-structure nodes whose bounds were tested.
    pub node_visits: u64,
    /// The part of `primitive_tests` made by shadow rays (whatever method answered them).
    pub shadow_tests: u64,
    /// The part of `node_visits` made by shadow rays.
    pub shadow_node_visits: u64,
    /// Shadow rays answered by the shadow cache's remembered blocker alone.
    pub shadow_cache_hits: u64,
    /// Shadow rays answered by a light buffer.
    pub light_buffer_queries: u64,
    /// Of those, the ones whose line passes the light too far off for its cell to hold
    /// everything it may meet near the light: the accelerator answered.
    pub light_buffer_fallbacks: u64,
    /// Beams traced by the beam tracer (the view's tile beams included); its reflected and
    /// refracted beams are also counted as `reflected_rays` and `refracted_rays`.
    pub beams: u64,
    /// Visible fragments (convex cells) the beams found.
    pub beam_fragments: u64,
    /// Fragment ∩ pixel pieces the beam tracer shaded.
    pub beam_pieces: u64,
    /// Time the wavefront path tracer spent in each of its stages.
    pub stages: StageTimes,
}

/// Nanoseconds of the render threads' CPU time in each stage of the wavefront path tracer
/// (`StageTimes::NAMES`), summed over threads; zero for the other renderers. Times are
/// measurements, not statistics of the work: two renders' `Stats` are equal whatever
/// their times, so this compares equal to any other. Serialised as the plain list of
/// `ns`, which adds up as the other counters do.
#[derive(Clone, Copy, Debug, Default, Serialize)]
#[serde(transparent)]
pub struct StageTimes {
    /// Per stage, in the order of `NAMES`.
    pub ns: [u64; StageTimes::NAMES.len()],
}

impl StageTimes {
    /// The stages: new camera rays, their and the bounce rays' hits, the hits' emission,
    /// BSDF and light samples, the shadow rays, and the paths leaving (light added, a
    /// direction drawn, Russian roulette, the queue compacted).
    pub const NAMES: [&'static str; 5] = ["camera", "trace", "shade", "shadow", "leave"];

    /// All stages' time.
    pub fn total(&self) -> u64 {
        self.ns.iter().sum()
    }
}

impl PartialEq for StageTimes {
    fn eq(&self, _: &StageTimes) -> bool {
        true
    }
}

impl Eq for StageTimes {}

impl Stats {
    /// Records one intersection test against a shape of `kind`.
    #[inline(always)]
    pub fn count_test(&mut self, kind: ShapeKind) {
        self.primitive_tests += 1;
        self.tests_by_kind[kind as usize] += 1;
    }

    /// Records `n` intersection tests against shapes of `kind` (tested together).
    #[inline(always)]
    pub fn count_tests(&mut self, kind: ShapeKind, n: u64) {
        self.primitive_tests += n;
        self.tests_by_kind[kind as usize] += n;
    }

    /// Runs `query`, the walk of `rays` shadow rays, counting them as shadow rays and the
    /// primitive tests and node visits it makes as theirs (as well as in the totals).
    #[inline(always)]
    pub fn shadow_query<R>(&mut self, rays: u64, query: impl FnOnce(&mut Stats) -> R) -> R {
        self.shadow_rays += rays;
        let (tests, nodes) = (self.primitive_tests, self.node_visits);
        let answer = query(self);
        self.shadow_tests += self.primitive_tests - tests;
        self.shadow_node_visits += self.node_visits - nodes;
        answer
    }

    /// Every ray traced: camera, shadow (with continuations), reflected and refracted.
    pub fn total_rays(&self) -> u64 {
        self.primary_rays
            + self.shadow_rays
            + self.shadow_continuations
            + self.reflected_rays
            + self.refracted_rays
    }
}

impl AddAssign for Stats {
    fn add_assign(&mut self, o: Stats) {
        self.primary_rays += o.primary_rays;
        self.primary_hits += o.primary_hits;
        for (a, b) in self.tests_by_kind.iter_mut().zip(o.tests_by_kind) {
            *a += b;
        }
        self.shadow_rays += o.shadow_rays;
        self.shadow_continuations += o.shadow_continuations;
        self.reflected_rays += o.reflected_rays;
        self.refracted_rays += o.refracted_rays;
        self.pruned_rays += o.pruned_rays;
        self.pruned_shadow_rays += o.pruned_shadow_rays;
        self.adaptive_splits += o.adaptive_splits;
        self.adaptive_stratified += o.adaptive_stratified;
        self.total_internal_reflections += o.total_internal_reflections;
        self.primitive_tests += o.primitive_tests;
        self.node_visits += o.node_visits;
        self.shadow_tests += o.shadow_tests;
        self.shadow_node_visits += o.shadow_node_visits;
        self.shadow_cache_hits += o.shadow_cache_hits;
        self.light_buffer_queries += o.light_buffer_queries;
        self.light_buffer_fallbacks += o.light_buffer_fallbacks;
        self.beams += o.beams;
        self.beam_fragments += o.beam_fragments;
        self.beam_pieces += o.beam_pieces;
        for (a, b) in self.stages.ns.iter_mut().zip(o.stages.ns) {
            *a += b;
        }
    }
}
