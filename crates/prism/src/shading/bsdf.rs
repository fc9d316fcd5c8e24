//! The path tracer's view of a material: four lobes, evaluated, sampled and with their
//! density, built from the Whitted coefficients at one hit (`Coefficients`: a material's
//! own, or its texel's where a texture changes them; docs/path-tracing.md).
//!
//! - Lambert diffuse, albedo kd·C (f = kd·C/π);
//! - a glossy lobe, normalised Phong (Lafortune and Willems 1994) about the mirror
//!   direction: f = ks·(n + 2)/(2π)·cosⁿα, whose albedo is at most ks, reached at normal
//!   incidence; the Blinn–Phong exponent n maps to the Phong exponent n/4;
//! - a perfect mirror and a smooth dielectric, weighted exactly as Whitted's reflected and
//!   refracted rays (`Coefficients::specular_weights`): with exact Fresnel and kt = 1 the
//!   interface reflects R and transmits 1 − R.
//!
//! Whitted's weights may add up to more than one (kd + ks + kr + kt), which a path tracer
//! would turn into light from nowhere. The mirror and dielectric keep their weights unless
//! kr + max(kt) exceeds one (then both shrink to fit); diffuse and glossy share what is
//! left, shrunk together when max(kd·C) + ks would pass it. Ambient (ka) has no lobe: the
//! path tracer computes the light it stood for.
//!
//! Directions all point away from the surface: `wo` towards the viewer, `wi` towards the
//! light. The normals given to `Bsdf::new` face `wo`'s side.

use super::coefficients::Coefficients;
use super::material::Highlight;
use super::optics::{reflect, refract};
use crate::math::warp::{cosine_direction, cosine_hemisphere_pdf, cosine_power, cosine_power_pdf};
use crate::math::{Color, Frame, Vec3};
use std::f32::consts::FRAC_1_PI;

/// One hit's scattering: the lobes' weights and the probabilities of sampling each.
#[derive(Clone, Copy, Debug)]
pub struct Bsdf {
    /// Shading normal, on `wo`'s side.
    ns: Vec3,
    /// Geometric normal, on `wo`'s side: reflected light stays on this side.
    ng: Vec3,
    wo: Vec3,
    diffuse: Color,
    glossy: f32,
    exponent: f32,
    /// `wo` mirrored about `ns`: the glossy lobe's axis and the mirror's direction.
    mirrored: Vec3,
    reflect: f32,
    transmit: Color,
    /// η_incident / η_transmitted for the refracted direction.
    eta: f32,
    /// Probabilities of sampling diffuse, glossy, mirror; the rest is transmission.
    p_diffuse: f32,
    p_glossy: f32,
    p_reflect: f32,
}

/// A direction drawn from a `Bsdf`.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// Unit direction the light arrives from (away from the surface).
    pub wi: Vec3,
    /// f·|cos θi| / pdf: what the sample's radiance is multiplied by.
    pub weight: Color,
    /// The density the direction was drawn with over the non-delta lobes (solid angle);
    /// meaningless for a delta sample.
    pub pdf: f32,
    /// Drawn from the mirror or the dielectric: no light sample could have found it.
    pub delta: bool,
    /// It went through the surface (refraction).
    pub transmitted: bool,
}

/// What `Bsdf::sample` reads when it draws from the diffuse lobe of a BSDF without a
/// glossy one: the direction is `warp::cosine_direction` about `ns`, its density
/// `p_diffuse`·cos θ/π (zero below `ns` or `ng`), its weight (`diffuse`/π)·(cos θ / pdf).
#[derive(Clone, Copy, Debug)]
pub(crate) struct DiffuseLobe {
    /// Shading normal, on `wo`'s side.
    pub(crate) ns: Vec3,
    /// Geometric normal, on `wo`'s side.
    pub(crate) ng: Vec3,
    /// The lobe's albedo.
    pub(crate) diffuse: Color,
    /// The probability of drawing from it.
    pub(crate) p_diffuse: f32,
}

