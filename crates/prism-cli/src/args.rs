//! Command-line arguments. Every render setting maps onto `prism::RenderOptions`; options
//! not given keep the scene's value, and the scene's defaults come from the library.

use anyhow::{bail, Result};
use clap::{Args, Parser, Subcommand};
use prism::accel::AccelSpec;
use prism::render::FilterKind;
use prism::sampling::SamplerKind;
use prism::scene::builtin;
use prism::{RenderOptions, Scene};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    name = "prism",
    version,
    about = "A Whitted ray tracer with switchable, measurable acceleration methods",
    long_about = "A Whitted ray tracer with switchable, measurable acceleration methods.\n\n\
                  Run `prism render` to render the built-in Whitted scene to prism.png. \
                  `render` is the default command: its arguments work without its name \
                  (`prism -W 320 -H 240 scene.toml`).",
    args_conflicts_with_subcommands = true
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,

    /// `render`'s arguments, for `prism` without a command.
    #[command(flatten)]
    pub render: RenderArgs,
}

impl Cli {
    /// The command to run: the one named, or `render` with the arguments given without
    /// one. A first word that is no command, no file and no scene name (`prism
    /// frobnicate`) is bad usage, as clap reports an unknown command, not a missing file.
    pub(crate) fn into_command(self) -> Result<Command, clap::Error> {
        if let Some(command) = self.command {
            return Ok(command);
        }
        if let Some(word) = self.render.scene.as_deref() {
            let named = word.to_str().is_some_and(|w| w.starts_with("builtin:"));
            if !named && word.extension().is_none() && !word.exists() {
                use clap::CommandFactory;
                return Err(Cli::command().error(
                    clap::error::ErrorKind::InvalidSubcommand,
                    format!("unrecognized subcommand or scene file '{}'", word.display()),
                ));
            }
        }
        Ok(Command::Render(self.render))
    }
}

#[derive(Subcommand, Debug)]
pub(crate) enum Command {
    /// Render a scene file or a built-in scene to an image (the default command).
    Render(RenderArgs),
    /// List the built-in scenes.
    List,
    /// Describe a scene without rendering it: shapes, materials, lights, bounds, memory
    /// and the acceleration structure built for it.
    #[command(override_usage = "prism info [OPTIONS] <SCENE>\n       \
                                prism info [OPTIONS] --builtin <NAME>")]
    Info(InfoArgs),
    /// Measure acceleration methods on scenes: build time, memory, node visits and
    /// primitive tests per ray, primary and shadow rays per second; a table, CSV, JSON and
    /// an SVG chart.
    Bench(crate::bench::BenchArgs),
    /// Compare two images: RMSE, PSNR, SSIM and FLIP of TEST against REFERENCE.
    Compare(crate::compare::CompareArgs),
    /// Write the exact box-filtered image of the checkerboard scene (no sampling).
    Reference(crate::reference::ReferenceArgs),
    /// Render a scene with each sampling pattern at several sample counts and plot the
    /// error against the rays per pixel.
    Sweep(crate::sweep::SweepArgs),
    /// Draw each sampling pattern's points (SVG).
    Patterns(crate::patterns::PatternsArgs),
    /// Start the live viewer: a local web page that shows the render refining and lets
    /// the mouse and keys move the camera (docs/viewer.md).
    Serve(crate::serve::ServeArgs),
}

#[derive(Args, Debug)]
pub(crate) struct InfoArgs {
    /// Scene file (.toml, .nff, .gltf, .glb) or mesh file (.obj, .ply), or builtin:NAME for
    /// a built-in scene. Required unless --builtin is given.
    #[arg(required_unless_present = "builtin", value_name = "SCENE")]
    pub scene: Option<String>,

    /// Built-in scene to describe instead of a file, as `render --builtin` takes it.
    #[arg(short, long, value_name = "NAME", conflicts_with = "scene")]
    pub builtin: Option<String>,

