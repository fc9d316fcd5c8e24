//! Whitted's coefficients at one surface point: ka, kd, ks and the highlight's exponent,
//! kr, kt, the index of refraction and the emission. A material holds one set; where a
//! texture changes them per texel (glTF's metallic-roughness and emissive textures), the
//! tracers ask the material for the set at the hit (`Material::coefficients_at`) and
//! shade with that. How they split light between the mirror and refracted rays and how
//! bright the highlight is live here, so both cases share one formula.

use super::fresnel::FresnelMode;
use super::material::Highlight;
use crate::math::{Color, Vec3};

/// The coefficients of Whitted's model at one point: what the `Material` fields of the
/// same names hold there (their meaning is documented on `Material`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(missing_docs)]
pub struct Coefficients {
    pub ambient: f32,
    pub diffuse: f32,
    pub specular: f32,
    pub shininess: f32,
    pub highlight: Highlight,
    pub reflect: f32,
    pub transmit: Color,
    pub ior: f32,
    pub fresnel: FresnelMode,
    pub emission: Color,
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

impl Coefficients {
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
        self.highlight_of(self.highlight_cosine(n, l, v))
    }

    /// The cosine the highlight raises to `shininess`: R·V (Phong) or N·H (Blinn–Phong).
    #[inline]
    fn highlight_cosine(&self, n: Vec3, l: Vec3, v: Vec3) -> f32 {
        match self.highlight {
            Highlight::Phong => super::optics::reflect(-l, n).dot(v),
            Highlight::BlinnPhong => match (l + v).try_normalize() {
                Some(h) => n.dot(h),
                None => 0.0,
            },
        }
    }

    /// The highlight for cosine `c` (with `specular > 0`).
    #[inline]
    fn highlight_of(&self, c: f32) -> f32 {
        if c <= 0.0 {
            0.0
        } else {
            self.specular * c.powf(self.shininess)
        }
    }

    /// `highlight_term(n, l, v)` where it is needed only when it is not zero: `None`
    /// when it is certainly not zero (left to be worked out later, if at all), else its
    /// value. Bounds decide most cases without the power function: a sharp highlight
    /// (glass's exponent of 200) underflows to exactly zero a few degrees off the mirror
    /// direction and is large near it, and shading asks only which, to know whether a
    /// shadow ray could add anything. The power is worked out (exactly as
    /// `highlight_term` does) only in the band between.
    #[inline]
    pub fn highlight_unless_nonzero(&self, n: Vec3, l: Vec3, v: Vec3) -> Option<f32> {
        if self.specular <= 0.0 {
            return Some(0.0);
        }
        self.highlight_decision(self.highlight_cosine(n, l, v)).0
    }

    /// `highlight_unless_nonzero` for cosine `c` (with `specular > 0`), and whether the
    /// bounds decided it without the power function.
    #[inline(always)]
    fn highlight_decision(&self, c: f32) -> (Option<f32>, bool) {
        match power_bound(c, self.shininess) {
            // c^s ≤ 2⁻¹⁶⁰: `powf` returns +0 (its true value is far below the smallest
            // subnormal), and so does the product.
            Some((_, high)) if high <= -160.0 => (Some(0.0), true),
            // c^s ≥ 2⁻¹⁰⁰ and ks ≥ 2⁻²⁰: the product is a normal number, not zero.
            Some((low, _)) if low >= -100.0 && self.specular >= SPECULAR_FLOOR => (None, true),
            _ => (Some(self.highlight_of(c)), false),
        }
    }
}

/// 2⁻²⁰: a highlight weight at least this, times a power of at least 2⁻¹⁰⁰, is a normal
/// number.
const SPECULAR_FLOOR: f32 = 1.0 / (1u32 << 20) as f32;

