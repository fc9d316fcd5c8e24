//! The engine's test suites, built as one test binary: each suite is a file beside this
//! one, declared here as a module, so that the suites share one compilation and one link
//! instead of one each (ARCHITECTURE.md, "How to add a test suite"). `cargo test --release
//! -p prism --test suites -- NAME::` runs the suite of NAME.rs alone.

mod common;

mod accel;
mod architecture;
mod area_lights;
mod beam;
mod bvh_builders;
mod determinism;
mod geometry;
mod golden;
mod methods;
mod normal_maps;
mod optics;
mod packets;
mod path_tracing;
mod patterns;
mod sampling;
mod scale;
mod settings;
mod shadows;
mod texel_materials;
mod toy_methods;
mod transmission;
mod volumes;
mod wavefront;