/// The Phong exponent a highlight's `shininess` stands for: near the peak the half vector's
/// angle to N is half the mirror direction's angle to V, so (N·H)ⁿ ≈ (R·V)^(n/4)
/// (cos(θ/2)ⁿ ≈ e^(−nθ²/8) = cos(θ)^(n/4) for small θ).
fn phong_exponent(material: &Coefficients) -> f32 {
    let n = material.shininess.max(0.0);
    match material.highlight {
        Highlight::Phong => n,
        Highlight::BlinnPhong => n / 4.0,
    }
}

/// What `Bsdf::new` computes from the coefficients and the diffuse colour alone, before it
/// looks at the hit's directions: made once per material where neither varies over its
/// surface (`integrator/path.rs` keeps one per such material), so that a hit there only
/// adds its directions and the angle-dependent specular weights (`MaterialLobes::at`).
/// `Bsdf::new` is `MaterialLobes::new` then `at`, so both ways give the same bits.
#[derive(Clone, Copy, Debug)]
pub struct MaterialLobes {
    /// η for a ray arriving from the front and from the back.
    eta_entering: f32,
    eta_leaving: f32,
    /// What the mirror and dielectric weights shrink by so that they add up to one at most.
    specular_scale: f32,
    diffuse: Color,
    glossy: f32,
    exponent: f32,
    /// The probabilities of diffuse, glossy and mirror where the specular weights at the
    /// hit come out +0 (the bits `at` checks): those of a material without mirror or
    /// dielectric, whatever the angle.
    p_plain: [f32; 3],
}

impl MaterialLobes {
    /// The lobes' hit-independent part for coefficients `material` with diffuse colour
    /// `color`.
    pub fn new(material: &Coefficients, color: Color) -> MaterialLobes {
        // Whitted's upper bound of reflect + transmit over all angles.
        let specular_total = material.reflect + material.interface_share();
        let specular_scale = if specular_total > 1.0 {
            1.0 / specular_total
        } else {
            1.0
        };
        let room = (1.0 - specular_total * specular_scale).max(0.0);
        let diffuse = material.diffuse * color;
        let local = diffuse.max_element().max(0.0) + material.specular.max(0.0);
        let local_scale = if local > room { room / local } else { 1.0 };
        let diffuse = diffuse.max(Color::ZERO) * local_scale;
        let glossy = material.specular.max(0.0) * local_scale;
        MaterialLobes {
            eta_entering: 1.0 / material.ior,
            eta_leaving: material.ior,
            specular_scale,
            diffuse,
            glossy,
            exponent: phong_exponent(material),
            p_plain: probabilities(diffuse, glossy, 0.0, Color::ZERO),
        }
    }

    /// The BSDF at a hit of coefficients `material` (those `new` was given, up to their
    /// emission) seen from `wo`, as `Bsdf::new` describes.
    #[inline]
    pub fn at(
        &self,
        material: &Coefficients,
        wo: Vec3,
        ns: Vec3,
        ng: Vec3,
        entering: bool,
    ) -> Bsdf {
        let eta = if entering {
            self.eta_entering
        } else {
            self.eta_leaving
        };
        let cos_o = wo.dot(ns).clamp(0.0, 1.0);
        let w = material.specular_weights(cos_o, eta);
        let reflect = w.reflect * self.specular_scale;
        let transmit = w.transmit * self.specular_scale;
        let plain = reflect.to_bits() == 0 && transmit.to_array().map(f32::to_bits) == [0; 3];
        let [p_diffuse, p_glossy, p_reflect] = if plain {
            self.p_plain
        } else {
            probabilities(self.diffuse, self.glossy, reflect, transmit)
        };
        Bsdf {
            ns,
            ng,
            wo,
            diffuse: self.diffuse,
            glossy: self.glossy,
            exponent: self.exponent,
            mirrored: reflect_about(wo, ns),
            reflect,
            transmit,
            eta,
            p_diffuse,
            p_glossy,
            p_reflect,
        }
    }
}

