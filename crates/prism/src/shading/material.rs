//! The Whitted material: ambient, Lambert diffuse and a Phong or Blinn–Phong highlight for
//! the local term; mirror reflection `kr` and refraction `kt` for the recursive terms.
//!
//! `kt` is a colour: a filter that tints what passes through (POV-Ray's `filter`, MTL's
//! `Tf`, glTF's transmission tinted by the base colour). Reflection at the interface is not
//! tinted: the colour of glass is what its body absorbs, not what its surface reflects.

use super::coefficients::{Coefficients, SpecularWeights};
use super::fresnel::FresnelMode;
use super::pbr::MetalRough;
use super::texture::Texture;
use crate::geometry::Uv;
use crate::math::{Color, Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// The specular highlight lobe of the local illumination.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Highlight {
    /// (R·V)^n, with R the light direction mirrored about the normal (Phong 1975).
    #[default]
    Phong,
    /// (N·H)^n, with H halfway between light and viewer (Blinn 1977).
    BlinnPhong,
}

/// A surface's response to light in Whitted's model: local (ambient, diffuse, highlight) plus the
/// weights of the reflected and refracted rays.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The name the scene file gave it (MTL's `newmtl`, a TOML table's key); rendering
    /// never reads it.
    pub name: String,
    /// Diffuse (and ambient) colour.
    pub color: Texture,
    /// ka: fraction of the scene's ambient light reflected.
    pub ambient: f32,
    /// kd: Lambert diffuse weight.
    pub diffuse: f32,
    /// ks: highlight weight (white highlights, as in Whitted's model).
    pub specular: f32,
    /// Highlight exponent.
    pub shininess: f32,
    /// Which highlight formula `shininess` applies to.
    pub highlight: Highlight,
    /// kr: weight of the mirror-reflected ray (Whitted's ks in I_R).
    pub reflect: f32,
    /// kt: weight of the refracted ray per channel; also what a shadow ray keeps, per
    /// channel, when crossing. A grey is `Color::splat(kt)`.
    pub transmit: Color,
    /// Index of refraction of the material's inside; the outside is taken to be vacuum.
    pub ior: f32,
    /// How the reflected and transmitted weights vary with the angle.
    pub fresnel: FresnelMode,
    /// Radiance the surface emits from its front side (the side its geometric normal
    /// faces): an area light. Zero for every surface that is not a light.
    pub emission: Color,
    /// A normal map turning the shading normal per texel (triangles with uvs); None for
    /// the interpolated normal alone.
    pub normal_map: Option<super::NormalMap>,
    /// A bump map turning the shading normal by the gradient of its heights (triangles
    /// with uvs); None for no bumps.
    pub bump_map: Option<super::BumpMap>,
    /// How much of the ambient light reaches each texel (glTF's `occlusionTexture`, its
    /// strength applied; the red channel counts): it scales the ambient term. None: all.
    pub occlusion: Option<super::ImageTexture>,
    /// glTF's metallicRoughnessTexture: the coefficients above worked out again at each
    /// hit from the metallic and roughness of the texel there (`MetalRough`). None: the
    /// coefficients above hold everywhere.
    pub metal_rough: Option<MetalRough>,
    /// An emissive texture (glTF's `emissiveTexture`, linear): multiplies `emission` per
    /// texel. None: `emission` everywhere.
    pub emission_map: Option<super::ImageTexture>,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            name: "default".into(),
            color: Texture::Solid(Color::splat(0.8)),
            ambient: 0.1,
            diffuse: 0.9,
            specular: 0.0,
            shininess: 32.0,
            highlight: Highlight::Phong,
            reflect: 0.0,
            transmit: Color::ZERO,
            ior: 1.5,
            fresnel: FresnelMode::Off,
            emission: Color::ZERO,
            normal_map: None,
            bump_map: None,
            occlusion: None,
            metal_rough: None,
            emission_map: None,
        }
    }
}

impl Material {
    /// A diffuse surface of one colour with ka `ambient` and kd `diffuse`, no highlight,
    /// mirror or transmission: where hand-made scenes start, adding the rest with
    /// `glossy`, `reflecting` and `glass`.
    pub fn matte(name: &str, color: Color, ambient: f32, diffuse: f32) -> Self {
        Material {
            name: name.into(),
            color: Texture::Solid(color),
            ambient,
            diffuse,
            ..Material::default()
        }
    }

