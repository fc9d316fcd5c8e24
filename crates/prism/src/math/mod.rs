//! Small vocabulary shared by every other module: rays, boxes, frames, the floating-point
//! error bookkeeping that keeps secondary rays off the surface they leave, and `hash`, the
//! one source of random numbers (sampling patterns, procedural scenes, measurements).
//!
//! Vector arithmetic itself is glam's; nothing here re-implements it.

mod aabb;
mod frame;
pub mod hash;
pub(crate) mod lanes;
mod ray;
pub mod robust;
pub mod warp;

pub use aabb::Aabb;
pub use frame::Frame;
pub use glam::{Vec2, Vec3, Vec4};
pub(crate) use ray::{permutation, watertight_axes};
pub use ray::{Ray, TraceRay};

/// Linear RGB radiance or reflectance. sRGB only appears when an 8-bit image is written.
pub type Color = Vec3;
