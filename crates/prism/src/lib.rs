//! prism: a CPU ray tracer built around Whitted's recursive algorithm, with acceleration
//! methods that can be switched and measured.
//!
//! Data flows one way: a loader or built-in makes a [`scene::Scene`] (plain data);
//! [`scene::Scene::prepare`] builds the accelerator; [`render::render`] traces tiles in
//! parallel through the [`integrator::Whitted`] integrator into a [`render::Film`]; and
//! [`output::write_image`] encodes it. ARCHITECTURE.md maps the modules.

#[macro_use]
mod kinds;

// The public API is documented module by module; `accel` is complete and held to it.
#[warn(missing_docs)]
pub mod accel;
pub mod bench;
pub mod camera;
pub mod geometry;
pub mod integrator;
pub mod light;
pub mod math;
pub mod metrics;
pub mod options;
pub mod output;
pub mod preset;
pub mod reference;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod shading;
pub mod stats;
pub mod transfer;

pub use options::RenderOptions;
pub use scene::Scene;
pub use stats::Stats;
