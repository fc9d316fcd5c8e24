//! The progress bar: percentage, rays per second and ETA on a terminal; nothing otherwise.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use prism::render::TileDone;
use prism::RenderOptions;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

pub struct RenderProgress {
    bar: ProgressBar,
    rays: AtomicU64,
    start: Instant,
}

impl RenderProgress {
    pub fn new(options: &RenderOptions, quiet: bool) -> Self {
        let pixels = prism::render::progress_total(options);
        let bar = if quiet || !std::io::stderr().is_terminal() {
            ProgressBar::hidden()
        } else {
            ProgressBar::with_draw_target(Some(pixels), ProgressDrawTarget::stderr())
        };
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}%  {msg}  ETA {eta}",
            )
            .expect("the template is valid"),
        );
        RenderProgress {
            bar,
            rays: AtomicU64::new(0),
            start: Instant::now(),
        }
    }

    pub fn tile_done(&self, tile: TileDone) {
        let rays = self.rays.fetch_add(tile.rays, Ordering::Relaxed) + tile.rays;
        let secs = self.start.elapsed().as_secs_f64().max(1e-9);
        self.bar
            .set_message(format!("{:.2} Mrays/s", rays as f64 / secs / 1e6));
        self.bar.inc(tile.pixels);
    }

    pub fn finish(&self, complete: bool) {
        if complete {
            self.bar.finish_and_clear();
        } else {
            self.bar.abandon_with_message("interrupted");
        }
    }
}
