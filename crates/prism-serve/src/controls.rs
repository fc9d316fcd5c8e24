//! The settings a page may change, as data: each control's name, label, kind and choices
//! go to the page in the `hello` message and the page builds its panel from them, so a new
//! choice is one line here and none in the page. `parse` turns a control's text value into
//! a checked [`Setting`] before it reaches the render thread.

use crate::limits::{MAX_DEPTH, MAX_PIXELS, MAX_SIDE, MIN_SIDE};
use prism::accel::AccelSpec;
use prism::integrator::{ShadowMethod, ShadowSpec};
use prism::sampling::SamplerKind;
use prism::RenderOptions;
use serde::Serialize;

/// The integrators the viewer offers, by their `RenderOptions::integrator` names.
pub const INTEGRATORS: &[&str] = &["whitted", "path"];

/// Suggested accelerator specs; the control takes any `--accel` spec.
pub const ACCELERATORS: &[&str] = &["bvh", "bvh:width=4", "kdtree", "grid", "octree"];

/// Samplers that give a new pattern each frame (or none: `centre`) at one sample per pixel;
/// grid-like and lattice samplers would trace the same rays every frame.
pub const SAMPLERS: &[SamplerKind] = &[
    SamplerKind::Jittered,
    SamplerKind::Random,
    SamplerKind::Centre,
];

/// Suggested thresholds of adaptive depth control and adaptive shadow testing: 0 traces
/// every ray, 1/255 (prism's default) what could change an 8-bit pixel; the control takes
/// any number or fraction from 0 to 1.
pub const MIN_WEIGHTS: &[&str] = &["0", "1/1024", "1/255", "1/64", "1/16"];

/// Suggested resolutions; the control takes any `WIDTHxHEIGHT` within the limits.
pub const RESOLUTIONS: &[&str] = &["320x180", "640x360", "960x540", "1280x720", "1920x1080"];

/// What the picture shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum View {
    /// The render.
    #[default]
    Image,
    /// Acceleration-structure node visits per camera ray, as a heat map.
    Cost,
    /// Rays (of every kind) per pixel and frame, as a heat map.
    Density,
}

impl View {
    /// Every view, as the control lists them.
    pub const ALL: [View; 3] = [View::Image, View::Cost, View::Density];

    /// The view's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            View::Image => "image",
            View::Cost => "cost",
            View::Density => "density",
        }
    }
}

/// A checked new value of one setting.
#[derive(Clone, Debug, PartialEq)]
pub enum Setting {
    /// The integrator, one of [`INTEGRATORS`].
    Integrator(String),
    /// The acceleration structure (rebuilds the prepared scene).
    Accel(AccelSpec),
    /// The sampling pattern.
    Sampler(SamplerKind),
    /// The ray-tree depth limit.
    Depth(u32),
    /// The weight below which Whitted rays and shadow rays are not traced
    /// (`RenderOptions::min_weight`).
    MinWeight(f32),
    /// The shadow-ray method.
    Shadows(ShadowSpec),
    /// What the picture shows.
    View(View),
    /// Width and height in pixels.
    Resolution(u32, u32),
}

impl Setting {
    /// Puts the setting on `options`, as a render reads it; `view`, which changes only
    /// what the picture shows, leaves them as they are.
    pub fn apply(&self, options: &mut RenderOptions) {
        match self {
            // `parse` accepts only the names in INTEGRATORS, which all parse.
            Setting::Integrator(name) => {
                if let Ok(kind) = name.parse() {
                    options.integrator = kind;
                }
            }
            Setting::Accel(spec) => options.accel = spec.clone(),
            Setting::Sampler(kind) => options.sampler = *kind,
            Setting::Depth(depth) => options.max_depth = *depth,
            Setting::MinWeight(w) => options.min_weight = *w,
            Setting::Shadows(spec) => options.shadows = *spec,
            Setting::View(_) => {}
            Setting::Resolution(w, h) => (options.width, options.height) = (*w, *h),
        }
    }
}

/// How the page shows a control.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ControlKind {
    /// A drop-down of the choices.
    Choice,
    /// A text field, with the choices as suggestions.
    Text,
    /// A number field between `min` and `max`.
    Number,
}

/// One control as the page receives it.
#[derive(Clone, Debug, Serialize)]
pub struct Control {
    /// Its name in `set` messages.
    pub name: &'static str,
    /// What the page shows beside it.
    pub label: &'static str,
    /// Drop-down, text or number.
    pub kind: ControlKind,
    /// The choices, or suggestions for a text control.
    pub choices: Vec<String>,
    /// Smallest number (number controls).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min: Option<u32>,
    /// Largest number (number controls).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max: Option<u32>,
}

