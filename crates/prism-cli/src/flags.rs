//! What the command line's flags share: a setting flag's help read from the settings
//! table, the engine's errors with the setting written as its flag, and `--spp` checked
//! as a square number.

use anyhow::{bail, Result};

/// A setting's `--help` text, read from the settings table (`prism::options::SETTINGS`):
/// its sentence, what it accepts and its default. Every render setting's flag takes its help
/// from here, so the command line says what the scene file and Python say.
pub(crate) fn setting_help(key: &str) -> String {
    use prism::options::SettingKind;
    let s = prism::options::setting(key).unwrap_or_else(|| panic!("no setting '{key}'"));
    let accepts = match s.kind {
        SettingKind::Integer { lo, hi } if hi <= 1 << 20 => format!(", {lo} to {hi}"),
        SettingKind::Number { lo, hi } => format!(", {lo} to {hi}"),
        SettingKind::Name(names) => format!(": {}", names.join(", ")),
        _ => String::new(),
    };
    let default = match key {
        "width" | "height" => "the scene's".to_string(),
        "filter_radius" => "per filter".to_string(),
        "min_weight" => "1/255".to_string(),
        "packets" => "packets on".to_string(),
        _ => s.default_text(),
    };
    format!("{}{accepts} [default: {default}]", s.help)
}

/// The parser of a whole-number setting flag (`--width`, `--depth`, …): it takes a
/// negative number too (with `allow_negative_numbers`), so that `-W -5` gets the setting's
/// range instead of clap's hint to write `-- -5`, which would not work either. Values of
/// the type's own range go on to the engine's checks, whose messages name the flag. A key
/// that is no setting (`bench --size`) says "a whole number"; `spp`, samples per pixel.
pub(crate) fn whole<T>(
    key: &'static str,
) -> impl Fn(&str) -> Result<T, String> + Clone + Send + Sync + 'static
where
    T: TryFrom<u64> + Clone + Send + Sync + 'static,
{
    move |text: &str| {
        let range = || match prism::options::setting(key).map(|s| s.kind) {
            // Samples per pixel, as `--spp` takes them (not a setting: `samples` per axis).
            _ if key == "spp" => {
                let most = prism::options::MAX_SAMPLES_PER_AXIS.pow(2);
                format!("a square number from 1 to {most}")
            }
            Some(prism::options::SettingKind::Integer { lo, hi }) => {
                format!("a whole number from {lo} to {hi}")
            }
            _ => "a whole number".to_string(),
        };
        // clap's message names the flag and the value; this adds what it takes.
        let whole = text.trim().parse::<i128>().ok();
        whole
            .and_then(|v| u64::try_from(v).ok())
            .and_then(|v| T::try_from(v).ok())
            .ok_or_else(|| format!("expected {}", range()))
    }
}

/// An options error of the engine, which names a setting by its key (`max_depth must be
/// …`), with the key written as the command line's flag (`--depth must be …`).
pub(crate) fn in_flags(message: &str) -> String {
    let named = prism::options::SETTINGS.iter().find_map(|s| {
        let rest = message.strip_prefix(s.key)?.strip_prefix(' ')?;
        Some((s.flag?, rest))
    });
    match named {
        Some((flag, rest)) => format!("--{flag} {rest}"),
        None => message.to_string(),
    }
}

/// Samples per axis for `spp` samples per pixel, which must be a square from 1 to
/// 64 × 64. Errors echo the value as the user typed it.
pub(crate) fn per_axis(spp: i64) -> Result<u32> {
    let max = prism::options::MAX_SAMPLES_PER_AXIS;
    let most = i64::from(max * max);
    if spp < 1 {
        bail!(
            "--spp takes a square number from 1 to {most}, got {spp}{}",
            if spp == 0 {
                ": a pixel takes at least 1 sample"
            } else {
                ""
            }
        );
    }
    if spp > most {
        bail!("--spp {spp} is too many: at most {most} ({max}×{max}) samples per pixel");
    }
    let n = (spp as f64).sqrt().round() as i64;
    if n * n != spp {
        let below = (spp as f64).sqrt().floor().max(1.0) as i64;
        bail!(
            "--spp {spp} is not a square number: every pattern takes n×n samples per pixel; \
             try {} or {}",
            below * below,
            (below + 1) * (below + 1)
        );
    }
    Ok(n as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_errors_name_the_flag() {
        assert_eq!(
            in_flags("max_depth must be between 1 (the eye ray alone) and 256, got 0"),
            "--depth must be between 1 (the eye ray alone) and 256, got 0"
        );
        assert_eq!(
            in_flags("tile_size must be at least 1"),
            "--tile-size must be at least 1"
        );
        assert_eq!(
            in_flags("image size must be at least 1×1"),
            "image size must be at least 1×1"
        );
    }
}
