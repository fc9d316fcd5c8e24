//! Refusing a render that cannot fit in memory, before anything is allocated: the engine's
//! estimate of its buffers, plus the acceleration structure, the encoded outputs and the
//! extra views, against the memory the system says is available.

use crate::args::RenderArgs;
use anyhow::{bail, Result};
use prism::render::memory::{format_bytes, ACCEL_BYTES_PER_PRIMITIVE};
use prism::{RenderOptions, Scene};

/// Bytes per pixel of an encoded image while it is built: the 8-bit or float pixels and
/// the compressed stream beside them.
fn output_bytes_per_pixel(path: &std::path::Path) -> u64 {
    match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("png") => 3 + 3,
        _ => 12 + 12,
    }
}

/// Fails with the bytes needed when the render would need more memory than is available.
pub(crate) fn check(scene: &Scene, options: &RenderOptions, args: &RenderArgs) -> Result<()> {
    let pixels = options.width as u64 * options.height as u64;
    let mut need = prism::render::memory_estimate(options);
    need.add(
        "acceleration structure",
        scene.geometry.primitives.len() as u64 * ACCEL_BYTES_PER_PRIMITIVE,
    );
    need.add("image file", pixels * output_bytes_per_pixel(&args.output));
    // A view: one f32 per pixel and its 8-bit heat map.
    let views = args.density.is_some() as u64 + args.cost.is_some() as u64;
    need.add("density and cost views", views * pixels * (4 + 6));
    let Some(available) = available_memory() else {
        // Unknown: the render's big buffers are allocated fallibly and report their size.
        return Ok(());
    };
    if need.total() > available {
        bail!(
            "a {}×{} render needs about {} of memory ({}), but only {} is available; \
             render a smaller image, or in parts",
            options.width,
            options.height,
            format_bytes(need.total()),
            need.breakdown(),
            format_bytes(available)
        );
    }
    Ok(())
}

/// Memory the system can give without swapping: MemAvailable from /proc/meminfo on Linux;
/// None elsewhere or when it cannot be read.
fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}