fn control(
    name: &'static str,
    label: &'static str,
    kind: ControlKind,
    choices: Vec<String>,
) -> Control {
    Control {
        name,
        label,
        kind,
        choices,
        min: None,
        max: None,
    }
}

/// Every control, in the order the page shows them.
pub fn controls() -> Vec<Control> {
    let strings = |list: &[&str]| list.iter().map(|s| s.to_string()).collect();
    vec![
        control(
            "integrator",
            "integrator",
            ControlKind::Choice,
            strings(INTEGRATORS),
        ),
        control(
            "accel",
            "accelerator",
            ControlKind::Text,
            strings(ACCELERATORS),
        ),
        control(
            "sampler",
            "sampler",
            ControlKind::Choice,
            SAMPLERS.iter().map(|s| s.name().to_string()).collect(),
        ),
        Control {
            min: Some(1),
            max: Some(MAX_DEPTH),
            ..control("depth", "max depth", ControlKind::Number, Vec::new())
        },
        control(
            "min_weight",
            "min weight",
            ControlKind::Text,
            strings(MIN_WEIGHTS),
        ),
        control(
            "shadows",
            "shadow rays",
            ControlKind::Choice,
            ShadowMethod::NAMES.iter().map(|s| s.to_string()).collect(),
        ),
        control(
            "view",
            "view",
            ControlKind::Choice,
            View::ALL.iter().map(|v| v.name().to_string()).collect(),
        ),
        control(
            "resolution",
            "resolution",
            ControlKind::Text,
            strings(RESOLUTIONS),
        ),
    ]
}

/// The setting of the settings table (`prism::options::SETTINGS`) that control `name`
/// changes, or None for the viewer's own controls (`view`; `resolution`, which sets
/// `width` and `height` together).
pub fn setting_key(name: &str) -> Option<&'static str> {
    match name {
        "depth" => Some("max_depth"),
        "view" | "resolution" => None,
        other => prism::options::setting(other).map(|s| s.key),
    }
}

