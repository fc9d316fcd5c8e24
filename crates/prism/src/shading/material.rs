//! The Whitted material: ambient, Lambert diffuse and a Phong or Blinn–Phong highlight for
//! the local term; mirror reflection `kr` and refraction `kt` for the recursive terms.
//!
//! `kt` is a colour: a filter that tints what passes through (POV-Ray's `filter`, MTL's
//! `Tf`, glTF's transmission tinted by the base colour). Reflection at the interface is not
//! tinted: the colour of glass is what its body absorbs, not what its surface reflects.

use super::fresnel::FresnelMode;
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
        }
    }
}

/// Weights of the reflected and refracted rays at one hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpecularWeights {
    /// Untinted: the interface reflects white light.
    pub reflect: f32,
    /// Per channel: the filter `kt`, less what the interface reflects.
    pub transmit: Color,
    /// Refraction was impossible (sin²θt > 1); its weight went to reflection.
    pub total_internal_reflection: bool,
}

impl Material {
    /// Whether the surface is a light (emits from its front side).
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }

    /// Whether any light passes through it (so shadow rays must look through it).
    pub fn is_transmissive(&self) -> bool {
        self.transmit.max_element() > 0.0
    }

    /// The share of light that meets the interface as a dielectric: the clearest channel
    /// of `kt`. Interface reflection and total internal reflection are weighted by it,
    /// untinted; for a grey `kt` it is that grey.
    pub fn interface_share(&self) -> f32 {
        self.transmit.max_element()
    }

    /// Splits light between the mirror and refraction directions. `cos_i` is the cosine of
    /// the incident angle, `eta` = η_incident / η_transmitted.
    ///
    /// Fresnel off: `kr` and `kt` as given. Fresnel on: reflectance R(θ) scales the mirror
    /// term of both a coating (`kr`) and the dielectric (its share `k̄t`, the clearest
    /// channel of `kt`), and the dielectric transmits `kt`·(1 − R) per channel. Under total
    /// internal reflection nothing is transmitted and the dielectric's share goes to
    /// reflection (R = 1 does this for the Fresnel modes).
    pub fn specular_weights(&self, cos_i: f32, eta: f32) -> SpecularWeights {
        let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
        let share = self.interface_share();
        let tir = share > 0.0 && sin2_t > 1.0;
        let (reflect, transmit) = match self.fresnel.reflectance(cos_i, eta) {
            None if tir => (self.reflect + share, Color::ZERO),
            None => (self.reflect, self.transmit),
            Some(r) => {
                let r = if tir { 1.0 } else { r };
                ((self.reflect + share) * r, self.transmit * (1.0 - r))
            }
        };
        SpecularWeights {
            reflect,
            transmit,
            total_internal_reflection: tir,
        }
    }

    /// The local highlight term for unit vectors: normal `n`, towards the light `l`,
    /// towards the viewer `v`.
    pub fn highlight_term(&self, n: Vec3, l: Vec3, v: Vec3) -> f32 {
        if self.specular <= 0.0 {
            return 0.0;
        }
        let c = match self.highlight {
            Highlight::Phong => super::optics::reflect(-l, n).dot(v),
            Highlight::BlinnPhong => match (l + v).try_normalize() {
                Some(h) => n.dot(h),
                None => 0.0,
            },
        };
        if c <= 0.0 {
            0.0
        } else {
            self.specular * c.powf(self.shininess)
        }
    }

    /// Whether `color_at` reads the surface's uv (see `geometry::Uv`).
    pub fn uv_need(&self) -> Uv {
        if self.color.reads_uv() {
            Uv::Compute
        } else {
            Uv::Skip
        }
    }

    /// The diffuse colour at a surface point, from its texture.
    pub fn color_at(&self, uv: Vec2, p: Vec3) -> Color {
        self.color.eval(uv, p)
    }
}
