//! `prism compare REFERENCE TEST`: how far TEST is from REFERENCE, as RMSE and PSNR of the
//! linear values, SSIM of the displayed luma and FLIP of the displayed colours.

use anyhow::{Context, Result};
use clap::Args;
use prism_io::output::{heatmap::heatmap, read_image};
use prism_lab::metrics::{self, flip::DEFAULT_PPD};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args, Debug)]
pub(crate) struct CompareArgs {
    /// The reference image (.png, .jpg, .exr or .pfm; 8-bit images are taken as sRGB).
    pub reference: PathBuf,

    /// The image to measure against it.
    pub test: PathBuf,

    /// The viewer's pixels per degree, for FLIP (67: a 0.7 m wide 3840-pixel monitor seen
    /// from 0.7 m).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_PPD)]
    pub ppd: f32,

    /// Also write the per-pixel FLIP error as a heat map (PNG).
    #[arg(long, value_name = "FILE")]
    pub flip_map: Option<PathBuf>,

    /// Print the numbers as JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

pub(crate) fn run(args: &CompareArgs) -> Result<ExitCode> {
    if !(args.ppd > 0.0 && args.ppd.is_finite()) {
        anyhow::bail!("--ppd must be a positive number, got {}", args.ppd);
    }
    // An output named by a symbolic link is written where the link points.
    let flip_map = args.flip_map.as_deref().map(crate::outputs::through_links);
    if let Some(path) = &flip_map {
        crate::outputs::Outputs::default().add(path, &["png"])?;
    }
    let reference = read_image(&args.reference)?;
    let test = read_image(&args.test)?;
    // The reference first, as the arguments and the size check (reference × test) take
    // them.
    let c = metrics::compare(&reference, &test, None, args.ppd).with_context(|| {
        format!(
            "cannot compare {} (the reference) with {} (the test)",
            args.reference.display(),
            args.test.display()
        )
    })?;
    if args.json {
        let json = serde_json::json!({
            "reference": args.reference.display().to_string(),
            "test": args.test.display().to_string(),
            "rmse": c.rmse,
            "psnr_db": if c.psnr.is_finite() { serde_json::json!(c.psnr) } else { serde_json::json!("inf") },
            "ssim": c.ssim,
            "flip_mean": c.flip,
            "flip_max": c.flip_max,
            "ppd": args.ppd,
            "pixels": c.pixels,
        });
        println!(
            "{}",
            serde_json::to_string_pretty(&json).expect("serialises")
        );
    } else {
        println!("RMSE   {:.6}   (linear RGB)", c.rmse);
        println!("PSNR   {:.2} dB (peak 1)", c.psnr);
        println!("SSIM   {:.5}   (displayed luma)", c.ssim);
        println!(
            "FLIP   {:.5}   mean, {:.4} max (LDR-FLIP at {} pixels per degree)",
            c.flip, c.flip_max, args.ppd
        );
    }
    if let Some(path) = &flip_map {
        let map = metrics::flip_map(&reference, &test, args.ppd)?;
        let caption = format!("FLIP ERROR: MEAN {:.4}, MAX {:.3}", c.flip, c.flip_max);
        let image = heatmap(
            &map.values,
            reference.width,
            reference.height,
            Some(1.0),
            &caption,
        );
        prism_io::output::write_png_rgb8(path, &image)?;
    }
    Ok(ExitCode::SUCCESS)
}
