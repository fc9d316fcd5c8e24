//! Problems found in a scene file and how they become `LoadError`s: byte spans turn into
//! line and column numbers, and serde's Rust-flavoured wording into the format's own.

use crate::source::LoadError;
use std::ops::Range;
use std::path::Path;

/// A problem found in the file, at a byte range when one is known.
#[derive(Debug)]
pub(super) struct Problem {
    pub span: Option<Range<usize>>,
    pub message: String,
}

impl Problem {
    pub(super) fn at(span: Range<usize>, message: impl Into<String>) -> Self {
        Problem {
            span: Some(span),
            message: message.into(),
        }
    }

    pub(super) fn from_toml(e: &toml::de::Error) -> Self {
        Problem {
            span: e.span(),
            message: reword(e.message()),
        }
    }

    pub(super) fn into_load_error(self, path: &Path, text: &str) -> LoadError {
        let path = path.display().to_string();
        match self.span {
            Some(span) => {
                let (line, column) = line_column(text, span.start);
                LoadError::Syntax {
                    path,
                    line,
                    column,
                    message: self.message,
                }
            }
            None => LoadError::Invalid {
                path,
                message: self.message,
            },
        }
    }
}

/// 1-based line and column (in characters) of a byte offset; an offset inside a
/// character or past the end is clamped rather than trusted.
pub(super) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text.as_bytes()[..offset.min(text.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let line_start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    // UTF-8 continuation bytes (10xxxxxx) do not start a character.
    let column = before[line_start..]
        .iter()
        .filter(|&&b| b & 0xC0 != 0x80)
        .count()
        + 1;
    (line, column)
}

/// TOML speaks of keys, not fields, and scene authors need not know Rust's number types.
fn reword(message: &str) -> String {
    const REPLACEMENTS: &[(&str, &str)] = &[
        ("unknown field", "unknown key"),
        ("missing field", "missing key"),
        ("duplicate field", "duplicate key"),
        ("expected u32", "expected a whole number ≥ 0"),
        ("expected u64", "expected a whole number ≥ 0"),
        ("expected usize", "expected a whole number ≥ 0"),
        ("expected f32", "expected a number"),
        ("expected a boolean", "expected true or false"),
        // The toml crate's words for a unit enum given something other than a string.
        (
            "wanted string or table",
            "expected a quoted name (a string)",
        ),
        ("invalid type: map", "invalid type: table"),
        ("invalid type: sequence", "invalid type: array"),
        ("expected a map", "expected a table"),
        ("expected a sequence", "expected an array"),
    ];
    let mut out = message.trim_end().to_string();
    for (from, to) in REPLACEMENTS {
        out = out.replace(from, to);
    }
    // Derived structs say "expected struct CameraDef"; the file only knows tables.
    const STRUCT: &str = "expected struct ";
    if let Some(start) = out.find(STRUCT) {
        let name = start + STRUCT.len();
        let end = out[name..]
            .find(|c: char| !c.is_alphanumeric())
            .map_or(out.len(), |i| name + i);
        out.replace_range(start..end, "expected a table");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_count_characters_from_one() {
        let text = "ab\nçd = 1\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 2), (1, 3));
        assert_eq!(line_column(text, 3), (2, 1));
        // 'ç' is two bytes but one column.
        assert_eq!(line_column(text, 5), (2, 2));
        assert_eq!(line_column(text, 999), (3, 1));
    }

    #[test]
    fn rewording_speaks_toml() {
        assert_eq!(
            reword("unknown field `radus`, expected `radius`"),
            "unknown key `radus`, expected `radius`"
        );
        assert_eq!(
            reword("invalid type: string \"a\", expected u32"),
            "invalid type: string \"a\", expected a whole number ≥ 0"
        );
        assert_eq!(
            reword("invalid type: integer `3`, expected struct CameraDef"),
            "invalid type: integer `3`, expected a table"
        );
    }
}
