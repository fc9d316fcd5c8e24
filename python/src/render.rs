//! A render from Python: the engine runs with the GIL released, on a thread of its own,
//! while the calling thread wakes every few milliseconds to take the GIL and ask Python
//! whether a signal arrived. Ctrl-C sets the engine's cancel flag (the one the CLI's
//! SIGINT sets), the tiles in flight stop within a row, and `KeyboardInterrupt` is raised. Other
//! Python threads run meanwhile.

use crate::errors::render_error;
use prism::render::{RenderResult, Tile};
use prism::scene::PreparedScene;
use prism::RenderOptions;
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

/// How often a waiting render looks for Ctrl-C: soon enough that a user does not wait.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Runs `work` with the GIL released, handing it a cancel flag that Ctrl-C (any signal
/// handler raising in Python) sets; the handler's exception is returned after `work`
/// stops.
pub(crate) fn without_gil<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> T + Send,
) -> PyResult<T> {
    let cancel = AtomicBool::new(false);
    py.allow_threads(|| {
        std::thread::scope(|s| {
            let (done, finished) = mpsc::channel();
            let cancel = &cancel;
            s.spawn(move || {
                // The receiver outlives this thread (the scope waits), so sending cannot fail.
                let _ = done.send(work(cancel));
            });
            let mut interrupted = None;
            loop {
                match finished.recv_timeout(SIGNAL_POLL) {
                    Ok(value) => {
                        return match interrupted {
                            Some(e) => Err(e),
                            None => Ok(value),
                        };
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) if interrupted.is_none() => {
                        // Signal handlers run only in the main thread; elsewhere this is Ok.
                        if let Err(e) = Python::with_gil(|py| py.check_signals()) {
                            cancel.store(true, Ordering::Relaxed);
                            interrupted = Some(e);
                        }
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) => {}
                    Err(mpsc::RecvTimeoutError::Disconnected) => {
                        // The worker died without an answer: only a panic in the engine
                        // does that, and the scope re-raises it as a Rust panic, which PyO3
                        // turns into `PanicException`.
                        return Err(crate::errors::RenderError::new_err(
                            "the render stopped without an answer",
                        ));
                    }
                }
            }
        })
    })
}

/// What `Scene.render` hands the Python side: the pixels of the region as little-endian
/// f32 RGB (linear light, as prism writes PFM and EXR), its size, and the statistics.
pub(crate) struct Rendered {
    pub(crate) pixels: Vec<u8>,
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) stats: serde_json::Value,
}

/// Renders `region` of `prepared` with `options`, releasing the GIL.
pub(crate) fn render(
    py: Python<'_>,
    prepared: &PreparedScene<'_>,
    options: &RenderOptions,
    region: Tile,
) -> PyResult<Rendered> {
    let result = without_gil(py, |cancel| {
        prism::render::render_region(prepared, options, region, &|_| {}, cancel)
    })?
    .map_err(render_error)?;
    Ok(rendered(result, prepared, options, region))
}

fn rendered(
    result: RenderResult,
    prepared: &PreparedScene<'_>,
    options: &RenderOptions,
    region: Tile,
) -> Rendered {
    let film = result.film.displayed_linear();
    let mut pixels = Vec::with_capacity(film.pixels.len() * 12);
    for c in &film.pixels {
        for v in [c.x, c.y, c.z] {
            pixels.extend_from_slice(&v.to_le_bytes());
        }
    }
    let stats = serde_json::json!({
        "counters": result.stats,
        "total_rays": result.stats.total_rays(),
        "complete": result.complete,
        "render_seconds": result.render_time.as_secs_f64(),
        "build_seconds": prepared.build_time.as_secs_f64(),
        "threads": prism::render::worker_threads(options),
        "width": options.width,
        "height": options.height,
        "region": [region.x0, region.y0, region.x1, region.y1],
        "sampling": options.sampling_summary(),
        "accel": options.accel.to_string(),
        "integrator": options.integrator.to_string(),
    });
    Rendered {
        pixels,
        width: film.width,
        height: film.height,
        stats,
    }
}
