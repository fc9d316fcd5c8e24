//! prism: a CPU ray tracer built around Whitted's recursive algorithm, with acceleration
//! methods that can be switched and measured.
//!
//! Data flows one way: a built-in or a loader (crate prism-io) makes a [`scene::Scene`]
//! (plain data); [`scene::Scene::prepare`] builds the accelerator; [`render::render`] traces
//! tiles in parallel through the [`integrator::Whitted`] integrator into a
//! [`render::Film`], which prism-io encodes. This crate reads and writes no files, so it
//! builds without any format's dependencies. ARCHITECTURE.md maps the modules.

#[macro_use]
pub mod choices;

pub mod accel;
pub mod camera;
pub mod cpu_time;
pub mod geometry;
pub mod integrator;
pub mod light;
pub mod math;
pub mod options;
pub mod preset;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod shading;
pub mod stats;
pub mod transfer;

pub use options::RenderOptions;
pub use scene::Scene;
pub use stats::Stats;
