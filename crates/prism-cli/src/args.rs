//! Command-line arguments. Every render setting maps onto `prism::RenderOptions`; options
//! not given keep the scene's value, and the scene's defaults come from the library.

use anyhow::{bail, Result};
use clap::{Args, Parser, Subcommand};
use prism::accel::AccelKind;
use prism::scene::builtin;
use prism::{RenderOptions, Scene};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    name = "prism",
    version,
    about = "A Whitted ray tracer with switchable, measurable acceleration methods",
    long_about = "A Whitted ray tracer with switchable, measurable acceleration methods.\n\n\
                  Run `prism render` to render the built-in Whitted scene to prism.png."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render a scene file or a built-in scene to an image (the default command).
    Render(RenderArgs),
    /// List the built-in scenes.
    List,
    /// Describe a scene without rendering it: shapes, materials, lights, bounds, memory
    /// and the acceleration structure built for it.
    Info(InfoArgs),
}

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Scene file (.toml, .nff, .gltf, .glb) or mesh file (.obj, .ply), or builtin:NAME for
    /// a built-in scene.
    pub scene: String,

    /// Acceleration structure to build and describe.
    #[arg(long, value_name = "NAME", default_value = "bvh")]
    pub accel: AccelKind,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    /// Eric Haines' Standard Procedural Databases testing procedure.
    Spd,
}

#[derive(Args, Debug, Default)]
pub struct RenderArgs {
    /// Scene file to render (.toml, .nff, .gltf, .glb) or mesh file (.obj, .ply: framed by a
    /// default camera and light). Without it, a built-in scene is rendered.
    pub scene: Option<PathBuf>,

    /// Built-in scene to render instead of a file (see `prism list`).
    #[arg(short, long, value_name = "NAME", conflicts_with = "scene")]
    pub builtin: Option<String>,

    /// Output image; the extension picks the format: .png, .exr or .pfm.
    #[arg(short, long, value_name = "FILE", default_value = "prism.png")]
    pub output: PathBuf,

    /// Write EXR output as 16-bit half floats instead of 32-bit floats.
    #[arg(long)]
    pub half: bool,

    /// Image width in pixels [default: the scene's].
    #[arg(short = 'W', long, value_name = "PIXELS")]
    pub width: Option<u32>,

    /// Image height in pixels [default: the scene's].
    #[arg(short = 'H', long, value_name = "PIXELS")]
    pub height: Option<u32>,

    /// Samples per pixel along each axis: N traces an N×N grid of subpixel centres.
    #[arg(short, long, value_name = "N")]
    pub samples: Option<u32>,

    /// Maximum ray-tree depth, counting the eye ray as 1 (1 to 256) [default: 5].
    #[arg(short, long, value_name = "N")]
    pub depth: Option<u32>,

    /// Worker threads; 0 uses every core [default: 0].
    #[arg(short, long, value_name = "N")]
    pub threads: Option<usize>,

    /// Seed for random decisions.
    #[arg(long, value_name = "N")]
    pub seed: Option<u64>,

    /// Acceleration structure: bvh (the default), grid, kdtree, octree or brute-force.
    #[arg(long, value_name = "NAME")]
    pub accel: Option<AccelKind>,

    /// Apply a published testing procedure: `spd` = Haines' SPD rules (corner rays, depth
    /// 5, a reflection ray at every reflective or transmitting surface).
    #[arg(long, value_name = "NAME")]
    pub preset: Option<Preset>,

    /// Print a table of ray counts, tests and times after rendering.
    #[arg(long)]
    pub stats: bool,

    /// Write the statistics as JSON to FILE ('-' for standard output).
    #[arg(long, value_name = "FILE")]
    pub stats_json: Option<PathBuf>,

    /// No progress bar and no closing message.
    #[arg(short, long)]
    pub quiet: bool,
}

impl RenderArgs {
    /// The scene to render and a name for reports.
    pub fn load_scene(&self) -> Result<(Scene, String)> {
        if let Some(path) = &self.scene {
            let scene = prism::scene::load(path)?;
            return Ok((scene, path.display().to_string()));
        }
        let name = self.builtin.as_deref().unwrap_or("whitted");
        match builtin::find(name) {
            Some(scene) => Ok((scene, format!("builtin:{name}"))),
            None => bail!(
                "no built-in scene named '{name}'; available: {} (or sphereflake:N)",
                builtin::names().join(", ")
            ),
        }
    }

    /// The scene's options with the command line's on top.
    pub fn options(&self, scene: &RenderOptions) -> RenderOptions {
        let mut o = scene.clone();
        if let Some(v) = self.width {
            o.width = v;
        }
        if let Some(v) = self.height {
            o.height = v;
        }
        if let Some(v) = self.samples {
            o.samples = v;
        }
        if let Some(v) = self.depth {
            o.max_depth = v;
        }
        if let Some(v) = self.threads {
            o.threads = v;
        }
        if let Some(v) = self.seed {
            o.seed = v;
        }
        if let Some(v) = self.accel {
            o.accel = v;
        }
        o
    }
}
