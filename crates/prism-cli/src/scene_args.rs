//! The scene a command works on, read the same way by every command that takes one: a
//! file, or a built-in scene as `builtin:NAME` in the file's place or as `--builtin NAME`;
//! and the size of the picture, where a command renders one.

use crate::flags::{setting_help, whole};
use anyhow::{bail, Result};
use clap::Args;
use prism::scene::builtin;
use prism::{RenderOptions, Scene};
use std::path::PathBuf;

#[derive(Args, Clone, Debug, Default)]
pub(crate) struct SceneArgs {
    // A command whose default scene is another names it with `scene_help` (`mut_arg`).
    #[arg(id = "scene", value_name = "SCENE", help = scene_help("`whitted` scene"))]
    pub path: Option<PathBuf>,

    /// Built-in scene instead of a file (see `prism list`).
    #[arg(short, long, value_name = "NAME", conflicts_with = "scene")]
    pub builtin: Option<String>,
}

impl SceneArgs {
    /// The scene named, or the built-in `default` where none is, and a name for reports.
    pub(crate) fn load(&self, default: &str) -> Result<(Scene, String)> {
        if let Some(path) = &self.path {
            // `builtin:NAME` in the file's place, as `prism info` takes it.
            if let Some(name) = path.to_str().and_then(|p| p.strip_prefix("builtin:")) {
                return Ok((find_builtin(name)?, format!("builtin:{name}")));
            }
            let scene = prism_io::scene::load(path)?;
            return Ok((scene, path.display().to_string()));
        }
        let name = self.builtin.as_deref().unwrap_or(default);
        Ok((find_builtin(name)?, format!("builtin:{name}")))
    }
}

/// The scene argument's help, with the built-in scene a command takes without one (and
/// what else it says of the scenes it takes).
pub(crate) fn scene_help(default: &str) -> String {
    format!(
        "Scene file (.toml, .nff, .gltf, .glb) or mesh file (.obj, .ply: framed by a default \
         camera and light), or builtin:NAME for a built-in scene (as --builtin NAME). Without \
         either, the built-in {default}"
    )
}

/// The picture's size, where a command renders one; each left out keeps the scene's.
#[derive(Args, Clone, Copy, Debug, Default)]
pub(crate) struct SizeArgs {
    #[arg(short = 'W', long, value_name = "PIXELS", allow_negative_numbers = true, value_parser = whole::<u32>("width"), help = setting_help("width"))]
    pub width: Option<u32>,

    #[arg(short = 'H', long, value_name = "PIXELS", allow_negative_numbers = true, value_parser = whole::<u32>("height"), help = setting_help("height"))]
    pub height: Option<u32>,
}

impl SizeArgs {
    /// `options` with the size given on top.
    pub(crate) fn apply(&self, options: &mut RenderOptions) {
        options.width = self.width.unwrap_or(options.width);
        options.height = self.height.unwrap_or(options.height);
    }
}

/// A built-in scene by name, or an error listing the names there are.
pub(crate) fn find_builtin(name: &str) -> Result<Scene> {
    match builtin::find(name) {
        Some(scene) => Ok(scene),
        None => bail!(
            "no built-in scene named '{name}'; available: {} (or sphereflake:N)",
            builtin::names().join(", ")
        ),
    }
}
