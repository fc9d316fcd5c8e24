//! Presets: named bundles of scene and option changes that reproduce a published procedure.

use crate::choices::{AdaptiveRule, SamplerKind};
use crate::options::RenderOptions;
use crate::scene::Scene;

/// POV-Ray 3.7's `+AM2` at its default recursion `+R3` (`AdaptiveSupersamplingM2` in POV's
/// `tracetask.cpp`): the four pixel corners, traced on the lattice; a square whose corners
/// differ splits into four, and `+Rn` allows n − 1 levels (the pixel counts as the first),
/// so `+R3` is `adaptive_depth` 2. No neighbourhood rule, no stratified pass. POV's `+J`
/// jitters only the interior points, by at most ±1/18 pixel at `+R3`; here they stay on the
/// lattice (POV's `-J`). The threshold is left alone: POV compares gamma-encoded colours
/// by the sum of the channel differences, prism by the largest channel spread, so POV's
/// `+A0.3` has no exact counterpart.
pub fn apply_pov_am2(options: &mut RenderOptions) {
    options.sampler = SamplerKind::Adaptive;
    options.adaptive.rule = AdaptiveRule::Corners;
    options.adaptive.jitter = 0.0;
    options.adaptive.texture_spp = 0;
    options.adaptive.depth = 2;
}

/// Eric Haines' SPD testing procedure (SPD 3.14 Readme, "Testing Procedures"): rays through
/// the pixel corners, i.e. (W+1)×(H+1) eye rays for a W×H image, with the extreme rays
/// exactly at ±angle/2; one ray per sample; depth limit 5 with the eye ray at depth 1; the
/// ray-tree rules of `RenderOptions::spd_rules`. The image written is the (W+1)×(H+1) grid of
/// corner samples.
pub fn apply_spd(scene: &mut Scene, options: &mut RenderOptions) {
    let n = options.width.min(options.height) as f64;
    // The camera's field of view spans the outer edges of the outer pixels; widen it so
    // the centres of the outer pixels of the (n+1)-pixel grid lie at ±angle/2.
    let half = (scene.camera.fov_degrees as f64).to_radians() * 0.5;
    let edge_half = (half.tan() * (n + 1.0) / n).atan();
    scene.camera.fov_degrees = (2.0 * edge_half).to_degrees() as f32;
    // The same widening for a window of parallel rays.
    if let crate::camera::Projection::Orthographic { size } = &mut scene.camera.projection {
        *size *= ((n + 1.0) / n) as f32;
    }
    options.width += 1;
    options.height += 1;
    options.samples = 1;
    options.sampler = SamplerKind::Grid;
    options.filter = crate::choices::FilterKind::Box;
    options.filter_radius = None;
    options.max_depth = 5;
    options.min_weight = 0.0;
    options.spd_rules = true;
}
