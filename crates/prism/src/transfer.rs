//! How pixel values reach a display: the output transfer.
//!
//! prism's colours are linear light by default, and an 8-bit image gets the sRGB curve.
//! Formats from before colour management (NFF, 1987) mean their colours as display values:
//! the SPD's own pictures write kd·C·(N·L) straight into the frame buffer. For those the
//! transfer is `Display`: values are written as they are. Everything that judges a picture
//! as shown (8-bit output, the adaptive sampler's contrast, the image metrics) asks this
//! module, so one setting changes them together.

use serde::{Deserialize, Serialize};

/// What a film's values mean, and so how they become 8-bit display values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Transfer {
    /// Linear light; displayed through the sRGB curve.
    #[default]
    Srgb,
    /// Display-referred: already display values, written as they are.
    Display,
}

impl Transfer {
    /// Every transfer, in the order their names are listed.
    pub const ALL: [Transfer; 2] = [Transfer::Srgb, Transfer::Display];

    /// The name the scene file and the command line use.
    pub fn name(self) -> &'static str {
        match self {
            Transfer::Srgb => "srgb",
            Transfer::Display => "display",
        }
    }

    /// The display value in [0, 1] of a film value (clamped; NaN counts as 0).
    #[inline]
    pub fn encode(self, v: f32) -> f32 {
        let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
        match self {
            Transfer::Srgb => srgb_encode(v),
            Transfer::Display => v,
        }
    }

    /// The 8-bit display value of a film value.
    #[inline]
    pub fn encode8(self, v: f32) -> u8 {
        (self.encode(v) * 255.0 + 0.5) as u8
    }

    /// The linear light a display shows for a film value: the value itself for `Srgb`
    /// (unclamped, so that HDR files keep their range), the sRGB decoding of the clamped
    /// value for `Display`. Float images and the metrics use this, so that a picture means
    /// the same in every file and a display-referred render compares with its PNG.
    #[inline]
    pub fn to_linear(self, v: f32) -> f32 {
        match self {
            Transfer::Srgb => v,
            Transfer::Display => srgb_decode(self.encode(v)),
        }
    }
}

impl std::str::FromStr for Transfer {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Transfer::ALL
            .into_iter()
            .find(|t| t.name() == s)
            .ok_or_else(|| format!("unknown transfer '{s}', expected srgb or display"))
    }
}

impl std::fmt::Display for Transfer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// The sRGB encoding curve on [0, 1].
#[inline]
pub fn srgb_encode(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The sRGB decoding curve on [0, 1].
#[inline]
pub fn srgb_decode(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_values_are_written_as_they_are() {
        // SPD's sky, b 0.078 0.361 0.753: (20, 92, 192) as written, (79, 162, 225) through
        // the sRGB curve.
        let sky = [0.078, 0.361, 0.753];
        assert_eq!(sky.map(|v| Transfer::Display.encode8(v)), [20, 92, 192]);
        assert_eq!(sky.map(|v| Transfer::Srgb.encode8(v)), [79, 162, 225]);
        assert_eq!(Transfer::Display.encode8(1.7), 255);
        assert_eq!(Transfer::Display.encode8(f32::NAN), 0);
    }

    #[test]
    fn to_linear_inverts_what_the_display_encodes() {
        for i in 0..=100 {
            let v = i as f32 / 100.0;
            let back = srgb_encode(Transfer::Display.to_linear(v));
            assert!((back - v).abs() < 1e-5, "{v} → {back}");
            assert_eq!(Transfer::Srgb.to_linear(v), v);
        }
        assert_eq!(Transfer::Srgb.to_linear(3.5), 3.5, "HDR values kept");
    }

    #[test]
    fn names_round_trip() {
        for t in Transfer::ALL {
            assert_eq!(t.name().parse::<Transfer>(), Ok(t));
        }
        assert!("gamma"
            .parse::<Transfer>()
            .unwrap_err()
            .contains("srgb or display"));
    }
}
