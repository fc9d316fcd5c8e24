//! Reading scene files. The extension picks the loader; a mesh file (.obj, .ply) on its
//! own becomes a scene with a camera and a light that frame it.

use super::Scene;
use std::cell::RefCell;
use std::path::{Path, PathBuf};

/// Why a scene file could not be loaded; every variant names the file, and syntax errors the line
/// and column.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file (or one it names) could not be read.
    #[error("cannot read {path}: {message}")]
    Io {
        /// The file that could not be read.
        path: String,
        /// Why, as the system said it.
        message: String,
    },
    /// The extension names no format prism reads.
    #[error(
        "{path}: unknown scene format '{ext}'; prism reads .toml, .nff, .gltf and .glb scenes \
         and .obj and .ply meshes"
    )]
    UnknownFormat {
        /// The file.
        path: String,
        /// Its extension, in lower case.
        ext: String,
    },
    /// A parse or validation error that names the file, line and column.
    #[error("{path}:{line}:{column}: {message}")]
    Syntax {
        /// The file.
        path: String,
        /// Line, from 1.
        line: usize,
        /// Column, from 1, in characters.
        column: usize,
        /// What is wrong there.
        message: String,
    },
    /// A problem with the scene as a whole (no single place in the file).
    #[error("{path}: {message}")]
    Invalid {
        /// The file.
        path: String,
        /// What is wrong with it.
        message: String,
    },
}

/// Loads a scene file, choosing the format by extension.
pub fn load(path: &Path) -> Result<Scene, LoadError> {
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
        "toml" => super::toml::load(path),
        "nff" => super::nff::load(path),
        "gltf" | "glb" => super::gltf::load(path),
        "obj" | "ply" => super::mesh_file::load_scene(path),
        _ => Err(LoadError::UnknownFormat {
            path: path.display().to_string(),
            ext,
        }),
    }
}

/// Reads a file that a scene file names (a glTF buffer or image, an MTL library). Only
/// regular files are read: a name such as "/dev/zero" or a pipe would be read until memory
/// runs out, or forever.
pub(crate) fn read_regular_file(path: &Path) -> std::io::Result<Vec<u8>> {
    note_read(path);
    if !std::fs::metadata(path)?.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file",
        ));
    }
    std::fs::read(path)
}

thread_local! {
    /// The files this thread's `load_listing_files` has read so far; None when no such
    /// load runs. Loading runs on the calling thread alone, so a thread-local sees it all.
    static FILES_READ: RefCell<Option<Vec<PathBuf>>> = const { RefCell::new(None) };
}

/// Notes that a load is about to read `path` (a scene file, an included mesh, an MTL
/// library, a glTF buffer, a texture), for `load_listing_files`.
pub(crate) fn note_read(path: &Path) {
    FILES_READ.with(|files| {
        if let Some(files) = files.borrow_mut().as_mut() {
            if !files.iter().any(|f| f == path) {
                files.push(path.to_path_buf());
            }
        }
    });
}

/// Loads a scene file as `load` does and lists every file the load read (or tried to),
/// the scene file first, as paths joined onto `path`'s folder. A scene is then shipped
/// with its meshes, textures and libraries to machines that do not share this one's file
/// system (prism's Python package does that for Dask workers).
pub fn load_listing_files(path: &Path) -> (Result<Scene, LoadError>, Vec<PathBuf>) {
    let outer = FILES_READ.with(|files| files.replace(Some(Vec::new())));
    let scene = load(path);
    let read = FILES_READ
        .with(|files| files.replace(outer))
        .unwrap_or_default();
    (scene, read)
}
