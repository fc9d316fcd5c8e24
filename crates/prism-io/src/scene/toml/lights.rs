//! `[[lights]]` entries to `Light`s: colour times intensity.

use super::diagnostics::Problem;
use super::schema::LightDef;
use super::values::{NonNegative, Rgb};
use prism::light::Light;
use prism::math::Color;
use toml::Spanned;

/// A spot light's outer cone angle when the file gives none: glTF's default, π/4.
const DEFAULT_SPOT_OUTER_DEGREES: f32 = 45.0;

/// The light whose table is `def`.
pub(super) fn light(def: Spanned<LightDef>) -> Result<Light, Problem> {
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
        LightDef::Spot(s) => {
            let angle = |a: &Option<Spanned<NonNegative>>, default: f32| {
                a.as_ref().map_or(Ok(default), |a| {
                    let v = a.get_ref().0;
                    if v <= 90.0 {
                        Ok(v)
                    } else {
                        Err(Problem::at(
                            a.span(),
                            format!("a cone angle of {v}°: expected 0 to 90 degrees"),
                        ))
                    }
                })
            };
            let outer = angle(&s.outer_angle, DEFAULT_SPOT_OUTER_DEGREES)?;
            let inner = angle(&s.inner_angle, 0.0)?;
            if inner > outer {
                let span = s.inner_angle.as_ref().map_or(span.clone(), |a| a.span());
                return Err(Problem::at(
                    span,
                    format!(
                        "inner_angle {inner}° is wider than outer_angle {outer}°: expected \
                         inner ≤ outer"
                    ),
                ));
            }
            Light::Spot {
                position: s.position.0,
                direction: s.direction.0,
                color: scaled(s.color, s.intensity)?,
                cos_inner: inner.to_radians().cos(),
                cos_outer: outer.to_radians().cos(),
            }
        }
    })
}