/// The probabilities of sampling diffuse, glossy and mirror (the rest is transmission):
/// lobes are chosen in proportion to their mean weight.
#[inline]
fn probabilities(diffuse: Color, glossy: f32, reflect: f32, transmit: Color) -> [f32; 3] {
    let weights = [mean(diffuse), glossy, reflect, mean(transmit)];
    let total: f32 = weights.iter().sum();
    let p = |w: f32| if total > 0.0 { w / total } else { 0.0 };
    [p(weights[0]), p(weights[1]), p(weights[2])]
}

impl Bsdf {
    /// The lobes of coefficients `material` (a material's at the hit, from
    /// `Material::coefficients_at`) with diffuse colour `color` at a hit seen from `wo`, with
    /// normals `ns` and `ng` facing `wo`; `entering` says the ray arrived from the front
    /// (outside) of the surface, which decides the refraction's η.
    pub fn new(
        material: &Coefficients,
        color: Color,
        wo: Vec3,
        ns: Vec3,
        ng: Vec3,
        entering: bool,
    ) -> Bsdf {
        MaterialLobes::new(material, color).at(material, wo, ns, ng, entering)
    }

    /// The diffuse lobe of a BSDF with no glossy lobe, for the wavefront's diffuse
    /// bounces in lanes (`integrator/diffuse_lanes.rs`): `sample` draws from it exactly when
    /// `u_lobe < p_diffuse`, and then its answer is `DiffuseLobe`'s arithmetic.
    pub(crate) fn diffuse_only(&self) -> Option<DiffuseLobe> {
        (self.glossy == 0.0).then_some(DiffuseLobe {
            ns: self.ns,
            ng: self.ng,
            diffuse: self.diffuse,
            p_diffuse: self.p_diffuse,
        })
    }

    /// The geometric normal it was made with, on `wo`'s side.
    #[inline]
    pub fn ng(&self) -> Vec3 {
        self.ng
    }

    /// Whether some lobe is not a delta: only then can a light sample find a direction.
    pub fn has_smooth_lobe(&self) -> bool {
        self.p_diffuse + self.p_glossy > 0.0
    }

    /// The cosine of the rendering equation for `wi`, at the shading normal (0 below it).
    #[inline]
    pub fn cos(&self, wi: Vec3) -> f32 {
        wi.dot(self.ns).max(0.0)
    }

    /// f(wo, wi) of the diffuse and glossy lobes (the delta lobes are zero for any given
    /// direction).
    pub fn eval(&self, wi: Vec3) -> Color {
        let cos_i = wi.dot(self.ns);
        if cos_i <= 0.0 || wi.dot(self.ng) <= 0.0 {
            return Color::ZERO;
        }
        let mut f = self.diffuse * FRAC_1_PI;
        if self.glossy > 0.0 {
            let cos_a = self.mirrored.dot(wi);
            if cos_a > 0.0 {
                let n = self.exponent;
                f += Color::splat(self.glossy * (n + 2.0) * (0.5 * FRAC_1_PI) * cos_a.powf(n));
            }
        }
        f
    }

    /// The density `sample` draws `wi` with from the diffuse and glossy lobes (solid angle).
    pub fn pdf(&self, wi: Vec3) -> f32 {
        let cos_i = wi.dot(self.ns);
        if cos_i <= 0.0 || wi.dot(self.ng) <= 0.0 {
            return 0.0;
        }
        let mut pdf = self.p_diffuse * cosine_hemisphere_pdf(cos_i);
        if self.p_glossy > 0.0 {
            pdf += self.p_glossy * cosine_power_pdf(self.mirrored.dot(wi), self.exponent);
        }
        pdf
    }

