//! Where the viewer's frames come from: [`Frames`] keeps the engine's
//! `prism::render::Progressive` accumulation and adds one sample per pixel a frame,
//! continuing one sample sequence until a reset. Progressive traces the Whitted tracer's
//! camera rays as packets, like `prism render`, and does every per-pixel step (adding the
//! frame, the means for the page) in parallel, so that a frame's time is its tracing.

use prism::render::{Progressive, RenderError};
use prism::scene::PreparedScene;
use prism::RenderOptions;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

/// What one call of [`Frames::advance`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Advance {
    /// Rays traced (of every kind).
    pub rays: u64,
    /// Wall-clock time of the frame's render.
    pub time: Duration,
}

/// An image that refines as frames are added, and forgets them on `reset`.
#[derive(Default)]
pub struct Frames {
    /// None before the first frame; replaced when the resolution changes.
    progressive: Option<Progressive>,
}

impl Frames {
    /// No frames yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one frame of one sample per pixel rendered with `options` (a new resolution
    /// starts a new accumulation). Returns None when `cancel` stopped the frame: its
    /// samples are dropped, the image keeps the frames before it.
    pub fn advance(
        &mut self,
        scene: &PreparedScene,
        options: &RenderOptions,
        cancel: &AtomicBool,
    ) -> Result<Option<Advance>, RenderError> {
        let size = (options.width, options.height);
        let progressive = match &mut self.progressive {
            Some(p) if p.size() == size => p,
            slot => slot.insert(Progressive::new(size.0, size.1)?),
        };
        let before = progressive.samples();
        let start = Instant::now();
        let stats = progressive.advance(scene, options, 1, cancel)?;
        let time = start.elapsed();
        Ok((progressive.samples() > before).then(|| Advance {
            rays: stats.total_rays(),
            time,
        }))
    }

    /// Forgets every frame (after a camera or settings change).
    pub fn reset(&mut self) {
        if let Some(p) = &mut self.progressive {
            p.reset();
        }
    }

    /// Samples per pixel in the image (one per frame).
    pub fn samples(&self) -> u32 {
        self.progressive.as_ref().map_or(0, Progressive::samples)
    }

    /// The accumulation: None until a frame has been added since the last reset.
    pub fn image(&self) -> Option<&Progressive> {
        self.progressive.as_ref().filter(|p| p.samples() > 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use prism::math::Color;
    use prism::sampling::SamplerKind;

    #[test]
    fn the_image_is_the_mean_of_the_frames_and_reset_forgets_them() {
        let scene = prism::scene::builtin::find("whitted").unwrap();
        let options = RenderOptions {
            width: 32,
            height: 18,
            sampler: SamplerKind::Jittered,
            threads: 2,
            ..scene.options.clone()
        };
        let prepared = scene.prepare_for(&options);
        let cancel = AtomicBool::new(false);
        let mut frames = Frames::new();
        assert!(frames.image().is_none());
        for _ in 0..3 {
            frames
                .advance(&prepared, &options, &cancel)
                .unwrap()
                .unwrap();
        }
        assert_eq!(frames.samples(), 3);
        // Three frames are the progressive render of three samples per pixel, on any
        // number of threads.
        let mut once = Progressive::new(32, 18).unwrap();
        let one = RenderOptions {
            threads: 1,
            ..options.clone()
        };
        once.advance(&prepared, &one, 3, &cancel).unwrap();
        let image = frames.image().unwrap();
        assert_eq!(image.film(), once.film());
        assert!(image.film().pixels.iter().any(|&c| c != Color::ZERO));
        let camera: u64 = image.pixels().iter().map(|p| p.camera_rays).sum();
        assert_eq!(camera, 3 * 32 * 18);

        frames.reset();
        assert_eq!(frames.samples(), 0);
        assert!(frames.image().is_none());
        cancel.store(true, std::sync::atomic::Ordering::Relaxed);
        assert_eq!(frames.advance(&prepared, &options, &cancel).unwrap(), None);
        assert!(frames.image().is_none());

        // A new resolution starts a new accumulation.
        cancel.store(false, std::sync::atomic::Ordering::Relaxed);
        let small = RenderOptions {
            width: 8,
            height: 8,
            ..options
        };
        frames.advance(&prepared, &small, &cancel).unwrap().unwrap();
        assert_eq!(frames.image().unwrap().size(), (8, 8));
        assert_eq!(frames.samples(), 1);
    }
}
