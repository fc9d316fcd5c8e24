//! The glTF JSON document: parsed by serde (syntax errors keep their line and column) and
//! validated by the gltf crate, whose terse findings ("Index out of bounds" at a JSON path)
//! are reworded here to say what the path refers to and what exists.

use crate::source::LoadError;
use gltf::json::mesh::Semantic;
use gltf::json::validation::{Checked, Error as Finding, Validate};
use gltf::json::Root;
use serde_json::Value;
use std::path::Path;

/// At most this many validation findings are listed in one error.
const MAX_FINDINGS: usize = 5;

/// Parses and validates the JSON text of a .gltf file or of a .glb's JSON chunk.
pub(super) fn parse(json: &[u8], path: &Path, in_glb: bool) -> Result<Root, LoadError> {
    let file = path.display().to_string();
    let root = Root::from_slice(json).map_err(|e| {
        let message = without_position(&e.to_string(), e.line(), e.column());
        let message = if in_glb {
            format!("in the GLB's JSON chunk: {message}")
        } else {
            message
        };
        if e.line() == 0 {
            LoadError::Invalid {
                path: file.clone(),
                message,
            }
        } else {
            LoadError::Syntax {
                path: file.clone(),
                line: e.line(),
                // serde_json counts 0 for an error right after a line break.
                column: e.column().max(1),
                message,
            }
        }
    })?;

    let mut findings = position_references_out_of_range(&root);
    if findings.is_empty() {
        root.validate(&root, gltf::json::Path::new, &mut |p, finding| {
            let p = p().to_string();
            // The specification requires POSITION accessors to state min and max, for
            // viewers to frame the model. Prism computes bounds itself; hand-written files
            // often leave them out.
            let bounds = p.ends_with(".min") || p.ends_with(".max");
            if !(bounds && finding == Finding::Missing) {
                findings.push((p, finding))
            }
        });
    }
    if findings.is_empty() {
        return Ok(root);
    }
    // The text parsed once already; read it again as plain JSON to quote offending values.
    let tree: Value = serde_json::from_slice(json).unwrap_or(Value::Null);
    let mut lines: Vec<String> = findings
        .iter()
        .take(MAX_FINDINGS)
        .map(|(p, finding)| describe(p, *finding, &tree, &root))
        .collect();
    if findings.len() > MAX_FINDINGS {
        lines.push(format!(
            "and {} more problems",
            findings.len() - MAX_FINDINGS
        ));
    }
    Err(LoadError::Invalid {
        path: file,
        message: format!("invalid glTF: {}", lines.join("; ")),
    })
}

/// POSITION attributes that name a missing accessor. gltf-json 1.4's validator indexes
/// the accessor array with them unchecked (it panics), so they are looked for first and
/// the crate's validation runs only on documents without them.
fn position_references_out_of_range(root: &Root) -> Vec<(String, Finding)> {
    let position = Checked::Valid(Semantic::Positions);
    let mut findings = Vec::new();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            if let Some(a) = primitive.attributes.get(&position) {
                if a.value() >= root.accessors.len() {
                    findings.push((
                        format!("meshes[{m}].primitives[{p}].attributes[\"POSITION\"]"),
                        Finding::IndexOutOfBounds,
                    ));
                }
            }
        }
    }
    findings
}

/// serde_json appends " at line L column C"; the error already carries both.
fn without_position(message: &str, line: usize, column: usize) -> String {
    let suffix = format!(" at line {line} column {column}");
    message.strip_suffix(&suffix).unwrap_or(message).to_string()
}

fn describe(path: &str, finding: Finding, tree: &Value, root: &Root) -> String {
    let value = lookup(tree, path);
    match finding {
        Finding::IndexOutOfBounds => {
            let quoted = value.map_or_else(|| "an index".to_string(), |v| v.to_string());
            match collection(path, root) {
                Some((name, count)) => format!(
                    "{path} refers to {name} {quoted}, but the file has {count} {name}s \
                     (expected an index from 0 to {})",
                    count as i64 - 1
                ),
                None => format!("{path} = {quoted} refers to something that does not exist"),
            }
        }
        Finding::Invalid => match value {
            Some(v) => format!("{path} = {v} is not a valid value"),
            None => format!("{path} is not valid"),
        },
        Finding::Missing => format!("{path} is required but missing"),
        Finding::Oversize => format!("{path} is larger than this machine can address"),
        Finding::Unsupported => format!(
            "the file requires the extension {}, which prism does not support (it reads \
             KHR_lights_punctual, KHR_materials_transmission, KHR_materials_ior and \
             KHR_materials_emissive_strength)",
            value.map_or_else(|| path.to_string(), |v| v.to_string())
        ),
    }
}

/// Which top-level array an out-of-range index at `path` points into, and its length.
fn collection(path: &str, root: &Root) -> Option<(&'static str, usize)> {
    let last = path.rsplit('.').next()?;
    let parent = path.rsplit('.').nth(1).unwrap_or("");
    let field = last.split('[').next()?;
    let lights = root
        .extensions
        .as_ref()
        .and_then(|e| e.khr_lights_punctual.as_ref())
        .map_or(0, |l| l.lights.len());
    Some(match field {
        "indices"
        | "attributes"
        | "POSITION"
        | "NORMAL"
        | "TANGENT"
        | "inverseBindMatrices"
        | "input"
        | "output" => ("accessor", root.accessors.len()),
        "bufferView" => ("bufferView", root.buffer_views.len()),
        "buffer" => ("buffer", root.buffers.len()),
        "mesh" => ("mesh", root.meshes.len()),
        "material" => ("material", root.materials.len()),
        "camera" => ("camera", root.cameras.len()),
        "children" | "nodes" | "node" | "skeleton" | "joints" => ("node", root.nodes.len()),
        "scene" => ("scene", root.scenes.len()),
        "skin" => ("skin", root.skins.len()),
        "source" => ("image", root.images.len()),
        "sampler" if parent.starts_with("textures") => ("sampler", root.samplers.len()),
        "index" => ("texture", root.textures.len()),
        "light" => ("light", lights),
        _ => return None,
    })
}

/// Follows a validation path such as `meshes[0].primitives[1].attributes["POSITION"]`.
fn lookup<'v>(tree: &'v Value, path: &str) -> Option<&'v Value> {
    let mut node = tree;
    let mut rest = path;
    while !rest.is_empty() {
        rest = rest.strip_prefix('.').unwrap_or(rest);
        if let Some(inner) = rest.strip_prefix('[') {
            let end = inner.find(']')?;
            let key = &inner[..end];
            node = match key.strip_prefix('"').and_then(|k| k.strip_suffix('"')) {
                Some(name) => node.get(name)?,
                None => node.get(key.parse::<usize>().ok()?)?,
            };
            rest = &inner[end + 1..];
        } else {
            let end = rest.find(['.', '[']).unwrap_or(rest.len());
            node = node.get(&rest[..end])?;
            rest = &rest[end..];
        }
    }
    Some(node)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lookup_follows_fields_indices_and_keys() {
        let tree: Value =
            serde_json::from_str(r#"{"meshes":[{"primitives":[{"attributes":{"POSITION":7}}]}]}"#)
                .unwrap();
        assert_eq!(
            lookup(&tree, r#"meshes[0].primitives[0].attributes["POSITION"]"#),
            Some(&Value::from(7))
        );
        assert_eq!(lookup(&tree, "meshes[1]"), None);
    }
}
