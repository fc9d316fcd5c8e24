//! Mesh files included from a scene: an object `type = "mesh"` with `file = "…"` (OBJ or
//! PLY, relative to the scene file), placed by the mesh `transform`, in the object's
//! material or else the file's own materials.

use super::diagnostics::Problem;
use super::mesh::Transform;
use super::schema::MeshDef;
use crate::scene::mesh_file::{extension, load_mesh_file_with, Materials, MESH_EXTENSIONS};
use crate::source::Reader;
use prism::scene::Scene;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

/// Adds the meshes of the file named by `def` (whose table starts at `span`). `material`
/// is the object's own; without it the file's materials apply, and faces the file gives no
/// material get `default(scene)`. The file is read through `reader`.
#[allow(clippy::too_many_arguments)]
pub(super) fn add_mesh_file(
    scene: &mut Scene,
    def: MeshDef,
    file: Spanned<String>,
    span: Range<usize>,
    base_dir: &Path,
    material: Option<u32>,
    default: &mut dyn FnMut(&mut Scene) -> u32,
    reader: &mut Reader,
) -> Result<(), Problem> {
    if def.positions.is_some()
        || def.indices.is_some()
        || def.normals.is_some()
        || def.uvs.is_some()
    {
        return Err(Problem::at(
            file.span(),
            "a mesh takes either `file` or `positions`, `indices`, `normals` and `uvs`, not both",
        ));
    }
    let path = base_dir.join(file.get_ref());
    if !MESH_EXTENSIONS.contains(&extension(&path).as_str()) {
        return Err(Problem::at(
            file.span(),
            format!(
                "expected a mesh file ending in .obj or .ply, found \"{}\"",
                file.get_ref()
            ),
        ));
    }
    let materials = match material {
        Some(_) => Materials::Ignore,
        None => Materials::Read,
    };
    let loaded = load_mesh_file_with(&path, materials, reader)
        .map_err(|e| Problem::at(file.span(), format!("cannot load the mesh file: {e}")))?;

    scene.warnings.extend(loaded.warnings);
    let offset = scene.materials.len() as u32;
    if loaded.parts.iter().any(|p| p.material.is_some()) {
        scene.materials.extend(loaded.materials);
    }
    let transform = def.transform.as_ref().map(Transform::new);
    for part in loaded.parts {
        let mut mesh = part.mesh;
        if let Some(t) = &transform {
            t.apply(&mut mesh)
                .map_err(|m| Problem::at(span.clone(), format!("{}: {m}", file.get_ref())))?;
        }
        let material = match (material, part.material) {
            (Some(m), _) => m,
            (None, Some(own)) => offset + own as u32,
            (None, None) => default(scene),
        };
        scene.geometry.add_mesh(mesh, material);
    }
    Ok(())
}
