//! glTF's metallic-roughness materials mapped onto prism's Whitted material.
//!
//! Whitted shading has a diffuse colour, a white highlight, a sharp mirror term and a
//! refracted term; glTF describes a microfacet BRDF. The mapping (docs/formats.md,
//! "glTF 2.0") keeps what a Whitted renderer can show: base colour → diffuse colour;
//! metals and smooth surfaces → mirror reflection; roughness → highlight size and weight;
//! KHR_materials_ior → the dielectric's reflectance; KHR_materials_transmission →
//! Fresnel-weighted glass whose transmission the base colour tints (as the extension says).

use super::images::Images;
use gltf::json::Root;
use prism::math::Color;
use prism::shading::{FresnelMode, Highlight, Material, NormalMap, Texture};

/// Highlight exponents are capped here: a mirror-smooth surface's highlight is already
/// a single bright pixel at this exponent.
const MAX_SHININESS: f32 = 10_000.0;

/// The glTF inputs of one material, after textures' constant parts are folded in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Pbr {
    /// Linear RGB base colour (baseColorFactor's rgb; alpha is ignored).
    pub base: Color,
    pub metallic: f32,
    pub roughness: f32,
    /// KHR_materials_transmission's transmissionFactor (0 without the extension).
    pub transmission: f32,
    /// KHR_materials_ior's ior (1.5 without the extension; 0 is the extension's
    /// "reflect everything" value).
    pub ior: f32,
    /// emissiveFactor, times the mean of emissiveTexture where there is one.
    pub emission: Color,
}

impl Default for Pbr {
    /// glTF's default material: white, fully metallic, fully rough.
    fn default() -> Self {
        Pbr {
            base: Color::ONE,
            metallic: 1.0,
            roughness: 1.0,
            transmission: 0.0,
            ior: 1.5,
            emission: Color::ZERO,
        }
    }
}

