//! The progress bar: percentage, rays per second and the time left on a terminal; nothing
//! otherwise.
//!
//! The time left is the elapsed time scaled by the share of the work still to do, shown
//! only once a second has passed and a few percent are done: the first tiles are often
//! sky or the cheap top of a scene, and an estimate from them alone would be wild.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use prism::render::TileDone;
use prism::RenderOptions;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// No estimate before this much time and this share of the work.
const ETA_MIN_ELAPSED: Duration = Duration::from_secs(1);
const ETA_MIN_DONE: f64 = 0.03;

pub(crate) struct RenderProgress {
    bar: ProgressBar,
    total: u64,
    done: AtomicU64,
    rays: AtomicU64,
    start: Instant,
}

impl RenderProgress {
    pub(crate) fn new(options: &RenderOptions, quiet: bool) -> Self {
        let total = prism::render::progress_total(options);
        let bar = if quiet || !std::io::stderr().is_terminal() {
            ProgressBar::hidden()
        } else {
            let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
            // Drawn at once and kept turning: the first tiles of a large render can take
            // a while, and a bar that is not there yet looks like a hang.
            bar.enable_steady_tick(Duration::from_millis(250));
            bar
        };
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}%  {msg}",
            )
            .expect("the template is valid"),
        );
        RenderProgress {
            bar,
            total,
            done: AtomicU64::new(0),
            rays: AtomicU64::new(0),
            start: Instant::now(),
        }
    }

    pub(crate) fn tile_done(&self, tile: TileDone) {
        let rays = self.rays.fetch_add(tile.rays, Ordering::Relaxed) + tile.rays;
        let done = self.done.fetch_add(tile.pixels, Ordering::Relaxed) + tile.pixels;
        let elapsed = self.start.elapsed();
        let secs = elapsed.as_secs_f64().max(1e-9);
        let eta = eta(elapsed, done as f64 / self.total.max(1) as f64).map_or_else(
            || "ETA …".to_string(),
            |d| format!("ETA {}", short_duration(d)),
        );
        self.bar
            .set_message(format!("{:.2} Mrays/s  {eta}", rays as f64 / secs / 1e6));
        self.bar.inc(tile.pixels);
    }

    /// Removes the bar, so that whatever is printed next starts on a line of its own.
    pub(crate) fn finish(&self) {
        self.bar.finish_and_clear();
    }

    /// The share of the work done, 0 to 1.
    pub(crate) fn fraction_done(&self) -> f64 {
        self.done.load(Ordering::Relaxed) as f64 / self.total.max(1) as f64
    }
}

/// Time left when `fraction` of the work took `elapsed`; None while that is too little to
/// tell.
fn eta(elapsed: Duration, fraction: f64) -> Option<Duration> {
    if elapsed < ETA_MIN_ELAPSED || !(ETA_MIN_DONE..=1.0).contains(&fraction) {
        return None;
    }
    Some(elapsed.mul_f64((1.0 - fraction) / fraction))
}

/// "42s", "3m 05s", "2h 07m".
fn short_duration(d: Duration) -> String {
    let s = d.as_secs();
    match s {
        0..60 => format!("{s}s"),
        60..3600 => format!("{}m {:02}s", s / 60, s % 60),
        _ => format!("{}h {:02}m", s / 3600, s % 3600 / 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_estimate_from_the_first_tiles() {
        assert_eq!(eta(Duration::from_millis(300), 0.5), None);
        assert_eq!(eta(Duration::from_secs(5), 0.01), None);
    }

    #[test]
    fn the_estimate_scales_elapsed_time_by_the_work_left() {
        assert_eq!(
            eta(Duration::from_secs(10), 0.25),
            Some(Duration::from_secs(30))
        );
        assert_eq!(eta(Duration::from_secs(10), 1.0), Some(Duration::ZERO));
    }

    #[test]
    fn durations_read_short() {
        assert_eq!(short_duration(Duration::from_secs(42)), "42s");
        assert_eq!(short_duration(Duration::from_secs(185)), "3m 05s");
        assert_eq!(short_duration(Duration::from_secs(7620)), "2h 07m");
    }
}
