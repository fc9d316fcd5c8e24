//! Which scenes `prism bench` runs: built-in names (`sphereflake:N` too) and scene files,
//! checked before anything is measured so a typo fails at once; loaded one at a time.

use anyhow::{bail, Context, Result};
use prism::scene::builtin;
use prism::Scene;
use std::path::{Path, PathBuf};

pub(super) enum SceneSource {
    Builtin(String),
    File(PathBuf),
}

impl SceneSource {
    /// A built-in name or an existing file.
    pub(super) fn resolve(name: &str) -> Result<Self> {
        let name = name.trim();
        let known = builtin::names().contains(&name)
            || name
                .strip_prefix("sphereflake:")
                .and_then(|l| l.parse::<u32>().ok())
                .is_some_and(|l| l <= 6);
        if known {
            return Ok(SceneSource::Builtin(name.to_string()));
        }
        let path = Path::new(name);
        if path.is_file() {
            return Ok(SceneSource::File(path.to_path_buf()));
        }
        bail!(
            "unknown scene '{name}': not a built-in ({}, sphereflake:N) and no such file",
            builtin::names().join(", ")
        )
    }

    /// A short name for tables: the built-in's name or the file's stem.
    pub(super) fn name(&self) -> String {
        match self {
            SceneSource::Builtin(n) => n.clone(),
            SceneSource::File(p) => p
                .file_stem()
                .map_or_else(|| p.display().to_string(), |s| s.to_string_lossy().into()),
        }
    }

    pub(super) fn load(&self) -> Result<Scene> {
        match self {
            SceneSource::Builtin(n) => crate::scene_args::find_builtin(n),
            SceneSource::File(p) => {
                prism_io::scene::load(p).with_context(|| format!("cannot load {}", p.display()))
            }
        }
    }
}

/// The `.nff` files in `dir`, sorted by name.
pub(super) fn spd_files(dir: &Path) -> Result<Vec<SceneSource>> {
    let entries = std::fs::read_dir(dir)
        .with_context(|| format!("cannot read the SPD directory {}", dir.display()))?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("nff")))
        .collect();
    files.sort();
    if files.is_empty() {
        bail!("no .nff files in {}", dir.display());
    }
    Ok(files.into_iter().map(SceneSource::File).collect())
}
