//! Tagged tables: `{ type = "sphere", center = … }` is rewritten into the externally tagged
//! form `{ sphere = { center = … } }` before serde sees it, keeping every span, so the
//! derived enums check keys per type and errors still point into the file.

use super::diagnostics::Problem;
use super::schema::{LIGHT_TYPES, OBJECT_TYPES, TEXTURE_TYPES};
use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// Rewrites the tagged tables of a parsed scene: `objects`, `lights` and every
/// material's `texture`. Other values of the wrong shape are left for serde to report.
pub(super) fn retag_scene(root: &mut DeTable<'_>) -> Result<(), Problem> {
    if let Some(DeValue::Array(objects)) = root.get_mut("objects").map(Spanned::get_mut) {
        for object in objects.iter_mut() {
            retag(object, "an object", OBJECT_TYPES)?;
        }
    }
    if let Some(DeValue::Array(lights)) = root.get_mut("lights").map(Spanned::get_mut) {
        for light in lights.iter_mut() {
            retag(light, "a light", LIGHT_TYPES)?;
        }
    }
    if let Some(DeValue::Table(materials)) = root.get_mut("materials").map(Spanned::get_mut) {
        for (_, material) in materials.iter_mut() {
            if let DeValue::Table(material) = material.get_mut() {
                if let Some(texture) = material.get_mut("texture") {
                    retag(texture, "a texture", TEXTURE_TYPES)?;
                }
            }
        }
    }
    Ok(())
}

fn one_of(names: &[&str]) -> String {
    names
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

fn retag(item: &mut Spanned<DeValue<'_>>, what: &str, names: &[&str]) -> Result<(), Problem> {
    let span = item.span();
    let DeValue::Table(table) = item.get_mut() else {
        return Err(Problem::at(
            span,
            format!(
                "expected {what} as a table with a `type`, one of {}",
                one_of(names)
            ),
        ));
    };
    let Some(tag) = table.remove("type") else {
        return Err(Problem::at(
            span,
            format!(
                "{what} needs a `type`: expected type = one of {}",
                one_of(names)
            ),
        ));
    };
    let tag_span = tag.span();
    let DeValue::String(name) = tag.into_inner() else {
        return Err(Problem::at(
            tag_span,
            format!("expected `type` to be a string, one of {}", one_of(names)),
        ));
    };
    let body = std::mem::take(table);
    let mut outer = DeTable::new();
    outer.insert(
        Spanned::new(tag_span, name),
        Spanned::new(span.clone(), DeValue::Table(body)),
    );
    *item = Spanned::new(span, DeValue::Table(outer));
    Ok(())
}
