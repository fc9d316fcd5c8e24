//! Wavefront OBJ files with their MTL material libraries, read through the tobj crate.
//!
//! `scan` checks the OBJ text first (tobj's errors carry no position) and hands tobj a
//! plain rewrite of it; `mtl` does the same for each library, and `material` maps MTL
//! materials onto prism's. tobj then groups the faces by object, group and material and
//! gives each group one index per distinct (position, uv, normal) corner; faces of more
//! than three corners are triangulated here, not by tobj, whose fans are wrong for concave
//! faces. docs/formats.md describes what is read.

mod material;
mod mtl;
mod scan;

use super::faces;
use super::mesh_file::{Materials, MeshFile, MeshPart};
use crate::source::{LoadError, Reader};
use mtl::{Library, TextureCache};
use prism::geometry::TriangleMesh;
use prism::math::{Vec2, Vec3};
use std::path::Path;

/// Reads the OBJ file at `path` and, unless told to ignore them, its material libraries,
/// through `reader`.
pub fn load(path: &Path, materials: Materials, reader: &mut Reader) -> Result<MeshFile, LoadError> {
    let bytes = reader
        .read(path)
        .map_err(|e| LoadError::unreadable(path, e))?;
    // Some exporters write comments or names in Latin-1; numbers are ASCII either way.
    parse_with(&String::from_utf8_lossy(&bytes), path, materials, reader)
}

/// Reads OBJ text; `path` names it in errors and anchors material libraries.
pub fn parse(text: &str, path: &Path, materials: Materials) -> Result<MeshFile, LoadError> {
    parse_with(text, path, materials, &mut Reader::new())
}

/// Reads OBJ text as `parse` does, its libraries and their images through `reader`.
fn parse_with(
    text: &str,
    path: &Path,
    materials: Materials,
    reader: &mut Reader,
) -> Result<MeshFile, LoadError> {
    let name = path.display().to_string();
    let mut opener = LibraryOpener {
        obj_path: &name,
        dir: path.parent().unwrap_or(Path::new("")),
        reader,
        libraries: Vec::new(),
        textures: TextureCache::new(),
        warnings: Vec::new(),
        missing_library: false,
    };
    let checked = match materials {
        Materials::Read => scan::check(text, &name, Some(&mut opener))?,
        Materials::Ignore => scan::check(text, &name, None)?,
    };
    let libraries = opener.libraries;
    let mut warnings = opener.warnings;
    if !checked.skipped.is_empty() {
        warnings.push(format!(
            "{name}: read but not rendered: {}",
            checked.skipped.join("; ")
        ));
    }

    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: false,
        ignore_points: true,
        ignore_lines: true,
    };
    // After the scan, `mtllib` lines name libraries by their number in `libraries`.
    let (models, tobj_materials) =
        tobj::load_obj_buf(&mut checked.text.as_bytes(), &options, |key| {
            key.to_str()
                .and_then(|k| k.parse::<usize>().ok())
                .and_then(|k| libraries.get(k))
                .map(|l| l.tobj.clone())
                .ok_or(tobj::LoadError::OpenFileFailed)
        })
        .map_err(|e| tobj_failed(&name, e))?;
    let tobj_count = tobj_materials.map_err(|e| tobj_failed(&name, e))?.len();

    let mut file = MeshFile {
        parts: Vec::new(),
        defined_vertices: checked.positions,
        materials: libraries.into_iter().flat_map(|l| l.materials).collect(),
        warnings,
    };
    if tobj_count != file.materials.len() {
        return Err(tobj_failed(&name, tobj::LoadError::MaterialParseError));
    }
    for model in models {
        if let Some(part) = part(&model, &name, &mut file.warnings)? {
            file.parts.push(part);
        }
    }
    Ok(file)
}

/// Reads MTL library text on its own: the materials it defines, in order. `path` names it
/// in errors and anchors its image files.
pub fn parse_mtl(text: &str, path: &Path) -> Result<Vec<prism::shading::Material>, LoadError> {
    let mut reader = Reader::new();
    mtl::parse(text, path, &mut TextureCache::new(), &mut reader).map(|library| library.materials)
}

fn tobj_failed(path: &str, e: tobj::LoadError) -> LoadError {
    LoadError::Invalid {
        path: path.to_string(),
        message: format!(
            "the OBJ reader (tobj) failed with '{e}' where prism's own checks found nothing \
             wrong (tobj gives no line)"
        ),
    }
}

