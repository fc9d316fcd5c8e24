//! Mirror reflection and Snell refraction of unit directions.

use crate::math::Vec3;

/// ω_o = ω_i − 2(ω_i·n)n, for an incident direction `wi` travelling towards the surface.
#[inline]
pub fn reflect(wi: Vec3, n: Vec3) -> Vec3 {
    wi - 2.0 * wi.dot(n) * n
}

/// Refracts `wi` (travelling towards the surface) through a surface with normal `n` facing
/// the incident side, with `eta` = η_incident / η_transmitted. `None` on total internal
/// reflection, i.e. when sin²θt = η²·sin²θi > 1.
#[inline]
pub fn refract(wi: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -wi.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t > 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((eta * wi + (eta * cos_i - cos_t) * n).normalize())
}
