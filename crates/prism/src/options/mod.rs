//! Render options: the one home of every setting, plain data made of the choices' specs
//! (`choices`) and the accelerator's (`accel::AccelSpec`). The scene file, the CLI and the
//! library API all fill this struct; anything they leave out keeps the default documented
//! here.

pub mod settings;
mod wire;

pub use settings::{setting, Setting, SettingKind, SETTINGS};

pub use crate::choices::sampler::{
    DEFAULT_ADAPTIVE_DEPTH, DEFAULT_ADAPTIVE_TEXTURE_SPP, DEFAULT_ADAPTIVE_THRESHOLD,
};
pub use crate::choices::IntegratorKind;
pub use crate::choices::MAX_FILTER_RADIUS;

use crate::accel::{AccelSpec, RayOrigins};
use crate::choices::{AdaptiveSpec, FilterKind, SamplerKind, ShadowSpec, Strategy, Transfer};
use serde::{Deserialize, Serialize};

/// Largest accepted `max_depth`.
pub const MAX_DEPTH_LIMIT: u32 = 256;
/// POV-Ray's `adc_bailout`: one 8-bit level.
pub const DEFAULT_MIN_WEIGHT: f32 = 1.0 / 255.0;
/// Points on the area lights per shading point: a 4 × 4 grid's worth, as POV-Ray's
/// `area_light` examples take.
pub const DEFAULT_AREA_SAMPLES: u32 = 16;
/// Most points on the area lights per shading point.
pub const MAX_AREA_SAMPLES: u32 = 4096;
/// Most worker threads a render may ask for. Far above any core count a machine offers
/// today; beyond it a typo (`--threads 1000000000000`) would start thousands of OS threads.
pub const MAX_THREADS: usize = 1024;
/// Most samples per pixel along each axis (`samples`).
pub const MAX_SAMPLES_PER_AXIS: u32 = 64;

