//! The exact box-filtered image of any scene of planar polygons, by the engine's beam
//! tracer (`prism::integrator::beam`): every pixel is the area-weighted sum over the exact
//! visible fragments that cover it, shaded per fragment and pixel at the piece's centroid.
//! Exact where shading is constant over each polygon (flat colours, checker squares, ambient
//! light); where light varies across a pixel's piece, its centroid stands for it.

use super::checkerboard::ReferenceError;
use prism::options::{IntegratorKind, RenderOptions};
use prism::render::{render_beam, Film, RenderError};
use prism::scene::Scene;
use std::sync::atomic::AtomicBool;

/// A beam-traced reference and its figures.
#[derive(Clone, Debug)]
pub struct BeamReference {
    /// The image.
    pub film: Film,
    /// The largest error bound of any pixel (from checker squares beside a horizon).
    pub error_bound: f64,
    /// Beams traced.
    pub beams: u64,
    /// Visible fragments over all beams.
    pub fragments: u64,
    /// Fragment ∩ pixel pieces shaded.
    pub pieces: u64,
    /// The deepest beam of the tree.
    pub depth: u32,
}

/// The beam tracer's image of `scene` at `width` × `height` with the scene's depth and
/// weight settings, each pixel within `tolerance` where checker squares are averaged.
pub fn beam(
    scene: &Scene,
    width: u32,
    height: u32,
    tolerance: f64,
) -> Result<BeamReference, ReferenceError> {
    if !(tolerance > 0.0 && tolerance.is_finite()) {
        return Err(ReferenceError::Tolerance(tolerance));
    }
    let options = RenderOptions {
        width,
        height,
        integrator: IntegratorKind::Beam,
        ..scene.options.clone()
    };
    let prepared = scene.prepare_for(&options);
    let r = render_beam(
        &prepared,
        &options,
        tolerance,
        &|_| {},
        &AtomicBool::new(false),
    )
    .map_err(|e| match e {
        RenderError::Camera(c) => ReferenceError::Camera(c),
        other => ReferenceError::Unsupported(other.to_string()),
    })?;
    Ok(BeamReference {
        error_bound: r.error_bound(),
        film: r.film,
        beams: r.stats.beams,
        fragments: r.stats.beam_fragments,
        pieces: r.stats.beam_pieces,
        depth: r.deepest,
    })
}
