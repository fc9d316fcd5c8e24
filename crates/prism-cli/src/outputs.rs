//! Every file a command will write is checked before any work starts: a read-only or
//! missing folder, a directory in place of a file or two outputs with one name are
//! reported at once, not after a long render (and then nothing at all is written).

use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};

/// The outputs of one command, checked together.
#[derive(Default)]
pub(crate) struct Outputs {
    paths: Vec<PathBuf>,
}

impl Outputs {
    /// Checks that `path` can be written and that no other output of this command has the
    /// same name; `extensions` (lower case) are the ones accepted, if any are required.
    pub(crate) fn add(&mut self, path: &Path, extensions: &[&str]) -> Result<()> {
        if !extensions.is_empty()
            && !path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| extensions.iter().any(|x| x.eq_ignore_ascii_case(e)))
        {
            let names: Vec<String> = extensions.iter().map(|e| format!(".{e}")).collect();
            bail!(
                "{}: expected a {} file name",
                path.display(),
                names.join(" or ")
            );
        }
        if let Some(other) = self.paths.iter().find(|p| same_file(p, path)) {
            bail!(
                "{} is named twice as an output ({} and {}); give each output its own name",
                path.display(),
                other.display(),
                path.display()
            );
        }
        check_writable(path)?;
        self.paths.push(path.to_path_buf());
        Ok(())
    }
}

/// The file writing `path` should replace: a symbolic link's target (followed through
/// chains of links), so that an output named by a link is written where the link points
/// and the link stays, rather than the atomic rename replacing the link itself. A path
/// that is no link is itself.
pub(crate) fn through_links(path: &Path) -> PathBuf {
    let mut path = path.to_path_buf();
    // As many links as the system follows; a loop of links is left for the write to report.
    for _ in 0..40 {
        let is_link = std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink());
        let Some(target) = is_link.then(|| std::fs::read_link(&path).ok()).flatten() else {
            break;
        };
        path = match path.parent() {
            Some(parent) if target.is_relative() => parent.join(target),
            _ => target,
        };
    }
    path
}

/// Whether two output names point at the same file (spelled alike, or the same existing
/// file under two spellings).
fn same_file(a: &Path, b: &Path) -> bool {
    if a == b {
        return true;
    }
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// Fails, before any work, on an output that could not be written at the end: a directory
/// in its place, a folder that does not exist or cannot be written.
pub(crate) fn check_writable(path: &Path) -> Result<()> {
    if path.is_dir() {
        bail!("cannot write {}: it is a directory", path.display());
    }
    if path.file_name().is_none() {
        bail!("cannot write {}: not a file name", path.display());
    }
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !parent.is_dir() {
        bail!(
            "cannot write {}: the directory {} does not exist",
            path.display(),
            parent.display()
        );
    }
    // Try a scratch file beside it now, rather than learn after the whole render that the
    // folder is read-only: outputs are written to a temporary name there and renamed.
    let probe = parent.join(format!(".prism-probe-{}", std::process::id()));
    std::fs::write(&probe, b"").with_context(|| {
        format!(
            "cannot write {}: the directory {} is not writable",
            path.display(),
            parent.display()
        )
    })?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}
