//! Small geometric vocabulary shared by every other module: rays, boxes, frames and the
//! floating-point error bookkeeping that keeps secondary rays off the surface they leave.
//!
//! Vector arithmetic itself is glam's; nothing here re-implements it.

mod aabb;
mod frame;
mod ray;
pub mod robust;

pub use aabb::Aabb;
pub use frame::Frame;
pub use glam::{Vec2, Vec3};
pub use ray::{Ray, TraceRay};

/// Linear RGB radiance or reflectance. sRGB only appears when an 8-bit image is written.
pub type Color = Vec3;
