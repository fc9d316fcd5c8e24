//! The settings table: every setting of `RenderOptions` once, with its key (as the scene
//! file's `[render]` table writes it), its command-line flag, what it accepts, its default
//! and its help. `RenderOptions::set` parses a setting's text through it, and the front
//! ends read it: the command line's help texts, the Python keywords and the viewer's
//! controls, and docs/scene-format.md's `[render]` table are held to it by tests, so a
//! setting added here that a front end misses fails a test.

use super::{
    RenderOptions, MAX_AREA_SAMPLES, MAX_DEPTH_LIMIT, MAX_FILTER_RADIUS, MAX_SAMPLES_PER_AXIS,
    MAX_THREADS,
};
use crate::choices::sampler::{MAX_DEPTH as MAX_ADAPTIVE_DEPTH, MAX_TEXTURE_N};
use crate::choices::{AdaptiveRule, FilterKind, IntegratorKind, SamplerKind, Transfer};
use std::str::FromStr;

/// What a setting accepts, as the documentation names its type.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SettingKind {
    /// A whole number in `lo..=hi`.
    Integer {
        /// Smallest accepted value.
        lo: u64,
        /// Largest accepted value.
        hi: u64,
    },
    /// A finite number in `lo..=hi`.
    Number {
        /// Smallest accepted value.
        lo: f32,
        /// Largest accepted value.
        hi: f32,
    },
    /// `true` or `false`.
    Boolean,
    /// One of these names.
    Name(&'static [&'static str]),
    /// A spec string with keys of its own (`bvh:leaf=4`), parsed by its type.
    Spec,
}

impl SettingKind {
    /// The type's name in docs/scene-format.md's `[render]` table.
    pub fn type_name(&self) -> &'static str {
        match self {
            SettingKind::Integer { .. } => "integer",
            SettingKind::Number { .. } => "number",
            SettingKind::Boolean => "boolean",
            SettingKind::Name(_) => "name",
            SettingKind::Spec => "string",
        }
    }

    /// What it accepts, as errors say it.
    pub fn expected(&self) -> String {
        match self {
            SettingKind::Integer { lo, hi } => format!("a whole number from {lo} to {hi}"),
            SettingKind::Number { lo, hi } => format!("a number from {lo} to {hi}"),
            SettingKind::Boolean => "true or false".into(),
            SettingKind::Name(names) => format!("one of: {}", names.join(", ")),
            SettingKind::Spec => "a spec, METHOD[:KEY=VALUE,...]".into(),
        }
    }
}

/// One setting of the table.
pub struct Setting {
    /// The key, as the scene file's `[render]` table and the Python keywords write it.
    pub key: &'static str,
    /// The command line's long flag (without `--`), where it has one of its own.
    pub flag: Option<&'static str>,
    /// What it accepts.
    pub kind: SettingKind,
    /// What it sets, in a sentence.
    pub help: &'static str,
    /// Its value, written as `set` reads it.
    pub get: fn(&RenderOptions) -> String,
    /// Sets it from a value already checked against `kind`.
    put: fn(&mut RenderOptions, &str) -> Result<(), String>,
}

impl Setting {
    /// The default value, written as `set` reads it.
    pub fn default_text(&self) -> String {
        (self.get)(&RenderOptions::default())
    }

    /// `--flag`, or the key where the command line has no flag of its own.
    pub fn flag_or_key(&self) -> String {
        match self.flag {
            Some(f) => format!("--{f}"),
            None => self.key.to_string(),
        }
    }

    /// Checks `text` against the kind and sets it on `options`; the error names the key.
    pub fn set(&self, options: &mut RenderOptions, text: &str) -> Result<(), String> {
        let text = text.trim();
        let bad = || {
            format!(
                "bad value '{text}' for {}: expected {}",
                self.key,
                self.kind.expected()
            )
        };
        match self.kind {
            SettingKind::Integer { lo, hi } => match text.parse::<u64>() {
                Ok(v) if (lo..=hi).contains(&v) => {}
                _ => return Err(bad()),
            },
            SettingKind::Number { lo, hi } => match text.parse::<f32>() {
                Ok(v) if v.is_finite() && (lo..=hi).contains(&v) => {}
                _ => return Err(bad()),
            },
            SettingKind::Boolean => {
                if text != "true" && text != "false" {
                    return Err(bad());
                }
            }
            SettingKind::Name(_) | SettingKind::Spec => {}
        }
        (self.put)(options, text)
    }
}

