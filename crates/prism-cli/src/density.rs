//! The sample-density view: rays per pixel as a heat map with a colour bar and a caption
//! giving the mean and the largest count.

use crate::args::DensityRays;
use anyhow::{bail, Result};
use prism::output::heatmap::heatmap;
use prism::render::RayCounts;
use std::path::Path;

/// Fails early on a name the view cannot be written under.
pub fn check(path: &Path) -> Result<()> {
    if !path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        bail!(
            "{}: the density view is written as PNG; use a .png name",
            path.display()
        );
    }
    Ok(())
}

pub fn write(path: &Path, rays: &RayCounts, kind: DensityRays) -> Result<()> {
    let (counts, what) = match kind {
        DensityRays::All => (&rays.total, "RAYS"),
        DensityRays::Camera => (&rays.camera, "CAMERA RAYS"),
    };
    let values: Vec<f32> = counts.iter().map(|&c| c as f32).collect();
    let mean = values.iter().map(|&v| v as f64).sum::<f64>() / values.len().max(1) as f64;
    let max = values.iter().copied().fold(0.0, f32::max);
    let caption = format!("{what} PER PIXEL: MEAN {mean:.2}, MAX {max:.0}");
    let image = heatmap(&values, rays.width, rays.height, None, &caption);
    prism::output::write_png_rgb8(path, &image)?;
    Ok(())
}