/// Bounds on log₂(cˢ) for 0 < c < 1 and a finite s ≥ 1, from c's exponent and mantissa
/// alone: with c = 2ᴱ(1 + x), x ≤ log₂(1 + x) ≤ x + 0.0861 (the gap peaks at
/// x = 1/ln 2 − 1), widened to 0.09 and worked out in f64, so the bounds hold with room
/// to spare. None outside that domain (NaN included).
#[inline]
fn power_bound(c: f32, s: f32) -> Option<(f64, f64)> {
    if !(c > 0.0 && c < 1.0 && s >= 1.0 && s.is_finite()) {
        return None;
    }
    let bits = c.to_bits();
    let biased = (bits >> 23) & 0xff;
    let mantissa = f64::from(bits & 0x7f_ffff) / f64::from(1u32 << 23);
    // A subnormal c is below 2⁻¹²⁶ = 2^(0 − 126) (its "x" taken as 0 bounds it above too).
    let (e, x) = if biased == 0 {
        (-126.0, 0.0)
    } else {
        (f64::from(biased) - 127.0, mantissa)
    };
    let s = f64::from(s);
    let low = if biased == 0 {
        f64::NEG_INFINITY
    } else {
        s * (e + x)
    };
    Some((low, s * (e + x + 0.09)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::hash::uniform;
    use crate::shading::Material;

    /// The bounds' decision is the power function's: `None` only where the highlight is
    /// not zero, a value only as `highlight_term` computes it, bit for bit; over cosines
    /// across every binade (subnormals, the band near the underflow, just below one) and
    /// exponents from 1 to 10⁴. Both bounds must also decide most of them, or the
    /// shortcut would buy nothing.
    #[test]
    fn the_bounds_decide_as_the_power_does() {
        let mut cosines: Vec<f32> = (0..4000)
            .map(|k| 2f32.powf(-160.0 * uniform(k, 1, 0, 0, 5)))
            .collect();
        cosines.extend((0..2000).map(|k| uniform(k, 2, 0, 0, 5)));
        cosines.extend([
            f32::from_bits(1),
            f32::MIN_POSITIVE,
            0.5,
            1.0 - f32::EPSILON,
            1.0,
            1.5,
            0.0,
            -0.3,
            f32::NAN,
        ]);
        let (mut decided, mut total) = (0, 0);
        for shininess in [1.0f32, 2.0, 7.5, 20.0, 80.0, 200.0, 1000.0, 1e4] {
            for specular in [1e-7f32, 0.01, 0.7, 1.0] {
                let m = Coefficients {
                    specular,
                    shininess,
                    ..Material::default().coefficients()
                };
                for &c in &cosines {
                    let exact = m.highlight_of(c);
                    let (decision, by_bounds) = m.highlight_decision(c);
                    total += 1;
                    decided += usize::from(by_bounds);
                    match decision {
                        None => assert!(exact != 0.0, "c {c} s {shininess} ks {specular}"),
                        Some(h) => assert_eq!(
                            h.to_bits(),
                            exact.to_bits(),
                            "c {c} s {shininess} ks {specular}"
                        ),
                    }
                    // The bounds bracket the exact logarithm.
                    if let Some((low, high)) = power_bound(c, shininess) {
                        let log = f64::from(shininess) * f64::from(c).log2();
                        assert!(low <= log && log <= high, "c {c}: {low} {log} {high}");
                    }
                }
            }
        }
        assert!(decided * 2 > total, "decided {decided} of {total}");
    }

    /// Through the public entry: the same cosine as `highlight_term`, for both lobes.
    #[test]
    fn the_decision_matches_highlight_term() {
        for highlight in [Highlight::Phong, Highlight::BlinnPhong] {
            let m = Coefficients {
                specular: 0.7,
                shininess: 200.0,
                highlight,
                ..Material::default().coefficients()
            };
            let dir = |k: u32| {
                let u = |j: u32| uniform(k, j, 0, 0, 9) * 2.0 - 1.0;
                Vec3::new(u(0), u(1), u(2)).normalize()
            };
            let n = Vec3::Y;
            let (mut none, mut zero) = (0, 0);
            for k in 0..20_000 {
                let (l, v) = (dir(2 * k), dir(2 * k + 1));
                let term = m.highlight_term(n, l, v);
                match m.highlight_unless_nonzero(n, l, v) {
                    None => {
                        none += 1;
                        assert!(term != 0.0);
                    }
                    Some(h) => {
                        zero += usize::from(h == 0.0);
                        assert_eq!(h.to_bits(), term.to_bits());
                    }
                }
            }
            assert!(none > 0 && zero > 0);
        }
    }
}
