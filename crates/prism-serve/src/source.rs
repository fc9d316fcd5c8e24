//! Where the viewer's frames come from: a [`FrameSource`] adds samples to an image it keeps
//! until it is reset. The one implementation today, [`Accumulator`], renders one sample per
//! pixel per frame with `prism::render::render` (the seed is the frame's index, so each
//! frame's random or jittered positions are new) and averages the frames here.
//!
//! The seam: the engine's `prism::render::Progressive` (new / advance(scene, options, spp,
//! cancel) / samples / film / reset) continues one sample sequence frame after frame; a
//! second `FrameSource` wrapping it would be made in `engine.rs` instead, and nothing else
//! in this crate would change. The `Accumulator` stays the viewer's source because it
//! renders through `prism::render::render`, with its packets for the Whitted integrator.

use prism::math::Color;
use prism::render::{Film, RenderError};
use prism::scene::PreparedScene;
use prism::RenderOptions;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// What one call of [`FrameSource::advance`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Advance {
    /// Rays traced (of every kind).
    pub rays: u64,
    /// Wall-clock time of the frame's render.
    pub time: Duration,
}

/// Per-pixel work summed over the accumulated frames, for the cost and density views.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WorkTotals {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Camera rays per pixel.
    pub camera: Vec<u64>,
    /// Rays of every kind per pixel.
    pub rays: Vec<u64>,
    /// Acceleration-structure node visits per pixel.
    pub node_visits: Vec<u64>,
}

/// An image that refines as samples are added, and forgets them on `reset`.
pub trait FrameSource: Send {
    /// Adds one frame of samples rendered with `options` (whose size must stay the same
    /// until `reset`). Returns None when `cancel` stopped the frame: its samples are
    /// dropped, the image keeps the frames before it.
    fn advance(
        &mut self,
        scene: &PreparedScene,
        options: &RenderOptions,
        cancel: &AtomicBool,
    ) -> Result<Option<Advance>, RenderError>;

    /// Forgets every sample (after a camera or settings change).
    fn reset(&mut self);

    /// Samples per pixel in the image.
    fn samples(&self) -> u32;

    /// The image: the mean of the samples so far (black before the first frame).
    fn film(&self) -> Film;

    /// Per-pixel work summed over the frames, where the source counts it.
    fn work(&self) -> Option<&WorkTotals>;
}

/// Renders one sample per pixel per frame and keeps the running sums: the first
/// [`FrameSource`].
#[derive(Default)]
pub struct Accumulator {
    sums: Vec<[f64; 3]>,
    frames: u32,
    width: u32,
    height: u32,
    transfer: prism::transfer::Transfer,
    work: WorkTotals,
}

impl Accumulator {
    /// An empty accumulation.
    pub fn new() -> Self {
        Self::default()
    }
}

impl FrameSource for Accumulator {
    fn advance(
        &mut self,
        scene: &PreparedScene,
        options: &RenderOptions,
        cancel: &AtomicBool,
    ) -> Result<Option<Advance>, RenderError> {
        let frame = RenderOptions {
            samples: 1,
            seed: self.frames as u64,
            ..options.clone()
        };
        let start = Instant::now();
        let result = prism::render::render(scene, &frame, &|_| {}, cancel)?;
        let time = start.elapsed();
        if !result.complete {
            return Ok(None);
        }
        let (w, h) = (frame.width, frame.height);
        if (w, h) != (self.width, self.height) {
            let n = w as usize * h as usize;
            self.sums = vec![[0.0; 3]; n];
            self.work = WorkTotals {
                width: w,
                height: h,
                camera: vec![0; n],
                rays: vec![0; n],
                node_visits: vec![0; n],
            };
            (self.width, self.height, self.frames) = (w, h, 0);
        } else if self.frames == 0 {
            // The buffers of the last accumulation, zeroed rather than allocated again:
            // a camera drag resets once a frame.
            self.sums.fill([0.0; 3]);
            let work = &mut self.work;
            for v in [&mut work.camera, &mut work.rays, &mut work.node_visits] {
                v.fill(0);
            }
        }
        self.transfer = frame.transfer;
        for (sum, c) in self.sums.iter_mut().zip(&result.film.pixels) {
            for (s, v) in sum.iter_mut().zip(c.to_array()) {
                *s += v as f64;
            }
        }
        let r = &result.rays;
        let work = &mut self.work;
        for (total, add) in [(&mut work.camera, &r.camera), (&mut work.rays, &r.total)] {
            total.iter_mut().zip(add).for_each(|(t, &a)| *t += a as u64);
        }
        work.node_visits
            .iter_mut()
            .zip(&r.node_visits)
            .for_each(|(t, &a)| *t += a);
        self.frames += 1;
        Ok(Some(Advance {
            rays: result.stats.total_rays(),
            time,
        }))
    }

    fn reset(&mut self) {
        self.frames = 0;
    }

    fn samples(&self) -> u32 {
        self.frames
    }

    fn film(&self) -> Film {
        let mut film = Film::new(self.width, self.height);
        film.transfer = self.transfer;
        if self.frames > 0 {
            let inv = 1.0 / self.frames as f64;
            for (p, s) in film.pixels.iter_mut().zip(&self.sums) {
                *p = Color::new(
                    (s[0] * inv) as f32,
                    (s[1] * inv) as f32,
                    (s[2] * inv) as f32,
                );
            }
        }
        film
    }

    fn work(&self) -> Option<&WorkTotals> {
        (self.frames > 0).then_some(&self.work)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_image_is_the_mean_of_the_frames_and_reset_forgets_them() {
        let scene = prism::scene::builtin::find("whitted").unwrap();
        let options = RenderOptions {
            width: 32,
            height: 18,
            sampler: prism::sampling::SamplerKind::Jittered,
            threads: 1,
            ..scene.options.clone()
        };
        let prepared = scene.prepare(&options.accel);
        let cancel = AtomicBool::new(false);
        let mut acc = Accumulator::new();
        let mut frames = Vec::new();
        for _ in 0..3 {
            acc.advance(&prepared, &options, &cancel).unwrap().unwrap();
            frames.push(acc.film());
        }
        assert_eq!(acc.samples(), 3);
        // Frame k alone is the render with seed k; the mean of three is their average.
        let one = |seed| {
            let o = RenderOptions {
                seed,
                ..options.clone()
            };
            prism::render::render(&prepared, &o, &|_| {}, &cancel)
                .unwrap()
                .film
        };
        let singles: Vec<Film> = (0..3).map(one).collect();
        assert_eq!(frames[0].pixels, singles[0].pixels);
        for (i, p) in frames[2].pixels.iter().enumerate() {
            let mean = (singles[0].pixels[i] + singles[1].pixels[i] + singles[2].pixels[i]) / 3.0;
            assert!((*p - mean).abs().max_element() < 1e-5);
        }
        assert_eq!(acc.work().unwrap().camera.iter().sum::<u64>(), 3 * 32 * 18);
        acc.reset();
        assert_eq!(acc.samples(), 0);
        assert!(acc.work().is_none());
        cancel.store(true, std::sync::atomic::Ordering::Relaxed);
        assert_eq!(acc.advance(&prepared, &options, &cancel).unwrap(), None);
    }
}
