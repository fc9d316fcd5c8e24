//! glTF 2.0 scenes (.gltf and .glb), read into prism's `Scene`. docs/formats.md ("glTF
//! 2.0") says what is read and how PBR materials and physical lights become Whitted ones.
//!
//! The steps: split a GLB container (`glb`); parse and validate the JSON (`document`);
//! load the buffers (`buffers`, `uri`); walk the default scene's nodes (`nodes`,
//! `transform`); decode each mesh once (`mesh`, `accessor`, with MikkTSpace tangents from
//! `tangents` where a normal map needs them) and place a copy per node;
//! map materials (`materials`, `images`); then the camera (`camera`) and lights (`lights`),
//! which both need the scene's bounds. The gltf crate parses and validates; reading
//! buffer data is done here, with every offset checked, so a hostile file cannot panic.

mod accessor;
mod buffers;
mod camera;
mod document;
mod dropped;
mod glb;
mod images;
mod lights;
mod materials;
mod mesh;
mod nodes;
mod tangents;
mod transform;
mod uri;

use super::Scene;
use crate::source::{LoadError, Reader};
use accessor::Accessors;
use gltf::json::Root;
use images::Images;
use std::collections::hash_map::Entry;
use std::collections::HashMap;
use std::path::Path;
use transform::Placement;

/// Reads a .gltf or .glb file, and its buffers and images, through `reader`. The content
/// decides which: GLB files start with "glTF".
pub(super) fn load(path: &Path, reader: &mut Reader) -> Result<Scene, LoadError> {
    let bytes = reader
        .read(path)
        .map_err(|e| LoadError::unreadable(path, e))?;
    parse_with(&bytes, path, reader)
}

/// Parses the bytes of a .gltf or .glb file. `path` names it in errors; buffers and images
/// with relative URIs are read from its folder, the document itself is not read again.
pub fn parse(bytes: &[u8], path: &Path) -> Result<Scene, LoadError> {
    parse_with(bytes, path, &mut Reader::new())
}

/// Parses the bytes of a .gltf or .glb file as `parse` does, reading buffers and images
/// through `reader`.
fn parse_with(bytes: &[u8], path: &Path, reader: &mut Reader) -> Result<Scene, LoadError> {
    let file = path.display().to_string();
    let invalid = |message: String| LoadError::Invalid {
        path: file.clone(),
        message,
    };
    let (json, bin, is_glb) = if glb::is_glb(bytes) {
        let g = glb::split(bytes).map_err(|m| invalid(format!("invalid GLB file: {m}")))?;
        (g.json, g.bin, true)
    } else {
        // JSON has no byte order mark, but editors on some systems write one.
        let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        (text, None, false)
    };
    let root = document::parse(json, path, is_glb)?;
    let base_dir = path.parent().unwrap_or(Path::new(""));
    let mut scene = build(&root, json.len(), bin, base_dir, reader).map_err(invalid)?;
    for w in &mut scene.warnings {
        *w = format!("{file}: {w}");
    }
    Ok(scene)
}

/// Nodes may place one mesh any number of times, and prism copies every placement: a
/// 100 KB file placing a strip of 40 000 triangles in 4 000 nodes would ask for 160 million
/// triangles (some 16 GB). The placed triangles may number at most this many per byte of
/// the JSON and buffers, which keeps memory proportional to the file's size while leaving
/// room for instancing.
const MAX_PLACED_TRIANGLES_PER_BYTE: usize = 64;

fn build(
    root: &Root,
    json_len: usize,
    bin: Option<&[u8]>,
    base_dir: &Path,
    reader: &mut Reader,
) -> Result<Scene, String> {
    let buffers = buffers::load(root, bin, base_dir, reader)?;
    let accessors = Accessors::new(root, &buffers);
    let mut images = Images::new(root, &buffers, base_dir, reader);
    let placed = nodes::walk(root)?;

    let mut decoded: HashMap<usize, Vec<mesh::Primitive>> = HashMap::new();
    let mut mesh_warnings = Vec::new();
    let mut placed_triangles = 0usize;
    for &(_, mesh_index, _) in &placed.meshes {
        let primitives = match decoded.entry(mesh_index) {
            Entry::Occupied(e) => e.into_mut(),
            Entry::Vacant(e) => e.insert(mesh::decode(
                root,
                &accessors,
                mesh_index,
                |m| materials::uv_set(root, m),
                &mut mesh_warnings,
            )?),
        };
        let triangles: usize = primitives.iter().map(mesh::Primitive::triangle_count).sum();
        placed_triangles = placed_triangles.saturating_add(triangles);
    }
    let data_len = buffers
        .iter()
        .fold(json_len, |n, b| n.saturating_add(b.len()));
    let budget = data_len.saturating_mul(MAX_PLACED_TRIANGLES_PER_BYTE);
    if placed_triangles > budget {
        return Err(format!(
            "the nodes place {placed_triangles} triangles in all, more than prism accepts from \
             {data_len} bytes of JSON and buffers ({MAX_PLACED_TRIANGLES_PER_BYTE} per byte): \
             expected fewer nodes placing large meshes"
        ));
    }

    let mut scene = Scene {
        warnings: mesh_warnings,
        ..Scene::default()
    };
    let mut material_ids: HashMap<Option<usize>, u32> = HashMap::new();
    for &(node, mesh_index, world) in &placed.meshes {
        // Every placed mesh was decoded above.
        let Some(primitives) = decoded.get(&mesh_index) else {
            continue;
        };
        let at = Placement::new(world);
        for primitive in primitives.iter() {
            if primitive.is_empty() {
                continue;
            }
            let material = match material_ids.get(&primitive.material) {
                Some(&id) => id,
                None => {
                    let m = materials::material(
                        root,
                        &mut images,
                        primitive.material,
                        &mut scene.warnings,
                    )?;
                    let id = scene.add_material(m);
                    material_ids.insert(primitive.material, id);
                    id
                }
            };
            let mesh = primitive
                .place(&at)
                .map_err(|e| format!("mesh {mesh_index} placed by node {node}: {e}"))?;
            scene.geometry.add_mesh(mesh, material);
        }
    }

    let bounds = scene.geometry.world_bounds();
    scene.camera = camera::camera(root, placed.camera, bounds, &mut scene.options)?;

    scene.lights = lights::lights(root, &placed.lights, bounds)?;
    if scene.lights.is_empty() {
        scene.lights.push(lights::default_light(&scene.camera));
    }
    scene.validate().map_err(|e| e.to_string())?;
    scene.warnings.extend(dropped::warning(root));
    Ok(scene)
}
