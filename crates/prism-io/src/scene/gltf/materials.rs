//! glTF's metallic-roughness materials as prism materials: the base colour as the diffuse
//! colour (a constant or a tinted image), the metallic, roughness, transmission and ior
//! inputs through the engine's mapping onto Whitted's coefficients (`prism::shading::Pbr`),
//! a metallicRoughnessTexture kept for the tracers to map per texel, the emissive factor
//! and texture, the normal and occlusion textures (docs/formats.md, "glTF 2.0").

use super::images::Images;
use gltf::json::Root;
use prism::math::Color;
use prism::shading::{Material, MetalRough, NormalMap, Pbr, Texture};

/// The material for `pbr`, emitting `emission`, its diffuse colour from `color` (which
/// already holds the base colour, as a constant or a tinted image).
fn whitted(name: String, pbr: &Pbr, emission: Color, color: Texture) -> Material {
    Material {
        name,
        color,
        ..Material::default()
    }
    .with_coefficients(pbr.coefficients(emission))
}

/// Builds prism's material for glTF material `index` (`None`: the default material).
pub(super) fn material(
    root: &Root,
    images: &mut Images,
    index: Option<usize>,
    warnings: &mut Vec<String>,
) -> Result<Material, String> {
    let Some(index) = index else {
        return Ok(whitted(
            "gltf default".into(),
            &Pbr::default(),
            Color::ZERO,
            Texture::Solid(Color::ONE),
        ));
    };
    let json = root.materials.get(index).ok_or_else(|| {
        format!(
            "material {index} does not exist (the file has {})",
            root.materials.len()
        )
    })?;
    let context = |e: String| format!("material {index}: {e}");
    let pbr_json = &json.pbr_metallic_roughness;
    let [r, g, b, _alpha] = pbr_json.base_color_factor.0;
    let mut pbr = Pbr {
        base: Color::new(r, g, b),
        metallic: pbr_json.metallic_factor.0,
        roughness: pbr_json.roughness_factor.0,
        ..Pbr::default()
    };
    let ext = json.extensions.as_ref();
    if let Some(t) = ext.and_then(|e| e.transmission.as_ref()) {
        pbr.transmission = t.transmission_factor.0;
    }
    if let Some(ior) = ext.and_then(|e| e.ior.as_ref()) {
        let v = ior.ior.0;
        // The extension's schema allows 0 (full reflection) besides values ≥ 1.
        if !(v == 0.0 || (v >= 1.0 && v.is_finite())) {
            return Err(context(format!(
                "KHR_materials_ior.ior is {v}; expected 0 or a number ≥ 1"
            )));
        }
        pbr.ior = v;
    }
    let scalars = [pbr.metallic, pbr.roughness, pbr.transmission];
    if !pbr.base.is_finite()
        || pbr.base.min_element() < 0.0
        || scalars.iter().any(|v| !v.is_finite())
    {
        return Err(context(
            "expected finite factors, and a baseColorFactor of numbers ≥ 0".into(),
        ));
    }

    // The tracers look the texture up per texel (blue = metallic, green = roughness, both
    // linear, times the factors); the material's own coefficients take its mean, for
    // what asks one value of a whole material (the beam tracer, shadow rays through it).
    let factors = pbr;
    let metallic_roughness = match &pbr_json.metallic_roughness_texture {
        Some(info) => image_or_warn(
            images,
            (index, info.index.value()),
            (
                "metallicRoughnessTexture",
                "keeps its metallic and roughness factors",
            ),
            warnings,
        )
        .map_err(context)?,
        None => None,
    };
    let metal_rough = metallic_roughness.map(|img| MetalRough {
        texture: crate::texture::from_linear(&img),
        factors,
    });
    if let Some(map) = &metal_rough {
        let mean = map.texture.mean();
        pbr.roughness *= mean.y;
        pbr.metallic *= mean.z;
    }
    // Emission per texel: emissiveFactor (times KHR_materials_emissive_strength) times the
    // emissiveTexture's colour, which is sRGB-encoded like a base colour.
    let mut emission = Color::from_array(json.emissive_factor.0);
    if let Some(strength) = ext.and_then(|e| e.emissive_strength.as_ref()) {
        let s = strength.emissive_strength.0;
        if !(s.is_finite() && s >= 0.0) {
            return Err(context(format!(
                "KHR_materials_emissive_strength.emissiveStrength is {s}; expected a finite \
                 number ≥ 0"
            )));
        }
        emission *= s;
    }
    if !emission.is_finite() || emission.min_element() < 0.0 {
        return Err(context(
            "expected an emissiveFactor of finite numbers ≥ 0".into(),
        ));
    }
    let emission_map = match &json.emissive_texture {
        Some(info) => image_or_warn(
            images,
            (index, info.index.value()),
            ("emissiveTexture", "keeps its emissiveFactor"),
            warnings,
        )
        .map_err(context)?,
        None => None,
    }
    .map(|img| crate::texture::from_srgb(&img));
    let base_color = match &pbr_json.base_color_texture {
        Some(info) => image_or_warn(
            images,
            (index, info.index.value()),
            ("baseColorTexture", "keeps its baseColorFactor"),
            warnings,
        )
        .map_err(context)?,
        None => None,
    };
    let color = match base_color {
        Some(img) => Texture::Image(crate::texture::from_srgb(&img).tinted(pbr.base)),
        None => Texture::Solid(pbr.base),
    };
    let name = json
        .name
        .clone()
        .unwrap_or_else(|| format!("gltf material {index}"));
    let mut material = whitted(name, &pbr, emission, color);
    material.metal_rough = metal_rough;
    material.emission_map = emission_map;
    // The normal map's texels are directions, not colours: read without the sRGB curve.
    if let Some(info) = &json.normal_texture {
        if !info.scale.is_finite() {
            return Err(context(format!(
                "normalTexture.scale is {}; expected a finite number",
                info.scale
            )));
        }
        let image = image_or_warn(
            images,
            (index, info.index.value()),
            ("normalTexture", "keeps its surfaces' own normals"),
            warnings,
        )
        .map_err(context)?;
        material.normal_map = image.map(|img| NormalMap {
            texture: crate::texture::from_linear(&img),
            scale: info.scale,
        });
    }
    // Occlusion is data too: the red channel, its strength applied (1 + s·(r − 1)).
    if let Some(info) = &json.occlusion_texture {
        let strength = info.strength.0;
        if !(0.0..=1.0).contains(&strength) {
            return Err(context(format!(
                "occlusionTexture.strength is {strength}; expected a number from 0 to 1"
            )));
        }
        let image = image_or_warn(
            images,
            (index, info.index.value()),
            ("occlusionTexture", "has no ambient occlusion"),
            warnings,
        )
        .map_err(context)?;
        material.occlusion = image.map(|img| {
            let rgb = img.to_rgb8();
            let texels = rgb
                .pixels()
                .map(|p| Color::splat(1.0 + strength * (p[0] as f32 / 255.0 - 1.0)))
                .collect();
            prism::shading::ImageTexture::from_texels(
                rgb.width() as usize,
                rgb.height() as usize,
                texels,
            )
        });
    }
    Ok(material)
}

