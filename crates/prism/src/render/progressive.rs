//! Progressive rendering: an image that refines while someone watches, for the live viewer.
//! Each `advance` traces more samples per pixel and adds them to per-pixel sums; the film
//! is their mean. Sample i of pixel (x, y) lands at a uniform random point of the pixel (or
//! its centre, for the `centre` sampler) and draws every number from
//! `Stream::new(x, y, i, seed)`, so frame k + 1 continues frame k's sequence and k advances
//! of n samples equal one of k·n bit for bit (each pixel adds its samples one by one, in
//! index order, in f64), for any thread count.
//!
//! Both integrators work: the Whitted tracer gets one randomly placed ray per sample, so a
//! still camera refines its antialiasing, and traces the camera rays of 8 × 8 pixels as a
//! packet (when the options' packets are on), which gives every ray the value it has
//! alone. Each pixel also counts what its samples cost (camera rays, all rays, node
//! visits), for the viewer's cost and density views. The pieces of work are bands of
//! `PACKET_EDGE` rows; the filter, tile size and image size of the options are not used:
//! each pixel is its own box, and the size is the one `new` was given.
//!
//! A frame at the viewer's rate leaves little time for anything but tracing, so nothing
//! here is serial over the pixels: an advance writes each band's old sums plus its new
//! samples into a second buffer (swapped in when every band is done, so a cancelled advance
//! changes nothing), and `map_pixels` turns the sums into what a page shows in parallel.

use super::packet::trace_camera_packet;
use super::rays::{PixelRays, RayMark};
use super::{Film, RenderError};
use crate::accel::PACKET_MAX;
use crate::camera::CameraRays;
use crate::integrator::{begin_piece, CameraBatch, CameraTracer};
use crate::math::hash::Stream;
use crate::math::{Color, Ray, Vec2};
use crate::options::{RenderOptions, PACKET_EDGE};
use crate::sampling::SamplerKind;
use crate::scene::PreparedScene;
use crate::stats::Stats;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Most samples per pixel one accumulation holds, so sample indices stay in u32.
pub const MAX_PROGRESSIVE_SAMPLES: u32 = u32::MAX / 2;

/// One pixel's accumulation: the sum of its samples' radiance, and what tracing them cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PixelTotals {
    /// Sum of the samples' radiance, per channel.
    pub sum: [f64; 3],
    /// Camera rays (one per sample).
    pub camera_rays: u64,
    /// Rays of every kind.
    pub rays: u64,
    /// Acceleration-structure node visits of all the pixel's rays (a packet's shared
    /// visits split evenly among its pixels).
    pub node_visits: u64,
}

impl PixelTotals {
    fn add(&mut self, c: Color, work: PixelRays) {
        for (s, v) in self.sum.iter_mut().zip(c.to_array()) {
            *s += v as f64;
        }
        self.camera_rays += u64::from(work.camera);
        self.rays += u64::from(work.total);
        self.node_visits += work.node_visits;
    }
}

/// Per-pixel sums of the samples traced so far, and their count.
pub struct Progressive {
    width: u32,
    height: u32,
    /// Row-major totals of the samples so far.
    pixels: Vec<PixelTotals>,
    /// Where an advance writes the next totals; swapped with `pixels` when it completes.
    next: Vec<PixelTotals>,
    samples: u32,
    transfer: crate::transfer::Transfer,
    /// The pool of the last advance, kept while the thread count stays the same.
    pool: Option<(usize, rayon::ThreadPool)>,
}

impl Progressive {
    /// An empty accumulation for a width × height image.
    pub fn new(width: u32, height: u32) -> Result<Self, RenderError> {
        let size = RenderOptions {
            width,
            height,
            ..RenderOptions::default()
        };
        size.validate().map_err(RenderError::Options)?;
        let n = width as usize * height as usize;
        let zero = PixelTotals::default();
        Ok(Progressive {
            width,
            height,
            pixels: super::memory::try_filled(n, zero, "progressive sums")?,
            next: super::memory::try_filled(n, zero, "progressive sums")?,
            samples: 0,
            transfer: Default::default(),
            pool: None,
        })
    }

    /// The image's width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Samples per pixel so far.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Every pixel's totals, row-major; empty before the first sample.
    pub fn pixels(&self) -> &[PixelTotals] {
        if self.samples == 0 {
            &[]
        } else {
            &self.pixels
        }
    }

    /// The transfer of the last advance's options: what the film's values mean.
    pub fn transfer(&self) -> crate::transfer::Transfer {
        self.transfer
    }

    /// Forgets every sample (after a camera move or any other change of the picture).
    pub fn reset(&mut self) {
        self.samples = 0;
    }

    /// The current image: each pixel the mean of its samples (black before the first).
    pub fn film(&self) -> Film {
        let mut pixels = vec![Color::ZERO; self.pixels.len()];
        self.map_pixels(&mut pixels, |mean, _| mean);
        Film {
            width: self.width,
            height: self.height,
            pixels,
            transfer: self.transfer,
        }
    }

