//! `render`'s arguments. Every render setting maps onto `prism::RenderOptions`; options
//! not given keep the scene's value, and the scene's defaults come from the library.

use crate::density::DensityRays;
use crate::flags::{per_axis, setting_help, whole};
use crate::scene_args::{SceneArgs, SizeArgs};
use anyhow::{bail, Result};
use clap::Args;
use prism::accel::AccelSpec;
use prism::render::FilterKind;
use prism::sampling::SamplerKind;
use prism::{RenderOptions, Scene};
use std::path::PathBuf;

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
    #[command(flatten)]
    pub scene: SceneArgs,

    /// Output image; the extension picks the format: .png, .exr or .pfm.
    #[arg(short, long, value_name = "FILE", default_value = "prism.png")]
    pub output: PathBuf,

    /// Write EXR output as 16-bit half floats instead of 32-bit floats (EXR only).
    #[arg(long)]
    pub half: bool,

    #[command(flatten)]
    pub size: SizeArgs,

    #[arg(short, long, value_name = "N", conflicts_with = "spp", allow_negative_numbers = true, value_parser = whole::<u32>("samples"), help = setting_help("samples"))]
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

    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u32>("adaptive_depth"), help = setting_help("adaptive_depth"))]
    pub adaptive_depth: Option<u32>,

    #[arg(long, value_name = "RULE", help = setting_help("adaptive_rule"))]
    pub adaptive_rule: Option<prism::sampling::AdaptiveRule>,

    #[arg(long, value_name = "X", allow_negative_numbers = true, help = setting_help("adaptive_jitter"))]
    pub adaptive_jitter: Option<f32>,

    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u32>("adaptive_texture_spp"), help = setting_help("adaptive_texture_spp"))]
    pub adaptive_texture_spp: Option<u32>,

    #[arg(long, value_name = "W", allow_negative_numbers = true, help = setting_help("min_weight"))]
    pub min_weight: Option<f32>,

    #[arg(long, value_name = "NAME", help = setting_help("transfer"))]
    pub transfer: Option<prism::transfer::Transfer>,

    #[arg(short, long, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u32>("max_depth"), help = setting_help("max_depth"))]
    pub depth: Option<u32>,

    #[arg(short, long, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>("threads"), help = setting_help("threads"))]
    pub threads: Option<usize>,

    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u64>("seed"), help = setting_help("seed"))]
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

    #[arg(long, value_name = "PIXELS", allow_negative_numbers = true, value_parser = whole::<u32>("tile_size"), help = setting_help("tile_size"))]
    pub tile_size: Option<u32>,

    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = whole::<u32>("area_samples"), help = setting_help("area_samples"))]
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

impl RenderArgs {
    /// The scene to render and a name for reports.
    pub(crate) fn load_scene(&self) -> Result<(Scene, String)> {
        self.scene.load("whitted")
    }

    /// The scene's options with the command line's on top.
    pub(crate) fn options(&self, scene: &RenderOptions) -> Result<RenderOptions> {
        let mut o = scene.clone();
        // A bundle of sampling options: the command line's own options refine it.
        if self.preset == Some(Preset::Pov) {
            prism::preset::apply_pov_am2(&mut o);
        }
        self.size.apply(&mut o);
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
