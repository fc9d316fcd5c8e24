//! The sample-density view: rays per pixel as a heat map with a colour bar and a caption
//! giving the mean and the largest count (PNG), or the raw counts as grey values for
//! scripts (PFM or EXR).

use anyhow::{bail, Result};
use prism::render::RayCounts;
use prism_io::output::heatmap::heatmap;
use std::path::Path;

/// Which rays the density view counts.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum DensityRays {
    #[default]
    All,
    Camera,
}

/// Fails early on a name the view cannot be written under.
pub(crate) fn check(path: &Path) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("png" | "pfm" | "exr")) {
        bail!(
            "{}: the density view is written as PNG (heat map), PFM or EXR (raw counts); \
             use one of those names",
            path.display()
        );
    }
    Ok(())
}

pub(crate) fn write(path: &Path, rays: &RayCounts, kind: DensityRays) -> Result<()> {
    let (counts, what) = match kind {
        DensityRays::All => (&rays.total, "RAYS"),
        DensityRays::Camera => (&rays.camera, "CAMERA RAYS"),
    };
    let values: Vec<f32> = counts.iter().map(|&c| c as f32).collect();
    if !path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        let mut film = prism::render::Film::new(rays.width, rays.height);
        for (p, &v) in film.pixels.iter_mut().zip(&values) {
            *p = prism::math::Color::splat(v);
        }
        prism_io::output::write_image(path, &film)?;
        return Ok(());
    }
    let mean = values.iter().map(|&v| v as f64).sum::<f64>() / values.len().max(1) as f64;
    let max = values.iter().copied().fold(0.0, f32::max);
    let caption = format!("{what} PER PIXEL: MEAN {mean:.2}, MAX {max:.0}");
    let image = heatmap(&values, rays.width, rays.height, None, &caption);
    prism_io::output::write_png_rgb8(path, &image)?;
    Ok(())
}
