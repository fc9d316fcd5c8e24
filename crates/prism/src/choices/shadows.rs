//! Who answers shadow rays (`--shadows`, the scene file's `shadows`): a method and the
//! light buffer's keys, `METHOD[:res=N,budget=MIB]`, e.g. `light-buffer:res=64`. The
//! methods themselves live in `integrator::shadow`.

use super::keys::{parse_params, Key, Keyed};
use crate::field_key;
use std::fmt;
use std::str::FromStr;

/// Who answers shadow rays.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShadowMethod {
    /// The accelerator's any-hit query, for every shadow ray.
    #[default]
    AnyHit,
    /// The shadow cache first (the last blocker per light and depth), then the accelerator.
    Cache,
    /// A light buffer per light (a direction cube around a point or spot light, an
    /// orthographic grid across a directional one); the accelerator where none was built.
    LightBuffer,
    /// The cache first, then the light buffer.
    Both,
    /// The method prism expects to make renders fastest; today `any-hit`: in packets, as
    /// renders trace shadow rays, the cache and the light buffer are level with it or
    /// behind in whole renders of the SPD scenes measured in docs/shadows.md (even where
    /// `both` wins on single rays).
    Auto,
}

named_kinds! {
    ShadowMethod, "shadow method" {
        AnyHit => "any-hit",
        Cache => "cache",
        LightBuffer => "light-buffer",
        Both => "both",
        Auto => "auto",
    }
}

impl ShadowMethod {
    /// Whether the method asks the shadow cache first.
    #[inline]
    pub fn uses_cache(self) -> bool {
        matches!(self, ShadowMethod::Cache | ShadowMethod::Both)
    }

    /// Whether the method takes the light buffer's keys.
    pub fn uses_light_buffer(self) -> bool {
        matches!(self, ShadowMethod::LightBuffer | ShadowMethod::Both)
    }
}

/// A shadow method and its parameters, as `--shadows` and the scene file's `shadows` key
/// write it: `METHOD[:res=N,budget=MIB]`, e.g. `light-buffer:res=64`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ShadowSpec {
    /// Who answers the shadow rays.
    pub method: ShadowMethod,
    /// Cells along a light buffer face's side; 0 chooses from the primitive count.
    pub res: u32,
    /// The light buffers' memory budget in MiB; 0 takes the default.
    pub budget_mib: u32,
}

impl Keyed for ShadowSpec {
    const NAME: &'static str = "shadows";
    const SUMMARY: &'static str = "who answers shadow rays";
    const KEYS: &'static [Key<Self>] = &[
        field_key!("res" => res as u32, int 1..=1024,
            "cells along a light buffer face's side (unset: from the primitive count)"),
        field_key!("budget" => budget_mib as u32, int 1..=1 << 20,
            "the light buffers' memory budget in MiB (unset: 256)"),
    ];
}

impl FromStr for ShadowSpec {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let (name, params) = match s.split_once(':') {
            Some((n, p)) => (n, Some(p)),
            None => (s, None),
        };
        let mut spec = ShadowSpec {
            method: name.trim().parse()?,
            ..ShadowSpec::default()
        };
        parse_params(s, params, |key, value| {
            if !spec.method.uses_light_buffer() {
                return Err(format!(
                    "'{key}' is a light buffer parameter; {} takes none",
                    spec.method
                ));
            }
            spec.set_param(key, value)
        })?;
        Ok(spec)
    }
}

impl fmt::Display for ShadowSpec {
    /// The canonical spelling, which parses back to the same spec.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        super::keys::write_spec(f, self.method.name(), &self.non_default_params())
    }
}

serde_as_text!(ShadowSpec);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_read_and_print_alike() {
        for text in [
            "any-hit",
            "cache",
            "light-buffer",
            "both",
            "auto",
            "light-buffer:res=64,budget=32",
        ] {
            let spec: ShadowSpec = text.parse().unwrap();
            assert_eq!(spec.to_string(), text);
        }
        let err = "cache:res=4".parse::<ShadowSpec>().unwrap_err();
        assert!(err.contains("cache takes none"), "{err}");
        let err = "light-buffer:res=0".parse::<ShadowSpec>().unwrap_err();
        assert!(
            err.contains("bad value '0' for 'res': expected an integer from 1 to 1024"),
            "{err}"
        );
        let err = "light-buffer:size=3".parse::<ShadowSpec>().unwrap_err();
        assert!(
            err.contains("unknown parameter 'size' for shadows, expected one of: res, budget"),
            "{err}"
        );
        let err = "buffer".parse::<ShadowSpec>().unwrap_err();
        assert!(
            err.contains("any-hit, cache, light-buffer, both, auto"),
            "{err}"
        );
    }
}
