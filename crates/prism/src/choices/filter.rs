//! The reconstruction filter's name (`--filter`, the scene file's `filter`) and its usual
//! radius; the filters themselves live in `render::filter`.

use serde::{Deserialize, Serialize};

/// Largest accepted filter radius, in pixels.
pub const MAX_FILTER_RADIUS: f32 = 8.0;

/// The reconstruction filters a render can use (`--filter`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FilterKind {
    /// Every sample within the radius counts the same; radius 0.5 is the pixel itself.
    #[default]
    Box,
    /// Weight falling linearly to 0 at the radius.
    Tent,
    /// exp(−d²/2σ²) with σ = radius/3, shifted down to reach 0 at the radius.
    Gaussian,
    /// Mitchell–Netravali cubic with B = C = 1/3: sharper, with small negative lobes.
    Mitchell,
}

named_kinds! {
    FilterKind, "filter" {
        Box => "box",
        Tent => "tent",
        Gaussian => "gaussian",
        Mitchell => "mitchell",
    }
}

impl FilterKind {
    /// Radius in pixels when the options give none.
    pub fn default_radius(self) -> f32 {
        match self {
            FilterKind::Box => 0.5,
            FilterKind::Tent => 1.0,
            FilterKind::Gaussian => 1.5,
            FilterKind::Mitchell => 2.0,
        }
    }
}
