//! Checked value types of the scene format: numbers that must be finite (and perhaps
//! non-negative or positive), points, non-zero directions, colours and scale factors.
//!
//! They check while deserializing, so the toml crate attaches the span of the offending
//! value to the error and the message can point at it.

use prism::math::{Color, Vec2, Vec3};
use serde::de::{self, Deserializer, SeqAccess, Unexpected, Visitor};
use serde::Deserialize;
use std::fmt;

/// A finite number, written as a TOML integer or float.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Finite(pub f32);

/// A finite number ≥ 0 (radii, weights, intensities).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct NonNegative(pub f32);

/// A finite number > 0 (sizes, indices of refraction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Positive(pub f32);

/// A position or offset `[x, y, z]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Point(pub Vec3);

/// A direction `[x, y, z]` of any non-zero length, stored normalised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Direction(pub Vec3);

/// A texture coordinate `[u, v]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Uv(pub Vec2);

/// A linear RGB colour `[r, g, b]` with components ≥ 0, or one number for a grey.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Rgb(pub Color);

/// A scale factor per axis, each finite and non-zero, written as one number (uniform) or
/// `[x, y, z]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Scale3(pub Vec3);

/// A positive scale per texture axis, one number (uniform) or `[u, v]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Scale2(pub Vec2);

/// Accepts TOML integers and floats; `what` completes "expected …" in messages.
struct NumberVisitor {
    what: &'static str,
}

impl<'de> Visitor<'de> for NumberVisitor {
    type Value = f32;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(self.what)
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<f32, E> {
        Ok(v as f32)
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<f32, E> {
        Ok(v as f32)
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<f32, E> {
        finite(v, self.what)
    }
}

/// `v` as an f32, or the error for nan, ±inf and doubles beyond the f32 range.
fn finite<E: de::Error>(v: f64, what: &str) -> Result<f32, E> {
    let f = v as f32;
    if f.is_finite() {
        return Ok(f);
    }
    let got = if v.is_nan() {
        "nan".to_string()
    } else if v.is_infinite() {
        format!("{v}")
    } else {
        format!("{v:e}, beyond the ±3.4e38 range of 32-bit floats")
    };
    Err(E::custom(format!("expected {what}, got {got}")))
}

fn number<'de, D: Deserializer<'de>>(d: D, what: &'static str) -> Result<f32, D::Error> {
    d.deserialize_any(NumberVisitor { what })
}

impl<'de> Deserialize<'de> for Finite {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        number(d, "a finite number").map(Finite)
    }
}

impl<'de> Deserialize<'de> for NonNegative {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = number(d, "a finite number ≥ 0")?;
        if v < 0.0 {
            return Err(de::Error::custom(format!("expected a number ≥ 0, got {v}")));
        }
        Ok(NonNegative(v))
    }
}

impl<'de> Deserialize<'de> for Positive {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = number(d, "a finite number > 0")?;
        if v <= 0.0 {
            return Err(de::Error::custom(format!("expected a number > 0, got {v}")));
        }
        Ok(Positive(v))
    }
}

/// Reads exactly `N` numbers from an array, or (when `scalar` is set) one number that
/// stands for all `N`.
struct ArrayVisitor<const N: usize> {
    what: &'static str,
    scalar: bool,
}

impl<'de, const N: usize> Visitor<'de> for ArrayVisitor<N> {
    type Value = [f32; N];

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(self.what)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[f32; N], A::Error> {
        let mut out = [0.0; N];
        for (i, slot) in out.iter_mut().enumerate() {
            match seq.next_element::<Finite>()? {
                Some(Finite(v)) => *slot = v,
                None => return Err(de::Error::invalid_length(i, &self)),
            }
        }
        let mut extra = 0;
        while seq.next_element::<de::IgnoredAny>()?.is_some() {
            extra += 1;
        }
        if extra > 0 {
            return Err(de::Error::invalid_length(N + extra, &self));
        }
        Ok(out)
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<[f32; N], E> {
        self.scalar_value(v as f32, Unexpected::Signed(v))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<[f32; N], E> {
        self.scalar_value(v as f32, Unexpected::Unsigned(v))
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<[f32; N], E> {
        self.scalar_value(finite(v, "a finite number")?, Unexpected::Float(v))
    }
}

impl<const N: usize> ArrayVisitor<N> {
    fn scalar_value<E: de::Error>(&self, v: f32, unexpected: Unexpected) -> Result<[f32; N], E> {
        if self.scalar {
            Ok([v; N])
        } else {
            Err(E::invalid_type(unexpected, self))
        }
    }
}

fn array<'de, D: Deserializer<'de>, const N: usize>(
    d: D,
    what: &'static str,
    scalar: bool,
) -> Result<[f32; N], D::Error> {
    d.deserialize_any(ArrayVisitor::<N> { what, scalar })
}

impl<'de> Deserialize<'de> for Point {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        array(d, "an array of 3 numbers [x, y, z]", false).map(|a| Point(Vec3::from_array(a)))
    }
}

impl<'de> Deserialize<'de> for Direction {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = Vec3::from_array(array(d, "a direction [x, y, z]", false)?);
        // Divide by the largest component first: tiny and huge vectors normalise alike.
        let largest = v.abs().max_element();
        match (v / largest).try_normalize() {
            Some(n) if largest > 0.0 => Ok(Direction(n)),
            _ => Err(de::Error::custom(
                "expected a direction of non-zero length, got [0, 0, 0]",
            )),
        }
    }
}

impl<'de> Deserialize<'de> for Uv {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        array(d, "an array of 2 numbers [u, v]", false).map(|a| Uv(Vec2::from_array(a)))
    }
}

impl<'de> Deserialize<'de> for Rgb {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let c = array(d, "a colour: [r, g, b] or one number for a grey", true)?;
        if c.iter().any(|&v| v < 0.0) {
            return Err(de::Error::custom(format!(
                "expected colour components ≥ 0, got {c:?}"
            )));
        }
        Ok(Rgb(Color::from_array(c)))
    }
}

impl<'de> Deserialize<'de> for Scale3 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = array(d, "a scale: one number or [x, y, z]", true)?;
        if s.contains(&0.0) {
            return Err(de::Error::custom(format!(
                "expected non-zero scale factors, got {s:?}"
            )));
        }
        Ok(Scale3(Vec3::from_array(s)))
    }
}

impl<'de> Deserialize<'de> for Scale2 {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = array(d, "a scale: one number or [u, v]", true)?;
        if s.iter().any(|&v| v <= 0.0) {
            return Err(de::Error::custom(format!(
                "expected scale factors > 0, got {s:?}"
            )));
        }
        Ok(Scale2(Vec2::from_array(s)))
    }
}
