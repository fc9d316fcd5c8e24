//! Reading scene files into the engine's [`Scene`]: the extension picks the loader
//! (`load`), after `sniff` has named a file whose content does not match it. One module per
//! format: `toml` (prism's own), `nff` (NFF/SPD), `gltf` (glTF 2.0 and GLB), and the mesh
//! files `obj` (with MTL) and `ply`, which `mesh_file` turns into parts of a scene or, with
//! `framing`, into a scene of their own; `faces` cuts their polygons into triangles.

mod faces;
mod framing;
mod gltf;
mod load;
pub mod mesh_file;
pub mod nff;
pub mod obj;
pub mod ply;
mod sniff;
mod toml;

/// Parses the bytes of a .gltf or .glb file; the path names it in errors and anchors the
/// relative URIs of its buffers and images.
pub use self::gltf::parse as parse_gltf;
/// Parses TOML scene text; the path names it in errors and anchors relative file names.
pub use self::toml::parse as parse_toml;
pub use crate::source::LoadError;
pub use load::{load, load_listing_files, load_with};
pub use mesh_file::{load_mesh_file, load_mesh_file_with, mesh_scene, MeshFile, MeshPart};

use prism::Scene;