/// Checks `value` for the control `name`; the error says what is accepted.
pub fn parse(name: &str, value: &str) -> Result<Setting, String> {
    let value = value.trim();
    match name {
        "integrator" => match INTEGRATORS.contains(&value) {
            true => Ok(Setting::Integrator(value.to_string())),
            false => Err(format!(
                "unknown integrator '{value}'; available: {}",
                INTEGRATORS.join(", ")
            )),
        },
        "accel" => value.parse::<AccelSpec>().map(Setting::Accel),
        "sampler" => {
            let kind: SamplerKind = value.parse()?;
            if !SAMPLERS.contains(&kind) {
                return Err(format!(
                    "the viewer takes one sample per pixel and frame from {}; '{value}' is \
                     not one of them",
                    SAMPLERS
                        .iter()
                        .map(|s| s.name())
                        .collect::<Vec<_>>()
                        .join(", ")
                ));
            }
            Ok(Setting::Sampler(kind))
        }
        "depth" => match value.parse::<u32>() {
            Ok(d) if (1..=MAX_DEPTH).contains(&d) => Ok(Setting::Depth(d)),
            _ => Err(format!(
                "depth must be a whole number from 1 to {MAX_DEPTH}, got '{value}'"
            )),
        },
        "min_weight" => min_weight(value).map(Setting::MinWeight),
        "shadows" => value.parse::<ShadowSpec>().map(Setting::Shadows),
        "view" => View::ALL
            .into_iter()
            .find(|v| v.name() == value)
            .map(Setting::View)
            .ok_or_else(|| format!("unknown view '{value}'; available: image, cost, density")),
        "resolution" => resolution(value).map(|(w, h)| Setting::Resolution(w, h)),
        _ => Err(format!(
            "unknown control '{name}'; available: {}",
            controls()
                .iter()
                .map(|c| c.name)
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// A weight from 0 to 1, as a number or a fraction `A/B`.
fn min_weight(value: &str) -> Result<f32, String> {
    let bad =
        || format!("min weight must be a number or a fraction A/B from 0 to 1, got '{value}'");
    let w = match value.split_once('/') {
        Some((a, b)) => {
            let (a, b): (f32, f32) = (
                a.trim().parse().map_err(|_| bad())?,
                b.trim().parse().map_err(|_| bad())?,
            );
            a / b
        }
        None => value.parse().map_err(|_| bad())?,
    };
    if (0.0..=1.0).contains(&w) {
        // A negative zero is a zero.
        Ok(w.abs())
    } else {
        Err(bad())
    }
}

/// How the state message shows a weight: `1/N` where that is the value exactly.
pub fn weight_text(w: f32) -> String {
    let n = (1.0 / w).round();
    if w > 0.0 && w < 1.0 && n.is_finite() && n <= 1e6 && 1.0 / n == w {
        format!("1/{n}")
    } else {
        w.to_string()
    }
}

/// `WIDTHxHEIGHT` within the limits.
fn resolution(value: &str) -> Result<(u32, u32), String> {
    let bad = || {
        format!(
            "resolution must be WIDTHxHEIGHT, each side {MIN_SIDE} to {MAX_SIDE} pixels and \
             at most {MAX_PIXELS} pixels in all, got '{value}'"
        )
    };
    let (w, h) = value.split_once(['x', 'X', '×']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    let side = MIN_SIDE..=MAX_SIDE;
    if !side.contains(&w) || !side.contains(&h) || w as u64 * h as u64 > MAX_PIXELS as u64 {
        return Err(bad());
    }
    Ok((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The viewer offers a subset of the settings (those worth changing between frames);
    /// each is a setting of the table under its key, and a value it accepts the table
    /// accepts too.
    #[test]
    fn every_control_is_a_setting_of_the_table_or_the_viewers_own() {
        for c in controls() {
            match setting_key(c.name) {
                Some(key) => {
                    let setting = prism::options::setting(key).unwrap();
                    for choice in &c.choices {
                        let text = match key {
                            // The viewer writes weights as fractions too.
                            "min_weight" => match parse(c.name, choice) {
                                Ok(Setting::MinWeight(w)) => w.to_string(),
                                other => panic!("{choice}: {other:?}"),
                            },
                            _ => choice.clone(),
                        };
                        let mut o = prism::RenderOptions::default();
                        setting
                            .set(&mut o, &text)
                            .unwrap_or_else(|e| panic!("{}: {choice}: {e}", c.name));
                    }
                }
                None => assert!(["view", "resolution"].contains(&c.name), "{}", c.name),
            }
        }
    }

    #[test]
    fn every_listed_choice_parses() {
        for c in controls() {
            for choice in &c.choices {
                assert!(parse(c.name, choice).is_ok(), "{} = {choice}", c.name);
            }
        }
    }

    #[test]
    fn bad_values_name_what_is_accepted() {
        for (name, value) in [
            ("resolution", "100000x100000"),
            ("resolution", "4000x4000"),
            ("resolution", "8x8"),
            ("resolution", "-1x5"),
            ("depth", "0"),
            ("depth", "99999999999999999999"),
            ("min_weight", "-0.1"),
            ("min_weight", "1.5"),
            ("min_weight", "NaN"),
            ("min_weight", "1/0"),
            ("min_weight", "0/0"),
            ("min_weight", "a/b"),
            ("min_weight", ""),
            ("accel", "nonsense"),
            ("sampler", "adaptive"),
            ("integrator", "beam"),
            ("volume", "11"),
        ] {
            let e = parse(name, value).unwrap_err();
            assert!(!e.is_empty(), "{name} = {value}");
        }
        assert_eq!(
            parse("resolution", "640x360"),
            Ok(Setting::Resolution(640, 360))
        );
    }

    #[test]
    fn weights_parse_as_numbers_and_fractions_and_read_back() {
        assert_eq!(parse("min_weight", "0"), Ok(Setting::MinWeight(0.0)));
        assert_eq!(parse("min_weight", "-0"), Ok(Setting::MinWeight(0.0)));
        assert_eq!(parse("min_weight", "1"), Ok(Setting::MinWeight(1.0)));
        assert_eq!(parse("min_weight", "0.25"), Ok(Setting::MinWeight(0.25)));
        assert_eq!(
            parse("min_weight", " 1 / 255 "),
            Ok(Setting::MinWeight(1.0 / 255.0))
        );
        assert_eq!(weight_text(1.0 / 255.0), "1/255");
        assert_eq!(weight_text(1.0), "1");
        assert_eq!(weight_text(0.0), "0");
        assert_eq!(weight_text(0.3), "0.3");
        for text in MIN_WEIGHTS {
            let Ok(Setting::MinWeight(w)) = parse("min_weight", text) else {
                panic!("{text}");
            };
            assert_eq!(&weight_text(w), text);
        }
    }
}