    /// Sets `out[i]` to `f(mean of pixel i, its totals)` for every pixel (row-major), in
    /// parallel on the last advance's threads: how a viewer turns the sums into a frame
    /// without a serial pass. The mean is black before the first sample.
    pub fn map_pixels<T: Send>(&self, out: &mut [T], f: impl Fn(Color, &PixelTotals) -> T + Sync) {
        assert_eq!(out.len(), self.pixels.len(), "one output per pixel");
        let scale = if self.samples == 0 {
            0.0
        } else {
            1.0 / self.samples as f64
        };
        let zero = PixelTotals::default();
        let f = &f;
        let mut run = move || {
            let chunk = self.width as usize * PACKET_EDGE as usize;
            (out.par_chunks_mut(chunk))
                .zip(self.pixels.par_chunks(chunk))
                .for_each(|(out, pixels)| {
                    for (o, p) in out.iter_mut().zip(pixels) {
                        // After a reset the old sums stay until the next advance overwrites
                        // them; they are not the image.
                        let p = if self.samples == 0 { &zero } else { p };
                        let s = p.sum;
                        let mean = Color::new(
                            (s[0] * scale) as f32,
                            (s[1] * scale) as f32,
                            (s[2] * scale) as f32,
                        );
                        *o = f(mean, p);
                    }
                })
        };
        match &self.pool {
            Some((_, pool)) => pool.install(run),
            None => run(),
        }
    }

    /// Traces `spp` more samples per pixel, continuing the sample sequence (sample indices
    /// `samples()..samples() + spp`), with the integrator, depth, seed, threads, packets
    /// and transfer of `options` (its sampler: `centre` puts every sample at the pixel's
    /// centre, any other at a random point of the pixel), and adds them. Setting `cancel`
    /// stops it after the bands in flight; a cancelled advance adds nothing, so the
    /// accumulation stays consistent.
    pub fn advance(
        &mut self,
        scene: &PreparedScene,
        options: &RenderOptions,
        spp: u32,
        cancel: &AtomicBool,
    ) -> Result<Stats, RenderError> {
        options.validate().map_err(RenderError::Options)?;
        let start = self.samples;
        let end = start
            .checked_add(spp)
            .filter(|&e| e <= MAX_PROGRESSIVE_SAMPLES)
            .ok_or_else(|| {
                RenderError::Options(format!(
                    "a progressive render holds at most {MAX_PROGRESSIVE_SAMPLES} samples per pixel"
                ))
            })?;
        if spp == 0 {
            return Ok(Stats::default());
        }
        let integrator = super::integrator_method(options.integrator).tracer(scene, options);
        let bands = self.height.div_ceil(PACKET_EDGE) as usize;
        let threads = super::requested_threads(options).clamp(1, bands);
        if self.pool.as_ref().map(|(n, _)| *n) != Some(threads) {
            self.pool = Some((threads, super::thread_pool(threads)?));
        }
        let pass = Pass {
            camera: scene.scene.camera.setup(self.width, self.height)?,
            packets: options.uses_packets(),
            integrator: &*integrator,
            centre: options.sampler == SamplerKind::Centre,
            seed: options.seed,
            samples: start..end,
            width: self.width,
        };
        let band_len = self.width as usize * PACKET_EDGE as usize;
        // The first advance after a reset starts from zero, not from the old sums.
        let fresh = start == 0;
        let (old, next) = (&self.pixels, &mut self.next);
        let pool = &self.pool.as_ref().expect("just built").1;
        let done: Vec<Option<Stats>> = pool.install(|| {
            (next.par_chunks_mut(band_len))
                .zip(old.par_chunks(band_len))
                .enumerate()
                .map(|(band, (next, old))| {
                    if cancel.load(Ordering::Relaxed) {
                        return None;
                    }
                    begin_piece();
                    if fresh {
                        next.fill(PixelTotals::default());
                    } else {
                        next.copy_from_slice(old);
                    }
                    let mut stats = Stats::default();
                    pass.band(band as u32 * PACKET_EDGE, next, &mut stats);
                    Some(stats)
                })
                .collect()
        });
        let mut stats = Stats::default();
        for band in done {
            match band {
                Some(s) => stats += s,
                // A cancelled advance: `pixels` is untouched, `next` is scratch.
                None => return Ok(stats),
            }
        }
        std::mem::swap(&mut self.pixels, &mut self.next);
        self.samples = end;
        self.transfer = options.transfer;
        Ok(stats)
    }
}

/// What every band of one advance shares.
struct Pass<'i, 's> {
    camera: CameraRays,
    integrator: &'i (dyn CameraTracer + 's),
    /// Whether camera rays go as packets.
    packets: bool,
    centre: bool,
    seed: u64,
    samples: std::ops::Range<u32>,
    width: u32,
}