/// Every setting of a render, in one place: filled from defaults, then the scene file, then the
/// command line.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "wire::RenderTable", into = "wire::RenderTable")]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel along each axis: n gives n×n samples per pixel with the `grid`,
    /// `random`, `jittered` and `relaxed` samplers (1 = one ray per pixel). The `centre`,
    /// `corners` and `adaptive` samplers choose their own count and ignore this.
    pub samples: u32,
    /// Where a pixel's camera rays go (see `SamplerKind`).
    pub sampler: SamplerKind,
    /// The reconstruction filter that turns samples into pixels.
    pub filter: FilterKind,
    /// The filter's radius in pixels; None takes the filter's usual radius (box 0.5, tent
    /// 1, Gaussian 1.5, Mitchell 2).
    pub filter_radius: Option<f32>,
    /// The adaptive sampler's settings (threshold, depth, rule, jitter, texture spp); the
    /// scene file writes them as `adaptive_threshold`, `adaptive_depth`, … .
    pub adaptive: AdaptiveSpec,
    /// What the pixel values mean: linear light shown through the sRGB curve (`srgb`), or
    /// display values written as they are (`display`, the default of NFF scenes).
    pub transfer: Transfer,
    /// Maximum ray-tree depth; the eye ray has depth 1, so 5 allows four bounces. For the
    /// path tracer, the most segments a path has (1 sees emitters, 2 adds direct light).
    pub max_depth: u32,
    /// Adaptive depth control: a reflected or refracted ray whose weight in the pixel (the
    /// product of reflection and transmission weights from the eye) is below this is not
    /// traced. The default, 1/255, is POV-Ray's `adc_bailout`: such a ray cannot change an
    /// 8-bit pixel by more than about a level. The same threshold tests shadows
    /// adaptively: a light whose diffuse and highlight terms, unshadowed and times the
    /// ray's weight, would stay below it in every channel casts no shadow ray; it gets
    /// through as much as the lights tested there do (Ward 1991). 0 traces every ray up to
    /// `max_depth` and tests every light.
    pub min_weight: f32,
    /// Whitted's tracer: points sampled on the emitting surfaces (area lights) per shading
    /// point, one shadow ray each; 0 lights nothing by them (their emission is still seen
    /// directly). More points, softer and smoother shadows.
    pub area_samples: u32,
    /// Follow the SPD testing procedure's ray-tree rules (Haines, SPD rules 8 and 9): every
    /// hit on a surface with Ks > 0 or T > 0 spawns a reflection ray, and every hit on a
    /// transmitter a refraction ray, whatever their weight; `min_weight` is ignored.
    pub spd_rules: bool,
    /// Worker threads; 0 uses every core.
    pub threads: usize,
    /// Seed for every random decision (the random, jittered and relaxed samplers); a
    /// render is a pure function of scene, options and seed.
    pub seed: u64,
    /// The acceleration structure for ray queries.
    pub accel: AccelSpec,
    /// Who answers shadow rays: the accelerator's any-hit query, a shadow cache, light
    /// buffers or both (`integrator::ShadowSpec`); every method gives the same image.
    pub shadows: ShadowSpec,
    /// Edge length of the square tiles handed to worker threads (rounded up to whole
    /// packets, `PACKET_EDGE`, when `packets` is on).
    pub tile_size: u32,
    /// Trace the camera rays of neighbouring pixels as packets (`PACKET_EDGE` ×
    /// `PACKET_EDGE` pixels, one packet per sample index) through the accelerator's packet
    /// query; every ray gets the answer its own query gives, so the image is the same
    /// either way. The per-pixel samplers trace blocks of pixels, the `corners` pattern
    /// (and the adaptive sampler's first lattice) runs of 64 corners along a row; the
    /// adaptive sampler's refinement traces single rays. The path tracer runs as a
    /// wavefront (`wavefront`), or without it follows a packet's paths breadth first: the
    /// rays of the paths still alive, and their shadow rays, go as packets at every depth.
    /// The node visits and tests of a packet are shared evenly among its rays' pixels in
    /// the cost view.
    pub packets: bool,
    /// The path tracer keeps a wavefront of paths per thread (`integrator::WavefrontPathTracer`),
    /// advanced a bounce at a time over the whole queue, where packets are on; off, it
    /// follows a packet's paths breadth first. Every sample's value, and so the image, is
    /// the same either way.
    pub wavefront: bool,
    /// Which integrator renders: `whitted` (the default), `path` (docs/path-tracing.md) or
    /// `beam` (docs/beam-tracing.md).
    pub integrator: IntegratorKind,
    /// The path tracer's estimator of area light: MIS (the default) or one strategy alone.
    /// A switch for tests and experiments; scene files and the CLI do not set it.
    pub path_strategy: Strategy,
    /// Count every pixel's rays and their work (`RenderResult::rays`, for the density and
    /// cost views). Off, `rays` holds no counts and the render writes 40 bytes a pixel
    /// less (a tenth of a gigabyte at 1080p, each page of it a page fault); `prism render`
    /// counts only for `--density` and `--cost`. Not a scene file's setting.
    pub per_pixel_rays: bool,
}

/// Pixels along each side of a camera-ray packet: 8 × 8 rays at one sample per pixel
/// (`accel::PACKET_MAX`).
pub const PACKET_EDGE: u32 = 8;

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 640,
            height: 480,
            samples: 1,
            sampler: SamplerKind::Grid,
            filter: FilterKind::Box,
            filter_radius: None,
            adaptive: AdaptiveSpec::default(),
            transfer: Transfer::Srgb,
            max_depth: 5,
            min_weight: DEFAULT_MIN_WEIGHT,
            area_samples: DEFAULT_AREA_SAMPLES,
            spd_rules: false,
            threads: 0,
            seed: 0,
            accel: AccelSpec::default(),
            shadows: Default::default(),
            tile_size: 16,
            packets: true,
            wavefront: true,
            integrator: IntegratorKind::Whitted,
            path_strategy: Strategy::Mis,
            per_pixel_rays: true,
        }
    }
}

impl RenderOptions {
    /// The sampling settings in words, e.g. "jittered 4×4 (16 spp), box filter (radius 0.5)".
    pub fn sampling_summary(&self) -> String {
        let n = self.samples;
        let pattern = match self.sampler {
            SamplerKind::Adaptive => format!("adaptive ({})", self.adaptive.summary()),
            SamplerKind::Centre | SamplerKind::Corners => self.sampler.name().to_string(),
            kind => format!("{kind} {n}×{n} ({} spp)", n * n),
        };
        let radius = self.filter_radius.unwrap_or(self.filter.default_radius());
        format!("{pattern}, {} filter (radius {radius})", self.filter)
    }

