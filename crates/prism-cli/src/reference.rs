//! `prism reference`: the exact box-filtered image of a scene, computed from the geometry
//! with no sampling (prism_lab::reference): the checkerboard in closed form, any other
//! scene of planar polygons by the beam tracer; with its error bound.

use crate::scene_args::{SceneArgs, SizeArgs};
use anyhow::Result;
use clap::Args;
use prism_lab::reference::{beam, checkerboard, ReferenceError, DEFAULT_TOLERANCE};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args, Debug)]
pub(crate) struct ReferenceArgs {
    /// The scene: any of planar polygons.
    #[command(flatten)]
    pub scene: SceneArgs,

    /// Output image (.exr or .pfm keep the exact values; .png rounds to 8 bits).
    #[arg(short, long, value_name = "FILE", default_value = "reference.exr")]
    pub output: PathBuf,

    #[command(flatten)]
    pub size: SizeArgs,

    /// Largest error allowed in any pixel (linear units); the pixels beside the horizon
    /// cost about 1/√tolerance.
    #[arg(long, value_name = "X", default_value_t = DEFAULT_TOLERANCE)]
    pub tolerance: f64,

    /// Beam-trace the checkerboard too, instead of its closed form (slower: its horizon
    /// holds unboundedly many squares per pixel).
    #[arg(long)]
    pub beam: bool,

    /// No closing message.
    #[arg(short, long)]
    pub quiet: bool,
}

pub(crate) fn run(args: &ReferenceArgs) -> Result<ExitCode> {
    let (scene, name) = args.scene.load("checkerboard")?;
    let mut options = scene.options.clone();
    args.size.apply(&mut options);
    let (width, height) = (options.width, options.height);
    options
        .validate()
        .map_err(|e| anyhow::anyhow!("invalid option: {e}"))?;
    prism_io::output::ImageFormat::from_path(&args.output)?;
    // An output named by a symbolic link is written where the link points.
    let output = crate::outputs::through_links(&args.output);
    crate::outputs::check_writable(&output)?;
    let start = std::time::Instant::now();
    // The closed form where the scene is the checkerboard, else the beam tracer.
    let analytic = if args.beam {
        Err(ReferenceError::Unsupported("--beam".into()))
    } else {
        checkerboard(&scene, width, height, args.tolerance)
    };
    let (mut film, bound, how) = match analytic {
        Ok(r) => (r.film, r.error_bound, "closed form".to_string()),
        Err(ReferenceError::Unsupported(_)) => {
            let r = beam(&scene, width, height, args.tolerance)?;
            let how = format!(
                "beam traced: {} beams, {} fragments, {} pixel pieces, tree depth {}",
                r.beams, r.fragments, r.pieces, r.depth
            );
            (r.film, r.error_bound, how)
        }
        Err(e) => return Err(e.into()),
    };
    film.transfer = options.transfer;
    prism_io::output::write_image_as(
        &output,
        &film,
        prism_io::output::ImageFormat::from_path(&args.output)?,
    )?;
    if !args.quiet {
        eprintln!(
            "prism: wrote {} ({name}, {width}×{height}, {how}, exact to {:.1e} per pixel, \
             {:.2} s)",
            args.output.display(),
            bound,
            start.elapsed().as_secs_f64()
        );
    }
    Ok(ExitCode::SUCCESS)
}
