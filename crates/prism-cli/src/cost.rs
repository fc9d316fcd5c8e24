//! The cost view: per pixel, the acceleration structure's work (node visits or primitive
//! tests) per camera ray, as a heat map with a colour bar. Every ray a pixel spawns counts
//! (camera, shadow, reflected, refracted), divided by the pixel's camera rays: the view shows
//! where the structure works hard for the image as rendered, and its sum over the image is
//! the render's total. The counts are exact per pixel, so the view is the same for any
//! thread count.

use anyhow::{bail, Result};
use prism::render::RayCounts;
use prism_io::output::heatmap::heatmap;
use std::path::Path;

/// Which work the cost view shows.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum CostMetric {
    /// Acceleration-structure nodes whose bounds were tested.
    #[default]
    Nodes,
    /// Ray–primitive intersection tests.
    Prims,
}

/// Fails early on a name the view cannot be written under.
pub(crate) fn check(path: &Path) -> Result<()> {
    if !path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"))
    {
        bail!(
            "{}: the cost view is written as PNG; use a .png name",
            path.display()
        );
    }
    Ok(())
}

/// Whose work the cost view counts.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum CostRays {
    /// Every ray a pixel spawned: camera, shadow, reflected, refracted.
    #[default]
    All,
    /// Shadow rays only: where the shadow method (`--shadows`) works hard.
    Shadow,
}

/// Work per camera ray of each pixel (0 where a pixel traced no camera ray).
pub(crate) fn per_camera_ray(rays: &RayCounts, metric: CostMetric, whose: CostRays) -> Vec<f32> {
    let work = match (metric, whose) {
        (CostMetric::Nodes, CostRays::All) => &rays.node_visits,
        (CostMetric::Prims, CostRays::All) => &rays.primitive_tests,
        (CostMetric::Nodes, CostRays::Shadow) => &rays.shadow_node_visits,
        (CostMetric::Prims, CostRays::Shadow) => &rays.shadow_tests,
    };
    work.iter()
        .zip(&rays.camera)
        .map(|(&w, &c)| if c == 0 { 0.0 } else { w as f32 / c as f32 })
        .collect()
}

pub(crate) fn write(
    path: &Path,
    rays: &RayCounts,
    (metric, whose): (CostMetric, CostRays),
    method: &str,
) -> Result<()> {
    let values = per_camera_ray(rays, metric, whose);
    // Short enough to fit under a 256-pixel view.
    let what = match (metric, whose) {
        (CostMetric::Nodes, CostRays::All) => "NODE VISITS",
        (CostMetric::Prims, CostRays::All) => "TESTS",
        (CostMetric::Nodes, CostRays::Shadow) => "SHADOW NODES",
        (CostMetric::Prims, CostRays::Shadow) => "SHADOW TESTS",
    };
    let mean = values.iter().map(|&v| v as f64).sum::<f64>() / values.len().max(1) as f64;
    let max = values.iter().copied().fold(0.0, f32::max);
    let caption = format!(
        "{what}/CAMERA RAY, {}: MEAN {mean:.1}, MAX {max:.0}",
        method.to_uppercase()
    );
    let image = heatmap(&values, rays.width, rays.height, None, &caption);
    prism_io::output::write_png_rgb8(path, &image)?;
    Ok(())
}