    /// The accelerator to build for these options: `accel`, with a BVH's `rays=auto`
    /// settled by the integrator (inside for the path tracer, whose rays start on
    /// surfaces within the scene; outside for camera rays and Whitted's trees).
    pub fn accel_to_build(&self) -> AccelSpec {
        let origins = match self.integrator.rays_start_inside() {
            true => RayOrigins::Inside,
            false => RayOrigins::Outside,
        };
        (self.accel.with_auto_rays(origins)).with_expected_rays(self.expected_rays())
    }

    /// The rays a render with these options is expected to trace, which a BVH's
    /// `build=auto` weighs against its build: per sample a camera ray and two shadow rays
    /// (Whitted; the bench scenes' mean), or a ray and a shadow ray per bounce of a path,
    /// three bounces at most counted (most paths end by then); the beam tracer traces
    /// none.
    pub fn expected_rays(&self) -> f64 {
        let pixels = self.width as f64 * self.height as f64;
        let samples = match self.sampler {
            SamplerKind::Centre | SamplerKind::Corners => 1.0,
            _ => (self.samples as f64).powi(2),
        };
        let per_sample = match self.integrator {
            IntegratorKind::Whitted => 3.0,
            IntegratorKind::Path => 2.0 * self.max_depth.min(3) as f64,
            IntegratorKind::Beam => 0.0,
        };
        pixels * samples * per_sample
    }

    /// Checks ranges; the message names the option as the CLI and scene file spell it.
    pub fn validate(&self) -> Result<(), String> {
        if self.width == 0 || self.height == 0 {
            return Err(format!(
                "image size must be at least 1×1, got {}×{}",
                self.width, self.height
            ));
        }
        if self.width > 65536 || self.height > 65536 {
            return Err(format!(
                "image size {}×{} is larger than the 65536×65536 limit",
                self.width, self.height
            ));
        }
        if self.samples == 0 || self.samples > MAX_SAMPLES_PER_AXIS {
            return Err(format!(
                "samples must be between 1 and {MAX_SAMPLES_PER_AXIS} per axis, got {}",
                self.samples
            ));
        }
        // The integrator recurses once per bounce; beyond this, contributions are far below
        // 8-bit precision anyway and deep recursion would exhaust worker stacks.
        if self.max_depth == 0 || self.max_depth > MAX_DEPTH_LIMIT {
            return Err(format!(
                "max_depth must be between 1 (the eye ray alone) and {MAX_DEPTH_LIMIT}, got {}",
                self.max_depth
            ));
        }
        if !(0.0..=1.0).contains(&self.min_weight) {
            return Err(format!(
                "min_weight must be between 0 and 1, got {}",
                self.min_weight
            ));
        }
        if let Some(r) = self.filter_radius {
            if !(0.5..=MAX_FILTER_RADIUS).contains(&r) {
                return Err(format!(
                    "filter_radius must be between 0.5 and {MAX_FILTER_RADIUS} pixels, got {r}"
                ));
            }
        }
        self.adaptive.validate()?;
        if self.area_samples > MAX_AREA_SAMPLES {
            return Err(format!(
                "area_samples must be between 0 and {MAX_AREA_SAMPLES}, got {}",
                self.area_samples
            ));
        }
        if self.threads > MAX_THREADS {
            return Err(format!(
                "threads must be between 0 (every core) and {MAX_THREADS}, got {}",
                self.threads
            ));
        }
        if self.tile_size == 0 {
            return Err("tile_size must be at least 1".into());
        }
        Ok(())
    }

    /// Whether the render traces camera rays in packets: `packets`, with the Whitted
    /// integrator or the path tracer (the beam tracer traces no rays).
    pub fn uses_packets(&self) -> bool {
        self.packets && self.integrator.traces_rays()
    }

    /// The edge of the tiles a render hands out: `tile_size`, rounded up to whole packets
    /// when packets are on, so that packets are the same blocks of pixels whatever the
    /// tile size (and with them the statistics).
    pub fn effective_tile_size(&self) -> u32 {
        let size = self.tile_size.max(1);
        if self.uses_packets() {
            size.div_ceil(PACKET_EDGE).saturating_mul(PACKET_EDGE)
        } else {
            size
        }
    }
}