/// The Whitted material for `pbr`, its diffuse colour from `color` (which already holds
/// the base colour, as a constant or a tinted image).
pub(super) fn whitted(name: String, pbr: &Pbr, color: Texture) -> Material {
    let m = pbr.metallic.clamp(0.0, 1.0);
    let r = pbr.roughness.clamp(0.0, 1.0);
    // The dielectric's reflectance at normal incidence: 0.04 for glTF's default ior 1.5.
    let f0 = if pbr.ior == 0.0 {
        1.0
    } else {
        ((pbr.ior - 1.0) / (pbr.ior + 1.0)).powi(2)
    };
    // Metals do not transmit; transmission takes the dielectric part only, and nothing
    // passes a surface whose reflectance is 1.
    let t = if f0 < 1.0 {
        pbr.transmission.clamp(0.0, 1.0) * (1.0 - m)
    } else {
        0.0
    };
    // Sharp reflections fade out as the surface gets rough (a Whitted tracer cannot blur
    // them); metals reflect nearly everything, dielectrics their F0.
    let gloss = (1.0 - r) * (1.0 - r);
    let mirror = gloss * (f0 + (1.0 - f0) * m);
    let opaque = 1.0 - t;
    let diffuse = opaque * (1.0 - mirror);
    // Blinn–Phong exponent matched to a GGX lobe of width α = roughness².
    let alpha = r * r;
    let shininess = (2.0 / (alpha * alpha) - 2.0).clamp(1.0, MAX_SHININESS);
    Material {
        name,
        color,
        ambient: diffuse,
        diffuse,
        specular: 1.0 - r,
        shininess,
        highlight: Highlight::BlinnPhong,
        reflect: opaque * mirror,
        transmit: t * pbr.base,
        ior: if pbr.ior >= 1.0 { pbr.ior } else { 1.5 },
        fresnel: if t > 0.0 {
            FresnelMode::Exact
        } else {
            FresnelMode::Off
        },
        emission: pbr.emission,
        normal_map: None,
        occlusion: None,
    }
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

    // Prism's material has one metallic and one roughness value: a metallicRoughness
    // texture contributes its average (blue = metallic, green = roughness, both linear).
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
    if let Some(img) = metallic_roughness {
        let rgb = img.to_rgb8();
        let n = (rgb.width() as f64 * rgb.height() as f64).max(1.0);
        let (g, b) = rgb.pixels().fold((0.0f64, 0.0f64), |(g, b), p| {
            (g + p[1] as f64 / 255.0, b + p[2] as f64 / 255.0)
        });
        pbr.roughness *= (g / n) as f32;
        pbr.metallic *= (b / n) as f32;
    }
    // Emission is one colour per material: an emissiveTexture contributes its mean
    // (decoded from sRGB), so a textured light keeps its power but not its pattern.
    pbr.emission = Color::from_array(json.emissive_factor.0);
    if !pbr.emission.is_finite() || pbr.emission.min_element() < 0.0 {
        return Err(context(
            "expected an emissiveFactor of finite numbers ≥ 0".into(),
        ));
    }
    let emissive = match &json.emissive_texture {
        Some(info) => image_or_warn(
            images,
            (index, info.index.value()),
            ("emissiveTexture", "keeps its emissiveFactor"),
            warnings,
        )
        .map_err(context)?,
        None => None,
    };
    if let Some(img) = emissive {
        let rgb = img.to_rgb8();
        let n = (rgb.width() as f64 * rgb.height() as f64).max(1.0);
        let mut sum = [0.0f64; 3];
        for p in rgb.pixels() {
            for (s, &v) in sum.iter_mut().zip(p.0.iter()) {
                *s += prism::transfer::srgb_decode(v as f32 / 255.0) as f64;
            }
        }
        pbr.emission *= Color::new(
            (sum[0] / n) as f32,
            (sum[1] / n) as f32,
            (sum[2] / n) as f32,
        );
    }
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
    let mut material = whitted(name, &pbr, color);
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

/// The TEXCOORD set the base colour texture of material `index` reads.
pub(super) fn uv_set(root: &Root, index: Option<usize>) -> u32 {
    index
        .and_then(|i| root.materials.get(i))
        .and_then(|m| m.pbr_metallic_roughness.base_color_texture.as_ref())
        .map_or(0, |info| info.tex_coord)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pbr(metallic: f32, roughness: f32) -> Pbr {
        Pbr {
            base: Color::new(0.8, 0.2, 0.1),
            metallic,
            roughness,
            ..Pbr::default()
        }
    }

    fn map(p: Pbr) -> Material {
        whitted("m".into(), &p, Texture::Solid(p.base))
    }

    #[test]
    fn rough_dielectrics_are_matte_and_smooth_metals_are_mirrors() {
        let matte = map(pbr(0.0, 1.0));
        assert_eq!(
            (matte.diffuse, matte.reflect, matte.specular),
            (1.0, 0.0, 0.0)
        );
        let mirror = map(pbr(1.0, 0.0));
        assert_eq!((mirror.diffuse, mirror.reflect), (0.0, 1.0));
        assert_eq!(mirror.shininess, MAX_SHININESS);
        let plastic = map(pbr(0.0, 0.0));
        assert!((plastic.reflect - 0.04).abs() < 1e-6);
        assert!((plastic.diffuse + plastic.reflect - 1.0).abs() < 1e-6);
        assert_eq!(plastic.fresnel, FresnelMode::Off);
    }

    #[test]
    fn rougher_surfaces_have_wider_weaker_highlights() {
        let smooth = map(pbr(0.0, 0.3));
        let rough = map(pbr(0.0, 0.7));
        assert!(smooth.shininess > rough.shininess);
        assert!(smooth.specular > rough.specular);
        assert!(smooth.reflect > rough.reflect);
    }

    #[test]
    fn transmission_makes_fresnel_glass() {
        let glass = map(Pbr {
            transmission: 1.0,
            ior: 1.33,
            roughness: 0.0,
            metallic: 0.0,
            ..Pbr::default()
        });
        assert_eq!(glass.transmit, Color::ONE);
        assert_eq!(glass.ior, 1.33);
        assert_eq!(glass.fresnel, FresnelMode::Exact);
        assert_eq!((glass.diffuse, glass.reflect), (0.0, 0.0));
    }

    #[test]
    fn the_base_colour_tints_transmission() {
        let red = map(Pbr {
            base: Color::new(0.9, 0.2, 0.1),
            transmission: 0.5,
            metallic: 0.0,
            roughness: 0.0,
            ..Pbr::default()
        });
        assert_eq!(red.transmit, Color::new(0.45, 0.1, 0.05));
        assert_eq!(red.fresnel, FresnelMode::Exact);
    }

    #[test]
    fn ior_sets_the_dielectric_reflectance() {
        let diamond = map(Pbr {
            ior: 2.42,
            ..pbr(0.0, 0.0)
        });
        assert!(
            (diamond.reflect - 0.172).abs() < 1e-3,
            "{}",
            diamond.reflect
        );
        // ior 0 is KHR_materials_ior's "Fresnel term always 1": a mirror, even for glass.
        let mirror = map(Pbr {
            ior: 0.0,
            transmission: 1.0,
            ..pbr(0.0, 0.0)
        });
        assert_eq!(
            (mirror.reflect, mirror.transmit, mirror.diffuse),
            (1.0, Color::ZERO, 0.0)
        );
        assert_eq!(mirror.ior, 1.5);
    }
}
