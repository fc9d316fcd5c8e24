//! Presets: named bundles of scene and option changes that reproduce a published procedure.

use crate::options::RenderOptions;
use crate::scene::Scene;

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
    options.sampler = crate::sampling::SamplerKind::Grid;
    options.filter = crate::render::FilterKind::Box;
    options.filter_radius = None;
    options.max_depth = 5;
    options.min_weight = 0.0;
    options.spd_rules = true;
}
