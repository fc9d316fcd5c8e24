//! Integrators turn a camera ray into radiance. Whitted's recursive ray tracer is the one
//! prism is built around.

mod light_buffer;
mod shadow;
mod whitted;

pub use light_buffer::{BufferParams, LightBuffer, LightBufferInfo};
pub use shadow::{begin_piece, ShadowMethod, ShadowSpec, Shadows};
pub use whitted::{Charge, Whitted};
