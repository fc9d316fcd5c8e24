//! `[materials.NAME]` tables to `Material`s: defaults from `Material::default()`, textures
//! (solid, checker, image files relative to the scene file).

use super::diagnostics::Problem;
use super::schema::{CheckerSpaceDef, MaterialDef, TextureDef};
use crate::source::Reader;
use prism::shading::{Checker, CheckerSpace, Material, Texture};
use std::path::Path;
use toml::Spanned;

/// Builds the material `name`; image paths are resolved against `base_dir` and read
/// through `reader`.
pub(super) fn material(
    name: &str,
    def: MaterialDef,
    base_dir: &Path,
    reader: &mut Reader,
    notes: &mut super::Notes,
) -> Result<Material, Problem> {
    let d = Material::default();
    let color = match (def.color, def.texture) {
        (Some(_), Some(t)) => {
            return Err(Problem::at(
                t.span(),
                "a material takes either `color` or `texture`, not both",
            ))
        }
        (Some(c), None) => Texture::Solid(c.0),
        (None, Some(t)) => texture(t, base_dir, reader, notes)?,
        (None, None) => d.color,
    };
    Ok(Material {
        name: name.to_string(),
        color,
        ambient: def.ambient.map_or(d.ambient, |v| v.0),
        diffuse: def.diffuse.map_or(d.diffuse, |v| v.0),
        specular: def.specular.map_or(d.specular, |v| v.0),
        shininess: def.shininess.map_or(d.shininess, |v| v.0),
        highlight: def.highlight.unwrap_or(d.highlight),
        reflect: def.reflect.map_or(d.reflect, |v| v.0),
        transmit: def.transmit.map_or(d.transmit, |c| c.0),
        ior: def.ior.map_or(d.ior, |v| v.0),
        fresnel: def.fresnel.unwrap_or(d.fresnel),
        emission: def.emission.map_or(d.emission, |c| c.0),
        normal_map: None,
        bump_map: None,
        occlusion: None,
        metal_rough: None,
        emission_map: None,
    })
}

fn texture(
    def: Spanned<TextureDef>,
    base_dir: &Path,
    reader: &mut Reader,
    notes: &mut super::Notes,
) -> Result<Texture, Problem> {
    Ok(match def.into_inner() {
        TextureDef::Solid(s) => Texture::Solid(s.color.0),
        TextureDef::Checker(c) => Texture::Checker(Checker {
            a: c.a.0,
            b: c.b.0,
            size: c.size.map_or(1.0, |s| s.0),
            space: match c.space {
                CheckerSpaceDef::Uv => CheckerSpace::Uv,
                CheckerSpaceDef::Solid => CheckerSpace::Solid,
            },
        }),
        TextureDef::Image(i) => {
            let file = base_dir.join(i.path.get_ref());
            if !file.exists() {
                // As a missing MTL library or map_Kd image: render without it, and say so.
                notes.push((
                    i.path.span(),
                    format!(
                        "the texture image {} is missing; the material keeps the default \
                         colour",
                        file.display()
                    ),
                ));
                return Ok(Material::default().color);
            }
            let mut image = crate::texture::load(&file, reader).map_err(|e| {
                Problem::at(
                    i.path.span(),
                    format!("expected a readable PNG or JPEG image: {e}"),
                )
            })?;
            if let Some(scale) = i.scale {
                image.scale = scale.0;
            }
            Texture::Image(image)
        }
    })
}
