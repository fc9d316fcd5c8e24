//! `[[lights]]` entries to `Light`s: colour times intensity.

use super::diagnostics::Problem;
use super::schema::LightDef;
use super::values::{NonNegative, Rgb};
use crate::light::Light;
use crate::math::Color;
use toml::Spanned;

/// The light whose table is `def`.
pub fn light(def: Spanned<LightDef>) -> Result<Light, Problem> {
    let span = def.span();
    let scaled = |color: Option<Rgb>, intensity: Option<NonNegative>| {
        let c = color.map_or(Color::ONE, |c| c.0) * intensity.map_or(1.0, |i| i.0);
        if c.is_finite() {
            Ok(c)
        } else {
            Err(Problem::at(
                span.clone(),
                "the light's color × intensity overflows: expected a finite product",
            ))
        }
    };
    Ok(match def.into_inner() {
        LightDef::Point(p) => Light::Point {
            position: p.position.0,
            color: scaled(p.color, p.intensity)?,
        },
        LightDef::Directional(d) => Light::Directional {
            direction: d.direction.0,
            color: scaled(d.color, d.intensity)?,
        },
    })
}