/// Opens the libraries of `mtllib` lines for the scan and keeps them for tobj.
struct LibraryOpener<'a> {
    obj_path: &'a str,
    dir: &'a Path,
    reader: &'a mut Reader,
    libraries: Vec<Library>,
    textures: TextureCache,
    /// Libraries that are not there (downloaded models often come without theirs) and
    /// statements the libraries hold that prism does not render.
    warnings: Vec<String>,
    missing_library: bool,
}

impl scan::Libraries for LibraryOpener<'_> {
    fn open(
        &mut self,
        names: &str,
        line: usize,
        column: usize,
    ) -> Result<(usize, Vec<String>), LoadError> {
        // One name with spaces, or (as the OBJ specification has it) several names.
        let whole = names.replace('\\', "/");
        let files: Vec<String> = if self.dir.join(&whole).is_file() {
            vec![whole]
        } else {
            whole.split_whitespace().map(str::to_string).collect()
        };
        let mut library = Library::default();
        for file in files {
            let path = self.dir.join(&file);
            if !path.exists() {
                // As other viewers do: render with the default material, and say so.
                self.warnings.push(format!(
                    "{}:{line}:{column}: the material library {} is missing; faces that use \
                     its materials get the default material",
                    self.obj_path,
                    path.display()
                ));
                self.missing_library = true;
                continue;
            }
            let parsed = mtl::load(&path, &mut self.textures, self.reader).map_err(|e| {
                LoadError::Syntax {
                    path: self.obj_path.to_string(),
                    line,
                    column,
                    message: format!(
                        "cannot read the material library {}: {e}; expected an MTL file beside \
                         the OBJ file (or, from a TOML scene, give the mesh a material to \
                         ignore the library)",
                        path.display()
                    ),
                }
            })?;
            library.append(parsed?);
        }
        self.warnings.append(&mut library.warnings);
        let names = library.names();
        self.libraries.push(library);
        Ok((self.libraries.len() - 1, names))
    }

    fn missing(&self) -> bool {
        self.missing_library
    }
}

/// A tobj model (one object, group and material) as a mesh; `None` when it has no faces,
/// or (with a warning) when every face has zero area.
fn part(
    model: &tobj::Model,
    path: &str,
    warnings: &mut Vec<String>,
) -> Result<Option<MeshPart>, LoadError> {
    let m = &model.mesh;
    if m.indices.is_empty() {
        return Ok(None);
    }
    let positions: Vec<Vec3> = m
        .positions
        .chunks_exact(3)
        .map(|p| Vec3::new(p[0], p[1], p[2]))
        .collect();
    let count = positions.len();
    // A group whose faces give normals (or uvs) for some corners only has them for some
    // vertices only, with no way to tell which: it is shaded flat (or left without uvs).
    let normals = (m.normals.len() == 3 * count).then(|| {
        m.normals
            .chunks_exact(3)
            .map(|n| Vec3::new(n[0], n[1], n[2]))
            .collect()
    });
    let uvs = (m.texcoords.len() == 2 * count).then(|| {
        m.texcoords
            .chunks_exact(2)
            .map(|t| Vec2::new(t[0], t[1]))
            .collect()
    });

    let invalid = |message: String| LoadError::Invalid {
        path: path.to_string(),
        message: format!("object '{}': {message}", model.name),
    };
    if let Some(&bad) = m.indices.iter().find(|&&i| i as usize >= count) {
        return Err(invalid(format!(
            "tobj gave vertex index {bad} for {count} vertices"
        )));
    }
    let mut triangles = Vec::with_capacity(m.indices.len() / 3);
    if m.face_arities.is_empty() {
        triangles.extend(m.indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]));
    } else {
        let mut scratch = Vec::new();
        let mut start = 0usize;
        for (face, &arity) in m.face_arities.iter().enumerate() {
            let corners = m
                .indices
                .get(start..start + arity as usize)
                .ok_or_else(|| invalid(format!("face {face} runs past the index list")))?;
            faces::triangulate(&positions, corners, &mut triangles, &mut scratch)
                .map_err(|e| invalid(format!("face {face} (counting from 0): {e}")))?;
            start += arity as usize;
        }
    }
    if !faces::any_with_area(&positions, &triangles) {
        let faces = match m.face_arities.len() {
            0 => m.indices.len() / 3,
            n => n,
        };
        warnings.push(format!(
            "{path}: object '{}' has only faces of zero area ({faces}); it is left out",
            model.name
        ));
        return Ok(None);
    }
    let mesh = TriangleMesh::new(positions, triangles, normals, uvs)
        .map_err(|e| invalid(e.to_string()))?;
    Ok(Some(MeshPart {
        mesh,
        material: m.material_id,
    }))
}
