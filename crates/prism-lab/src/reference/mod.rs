//! Exact reference images, computed from the scene's geometry rather than by sampling, so
//! that sampling error can be measured against the truth: the checkerboard in closed form,
//! and any scene of planar polygons by beam tracing.

mod beam;
mod checkerboard;

pub use beam::{beam, BeamReference};
pub use checkerboard::{checkerboard, CheckerReference, ReferenceError, DEFAULT_TOLERANCE};