/// The image of texture `texture` of material `material`, or None with a warning where
/// it names a file that is not there (a model downloaded without its textures): the
/// material then does without it, as `instead` says, rather than the load failing.
fn image_or_warn(
    images: &mut Images,
    (material, texture): (usize, usize),
    (what, instead): (&str, &str),
    warnings: &mut Vec<String>,
) -> Result<Option<std::rc::Rc<image::DynamicImage>>, String> {
    if let Some(path) = images.missing_file(texture) {
        warnings.push(format!(
            "material {material}: its {what}'s image {} is missing; the material {instead}",
            path.display()
        ));
        return Ok(None);
    }
    images.texture(texture).map(Some)
}

/// The TEXCOORD set the textures of material `index` read: its first texture's (base
/// colour, metallic-roughness, normal, occlusion, emissive); 0 without textures. A mesh
/// has one set of uvs: `dropped` warns of materials whose textures read several.
pub(super) fn uv_set(root: &Root, index: Option<usize>) -> u32 {
    index
        .and_then(|i| root.materials.get(i))
        .and_then(|m| texture_sets(m).into_iter().next())
        .unwrap_or(0)
}

/// The TEXCOORD sets of material `m`'s textures, in the order `uv_set` looks at them.
pub(super) fn texture_sets(m: &gltf::json::Material) -> Vec<u32> {
    let pbr = &m.pbr_metallic_roughness;
    [
        pbr.base_color_texture.as_ref().map(|t| t.tex_coord),
        pbr.metallic_roughness_texture.as_ref().map(|t| t.tex_coord),
        m.normal_texture.as_ref().map(|t| t.tex_coord),
        m.occlusion_texture.as_ref().map(|t| t.tex_coord),
        m.emissive_texture.as_ref().map(|t| t.tex_coord),
    ]
    .into_iter()
    .flatten()
    .collect()
}