/// `text` parsed as a `T` (all checks already made).
fn parse<T: FromStr>(text: &str) -> T
where
    T::Err: std::fmt::Debug,
{
    text.parse()
        .unwrap_or_else(|e| panic!("settings table: '{text}' passed its check: {e:?}"))
}

/// A name or spec parsed by its type, whose error lists what it takes.
fn named<T: FromStr<Err = String>>(text: &str) -> Result<T, String> {
    text.parse()
}

/// Every setting, in the order of docs/scene-format.md's `[render]` table.
pub const SETTINGS: &[Setting] = &[
    Setting {
        key: "width",
        flag: Some("width"),
        kind: SettingKind::Integer { lo: 1, hi: 65536 },
        help: "Image width in pixels",
        get: |o| o.width.to_string(),
        put: |o, t| {
            o.width = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "height",
        flag: Some("height"),
        kind: SettingKind::Integer { lo: 1, hi: 65536 },
        help: "Image height in pixels",
        get: |o| o.height.to_string(),
        put: |o, t| {
            o.height = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "samples",
        flag: Some("samples"),
        kind: SettingKind::Integer {
            lo: 1,
            hi: MAX_SAMPLES_PER_AXIS as u64,
        },
        help: "Samples per pixel along each axis: N gives N×N samples per pixel (grid, \
               random, jittered and relaxed; the other samplers choose their own count)",
        get: |o| o.samples.to_string(),
        put: |o, t| {
            o.samples = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "sampler",
        flag: Some("sampler"),
        kind: SettingKind::Name(&SamplerKind::NAMES),
        help: "Sampling pattern: where a pixel's camera rays go",
        get: |o| o.sampler.to_string(),
        put: |o, t| {
            o.sampler = named(t)?;
            Ok(())
        },
    },
    Setting {
        key: "filter",
        flag: Some("filter"),
        kind: SettingKind::Name(&FilterKind::NAMES),
        help: "Reconstruction filter",
        get: |o| o.filter.to_string(),
        put: |o, t| {
            o.filter = named(t)?;
            Ok(())
        },
    },
    Setting {
        key: "filter_radius",
        flag: Some("filter-radius"),
        kind: SettingKind::Number {
            lo: 0.5,
            hi: MAX_FILTER_RADIUS,
        },
        help: "Filter radius in pixels; left out, the filter's usual radius (box 0.5, tent 1, \
               gaussian 1.5, mitchell 2)",
        get: |o| match o.filter_radius {
            Some(r) => r.to_string(),
            None => o.filter.default_radius().to_string(),
        },
        put: |o, t| {
            o.filter_radius = Some(parse(t));
            Ok(())
        },
    },
    Setting {
        key: "adaptive_threshold",
        flag: Some("adaptive-threshold"),
        kind: SettingKind::Number { lo: 0.0, hi: 1.0 },
        help: "Adaptive sampling: split a square when its corners differ by more than this, \
               in display (sRGB) units",
        get: |o| o.adaptive.threshold.to_string(),
        put: |o, t| {
            o.adaptive.threshold = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "adaptive_depth",
        flag: Some("adaptive-depth"),
        kind: SettingKind::Integer {
            lo: 0,
            hi: MAX_ADAPTIVE_DEPTH as u64,
        },
        help: "Adaptive sampling: levels of splitting below the pixel",
        get: |o| o.adaptive.depth.to_string(),
        put: |o, t| {
            o.adaptive.depth = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "adaptive_rule",
        flag: Some("adaptive-rule"),
        kind: SettingKind::Name(&AdaptiveRule::NAMES),
        help: "Adaptive sampling: what splits a pixel, `neighbourhood` (the 16 corners around \
               it, and texture finer than the pixels) or `corners` (its own four, as POV-Ray)",
        get: |o| o.adaptive.rule.to_string(),
        put: |o, t| {
            o.adaptive.rule = named(t)?;
            Ok(())
        },
    },
    Setting {
        key: "adaptive_jitter",
        flag: Some("adaptive-jitter"),
        kind: SettingKind::Number { lo: 0.0, hi: 1.0 },
        help: "Adaptive sampling: 0 traces exactly on the lattice, 1 anywhere in each point's \
               lattice cell",
        get: |o| o.adaptive.jitter.to_string(),
        put: |o, t| {
            o.adaptive.jitter = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "adaptive_texture_spp",
        flag: Some("adaptive-texture-spp"),
        kind: SettingKind::Integer {
            lo: 0,
            hi: (MAX_TEXTURE_N * MAX_TEXTURE_N) as u64,
        },
        help: "Adaptive sampling: samples (a square number) that a textured pixel takes in a \
               stratified pass instead of being subdivided; 0 subdivides it",
        get: |o| o.adaptive.texture_spp.to_string(),
        put: |o, t| {
            let spp: u32 = parse(t);
            let n = spp.isqrt();
            if n * n != spp {
                return Err(format!(
                    "bad value '{t}' for adaptive_texture_spp: expected 0 or a square number"
                ));
            }
            o.adaptive.texture_spp = spp;
            Ok(())
        },
    },
    Setting {
        key: "transfer",
        flag: Some("transfer"),
        kind: SettingKind::Name(&["srgb", "display"]),
        help: "What pixel values mean: `srgb` (linear light, written through the sRGB curve) \
               or `display` (display values written as they are, as 1980s renderers did; the \
               default of NFF scenes)",
        get: |o| o.transfer.name().to_string(),
        put: |o, t| {
            o.transfer = match t {
                "srgb" => Transfer::Srgb,
                "display" => Transfer::Display,
                _ => return Err(format!("unknown transfer '{t}', expected srgb or display")),
            };
            Ok(())
        },
    },
    Setting {
        key: "integrator",
        flag: Some("integrator"),
        kind: SettingKind::Name(&IntegratorKind::NAMES),
        help: "The integrator: whitted (Whitted's recursive ray tracer), path (a path tracer \
               with area lights, next-event estimation and MIS; each sample of the sampler is \
               one path, so --samples 8 traces 64 paths per pixel; docs/path-tracing.md) or \
               beam (beam tracing of planar polygons, each pixel the exact area average of \
               what it sees; the sampler and filter are not used; docs/beam-tracing.md)",
        get: |o| o.integrator.to_string(),
        put: |o, t| {
            o.integrator = named(t)?;
            Ok(())
        },
    },
    Setting {
        key: "max_depth",
        flag: Some("depth"),
        kind: SettingKind::Integer {
            lo: 1,
            hi: MAX_DEPTH_LIMIT as u64,
        },
        help: "Maximum ray-tree depth, counting the eye ray as 1; for the path tracer, the \
               most segments of a path",
        get: |o| o.max_depth.to_string(),
        put: |o, t| {
            o.max_depth = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "min_weight",
        flag: Some("min-weight"),
        kind: SettingKind::Number { lo: 0.0, hi: 1.0 },
        help: "Adaptive depth control: stop a reflected or refracted branch whose weight in \
               the pixel is below this, and cast no shadow ray to a light that could add less \
               than this to the pixel (it gets through as much as the tested lights do); 0 \
               traces every branch to the depth limit and tests every light",
        get: |o| o.min_weight.to_string(),
        put: |o, t| {
            o.min_weight = parse::<f32>(t).abs();
            Ok(())
        },
    },
    Setting {
        key: "area_samples",
        flag: Some("area-samples"),
        kind: SettingKind::Integer {
            lo: 0,
            hi: MAX_AREA_SAMPLES as u64,
        },
        help: "Whitted's tracer: points sampled on the emitting surfaces (area lights) per \
               shading point, one shadow ray each, for soft shadows; 0 lights nothing by \
               them",
        get: |o| o.area_samples.to_string(),
        put: |o, t| {
            o.area_samples = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "spd_rules",
        flag: None,
        kind: SettingKind::Boolean,
        help: "Follow the SPD testing procedure's ray-tree rules: a reflection ray at every \
               reflective or transmitting surface whatever its weight (set by --preset spd)",
        get: |o| o.spd_rules.to_string(),
        put: |o, t| {
            o.spd_rules = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "threads",
        flag: Some("threads"),
        kind: SettingKind::Integer {
            lo: 0,
            hi: MAX_THREADS as u64,
        },
        help: "Worker threads; 0 uses every core. A render never starts more threads than it \
               has pieces of work",
        get: |o| o.threads.to_string(),
        put: |o, t| {
            o.threads = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "seed",
        flag: Some("seed"),
        kind: SettingKind::Integer {
            lo: 0,
            hi: u64::MAX,
        },
        help: "Seed for random decisions",
        get: |o| o.seed.to_string(),
        put: |o, t| {
            o.seed = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "accel",
        flag: Some("accel"),
        kind: SettingKind::Spec,
        help: "Acceleration structure and its parameters, METHOD[:KEY=VALUE,...]",
        get: |o| o.accel.to_string(),
        put: |o, t| {
            o.accel = named(t)?;
            Ok(())
        },
    },
    Setting {
        key: "shadows",
        flag: Some("shadows"),
        kind: SettingKind::Spec,
        help: "Who answers shadow rays, METHOD[:KEY=VALUE,...]: any-hit (the accelerator), \
               cache (the last blocker per light and depth tried first, after a blocked ray), \
               light-buffer (Haines & Greenberg's direction cube per point light, an \
               orthographic grid per directional light, its cells holding BVH subtrees; keys \
               res = cells along a face window's side, budget = MiB for all lights), both, or \
               auto (what is predicted to pay in a render: today any-hit, in packets). Every \
               method gives the same image",
        get: |o| o.shadows.to_string(),
        put: |o, t| {
            o.shadows = named(t)?;
            Ok(())
        },
    },
    Setting {
        key: "tile_size",
        flag: Some("tile-size"),
        kind: SettingKind::Integer {
            lo: 1,
            hi: u32::MAX as u64,
        },
        help: "Edge in pixels of the square tiles handed to worker threads (rounded up to \
               whole 8 × 8 packets with packets on); it changes neither the image nor the \
               statistics",
        get: |o| o.tile_size.to_string(),
        put: |o, t| {
            o.tile_size = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "packets",
        flag: Some("no-packets"),
        kind: SettingKind::Boolean,
        help: "Trace the camera rays of 8 × 8 neighbouring pixels as packets (--no-packets \
               traces every camera ray and path on its own); the image is the same either way",
        get: |o| o.packets.to_string(),
        put: |o, t| {
            o.packets = parse(t);
            Ok(())
        },
    },
    Setting {
        key: "wavefront",
        flag: Some("wavefront"),
        kind: SettingKind::Boolean,
        help: "The path tracer advances a queue of paths per thread a bounce at a time (a \
               wavefront) where packets are on; false follows a packet's paths breadth \
               first. The image is the same either way",
        get: |o| o.wavefront.to_string(),
        put: |o, t| {
            o.wavefront = parse(t);
            Ok(())
        },
    },
];

/// The setting with key `key`.
pub fn setting(key: &str) -> Option<&'static Setting> {
    SETTINGS.iter().find(|s| s.key == key)
}

impl RenderOptions {
    /// Sets the setting `key` from its text, checked against its range; the error names
    /// the key and what it accepts, or lists the keys when there is none such.
    pub fn set(&mut self, key: &str, text: &str) -> Result<(), String> {
        match setting(key) {
            Some(s) => s.set(self, text),
            None => Err(format!(
                "unknown setting '{key}', expected one of: {}",
                SETTINGS
                    .iter()
                    .map(|s| s.key)
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
    }

    /// The value of setting `key`, written as `set` reads it.
    pub fn get(&self, key: &str) -> Option<String> {
        setting(key).map(|s| (s.get)(self))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_setting_reads_back_what_it_writes() {
        let mut o = RenderOptions::default();
        for s in SETTINGS {
            let text = s.default_text();
            s.set(&mut o, &text)
                .unwrap_or_else(|e| panic!("{}: default '{text}': {e}", s.key));
            assert_eq!((s.get)(&o), text, "{}", s.key);
        }
        // Setting every default explicitly changes nothing but the filter radius, which
        // is then given rather than left to the filter.
        let explicit = RenderOptions {
            filter_radius: Some(0.5),
            ..RenderOptions::default()
        };
        assert_eq!(o, explicit);
    }

    /// The table's ranges are the ones `validate` holds a render to: its ends pass, one
    /// step beyond fails both.
    #[test]
    fn ranges_agree_with_validate() {
        for s in SETTINGS {
            let (inside, outside): (Vec<String>, Vec<String>) = match s.kind {
                SettingKind::Integer { lo, hi } => (
                    vec![lo.to_string(), hi.min(1 << 20).to_string()],
                    [lo.checked_sub(1), hi.checked_add(1)]
                        .into_iter()
                        .flatten()
                        .map(|v| v.to_string())
                        .collect(),
                ),
                SettingKind::Number { lo, hi } => (
                    vec![lo.to_string(), hi.to_string()],
                    vec![(lo - 0.01).to_string(), (hi + 0.01).to_string()],
                ),
                _ => continue,
            };
            // Sizes and tiles are only bounded by memory; threads by the pool.
            if matches!(s.key, "tile_size" | "seed") {
                continue;
            }
            for text in inside {
                let mut o = RenderOptions {
                    width: 4,
                    height: 4,
                    ..RenderOptions::default()
                };
                s.set(&mut o, &text)
                    .unwrap_or_else(|e| panic!("{} = {text}: {e}", s.key));
                if s.key == "adaptive_texture_spp"
                    && o.adaptive.texture_spp.isqrt().pow(2) != o.adaptive.texture_spp
                {
                    continue;
                }
                o.validate()
                    .unwrap_or_else(|e| panic!("{} = {text} passes the table: {e}", s.key));
            }
            for text in outside {
                let mut o = RenderOptions::default();
                assert!(s.set(&mut o, &text).is_err(), "{} = {text}", s.key);
            }
        }
    }

    #[test]
    fn bad_values_name_the_key_and_what_it_takes() {
        let mut o = RenderOptions::default();
        for (key, text, phrase) in [
            (
                "width",
                "0",
                "bad value '0' for width: expected a whole number from 1 to 65536",
            ),
            (
                "max_depth",
                "-1",
                "for max_depth: expected a whole number from 1 to 256",
            ),
            (
                "min_weight",
                "2",
                "for min_weight: expected a number from 0 to 1",
            ),
            (
                "sampler",
                "blue",
                "unknown sampler 'blue', expected one of: centre",
            ),
            ("packets", "yes", "expected true or false"),
            ("accel", "bvh:leaf=0", "bad value '0' for 'leaf'"),
            ("adaptive_texture_spp", "5", "expected 0 or a square number"),
            (
                "colour",
                "1",
                "unknown setting 'colour', expected one of: width, height",
            ),
        ] {
            let err = o.set(key, text).unwrap_err();
            assert!(err.contains(phrase), "{key} = {text}: {err}");
        }
        assert_eq!(
            o,
            RenderOptions::default(),
            "a refused value changes nothing"
        );
        o.set("sampler", "center").unwrap();
        assert_eq!(o.sampler, SamplerKind::Centre);
        o.set("adaptive_rule", "neighborhood").unwrap();
        assert_eq!(o.get("max_depth").as_deref(), Some("5"));
    }
}