    /// With a highlight of weight ks `specular` and exponent `shininess`.
    pub fn glossy(self, specular: f32, shininess: f32) -> Self {
        Material {
            specular,
            shininess,
            ..self
        }
    }

    /// With a mirror-reflected ray of weight kr `reflect`.
    pub fn reflecting(self, reflect: f32) -> Self {
        Material { reflect, ..self }
    }

    /// Glass: a refracted ray of weight `transmit` per channel through index `ior`, the
    /// mirror and refracted weights shared by the exact Fresnel terms.
    pub fn glass(self, transmit: Color, ior: f32) -> Self {
        Material {
            transmit,
            ior,
            fresnel: FresnelMode::Exact,
            ..self
        }
    }

    /// Its coefficients as given: what every point of it has, where no texture changes
    /// them per texel.
    #[inline]
    pub fn coefficients(&self) -> Coefficients {
        Coefficients {
            ambient: self.ambient,
            diffuse: self.diffuse,
            specular: self.specular,
            shininess: self.shininess,
            highlight: self.highlight,
            reflect: self.reflect,
            transmit: self.transmit,
            ior: self.ior,
            fresnel: self.fresnel,
            emission: self.emission,
        }
    }

    /// Its coefficients at `uv`: those of the texel hit where a metallic-roughness texture
    /// or an emissive texture changes them, else `coefficients()`.
    #[inline]
    pub fn coefficients_at(&self, uv: Vec2) -> Coefficients {
        let mut k = match &self.metal_rough {
            Some(map) => map.coefficients_at(uv, self.emission),
            None => self.coefficients(),
        };
        if self.emission_map.is_some() {
            k.emission = self.emission_at(uv);
        }
        k
    }

    /// The radiance it emits at `uv`: `emission`, times the emissive texture's texel there.
    #[inline]
    pub fn emission_at(&self, uv: Vec2) -> Color {
        match &self.emission_map {
            Some(map) => self.emission * map.eval(uv),
            None => self.emission,
        }
    }

    /// This material with the coefficients `k` (its colour, maps and name kept).
    pub fn with_coefficients(self, k: Coefficients) -> Material {
        Material {
            ambient: k.ambient,
            diffuse: k.diffuse,
            specular: k.specular,
            shininess: k.shininess,
            highlight: k.highlight,
            reflect: k.reflect,
            transmit: k.transmit,
            ior: k.ior,
            fresnel: k.fresnel,
            emission: k.emission,
            ..self
        }
    }

    /// The mean radiance it emits over its uv square: `emission`, times the emissive
    /// texture's mean texel where it has one (what area lights are chosen by).
    pub fn mean_emission(&self) -> Color {
        match &self.emission_map {
            Some(map) => self.emission * map.mean(),
            None => self.emission,
        }
    }

    /// Whether the surface may be a light (emits from its front side somewhere).
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// Whether any light passes through it (so shadow rays must look through it).
    pub fn is_transmissive(&self) -> bool {
        self.coefficients().is_transmissive()
    }

    /// `Coefficients::interface_share` of `coefficients()`.
    pub fn interface_share(&self) -> f32 {
        self.coefficients().interface_share()
    }

    /// `Coefficients::specular_weights` of `coefficients()`.
    pub fn specular_weights(&self, cos_i: f32, eta: f32) -> SpecularWeights {
        self.coefficients().specular_weights(cos_i, eta)
    }

    /// `Coefficients::highlight_term` of `coefficients()`.
    pub fn highlight_term(&self, n: Vec3, l: Vec3, v: Vec3) -> f32 {
        self.coefficients().highlight_term(n, l, v)
    }

    /// Whether shading a hit on it reads the surface's uv (see `geometry::Uv`): for its
    /// colour, maps or per-texel coefficients.
    pub fn uv_need(&self) -> Uv {
        if self.color.reads_uv()
            || self.normal_map.is_some()
            || self.bump_map.is_some()
            || self.occlusion.is_some()
            || self.metal_rough.is_some()
            || self.emission_map.is_some()
        {
            Uv::Compute
        } else {
            Uv::Skip
        }
    }

    /// The share of the ambient light that reaches the surface at `uv` (1 without an
    /// occlusion texture).
    #[inline]
    pub fn ambient_occlusion(&self, uv: Vec2) -> f32 {
        self.occlusion.as_ref().map_or(1.0, |t| t.eval(uv).x)
    }

    /// The diffuse colour at a surface point, from its texture.
    pub fn color_at(&self, uv: Vec2, p: Vec3) -> Color {
        self.color.eval(uv, p)
    }
}
