//! The TOML scene format (docs/scene-format.md).

use super::load::LoadError;
use super::Scene;
use std::path::Path;

pub fn load(path: &Path) -> Result<Scene, LoadError> {
    Err(LoadError::Invalid {
        path: path.display().to_string(),
        message: "the TOML scene format is not implemented yet".into(),
    })
}
