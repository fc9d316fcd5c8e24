//! Which integrator renders (`--integrator`, the scene file's `integrator`), and the path
//! tracer's estimator switch; the integrators themselves live in `integrator`.

use serde::{Deserialize, Serialize};

/// Which integrator renders (`--integrator`, the scene file's `integrator`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntegratorKind {
    /// Whitted's recursive ray tracer: point lights, mirror and refracted rays.
    #[default]
    Whitted,
    /// A path tracer with area lights, next-event estimation and MIS.
    Path,
    /// Heckbert & Hanrahan's beam tracer: exact visible polygons, box-filtered exactly
    /// (planar scenes only; docs/beam-tracing.md).
    Beam,
}

named_kinds! {
    IntegratorKind, "integrator" {
        Whitted => "whitted",
        Path => "path",
        Beam => "beam",
    }
}

impl IntegratorKind {
    /// Whether it traces rays (camera rays through the samplers, in packets where
    /// `packets` is on); the beam tracer traces beams.
    pub fn traces_rays(self) -> bool {
        matches!(self, IntegratorKind::Whitted | IntegratorKind::Path)
    }

    /// Whether most of its rays start on surfaces inside the scene (a path's bounces)
    /// rather than outside it (camera rays, Whitted's trees), which a BVH's `rays=auto`
    /// builds for.
    pub fn rays_start_inside(self) -> bool {
        self == IntegratorKind::Path
    }
}

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
