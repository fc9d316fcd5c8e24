//! prism-io: what the prism engine reads and writes. Scene files (TOML, NFF, glTF/GLB,
//! OBJ/MTL, PLY) become an engine [`prism::Scene`] through [`scene::load`]; texture images
//! are decoded by [`texture`]; every file a load reads goes through a [`source::Reader`],
//! which lists them afterwards; a rendered [`prism::render::Film`] is written as PNG, EXR or
//! PFM by [`output::write_image`], atomically, and read back by [`output::read_image`].
//!
//! The engine itself (crate `prism`) has none of these formats' dependencies, so it builds
//! alone; this crate is the only one that needs gltf, tobj, toml, image and exr.

pub mod output;
pub mod scene;
pub mod source;
pub mod texture;
