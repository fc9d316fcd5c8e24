//! Integrators turn a camera ray into radiance. Whitted's recursive ray tracer is the one
//! prism is built around.

mod shadow;
mod whitted;

pub use whitted::Whitted;
