//! The render settings Python passes by keyword, onto `prism::RenderOptions`. As with the
//! command line, a setting left out keeps the scene's value (its file's `[render]` table or
//! the built-in's), so the same words give the same image from either front end.

use crate::errors::bad_argument;
use prism::options::MAX_SAMPLES_PER_AXIS;
use prism::sampling::SamplerKind;
use prism::RenderOptions;
use pyo3::PyResult;
use std::str::FromStr;

/// The keyword arguments of `Scene.render`, each None when not given.
#[derive(Clone, Debug, Default)]
pub(crate) struct Settings {
    pub(crate) width: Option<u32>,
    pub(crate) height: Option<u32>,
    /// Samples per pixel, a square number (the CLI's `--spp`).
    pub(crate) spp: Option<u32>,
    pub(crate) sampler: Option<String>,
    pub(crate) filter: Option<String>,
    pub(crate) accel: Option<String>,
    pub(crate) integrator: Option<String>,
    pub(crate) shadows: Option<String>,
    pub(crate) seed: Option<u64>,
    pub(crate) threads: Option<usize>,
    /// Edge of the square tiles the render's threads take (`RenderOptions::tile_size`).
    pub(crate) tile: Option<u32>,
    pub(crate) depth: Option<u32>,
    pub(crate) packets: Option<bool>,
    /// Any other setting of the settings table, by key, as text (`RenderOptions::set`).
    pub(crate) others: Vec<(String, String)>,
}

/// `text` parsed as a `T`, or a `ValueError` naming the argument.
fn parsed<T: FromStr<Err = String>>(name: &str, text: &str) -> PyResult<T> {
    text.parse()
        .map_err(|e: String| bad_argument(format!("{name}={text:?}: {e}")))
}

/// n for n × n samples per pixel: `spp` must be a square, as every pattern takes a square
/// grid of samples.
fn samples_per_axis(spp: u32) -> PyResult<u32> {
    let n = (spp as f64).sqrt().round() as u32;
    if spp == 0 || n * n != spp || n > MAX_SAMPLES_PER_AXIS {
        return Err(bad_argument(format!(
            "spp={spp}: samples per pixel must be a square number from 1 to {} (n × n samples)",
            MAX_SAMPLES_PER_AXIS * MAX_SAMPLES_PER_AXIS
        )));
    }
    Ok(n)
}

impl Settings {
    /// The scene's options with these settings applied, checked.
    pub(crate) fn apply(&self, scene: &RenderOptions) -> PyResult<RenderOptions> {
        let mut o = scene.clone();
        if let Some(v) = self.width {
            o.width = v;
        }
        if let Some(v) = self.height {
            o.height = v;
        }
        if let Some(v) = &self.sampler {
            o.sampler = parsed::<SamplerKind>("sampler", v)?;
        }
        if let Some(spp) = self.spp {
            if !o.sampler.uses_sample_count() {
                return Err(bad_argument(format!(
                    "spp={spp}: the {} sampler chooses its own sample count",
                    o.sampler
                )));
            }
            o.samples = samples_per_axis(spp)?;
        }
        if let Some(v) = &self.filter {
            o.filter = parsed("filter", v)?;
        }
        if let Some(v) = &self.accel {
            o.accel = parsed("accel", v)?;
        }
        if let Some(v) = &self.integrator {
            o.integrator = parsed("integrator", v)?;
        }
        if let Some(v) = &self.shadows {
            o.shadows = parsed("shadows", v)?;
        }
        if let Some(v) = self.seed {
            o.seed = v;
        }
        if let Some(v) = self.threads {
            o.threads = v;
        }
        if let Some(v) = self.tile {
            o.tile_size = v;
        }
        if let Some(v) = self.depth {
            o.max_depth = v;
        }
        if let Some(v) = self.packets {
            o.packets = v;
        }
        for (key, text) in &self.others {
            o.set(key, text)
                .map_err(|e| bad_argument(format!("{key}={text:?}: {e}")))?;
        }
        o.validate()
            .map_err(|e| bad_argument(format!("invalid options: {e}")))?;
        Ok(o)
    }
}

/// Every setting of the settings table as (key, type, default, help): what `Scene.render`
/// takes by keyword.
#[pyo3::pyfunction]
pub(crate) fn settings() -> Vec<(&'static str, &'static str, String, &'static str)> {
    prism::options::SETTINGS
        .iter()
        .map(|s| (s.key, s.kind.type_name(), s.default_text(), s.help))
        .collect()
}

/// The whole-number settings of the settings table as (key, lowest, highest): the ranges
/// `Scene.render` checks its integer keywords against before they reach the native side,
/// so that a negative or too large number is a `ValueError` naming the keyword and range.
#[pyo3::pyfunction]
pub(crate) fn integer_ranges() -> Vec<(&'static str, u64, u64)> {
    use prism::options::SettingKind;
    prism::options::SETTINGS
        .iter()
        .filter_map(|s| match s.kind {
            SettingKind::Integer { lo, hi } => Some((s.key, lo, hi)),
            _ => None,
        })
        .collect()
}
