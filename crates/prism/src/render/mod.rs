//! Rendering: a sampler chooses where camera rays go, the integrator traces them, and a
//! reconstruction filter turns the samples into pixels. Per-pixel patterns render square
//! tiles that a rayon pool takes in any order (`pixels`); patterns that share samples
//! between pixels render in passes over rows (`lattice`). Either way each traced value
//! depends only on (scene, options, seed, position) and pixels are exact sums, so the image
//! and the statistics are identical for every thread count, tile size and order.

mod beam;
mod film;
mod filter;
mod integrators;
mod lattice;
pub mod memory;
mod packet;
mod pixels;
mod progressive;
mod rays;
mod samplers;
mod splat;

pub use beam::{render_beam, BeamRender};
pub use film::Film;
pub use filter::{Filter, FilterKind};
pub use integrators::{integrator_method, IntegratorMethod};
pub use memory::{estimate as memory_estimate, MemoryEstimate};
pub use progressive::{PixelTotals, Progressive, MAX_PROGRESSIVE_SAMPLES};
pub use rays::{PixelRays, RayCounts};
pub use samplers::{sampler_method, PixelSamples, SamplerMethod};

use crate::camera::{CameraError, CameraRays};
use crate::integrator::CameraTracer;
use crate::math::hash::Stream;
use crate::math::Color;
use crate::options::RenderOptions;
use crate::scene::PreparedScene;
use crate::stats::Stats;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// A rectangle of pixels `[x0, x1) × [y0, y1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    /// First column.
    pub x0: u32,
    /// First row.
    pub y0: u32,
    /// One past the last column.
    pub x1: u32,
    /// One past the last row.
    pub y1: u32,
}

impl Tile {
    /// Number of pixels in the tile.
    pub fn pixel_count(&self) -> u64 {
        (self.x1 - self.x0) as u64 * (self.y1 - self.y0) as u64
    }

    /// The whole of a width × height image.
    pub fn full(width: u32, height: u32) -> Self {
        Tile {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    /// Pixels per row.
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }

    /// Rows.
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }

    /// The pixels both rectangles hold, or None when they do not overlap.
    pub fn intersection(&self, other: &Tile) -> Option<Tile> {
        let t = Tile {
            x0: self.x0.max(other.x0),
            y0: self.y0.max(other.y0),
            x1: self.x1.min(other.x1),
            y1: self.y1.min(other.y1),
        };
        (t.x0 < t.x1 && t.y0 < t.y1).then_some(t)
    }

    /// The rectangle grown by `margin` pixels on every side, clipped to a width × height
    /// image.
    pub(crate) fn grown(&self, margin: u32, width: u32, height: u32) -> Tile {
        Tile {
            x0: self.x0.saturating_sub(margin),
            y0: self.y0.saturating_sub(margin),
            x1: self.x1.saturating_add(margin).min(width),
            y1: self.y1.saturating_add(margin).min(height),
        }
    }
}

/// Tiles in row-major order covering a width × height image.
pub fn tiles(width: u32, height: u32, size: u32) -> Vec<Tile> {
    let mut out = Vec::new();
    for y0 in (0..height).step_by(size as usize) {
        for x0 in (0..width).step_by(size as usize) {
            out.push(Tile {
                x0,
                y0,
                x1: (x0 + size).min(width),
                y1: (y0 + size).min(height),
            });
        }
    }
    out
}

/// The threads `options.threads` asks for: 0 means one per core.
pub(crate) fn requested_threads(options: &RenderOptions) -> usize {
    match options.threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    }
}

/// A pool of `threads` workers for one render.
pub(crate) fn thread_pool(threads: usize) -> Result<rayon::ThreadPool, RenderError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| RenderError::Threads {
            threads,
            message: e.to_string(),
        })
}

/// The worker threads a render starts: the requested count (every core for 0), but never
/// more than there are pieces of work (tiles, or rows for the lattice samplers), since
/// the others could only wait.
pub fn worker_threads(options: &RenderOptions) -> usize {
    workers_for(options, sampler_method(options.sampler))
}

