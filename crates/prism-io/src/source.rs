//! Where a load's bytes come from: `LoadError`, why a scene file could not be loaded, and
//! `Reader`, through which every loader reads the files it needs (the scene file, included
//! meshes, MTL libraries, glTF buffers, image textures) and which lists them afterwards.
//! The bottom of the crate: it imports no other module of it.

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

impl LoadError {
    /// The file a loader was given could not be read.
    pub(crate) fn unreadable(path: &Path, e: std::io::Error) -> LoadError {
        LoadError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        }
    }
}

/// Reads the files of one load and remembers each one it read (or tried to), in the order
/// first asked for, each once. A load is handed one and passes it on to every part that
/// reads a file, so what a load read is known without any state beside it.
#[derive(Debug, Default)]
pub struct Reader {
    files: Vec<PathBuf>,
}

impl Reader {
    /// A reader that has read nothing yet.
    pub fn new() -> Reader {
        Reader::default()
    }

    /// Every file read so far (or tried), the first first.
    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    /// The files read, as `files` lists them.
    pub fn into_files(self) -> Vec<PathBuf> {
        self.files
    }

    /// Reads the whole file at `path`.
    pub fn read(&mut self, path: &Path) -> std::io::Result<Vec<u8>> {
        self.note(path);
        std::fs::read(path)
    }

    /// Reads the whole file at `path` as UTF-8 text.
    pub fn read_to_string(&mut self, path: &Path) -> std::io::Result<String> {
        self.note(path);
        std::fs::read_to_string(path)
    }

    /// Reads a file that a scene file names (a glTF buffer or image, an MTL library). Only
    /// regular files are read: a name such as "/dev/zero" or a pipe would be read until
    /// memory runs out, or forever.
    pub fn read_regular_file(&mut self, path: &Path) -> std::io::Result<Vec<u8>> {
        self.note(path);
        if !std::fs::metadata(path)?.is_file() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "not a regular file",
            ));
        }
        std::fs::read(path)
    }

    /// Notes that the load is about to read `path`.
    fn note(&mut self, path: &Path) {
        if !self.files.iter().any(|f| f == path) {
            self.files.push(path.to_path_buf());
        }
    }
}
