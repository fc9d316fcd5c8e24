//! Light sources of the Whitted model: points and directions, without falloff (as in
//! Whitted 1980 and POV-Ray's default), so a light's colour is the irradiance it gives a
//! surface facing it.

use crate::math::{Color, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    Point {
        position: Vec3,
        color: Color,
    },
    /// Light arriving from infinitely far away, travelling along `direction` (unit).
    Directional {
        direction: Vec3,
        color: Color,
    },
}

/// What a light offers a shading point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit vector from the shading point towards the light.
    pub to_light: Vec3,
    /// Distance to the light (infinite for directional lights).
    pub distance: f32,
    pub color: Color,
}

impl Light {
    pub fn sample(&self, p: Vec3) -> Option<LightSample> {
        match *self {
            Light::Point { position, color } => {
                let d = position - p;
                let distance = d.length();
                (distance > 0.0).then(|| LightSample {
                    to_light: d / distance,
                    distance,
                    color,
                })
            }
            Light::Directional { direction, color } => Some(LightSample {
                to_light: -direction,
                distance: f32::INFINITY,
                color,
            }),
        }
    }
}