/// The worker threads `sampler` renders with for `options`.
fn workers_for(options: &RenderOptions, sampler: &dyn SamplerMethod) -> usize {
    requested_threads(options).clamp(1, sampler.pieces(options).max(1))
}

/// What a finished piece of work reports to a progress display. `pixels` counts pixel
/// passes: the total to expect is `progress_total`.
#[derive(Clone, Copy, Debug)]
pub struct TileDone {
    /// Pixel passes finished.
    pub pixels: u64,
    /// Rays traced for them.
    pub rays: u64,
}

/// The sum of `TileDone::pixels` over a whole render: pixels times the passes the
/// sampler makes over them.
pub fn progress_total(options: &RenderOptions) -> u64 {
    let pixels = options.width as u64 * options.height as u64;
    pixels * sampler_method(options.sampler).passes(options)
}

/// What a render produced: the image, its statistics and the per-pixel ray counts.
pub struct RenderResult {
    /// The image.
    pub film: Film,
    /// Counters summed over every thread.
    pub stats: Stats,
    /// False when the render was cancelled; unrendered pixels are black.
    pub complete: bool,
    /// The rows from the top of the image that finished work wrote into: every row of a
    /// complete render; of a cancelled one, the rows above which every pixel is black
    /// because no finished tile reached it. None where the sampler does not tell.
    pub rows_reached: Option<u32>,
    /// Wall-clock time of the render, without the accelerator's build.
    pub render_time: Duration,
    /// Rays per pixel and their work, for the density and cost views; without counts
    /// (`RayCounts::is_recorded` false) when `RenderOptions::per_pixel_rays` was off.
    pub rays: RayCounts,
    /// Per light, its light buffer's figures (None where the accelerator answered).
    pub light_buffers: Vec<Option<crate::integrator::LightBufferInfo>>,
    /// Per light, why it has no light buffer although the shadow method asked for one.
    pub light_buffer_notes: Vec<Option<String>>,
}

/// Why a render could not start or finish.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// Options that contradict each other or are out of range.
    #[error("invalid options: {0}")]
    Options(String),
    /// The scene's camera cannot make rays.
    #[error(transparent)]
    Camera(#[from] CameraError),
    /// The thread pool could not be built.
    #[error("cannot start {threads} worker threads: {message}")]
    Threads {
        /// Threads asked for.
        threads: usize,
        /// What the system said.
        message: String,
    },
    /// The beam tracer cannot render this scene (curved shapes, an orthographic camera, a
    /// beam tree past its budget).
    #[error(transparent)]
    Beam(#[from] crate::integrator::beam::BeamError),
    /// A buffer of the render could not be allocated; `what` names it.
    #[error("out of memory: the {what} would take {}", memory::format_bytes(*bytes))]
    OutOfMemory {
        /// The buffer, in words a user understands.
        what: &'static str,
        /// Its size.
        bytes: u64,
    },
}

/// Everything a sampler's workers need: where rays come from, how they are traced, how
/// samples become pixels, and whom to tell. A sampler renders it (`SamplerMethod::render`).
pub struct Job<'a> {
    width: u32,
    height: u32,
    /// The pixels the result holds: the whole image, or the region of `render_region`.
    area: Tile,
    camera: CameraRays,
    tracer: Box<dyn CameraTracer + 'a>,
    seed: u64,
    filter: Filter,
    /// Trace camera rays in packets (`RenderOptions::packets`).
    packets: bool,
    /// Keep per-pixel ray counts (`RenderOptions::per_pixel_rays`).
    per_pixel_rays: bool,
    /// The edge of the tiles of per-pixel patterns (`RenderOptions::effective_tile_size`).
    tile_size: u32,
    on_tile: &'a (dyn Fn(TileDone) + Sync),
    cancel: &'a AtomicBool,
}

