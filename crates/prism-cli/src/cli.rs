//! The command line as a whole: the commands and the arguments of each (clap), `render`
//! the default.

use crate::args::RenderArgs;
use crate::scene_args::{scene_help, SceneArgs};
use clap::{Args, Parser, Subcommand};
use prism::accel::AccelSpec;
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    name = "prism",
    version,
    about = "A Whitted ray tracer with switchable, measurable acceleration methods",
    long_about = "A Whitted ray tracer with switchable, measurable acceleration methods.\n\n\
                  Run `prism render` to render the built-in Whitted scene to prism.png. \
                  `render` is the default command: its arguments work without its name \
                  (`prism -W 320 -H 240 scene.toml`).",
    args_conflicts_with_subcommands = true
)]
pub(crate) struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,

    /// `render`'s arguments, for `prism` without a command.
    #[command(flatten)]
    pub render: RenderArgs,
}

impl Cli {
    /// The command to run: the one named, or `render` with the arguments given without
    /// one. A first word that is no command, no file and no scene name (`prism
    /// frobnicate`) is bad usage, as clap reports an unknown command, not a missing file.
    pub(crate) fn into_command(self) -> Result<Command, clap::Error> {
        if let Some(command) = self.command {
            return Ok(command);
        }
        if let Some(word) = self.render.scene.path.as_deref() {
            let named = word.to_str().is_some_and(|w| w.starts_with("builtin:"));
            if !named && word.extension().is_none() && !word.exists() {
                use clap::CommandFactory;
                return Err(Cli::command().error(
                    clap::error::ErrorKind::InvalidSubcommand,
                    format!("unrecognized subcommand or scene file '{}'", word.display()),
                ));
            }
        }
        Ok(Command::Render(self.render))
    }
}

#[derive(Subcommand, Debug)]
pub(crate) enum Command {
    /// Render a scene file or a built-in scene to an image (the default command).
    Render(RenderArgs),
    /// List the built-in scenes.
    List,
    /// Describe a scene without rendering it: shapes, materials, lights, bounds, memory
    /// and the acceleration structure built for it.
    #[command(override_usage = "prism info [OPTIONS] <SCENE>\n       \
                                prism info [OPTIONS] --builtin <NAME>")]
    Info(InfoArgs),
    /// Measure acceleration methods on scenes: build time, memory, node visits and
    /// primitive tests per ray, primary and shadow rays per second; a table, CSV, JSON and
    /// an SVG chart.
    Bench(crate::bench::BenchArgs),
    /// Compare two images: RMSE, PSNR, SSIM and FLIP of TEST against REFERENCE.
    Compare(crate::compare::CompareArgs),
    /// Write the exact box-filtered image of a scene of planar polygons, with no sampling
    /// (the checkerboard, the default, in closed form; others by the beam tracer).
    #[command(mut_arg("scene", |a| a.help(scene_help(
        "`checkerboard` scene. Any scene of planar polygons (curved shapes are refused)"
    ))))]
    Reference(crate::reference::ReferenceArgs),
    /// Render a scene (the checkerboard by default) with each sampling pattern at several
    /// sample counts, measure each image against a reference (exact, --reference FILE, or
    /// a render of many samples) and plot the error against the rays per pixel.
    #[command(mut_arg("scene", |a| a.help(scene_help(
        "`checkerboard` scene, whose reference is exact"
    ))))]
    Sweep(crate::sweep::SweepArgs),
    /// Draw each sampling pattern's points (SVG).
    Patterns(crate::patterns::PatternsArgs),
    /// Start the live viewer: a local web page that shows the render refining and lets
    /// the mouse and keys move the camera (docs/viewer.md).
    Serve(crate::serve::ServeArgs),
}

#[derive(Args, Debug)]
pub(crate) struct InfoArgs {
    // Not `SceneArgs`: here the scene is required, and its help says so. Required, not
    // `required_unless_present`, so that the help lists it as <SCENE>; --builtin, which
    // conflicts with it, stands in for it all the same.
    /// Scene file (.toml, .nff, .gltf, .glb) or mesh file (.obj, .ply), or builtin:NAME for
    /// a built-in scene. Required unless --builtin is given.
    #[arg(required = true, value_name = "SCENE")]
    pub scene: Option<PathBuf>,

    /// Built-in scene to describe instead of a file, as `render --builtin` takes it.
    #[arg(short, long, value_name = "NAME", conflicts_with = "scene")]
    pub builtin: Option<String>,

    /// Acceleration structure to build and describe, as for `render --accel`; the scene
    /// file's own `accel` setting when not given.
    #[arg(long, value_name = "SPEC")]
    pub accel: Option<AccelSpec>,
}

impl InfoArgs {
    /// The scene named, as the commands that render read it.
    pub(crate) fn scene(&self) -> SceneArgs {
        SceneArgs {
            path: self.scene.clone(),
            builtin: self.builtin.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use prism::sampling::{AdaptiveRule, SamplerKind};
    use prism::RenderOptions;

    fn options(args: &[&str]) -> RenderOptions {
        let mut argv = vec!["prism", "render"];
        argv.extend(args);
        match Cli::try_parse_from(argv).unwrap().command {
            Some(Command::Render(r)) => r.options(&RenderOptions::default()).unwrap(),
            other => panic!("expected render, got {other:?}"),
        }
    }

    #[test]
    fn the_pov_preset_is_povs_am2_pattern_and_flags_refine_it() {
        let o = options(&["--preset", "pov"]);
        assert_eq!(o.sampler, SamplerKind::Adaptive);
        assert_eq!(o.adaptive.rule, AdaptiveRule::Corners);
        assert_eq!((o.adaptive.jitter, o.adaptive.texture_spp), (0.0, 0));
        assert_eq!(o.adaptive.depth, 2, "+R3 counts the pixel: two levels");
        assert_eq!(
            o.adaptive.threshold,
            RenderOptions::default().adaptive.threshold
        );
        let o = options(&[
            "--preset",
            "pov",
            "--adaptive-depth",
            "3",
            "--adaptive-threshold",
            "0.3",
        ]);
        assert_eq!((o.adaptive.depth, o.adaptive.threshold), (3, 0.3));
        assert_eq!(o.adaptive.rule, AdaptiveRule::Corners);
    }
}
