//! Fresnel reflectance of a dielectric interface for unpolarised light: the exact
//! equations and Schlick's approximation.

use serde::{Deserialize, Serialize};

/// How a material splits light between reflection and refraction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FresnelMode {
    /// Constant coefficients: reflection `kr`, transmission `kt` (Whitted 1980).
    #[default]
    Off,
    /// The exact Fresnel equations, averaged over both polarisations.
    Exact,
    /// Schlick's approximation R₀ + (1 − R₀)(1 − cosθ)⁵.
    Schlick,
}

/// Exact unpolarised reflectance. `cos_i` is the cosine of the incident angle (≥ 0) and
/// `eta` = η_incident / η_transmitted. Returns 1 under total internal reflection.
pub fn exact(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    // The parallel and perpendicular amplitude ratios, divided through by η_t.
    let r_par = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_perp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (r_par * r_par + r_perp * r_perp)
}

/// Schlick's approximation. On leaving the denser medium it uses the transmitted angle,
/// as it must to agree with the exact form, and reports TIR as 1.
pub fn schlick(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let r0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
    let cos = if eta > 1.0 {
        let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
        if sin2_t >= 1.0 {
            return 1.0;
        }
        (1.0 - sin2_t).sqrt()
    } else {
        cos_i
    };
    r0 + (1.0 - r0) * (1.0 - cos).powi(5)
}

impl FresnelMode {
    /// Reflectance for this mode, or `None` when Fresnel is off.
    pub fn reflectance(self, cos_i: f32, eta: f32) -> Option<f32> {
        match self {
            FresnelMode::Off => None,
            FresnelMode::Exact => Some(exact(cos_i, eta)),
            FresnelMode::Schlick => Some(schlick(cos_i, eta)),
        }
    }
}