impl Job<'_> {
    /// Radiance through film position (x, y), in pixels from the top-left corner. A path
    /// draws its random numbers from a stream keyed by the position itself, which every
    /// sampler gives each sample its own of, whoever traces it.
    #[inline]
    fn trace(&self, x: f32, y: f32, stats: &mut Stats) -> Color {
        self.tracer
            .trace_camera_ray(&self.camera.ray(x, y), &self.stream(x, y), stats)
    }

    /// Renders the area with a per-pixel pattern: tiles over the thread pool, every pixel
    /// tracing its own samples (the rendering of every per-pixel sampler).
    pub fn render_pixels(&self, samples: &dyn PixelSamples) -> Result<Traced, RenderError> {
        pixels::render(self, samples, self.tile_size)
    }

    /// The random numbers of the sample at film position (x, y), keyed by the position.
    #[inline]
    fn stream(&self, x: f32, y: f32) -> Stream {
        Stream::new(x.to_bits(), y.to_bits(), 0, self.seed)
    }

    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// The rows of `area`, from its top, that finished work reaching down to image row
    /// `bottom` wrote into: its own and those the filter spreads its samples over.
    fn rows_reached(&self, area: Tile, bottom: u32) -> u32 {
        if bottom == 0 {
            return 0;
        }
        let reach = if self.filter.is_pixel_box() {
            0
        } else {
            self.filter.radius.ceil() as u32
        };
        (bottom + reach).saturating_sub(area.y0).min(area.height())
    }
}

/// What a sampler's render produces: the area's film, statistics and ray counts.
pub struct Traced {
    film: Film,
    stats: Stats,
    complete: bool,
    /// See `RenderResult::rows_reached`.
    rows_reached: Option<u32>,
    rays: RayCounts,
}

impl Traced {
    /// An empty result with its film and (when `job` keeps them) ray counts allocated; the
    /// film may be replaced by the one a reconstruction pass builds.
    fn try_new(job: &Job, width: u32, height: u32, film: Film) -> Result<Self, RenderError> {
        Ok(Traced {
            film,
            stats: Stats::default(),
            complete: true,
            rows_reached: None,
            rays: ray_counts(job.per_pixel_rays, width, height)?,
        })
    }

    /// Adds a row's statistics and its pixels' rays.
    fn add_row(&mut self, y: u32, stats: Stats, rays: &[PixelRays]) {
        self.stats += stats;
        for (x, &r) in rays.iter().enumerate() {
            self.rays.add(x as u32, y, r);
        }
    }
}

/// Zero ray counts for a `width` × `height` result, or none when they are not kept.
pub(crate) fn ray_counts(kept: bool, width: u32, height: u32) -> Result<RayCounts, RenderError> {
    if kept {
        RayCounts::try_new(width, height)
    } else {
        Ok(RayCounts::unrecorded(width, height))
    }
}

/// Renders `scene` with `options`. `on_tile` is called (from worker threads) after each
/// piece of work; setting `cancel` stops the render after the pieces in flight.
pub fn render(
    scene: &PreparedScene,
    options: &RenderOptions,
    on_tile: &(dyn Fn(TileDone) + Sync),
    cancel: &AtomicBool,
) -> Result<RenderResult, RenderError> {
    let full = Tile::full(options.width, options.height);
    render_region(scene, options, full, on_tile, cancel)
}

/// Renders only the pixels of `region` of the `options.width` × `options.height` image:
/// the result's film and ray counts are `region`'s size, and every pixel is bit for bit the
/// one `render` gives, since a sample depends only on its position and pixels are exact
/// sums. This is how a render is cut into pieces for several processes or machines
/// (prism's Python package hands them to Dask). A filter wider than the pixel also traces
/// the samples within its reach around the region, so the statistics count those too.
/// Only the per-pixel samplers render a region: `corners` and `adaptive` share samples
/// between pixels in passes over the whole image and refuse any region but all of it.
pub fn render_region(
    scene: &PreparedScene,
    options: &RenderOptions,
    region: Tile,
    on_tile: &(dyn Fn(TileDone) + Sync),
    cancel: &AtomicBool,
) -> Result<RenderResult, RenderError> {
    options.validate().map_err(RenderError::Options)?;
    let full = Tile::full(options.width, options.height);
    if region.intersection(&full) != Some(region) {
        return Err(RenderError::Options(format!(
            "region [{}, {}) × [{}, {}) is empty or reaches outside the {}×{} image",
            region.x0, region.x1, region.y0, region.y1, options.width, options.height
        )));
    }
    render_with(
        scene,
        options,
        region,
        sampler_method(options.sampler),
        integrator_method(options.integrator),
        on_tile,
        cancel,
    )
}