impl Pass<'_, '_> {
    /// Film position and random numbers of sample `i` of pixel (x, y).
    #[inline]
    fn sample(&self, x: u32, y: u32, i: u32) -> (Vec2, Stream) {
        let stream = Stream::new(x, y, i, self.seed);
        let (u, v) = if self.centre {
            (0.5, 0.5)
        } else {
            (stream.uniform(0), stream.uniform(1))
        };
        (Vec2::new(x as f32 + u, y as f32 + v), stream)
    }

    /// Adds this pass's samples to the band of rows from `y0` whose totals are `band`.
    fn band(&self, y0: u32, band: &mut [PixelTotals], stats: &mut Stats) {
        let width = self.width as usize;
        let rows = (band.len() / width) as u32;
        if !self.packets {
            for (k, totals) in band.iter_mut().enumerate() {
                let (x, y) = ((k % width) as u32, y0 + (k / width) as u32);
                for i in self.samples.clone() {
                    let (at, stream) = self.sample(x, y, i);
                    let mark = RayMark::of(stats);
                    let ray = self.camera.ray(at.x, at.y);
                    let c = self.integrator.trace_camera_ray(&ray, &stream, stats);
                    totals.add(c, PixelRays::since(mark, stats));
                }
            }
            return;
        }
        if self.integrator.traces_batches() {
            return self.band_batch(y0, band, stats);
        }
        // Blocks of PACKET_EDGE × PACKET_EDGE pixels, one packet per sample index; each
        // pixel still adds its samples in index order.
        // Per pixel of the block: its index in the band and its position.
        let mut block: arrayvec::ArrayVec<(usize, u32, u32), PACKET_MAX> =
            arrayvec::ArrayVec::new();
        let mut rays: arrayvec::ArrayVec<Ray, PACKET_MAX> = arrayvec::ArrayVec::new();
        let mut streams: arrayvec::ArrayVec<Stream, PACKET_MAX> = arrayvec::ArrayVec::new();
        let mut colors = [Color::ZERO; PACKET_MAX];
        let mut work = [PixelRays::default(); PACKET_MAX];
        for bx in (0..self.width).step_by(PACKET_EDGE as usize) {
            block.clear();
            for dy in 0..rows {
                for x in bx..(bx + PACKET_EDGE).min(self.width) {
                    block.push((dy as usize * width + x as usize, x, y0 + dy));
                }
            }
            let n = block.len();
            for i in self.samples.clone() {
                rays.clear();
                streams.clear();
                for &(_, x, y) in &block {
                    let (at, stream) = self.sample(x, y, i);
                    rays.push(self.camera.ray(at.x, at.y));
                    streams.push(stream);
                }
                work[..n].fill(PixelRays::default());
                let (colors, work) = (&mut colors[..n], &mut work[..n]);
                trace_camera_packet(self.integrator, &rays, &streams, colors, work, stats);
                for (j, &(k, _, _)) in block.iter().enumerate() {
                    band[k].add(colors[j], work[j]);
                }
            }
        }
    }

    /// `band` with all of this pass's samples of the band as one batch
    /// (`CameraTracer::trace_camera_batch`), in the packets' order: block by block,
    /// sample index by sample index. Each pixel adds its samples in index order; the
    /// batch's traversal work is shared evenly among its samples.
    fn band_batch(&self, y0: u32, band: &mut [PixelTotals], stats: &mut Stats) {
        let width = self.width as usize;
        let rows = (band.len() / width) as u32;
        let spp = self.samples.len();
        // Per sample of the batch: its pixel's index in the band and its sample index.
        let mut order: Vec<(u32, u32)> = Vec::with_capacity(band.len() * spp);
        for bx in (0..self.width).step_by(PACKET_EDGE as usize) {
            for i in 0..spp as u32 {
                for dy in 0..rows {
                    for x in bx..(bx + PACKET_EDGE).min(self.width) {
                        order.push(((dy as usize * width + x as usize) as u32, i));
                    }
                }
            }
        }
        let first = self.samples.start;
        let mut colors = vec![Color::ZERO; band.len() * spp];
        let mut rays = vec![(0u32, 0u32); band.len() * spp];
        let mark = RayMark::of(stats);
        let batch = CameraBatch {
            count: order.len(),
            sample: &mut |j| {
                let (k, i) = order[j];
                let (x, y) = (k % self.width, y0 + k / self.width);
                let (at, stream) = self.sample(x, y, first + i);
                Some((self.camera.ray(at.x, at.y), stream))
            },
            done: &mut |j, color, spawned| {
                let (k, i) = order[j];
                let slot = k as usize * spp + i as usize;
                colors[slot] = color;
                rays[slot] = (1, 1 + spawned);
            },
        };
        self.integrator.trace_camera_batch(batch, stats);
        let shared = PixelRays::since(mark, stats);
        let n = order.len();
        for (j, &(k, i)) in order.iter().enumerate() {
            let slot = k as usize * spp + i as usize;
            let mut work = shared.share(j, n);
            (work.camera, work.total) = rays[slot];
            band[k as usize].add(colors[slot], work);
        }
    }
}
