//! Warnings: what prism read but cannot render, what it had to guess, what looks like a
//! mistake. Each is printed once, before the work; `--strict` turns them into an error.

use anyhow::{bail, Result};

pub(crate) struct Warnings {
    strict: bool,
    list: Vec<String>,
}

impl Warnings {
    pub(crate) fn new(strict: bool) -> Self {
        Warnings {
            strict,
            list: Vec::new(),
        }
    }

    pub(crate) fn add(&mut self, warning: impl Into<String>) {
        self.list.push(warning.into());
    }

    pub(crate) fn extend(&mut self, warnings: impl IntoIterator<Item = String>) {
        self.list.extend(warnings);
    }

    /// Prints the warnings; with `--strict`, any warning is an error.
    pub(crate) fn report(&self) -> Result<()> {
        for w in &self.list {
            eprintln!("prism: warning: {w}");
        }
        if self.strict && !self.list.is_empty() {
            let n = self.list.len();
            bail!(
                "stopping before the render: {n} warning{} and --strict",
                if n == 1 { "" } else { "s" }
            );
        }
        Ok(())
    }
}