/// Renders `region` as `render_region` does, with the sampler and the integrator given as
/// methods rather than named by `options` (whose other settings still hold): how a method
/// of one's own renders without joining the lists.
pub fn render_with(
    scene: &PreparedScene,
    options: &RenderOptions,
    region: Tile,
    sampler: &dyn SamplerMethod,
    integrator: &dyn IntegratorMethod,
    on_tile: &(dyn Fn(TileDone) + Sync),
    cancel: &AtomicBool,
) -> Result<RenderResult, RenderError> {
    if !sampler.renders_regions() && region != Tile::full(options.width, options.height) {
        return Err(RenderError::Options(format!(
            "the {} sampler shares samples between pixels across the whole image, so it \
             renders no region smaller than the image; use a per-pixel sampler",
            options.sampler
        )));
    }
    integrator.render(scene, options, region, sampler, on_tile, cancel)
}

/// Renders `region` in the sampler's pieces over a pool of threads, each camera ray traced
/// by `tracer`: how integrators that trace rays render (`IntegratorMethod::render`).
pub fn render_tiled<'a>(
    scene: &'a PreparedScene<'a>,
    options: &RenderOptions,
    region: Tile,
    sampler: &dyn SamplerMethod,
    tracer: Box<dyn CameraTracer + 'a>,
    on_tile: &(dyn Fn(TileDone) + Sync),
    cancel: &AtomicBool,
) -> Result<RenderResult, RenderError> {
    let job = Job {
        width: options.width,
        height: options.height,
        area: region,
        camera: scene.scene.camera.setup(options.width, options.height)?,
        tracer,
        seed: options.seed,
        filter: Filter::new(options.filter, options.filter_radius),
        packets: options.uses_packets(),
        per_pixel_rays: options.per_pixel_rays,
        tile_size: options.effective_tile_size(),
        on_tile,
        cancel,
    };
    let pool = thread_pool(workers_for(options, sampler))?;

    let start = Instant::now();
    let traced = pool.install(|| sampler.render(&job, options))?;
    let render_time = start.elapsed();
    let (light_buffers, light_buffer_notes) = match job.tracer.shadows() {
        Some(shadows) => (shadows.buffer_info(), shadows.unbuilt.clone()),
        None => (Vec::new(), Vec::new()),
    };
    let mut film = traced.film;
    film.transfer = options.transfer;
    Ok(RenderResult {
        film,
        stats: traced.stats,
        complete: traced.complete,
        rows_reached: match traced.complete {
            true => Some(region.height()),
            false => traced.rows_reached,
        },
        render_time,
        rays: traced.rays,
        light_buffers,
        light_buffer_notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::SamplerKind;

    #[test]
    fn a_render_never_starts_more_workers_than_pieces_of_work() {
        let options = RenderOptions {
            width: 20,
            height: 20,
            tile_size: 16,
            threads: 64,
            ..RenderOptions::default()
        };
        // 2 × 2 tiles.
        assert_eq!(worker_threads(&options), 4);
        let lattice = RenderOptions {
            sampler: SamplerKind::Adaptive,
            ..options.clone()
        };
        // Rows, and the bottom corners' row.
        assert_eq!(worker_threads(&lattice), 21);
        let few = RenderOptions {
            threads: 3,
            ..options
        };
        assert_eq!(worker_threads(&few), 3);
    }
}
