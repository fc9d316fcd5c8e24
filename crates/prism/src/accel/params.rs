//! What makes a settings type an acceleration method: its key table (`choices::Keyed`)
//! and how it builds. Adding a method is one file that implements both and one line in
//! the `accel_methods!` list (accel/spec.rs).

use super::Accel;
use crate::geometry::Geometry;

/// An acceleration method's behaviour: it builds its structure.
pub trait Method: Send + Sync {
    /// Builds the structure over the given (bounded) primitive indices.
    fn build(&self, geometry: &Geometry, prims: Vec<u32>) -> Box<dyn Accel>;
}