    /// Acceleration structure to build and describe, as for `render --accel`; the scene
    /// file's own `accel` setting when not given.
    #[arg(long, value_name = "SPEC")]
    pub accel: Option<AccelSpec>,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum DensityRays {
    #[default]
    All,
    Camera,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Preset {
    /// Eric Haines' Standard Procedural Databases testing procedure.
    Spd,
    /// POV-Ray's adaptive anti-aliasing +AM2 at its default +R3: corners on the lattice,
    /// split where they differ, two levels (adaptive depth 2).
    Pov,
}

#[derive(Args, Debug, Default)]
pub(crate) struct RenderArgs {
    /// Scene file to render (.toml, .nff, .gltf, .glb) or mesh file (.obj, .ply: framed by a
    /// default camera and light), or builtin:NAME for a built-in scene (as --builtin NAME).
    /// Without it (and without --builtin), the built-in `whitted` scene is rendered.
    pub scene: Option<PathBuf>,

    /// Built-in scene to render instead of a file (see `prism list`).
    #[arg(short, long, value_name = "NAME", conflicts_with = "scene")]
    pub builtin: Option<String>,

    /// Output image; the extension picks the format: .png, .exr or .pfm.
    #[arg(short, long, value_name = "FILE", default_value = "prism.png")]
    pub output: PathBuf,

    /// Write EXR output as 16-bit half floats instead of 32-bit floats (EXR only).
    #[arg(long)]
    pub half: bool,

    #[arg(short = 'W', long, value_name = "PIXELS", help = setting_help("width"))]
    pub width: Option<u32>,

    #[arg(short = 'H', long, value_name = "PIXELS", help = setting_help("height"))]
    pub height: Option<u32>,

    #[arg(short, long, value_name = "N", conflicts_with = "spp", help = setting_help("samples"))]
    pub samples: Option<u32>,

    /// Samples per pixel, a square number (1, 4, 9, 16, …, 4096) for every pattern, so
    /// that patterns compare at equal counts.
    // Signed, so that a negative count gets the range rather than clap's `-- -4` hint.
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub spp: Option<i64>,

    #[arg(long, value_name = "NAME", help = setting_help("sampler"))]
    pub sampler: Option<SamplerKind>,

    #[arg(long, value_name = "NAME", help = setting_help("filter"))]
    pub filter: Option<FilterKind>,

    #[arg(long, value_name = "PIXELS", allow_negative_numbers = true, help = setting_help("filter_radius"))]
    pub filter_radius: Option<f32>,

    #[arg(long, value_name = "X", allow_negative_numbers = true, help = setting_help("adaptive_threshold"))]
    pub adaptive_threshold: Option<f32>,

    #[arg(long, value_name = "N", help = setting_help("adaptive_depth"))]
    pub adaptive_depth: Option<u32>,

    #[arg(long, value_name = "RULE", help = setting_help("adaptive_rule"))]
    pub adaptive_rule: Option<prism::sampling::AdaptiveRule>,

    #[arg(long, value_name = "X", allow_negative_numbers = true, help = setting_help("adaptive_jitter"))]
    pub adaptive_jitter: Option<f32>,

    #[arg(long, value_name = "N", help = setting_help("adaptive_texture_spp"))]
    pub adaptive_texture_spp: Option<u32>,

    #[arg(long, value_name = "W", allow_negative_numbers = true, help = setting_help("min_weight"))]
    pub min_weight: Option<f32>,

    #[arg(long, value_name = "NAME", help = setting_help("transfer"))]
    pub transfer: Option<prism::transfer::Transfer>,

    #[arg(short, long, value_name = "N", help = setting_help("max_depth"))]
    pub depth: Option<u32>,

    #[arg(short, long, value_name = "N", help = setting_help("threads"))]
    pub threads: Option<usize>,

    #[arg(long, value_name = "N", help = setting_help("seed"))]
    pub seed: Option<u64>,

    // The help lists every method's keys from their tables (`Method::KEYS`).
    #[arg(long, value_name = "SPEC", help = AccelSpec::help())]
    pub accel: Option<AccelSpec>,

    #[arg(long, value_name = "SPEC", help = setting_help("shadows"))]
    pub shadows: Option<prism::integrator::ShadowSpec>,

    #[arg(long, help = setting_help("packets"))]
    pub no_packets: bool,

    #[arg(long, value_name = "BOOL", help = setting_help("wavefront"))]
    pub wavefront: Option<bool>,

    #[arg(long, value_name = "PIXELS", help = setting_help("tile_size"))]
    pub tile_size: Option<u32>,

    #[arg(long, value_name = "N", help = setting_help("area_samples"))]
    pub area_samples: Option<u32>,

    #[arg(long, value_name = "NAME", help = setting_help("integrator"))]
    pub integrator: Option<prism::options::IntegratorKind>,

    /// Apply a published procedure: `spd` = Haines' SPD rules (corner rays, depth 5, a
    /// reflection ray at every reflective or transmitting surface); `pov` = POV-Ray's
    /// adaptive +AM2 +R3 pattern (the adaptive options given with it still apply on top).
    #[arg(long, value_name = "NAME")]
    pub preset: Option<Preset>,

    /// Also write the sample-density view: rays per pixel as a heat map with a colour
    /// bar (PNG), or the raw counts as grey values (PFM or EXR).
    #[arg(long, value_name = "FILE")]
    pub density: Option<PathBuf>,

    /// Which rays the density view counts: `all` (camera, shadow, reflected, refracted) or
    /// `camera`.
    #[arg(long, value_name = "KIND", default_value = "all")]
    pub density_rays: DensityRays,

    /// Also write the cost view: node visits (or primitive tests, see --cost-metric) per
    /// camera ray of each pixel, counting every ray the pixel spawned, as a heat map with a
    /// colour bar (PNG). For it every ray is traced alone, not in packets, so each pixel
    /// shows its own work (the image is the same; the render takes longer).
    #[arg(long, value_name = "FILE")]
    pub cost: Option<PathBuf>,

    /// What the cost view counts: `nodes` (node visits) or `prims` (primitive tests).
    #[arg(long, value_name = "KIND", default_value = "nodes")]
    pub cost_metric: crate::cost::CostMetric,

    /// Whose work the cost view counts: `all` rays a pixel spawned, or `shadow` rays only
    /// (to see where the shadow method, `--shadows`, works hard).
    #[arg(long, value_name = "RAYS", default_value = "all")]
    pub cost_rays: crate::cost::CostRays,

    /// Print a table of ray counts, tests and times after rendering.
    #[arg(long)]
    pub stats: bool,

    /// Write the statistics as JSON to FILE ('-' for standard output).
    #[arg(long, value_name = "FILE")]
    pub stats_json: Option<PathBuf>,

    /// No progress bar and no closing message (warnings and errors still show).
    #[arg(short, long)]
    pub quiet: bool,

    /// Treat warnings (a missing MTL file, a feature prism reads but cannot render, an
    /// empty scene, …) as errors: stop before rendering.
    #[arg(long)]
    pub strict: bool,
}

/// A setting's `--help` text, read from the settings table (`prism::options::SETTINGS`):
/// its sentence, what it accepts and its default. Every render setting's flag takes its help
/// from here, so the command line says what the scene file and Python say.
pub(crate) fn setting_help(key: &str) -> String {
    use prism::options::SettingKind;
    let s = prism::options::setting(key).unwrap_or_else(|| panic!("no setting '{key}'"));
    let accepts = match s.kind {
        SettingKind::Integer { lo, hi } if hi <= 1 << 20 => format!(", {lo} to {hi}"),
        SettingKind::Number { lo, hi } => format!(", {lo} to {hi}"),
        SettingKind::Name(names) => format!(": {}", names.join(", ")),
        _ => String::new(),
    };
    let default = match key {
        "width" | "height" => "the scene's".to_string(),
        "filter_radius" => "per filter".to_string(),
        "min_weight" => "1/255".to_string(),
        "packets" => "packets on".to_string(),
        _ => s.default_text(),
    };
    format!("{}{accepts} [default: {default}]", s.help)
}

/// An options error of the engine, which names a setting by its key (`max_depth must be
/// …`), with the key written as the command line's flag (`--depth must be …`).
pub(crate) fn in_flags(message: &str) -> String {
    let named = prism::options::SETTINGS.iter().find_map(|s| {
        let rest = message.strip_prefix(s.key)?.strip_prefix(' ')?;
        Some((s.flag?, rest))
    });
    match named {
        Some((flag, rest)) => format!("--{flag} {rest}"),
        None => message.to_string(),
    }
}

/// A built-in scene by name, or an error listing the names there are.
pub(crate) fn find_builtin(name: &str) -> Result<Scene> {
    match builtin::find(name) {
        Some(scene) => Ok(scene),
        None => bail!(
            "no built-in scene named '{name}'; available: {} (or sphereflake:N)",
            builtin::names().join(", ")
        ),
    }
}

impl RenderArgs {
    /// The scene to render and a name for reports.
    pub(crate) fn load_scene(&self) -> Result<(Scene, String)> {
        if let Some(path) = &self.scene {
            // `builtin:NAME` in the file's place, as `prism info` takes it.
            if let Some(name) = path.to_str().and_then(|p| p.strip_prefix("builtin:")) {
                return Ok((find_builtin(name)?, format!("builtin:{name}")));
            }
            let scene = prism_io::scene::load(path)?;
            return Ok((scene, path.display().to_string()));
        }
        let name = self.builtin.as_deref().unwrap_or("whitted");
        Ok((find_builtin(name)?, format!("builtin:{name}")))
    }

    /// The scene's options with the command line's on top.
    pub(crate) fn options(&self, scene: &RenderOptions) -> Result<RenderOptions> {
        let mut o = scene.clone();
        // A bundle of sampling options: the command line's own options refine it.
        if self.preset == Some(Preset::Pov) {
            prism::preset::apply_pov_am2(&mut o);
        }
        if let Some(v) = self.width {
            o.width = v;
        }
        if let Some(v) = self.height {
            o.height = v;
        }
        if let Some(v) = self.samples {
            o.samples = v;
        }
        if let Some(spp) = self.spp {
            o.samples = per_axis(spp)?;
        }
        if let Some(v) = self.sampler {
            o.sampler = v;
        }
        if (self.samples.is_some() || self.spp.is_some()) && !o.sampler.uses_sample_count() {
            bail!(
                "the {} sampler chooses its own sample count; leave out --spp and --samples{}",
                o.sampler,
                if o.sampler == SamplerKind::Adaptive {
                    " (--adaptive-depth, --adaptive-threshold and --adaptive-texture-spp set \
                     its effort)"
                } else {
                    ""
                }
            );
        }
        if let Some(v) = self.filter {
            o.filter = v;
        }
        if let Some(v) = self.filter_radius {
            o.filter_radius = Some(v);
        }
        if let Some(v) = self.adaptive_threshold {
            o.adaptive.threshold = v;
        }
        if let Some(v) = self.adaptive_depth {
            o.adaptive.depth = v;
        }
        if let Some(v) = self.adaptive_rule {
            o.adaptive.rule = v;
        }
        if let Some(v) = self.adaptive_jitter {
            o.adaptive.jitter = v;
        }
        if let Some(v) = self.adaptive_texture_spp {
            o.adaptive.texture_spp = v;
        }
        if let Some(v) = self.min_weight {
            o.min_weight = v;
        }
        if let Some(v) = self.transfer {
            o.transfer = v;
        }
        if let Some(v) = self.depth {
            o.max_depth = v;
        }
        if let Some(v) = self.threads {
            o.threads = v;
        }
        if let Some(v) = self.seed {
            o.seed = v;
        }
        if let Some(v) = &self.accel {
            o.accel = v.clone();
        }
        if let Some(v) = self.shadows {
            o.shadows = v;
        }
        if self.no_packets {
            o.packets = false;
        }
        if let Some(v) = self.wavefront {
            o.wavefront = v;
        }
        if let Some(v) = self.tile_size {
            o.tile_size = v;
        }
        if let Some(v) = self.area_samples {
            o.area_samples = v;
        }
        if let Some(v) = self.integrator {
            o.integrator = v;
        }
        Ok(o)
    }
}

/// Samples per axis for `spp` samples per pixel, which must be a square from 1 to
/// 64 × 64. Errors echo the value as the user typed it.
pub(crate) fn per_axis(spp: i64) -> Result<u32> {
    let max = prism::options::MAX_SAMPLES_PER_AXIS;
    let most = i64::from(max * max);
    if spp < 1 {
        bail!(
            "--spp takes a square number from 1 to {most}, got {spp}{}",
            if spp == 0 {
                ": a pixel takes at least 1 sample"
            } else {
                ""
            }
        );
    }
    if spp > most {
        bail!("--spp {spp} is too many: at most {most} ({max}×{max}) samples per pixel");
    }
    let n = (spp as f64).sqrt().round() as i64;
    if n * n != spp {
        let below = (spp as f64).sqrt().floor().max(1.0) as i64;
        bail!(
            "--spp {spp} is not a square number: every pattern takes n×n samples per pixel; \
             try {} or {}",
            below * below,
            (below + 1) * (below + 1)
        );
    }
    Ok(n as u32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use prism::sampling::AdaptiveRule;

    fn options(args: &[&str]) -> RenderOptions {
        let mut argv = vec!["prism", "render"];
        argv.extend(args);
        match Cli::try_parse_from(argv).unwrap().command {
            Some(Command::Render(r)) => r.options(&RenderOptions::default()).unwrap(),
            other => panic!("expected render, got {other:?}"),
        }
    }

    #[test]
    fn options_errors_name_the_flag() {
        assert_eq!(
            in_flags("max_depth must be between 1 (the eye ray alone) and 256, got 0"),
            "--depth must be between 1 (the eye ray alone) and 256, got 0"
        );
        assert_eq!(
            in_flags("tile_size must be at least 1"),
            "--tile-size must be at least 1"
        );
        assert_eq!(
            in_flags("image size must be at least 1×1"),
            "image size must be at least 1×1"
        );
    }

    #[test]
    fn the_pov_preset_is_povs_am2_pattern_and_flags_refine_it() {
        let o = options(&["--preset", "pov"]);
        assert_eq!(o.sampler, SamplerKind::Adaptive);
        assert_eq!(o.adaptive.rule, AdaptiveRule::Corners);
        assert_eq!((o.adaptive.jitter, o.adaptive.texture_spp), (0.0, 0));
        assert_eq!(o.adaptive.depth, 2, "+R3 counts the pixel: two levels");
        assert_eq!(
            o.adaptive.threshold,
            RenderOptions::default().adaptive.threshold
        );
        let o = options(&[
            "--preset",
            "pov",
            "--adaptive-depth",
            "3",
            "--adaptive-threshold",
            "0.3",
        ]);
        assert_eq!((o.adaptive.depth, o.adaptive.threshold), (3, 0.3));
        assert_eq!(o.adaptive.rule, AdaptiveRule::Corners);
    }
}
