//! glTF's metallic-roughness inputs mapped onto Whitted's coefficients, for a whole
//! material (the glTF loader) and per texel of a metallicRoughnessTexture (the tracers,
//! at each hit), by one formula.
//!
//! Whitted shading has a diffuse colour, a white highlight, a sharp mirror term and a
//! refracted term; glTF describes a microfacet BRDF. The mapping (docs/formats.md,
//! "glTF 2.0") keeps what a Whitted renderer can show: metals and smooth surfaces → mirror
//! reflection; roughness → highlight size and weight; the index of refraction → the
//! dielectric's reflectance; transmission → Fresnel-weighted glass tinted by the base
//! colour factor. The path tracer builds its lobes from the same coefficients.

use super::coefficients::Coefficients;
use super::fresnel::FresnelMode;
use super::material::Highlight;
use super::texture::ImageTexture;
use crate::math::{Color, Vec2};

/// Highlight exponents are capped here: a mirror-smooth surface's highlight is already
/// a single bright pixel at this exponent.
const MAX_SHININESS: f32 = 10_000.0;

/// The glTF inputs of one material (or one texel of it) that decide its coefficients.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pbr {
    /// Linear RGB base colour factor (its alpha is not read): it tints transmission.
    pub base: Color,
    /// 0 for a dielectric, 1 for a metal.
    pub metallic: f32,
    /// 0 for a mirror-smooth surface, 1 for a fully rough one.
    pub roughness: f32,
    /// KHR_materials_transmission's transmissionFactor (0 without the extension).
    pub transmission: f32,
    /// KHR_materials_ior's ior (1.5 without it; 0 is its "reflect everything" value).
    pub ior: f32,
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
        }
    }
}

impl Pbr {
    /// The Whitted coefficients for these inputs, emitting `emission`.
    pub fn coefficients(&self, emission: Color) -> Coefficients {
        let m = self.metallic.clamp(0.0, 1.0);
        let r = self.roughness.clamp(0.0, 1.0);
        // The dielectric's reflectance at normal incidence: 0.04 for the default ior 1.5.
        let f0 = if self.ior == 0.0 {
            1.0
        } else {
            ((self.ior - 1.0) / (self.ior + 1.0)).powi(2)
        };
        // Metals do not transmit; transmission takes the dielectric part only, and
        // nothing passes a surface whose reflectance is 1.
        let t = if f0 < 1.0 {
            self.transmission.clamp(0.0, 1.0) * (1.0 - m)
        } else {
            0.0
        };
        // Sharp reflections fade out as the surface gets rough (a Whitted tracer cannot
        // blur them); metals reflect nearly everything, dielectrics their F0.
        let gloss = (1.0 - r) * (1.0 - r);
        let mirror = gloss * (f0 + (1.0 - f0) * m);
        let opaque = 1.0 - t;
        let diffuse = opaque * (1.0 - mirror);
        // Blinn–Phong exponent matched to a GGX lobe of width α = roughness².
        let alpha = r * r;
        let shininess = (2.0 / (alpha * alpha) - 2.0).clamp(1.0, MAX_SHININESS);
        Coefficients {
            ambient: diffuse,
            diffuse,
            specular: 1.0 - r,
            shininess,
            highlight: Highlight::BlinnPhong,
            reflect: opaque * mirror,
            transmit: t * self.base,
            ior: if self.ior >= 1.0 { self.ior } else { 1.5 },
            fresnel: if t > 0.0 {
                FresnelMode::Exact
            } else {
                FresnelMode::Off
            },
            emission,
        }
    }
}

/// A metallicRoughnessTexture with the inputs it modulates: at a point, metallic is the
/// factor times the texel's blue channel and roughness the factor times its green one
/// (glTF 2.0), both linear, sampled as colour textures are (bilinear, wrapping).
#[derive(Clone, Debug, PartialEq)]
pub struct MetalRough {
    /// The texels, linear (no sRGB curve): green = roughness, blue = metallic.
    pub texture: ImageTexture,
    /// The material's inputs, `metallic` and `roughness` being the factors.
    pub factors: Pbr,
}

impl MetalRough {
    /// The coefficients of the texel at `uv`, emitting `emission`.
    #[inline]
    pub fn coefficients_at(&self, uv: Vec2, emission: Color) -> Coefficients {
        let texel = self.texture.eval(uv);
        Pbr {
            metallic: self.factors.metallic * texel.z,
            roughness: self.factors.roughness * texel.y,
            ..self.factors
        }
        .coefficients(emission)
    }
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

    fn map(p: Pbr) -> Coefficients {
        p.coefficients(Color::ZERO)
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

    /// Per texel, the factors scale the texture's blue (metallic) and green (roughness):
    /// a 2 × 1 texture of a metal texel and a dielectric one gives a mirror on one half
    /// and a matte surface on the other, which their mean could not.
    #[test]
    fn each_texel_has_its_own_metallic_and_roughness() {
        let texture = ImageTexture::from_texels(
            2,
            1,
            vec![Color::new(0.0, 0.0, 1.0), Color::new(0.0, 1.0, 0.0)],
        );
        let map = MetalRough {
            texture,
            factors: pbr(1.0, 1.0),
        };
        let metal = map.coefficients_at(Vec2::new(0.25, 0.5), Color::ZERO);
        let matte = map.coefficients_at(Vec2::new(0.75, 0.5), Color::ZERO);
        assert_eq!(metal, pbr(1.0, 0.0).coefficients(Color::ZERO));
        assert_eq!((metal.reflect, metal.diffuse), (1.0, 0.0));
        assert_eq!(
            (matte.reflect, matte.diffuse, matte.specular),
            (0.0, 1.0, 0.0)
        );
    }
}
