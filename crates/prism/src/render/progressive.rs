//! Progressive rendering: an image that refines while someone watches, for the live viewer.
//! Each `advance` traces more samples per pixel and adds them to per-pixel sums; the film
//! is their mean. Sample i of pixel (x, y) lands at a uniform random point of the pixel and
//! draws every number from `Stream::new(x, y, i, seed)`, so frame k + 1 continues frame k's
//! sequence and k advances of n samples equal one of k·n bit for bit (each pixel adds its
//! samples one by one, in index order, in f64), for any thread count.
//!
//! Both integrators work: the Whitted tracer gets one randomly placed ray per sample,
//! so a still camera refines its antialiasing. The sampler, filter, tile size and image
//! size of the options are not used: samples are uniform in their pixel, each pixel is its
//! own box, rows are the pieces of work, and the size is the one `new` was given.

use super::{Film, RenderError};
use crate::integrator::{begin_piece, Integrator};
use crate::math::hash::Stream;
use crate::math::Color;
use crate::options::RenderOptions;
use crate::scene::PreparedScene;
use crate::stats::Stats;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// Most samples per pixel one accumulation holds, so sample indices stay in u32.
pub const MAX_PROGRESSIVE_SAMPLES: u32 = u32::MAX / 2;

/// Per-pixel sums of the samples traced so far, and their count.
pub struct Progressive {
    width: u32,
    height: u32,
    /// Row-major RGB sums.
    sums: Vec<[f64; 3]>,
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
        Ok(Progressive {
            width,
            height,
            sums: super::memory::try_filled(n, [0.0; 3], "progressive sums")?,
            samples: 0,
            transfer: Default::default(),
            pool: None,
        })
    }

    /// Samples per pixel so far.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Forgets every sample (after a camera move or any other change of the picture).
    pub fn reset(&mut self) {
        self.sums.fill([0.0; 3]);
        self.samples = 0;
    }

    /// The current image: each pixel the mean of its samples (black before the first).
    pub fn film(&self) -> Film {
        let scale = if self.samples == 0 {
            0.0
        } else {
            1.0 / self.samples as f64
        };
        Film {
            width: self.width,
            height: self.height,
            pixels: (self.sums.iter())
                .map(|s| {
                    Color::new(
                        (s[0] * scale) as f32,
                        (s[1] * scale) as f32,
                        (s[2] * scale) as f32,
                    )
                })
                .collect(),
            transfer: self.transfer,
        }
    }

    /// Traces `spp` more samples per pixel, continuing the sample sequence (sample indices
    /// `samples()..samples() + spp`), with the integrator, depth, seed, threads and
    /// transfer of `options`, and adds them. Setting `cancel` stops it after the rows in
    /// flight; a cancelled advance adds nothing, so the accumulation stays consistent.
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
        let camera = scene.scene.camera.setup(self.width, self.height)?;
        let integrator = Integrator::new(scene, options);
        let threads = super::requested_threads(options).clamp(1, self.height as usize);
        if self.pool.as_ref().map(|(n, _)| *n) != Some(threads) {
            self.pool = Some((threads, super::thread_pool(threads)?));
        }
        let pool = &self.pool.as_ref().expect("just built").1;
        let seed = options.seed;
        let width = self.width as usize;
        // Work on a copy: a cancelled advance leaves the sums as they were.
        let mut next = super::memory::try_filled(self.sums.len(), [0.0; 3], "progressive sums")?;
        next.copy_from_slice(&self.sums);
        let rows: Vec<Option<Stats>> = pool.install(|| {
            next.par_chunks_mut(width)
                .enumerate()
                .map(|(y, row)| {
                    if cancel.load(Ordering::Relaxed) {
                        return None;
                    }
                    begin_piece();
                    let y = y as u32;
                    let mut stats = Stats::default();
                    for (x, sum) in row.iter_mut().enumerate() {
                        let x = x as u32;
                        for i in start..end {
                            let stream = Stream::new(x, y, i, seed);
                            let ray = camera
                                .ray(x as f32 + stream.uniform(0), y as f32 + stream.uniform(1));
                            let c = integrator.trace_camera_ray(&ray, &stream, &mut stats);
                            for (s, v) in sum.iter_mut().zip(c.to_array()) {
                                *s += v as f64;
                            }
                        }
                    }
                    Some(stats)
                })
                .collect()
        });
        let mut stats = Stats::default();
        let mut complete = true;
        for row in rows {
            match row {
                Some(s) => stats += s,
                None => complete = false,
            }
        }
        if !complete {
            return Ok(stats);
        }
        self.sums = next;
        self.samples = end;
        self.transfer = options.transfer;
        Ok(stats)
    }
}
