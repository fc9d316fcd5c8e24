//! The TOML scene format (docs/scene-format.md): reading a file into a `Scene`.
//!
//! Four steps: the toml crate parses the text into a tree that remembers byte spans;
//! `tagged` rewrites `type = "…"` tables so serde can check keys per type; serde fills the
//! `schema` structs, whose `values` types reject bad numbers on the spot; `build` below,
//! with `camera`, `lights`, `materials`, `objects`, `mesh` and `include` (mesh files),
//! checks what involves more than one value. Every problem carries a span, turned into a line
//! and column at the end (`diagnostics`).

mod camera;
mod diagnostics;
mod include;
mod lights;
mod materials;
mod mesh;
mod objects;
mod schema;
mod tagged;
mod values;

use super::Scene;
use crate::source::{LoadError, Reader};
use diagnostics::Problem;
use prism::shading::Material;
use schema::{ObjectDef, SceneDef};
use serde::Deserialize;
use std::collections::HashMap;
use std::path::Path;

/// Reads and parses the scene file at `path`, and the files it names, through `reader`.
pub(super) fn load(path: &Path, reader: &mut Reader) -> Result<Scene, LoadError> {
    let bytes = reader
        .read(path)
        .map_err(|e| LoadError::unreadable(path, e))?;
    let text = match String::from_utf8(bytes) {
        Ok(text) => text,
        Err(e) => {
            let valid = e.utf8_error().valid_up_to();
            // The valid prefix locates the bad byte; it is text, so lines count as usual.
            let prefix = String::from_utf8_lossy(&e.as_bytes()[..valid]).into_owned();
            let problem = Problem::at(
                valid..valid,
                "expected UTF-8 text (scene files are UTF-8 encoded)",
            );
            return Err(problem.into_load_error(path, &prefix));
        }
    };
    parse_with(&text, path, reader)
}

/// Parses scene text. `path` names the text in errors and anchors relative file names
/// (image textures); nothing is read from it but those.
pub fn parse(text: &str, path: &Path) -> Result<Scene, LoadError> {
    parse_with(text, path, &mut Reader::new())
}

/// Parses scene text as `parse` does, reading the files it names through `reader`.
fn parse_with(text: &str, path: &Path, reader: &mut Reader) -> Result<Scene, LoadError> {
    let base_dir = path.parent().unwrap_or(Path::new(""));
    let mut notes = Notes::new();
    let mut scene = parse_def(text)
        .and_then(|def| build(def, base_dir, reader, &mut notes))
        .map_err(|p| p.into_load_error(path, text))?;
    for (span, message) in notes {
        let (line, column) = diagnostics::line_column(text, span.start);
        scene
            .warnings
            .push(format!("{}:{line}:{column}: {message}", path.display()));
    }
    Ok(scene)
}

/// Warnings found while building, each at a span of the text, located once it is done.
type Notes = Vec<(std::ops::Range<usize>, String)>;

fn parse_def(text: &str) -> Result<SceneDef, Problem> {
    let mut root = toml::de::DeTable::parse(text).map_err(|e| Problem::from_toml(&e))?;
    tagged::retag_scene(root.get_mut())?;
    SceneDef::deserialize(toml::de::Deserializer::from(root)).map_err(|e| Problem::from_toml(&e))
}

fn build(
    def: SceneDef,
    base_dir: &Path,
    reader: &mut Reader,
    notes: &mut Notes,
) -> Result<Scene, Problem> {
    let mut scene = Scene::default();
    if let Some(render) = def.render {
        let span = render.span();
        let options = render.into_inner();
        options
            .validate()
            .map_err(|m| Problem::at(span, format!("invalid [render] option: {m}")))?;
        scene.options = options;
    }
    if let Some(camera) = def.camera {
        scene.camera = camera::camera(camera, scene.camera)?;
    }
    if let Some(c) = def.world.background {
        scene.background = c.0;
    }
    if let Some(c) = def.world.ambient {
        scene.ambient = c.0;
    }

    let mut material_index = HashMap::new();
    for (name, m) in def.materials {
        let m = materials::material(&name, m.into_inner(), base_dir, reader, notes)?;
        material_index.insert(name, scene.add_material(m));
    }
    let mut default_material = None;
    // Unnamed: the file's own "default" material if it has one, else the library's.
    let mut default = |scene: &mut Scene| match material_index.get("default") {
        Some(&m) => m,
        None => *default_material.get_or_insert_with(|| scene.add_material(Material::default())),
    };

    for light in def.lights {
        scene.lights.push(lights::light(light)?);
    }

    for object in def.objects {
        let span = object.span();
        let object = object.into_inner();
        let named = match object.material() {
            Some(name) => Some(*material_index.get(name.get_ref()).ok_or_else(|| {
                Problem::at(
                    name.span(),
                    unknown_material(name.get_ref(), &material_index),
                )
            })?),
            None => None,
        };
        // A mesh with a `file` is a mesh file's parts, not one inline mesh.
        let object = match object {
            ObjectDef::Mesh(mut mesh) => match mesh.file.take() {
                Some(file) => {
                    include::add_mesh_file(
                        &mut scene,
                        mesh,
                        file,
                        span,
                        base_dir,
                        named,
                        &mut default,
                        reader,
                    )?;
                    continue;
                }
                None => ObjectDef::Mesh(mesh),
            },
            other => other,
        };
        let material = match named {
            Some(m) => m,
            None => default(&mut scene),
        };
        objects::add_object(&mut scene.geometry, object, span, material)?;
    }

    scene.validate().map_err(|e| Problem {
        span: None,
        message: e.to_string(),
    })?;
    Ok(scene)
}

fn unknown_material(name: &str, known: &HashMap<String, u32>) -> String {
    let mut names: Vec<&str> = known.keys().map(String::as_str).collect();
    names.sort_unstable();
    if names.is_empty() {
        format!("unknown material \"{name}\": the file defines no [materials.NAME] tables")
    } else {
        format!(
            "unknown material \"{name}\": expected one of {}",
            names
                .iter()
                .map(|n| format!("\"{n}\""))
                .collect::<Vec<_>>()
                .join(", ")
        )
    }
}
