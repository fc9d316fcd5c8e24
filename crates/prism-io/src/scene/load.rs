//! Reading scene files. The extension picks the loader; a mesh file (.obj, .ply) on its
//! own becomes a scene with a camera and a light that frame it.

use super::Scene;
use crate::source::{LoadError, Reader};
use std::path::{Path, PathBuf};

/// Loads a scene file, choosing the format by extension.
pub fn load(path: &Path) -> Result<Scene, LoadError> {
    load_with(path, &mut Reader::new())
}

/// Loads a scene file as `load` does, reading every file through `reader`, which then
/// lists them.
pub fn load_with(path: &Path, reader: &mut Reader) -> Result<Scene, LoadError> {
    if path.is_dir() {
        return Err(LoadError::Io {
            path: path.display().to_string(),
            message: "it is a directory, not a scene file".into(),
        });
    }
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if let Some(message) = super::sniff::mismatch(path, &ext) {
        return Err(LoadError::Invalid {
            path: path.display().to_string(),
            message,
        });
    }
    match ext.as_str() {
        "toml" => super::toml::load(path, reader),
        "nff" => super::nff::load(path, reader),
        "gltf" | "glb" => super::gltf::load(path, reader),
        "obj" | "ply" => super::mesh_file::load_scene(path, reader),
        _ => Err(LoadError::UnknownFormat {
            path: path.display().to_string(),
            ext,
        }),
    }
}

/// Loads a scene file as `load` does and lists every file the load read (or tried to),
/// the scene file first, as paths joined onto `path`'s folder. A scene is then shipped
/// with its meshes, textures and libraries to machines that do not share this one's file
/// system (prism's Python package does that for Dask workers).
pub fn load_listing_files(path: &Path) -> (Result<Scene, LoadError>, Vec<PathBuf>) {
    let mut reader = Reader::new();
    let scene = load_with(path, &mut reader);
    (scene, reader.into_files())
}
