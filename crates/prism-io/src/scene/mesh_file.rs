//! Mesh files (Wavefront OBJ with its MTL materials, Stanford PLY): what a file holds as
//! meshes and materials, and a mesh file on its own turned into a scene with a camera and a
//! light (`prism render bunny.obj`). docs/formats.md describes both formats.

use super::{framing, obj, ply, Scene};
use crate::source::{LoadError, Reader};
use prism::geometry::TriangleMesh;
use prism::shading::Material;
use std::path::Path;

/// One mesh of a file with the material its faces use.
#[derive(Clone, Debug)]
pub struct MeshPart {
    /// The triangles.
    pub mesh: TriangleMesh,
    /// An index into `MeshFile::materials`; `None` when the file gives the faces none.
    pub material: Option<usize>,
}

/// Everything read from a mesh file.
#[derive(Clone, Debug, Default)]
pub struct MeshFile {
    /// The meshes, one per material the faces use.
    pub parts: Vec<MeshPart>,
    /// The materials the file's libraries define (OBJ's MTL), indexed by `MeshPart::material`.
    pub materials: Vec<Material>,
    /// Vertices the file defines. The parts keep only those that faces use (and an OBJ
    /// vertex once per distinct uv and normal it is used with), so this may differ from
    /// `vertex_count`.
    pub defined_vertices: usize,
    /// What was read but could not be used (see `Scene::warnings`).
    pub warnings: Vec<String>,
}

/// Whether to read the materials a mesh file refers to (OBJ's `mtllib` and `usemtl`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Materials {
    /// Read the material libraries the file names.
    Read,
    /// The caller supplies a material: material libraries are not even opened.
    Ignore,
}

impl MeshFile {
    /// Triangles over all parts.
    pub fn triangle_count(&self) -> usize {
        self.parts.iter().map(|p| p.mesh.triangle_count()).sum()
    }

    /// Vertices over all parts, as the meshes hold them.
    pub fn vertex_count(&self) -> usize {
        self.parts.iter().map(|p| p.mesh.vertex_count()).sum()
    }
}

/// The extensions `load_mesh_file` reads, for messages.
pub const MESH_EXTENSIONS: &[&str] = &["obj", "ply"];

/// Reads an OBJ or PLY file (chosen by extension). A file without faces is an error.
pub fn load_mesh_file(path: &Path, materials: Materials) -> Result<MeshFile, LoadError> {
    load_mesh_file_with(path, materials, &mut Reader::new())
}

/// Reads an OBJ or PLY file as `load_mesh_file` does, through `reader`.
pub fn load_mesh_file_with(
    path: &Path,
    materials: Materials,
    reader: &mut Reader,
) -> Result<MeshFile, LoadError> {
    let ext = extension(path);
    if let Some(message) = super::sniff::mismatch(path, &ext) {
        return Err(LoadError::Invalid {
            path: path.display().to_string(),
            message,
        });
    }
    let file = match ext.as_str() {
        "obj" => obj::load(path, materials, reader)?,
        "ply" => ply::load(path, reader)?,
        ext => {
            return Err(LoadError::UnknownFormat {
                path: path.display().to_string(),
                ext: ext.to_string(),
            })
        }
    };
    if file.triangle_count() == 0 {
        return Err(LoadError::Invalid {
            path: path.display().to_string(),
            message: "the file holds no faces (or only faces of zero area); expected at least one \
                      polygon"
                .into(),
        });
    }
    Ok(file)
}

/// A mesh file as a whole scene: its meshes and materials, faces without a material in
/// prism's default one, and a camera and light that frame the mesh; files are read through
/// `reader`.
pub fn load_scene(path: &Path, reader: &mut Reader) -> Result<Scene, LoadError> {
    mesh_scene(load_mesh_file_with(path, Materials::Read, reader)?, path)
}

/// A mesh file already read (from `path`, which names it in errors) as a whole scene, as
/// `load_scene` makes it.
pub fn mesh_scene(file: MeshFile, path: &Path) -> Result<Scene, LoadError> {
    let mut scene = Scene {
        materials: file.materials,
        warnings: file.warnings,
        ..Scene::default()
    };
    let mut default = None;
    for part in file.parts {
        let material = match part.material {
            Some(m) => m as u32,
            None => *default.get_or_insert_with(|| scene.add_material(Material::default())),
        };
        scene.geometry.add_mesh(part.mesh, material);
    }
    framing::frame(&mut scene).map_err(|message| LoadError::Invalid {
        path: path.display().to_string(),
        message,
    })?;
    Ok(scene)
}

/// The lower-case extension of `path` ("" when it has none), which picks the mesh format.
pub fn extension(path: &Path) -> String {
    path.extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase()
}
