//! Exact reference images, computed from the scene's geometry rather than by sampling, so
//! that sampling error can be measured against the truth.

mod checkerboard;

pub use checkerboard::{checkerboard, CheckerReference, ReferenceError, DEFAULT_TOLERANCE};