    /// Draws a direction from three uniform numbers: `u_lobe` picks the lobe, `(u1, u2)` the
    /// direction in it. `None` when the drawn direction carries no light (a glossy
    /// direction below the surface, or nothing to scatter).
    pub fn sample(&self, u_lobe: f32, u1: f32, u2: f32) -> Option<BsdfSample> {
        let smooth = self.p_diffuse + self.p_glossy;
        if u_lobe < smooth {
            let wi = if u_lobe < self.p_diffuse {
                let [x, y, z] = cosine_direction(self.ns.to_array(), u1, u2);
                Vec3::new(x, y, z)
            } else {
                Frame::from_z(self.mirrored)
                    .to_world(cosine_power(u1, u2, self.exponent))
                    .normalize()
            };
            let pdf = self.pdf(wi);
            if pdf <= 0.0 {
                return None;
            }
            let f = self.eval(wi);
            return Some(BsdfSample {
                wi,
                weight: f * (wi.dot(self.ns) / pdf),
                pdf,
                delta: false,
                transmitted: false,
            });
        }
        if u_lobe < smooth + self.p_reflect {
            let mut wi = self.mirrored;
            // An interpolated normal can mirror below the true surface; the geometric
            // normal's mirror stays above it.
            if wi.dot(self.ng) <= 0.0 {
                wi = reflect_about(self.wo, self.ng);
            }
            return Some(BsdfSample {
                wi,
                weight: Color::splat(self.reflect / self.p_reflect),
                pdf: 0.0,
                delta: true,
                transmitted: false,
            });
        }
        let p_transmit = 1.0 - smooth - self.p_reflect;
        if p_transmit <= 0.0 || self.transmit == Color::ZERO {
            return None;
        }
        let wi = refract(-self.wo, self.ns, self.eta)?;
        if wi.dot(self.ng) >= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.transmit / p_transmit,
            pdf: 0.0,
            delta: true,
            transmitted: true,
        })
    }
}

/// `w` (pointing away from the surface) mirrored about `n`.
fn reflect_about(w: Vec3, n: Vec3) -> Vec3 {
    reflect(-w, n)
}

fn mean(c: Color) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shading::{FresnelMode, Material};

    /// `MaterialLobes::at` takes the probabilities it made once wherever the specular
    /// weights come out +0; they must be the ones the weights at the hit give, for
    /// materials with and without mirror and dielectric, from both sides, at every angle.
    #[test]
    fn the_kept_probabilities_are_the_hits_own() {
        let plain = Material::default();
        let glossy = Material {
            specular: 0.4,
            shininess: 30.0,
            ..Material::default()
        };
        let mirror = Material {
            reflect: 0.6,
            ..Material::default()
        };
        let glass = |fresnel| Material {
            diffuse: 0.0,
            transmit: Color::splat(0.9),
            ior: 1.5,
            fresnel,
            ..Material::default()
        };
        let materials = [
            plain,
            glossy,
            mirror,
            glass(FresnelMode::Exact),
            glass(FresnelMode::Schlick),
            glass(FresnelMode::Off),
        ];
        let n = Vec3::Z;
        let mut kept = 0;
        for m in &materials {
            let k = m.coefficients();
            let lobes = MaterialLobes::new(&k, Color::new(0.9, 0.5, 0.1));
            for i in 0..=32 {
                let cos = i as f32 / 32.0;
                let wo = Vec3::new((1.0 - cos * cos).max(0.0).sqrt(), 0.0, cos);
                for entering in [true, false] {
                    let b = lobes.at(&k, wo, n, n, entering);
                    let direct = probabilities(b.diffuse, b.glossy, b.reflect, b.transmit);
                    let got = [b.p_diffuse, b.p_glossy, b.p_reflect];
                    assert_eq!(got.map(f32::to_bits), direct.map(f32::to_bits), "{k:?}");
                    kept += usize::from(got == lobes.p_plain);
                }
            }
        }
        // The diffuse and glossy materials took the kept ones at every angle.
        assert!(kept >= 2 * 33 * 2, "{kept}");
    }
}
