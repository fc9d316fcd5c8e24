//! The byte-mutation kit of the parser suites (TOML, glTF, OBJ/MTL, PLY): ways to damage a
//! file and how each is applied. Each suite keeps its own proptest strategy (which bytes
//! and values are likely to reach its parser's checks); the damage itself is defined once.

/// Ways to damage a file, for the fuzzing properties.
#[derive(Clone, Debug)]
pub(crate) enum Mutation {
    Delete {
        at: usize,
        len: usize,
    },
    Duplicate {
        at: usize,
        len: usize,
    },
    Replace {
        at: usize,
        byte: u8,
    },
    /// Overwrites four bytes with a 32-bit word (a count, an index, a float).
    Word {
        at: usize,
        word: u32,
    },
    Truncate {
        at: usize,
    },
    /// Replaces the first number at or after `at` with `value`.
    Number {
        at: usize,
        value: &'static str,
    },
}

/// Applies `m` to `bytes`; positions wrap around the length, so every mutation applies to
/// every file (an empty file stays empty).
pub(crate) fn apply(bytes: &mut Vec<u8>, m: &Mutation) {
    if bytes.is_empty() {
        return;
    }
    let n = bytes.len();
    match *m {
        Mutation::Delete { at, len } => {
            let at = at % n;
            bytes.drain(at..(at + len).min(n));
        }
        Mutation::Duplicate { at, len } => {
            let at = at % n;
            let end = (at + len).min(n);
            let copy = bytes[at..end].to_vec();
            bytes.splice(end..end, copy);
        }
        Mutation::Replace { at, byte } => bytes[at % n] = byte,
        Mutation::Word { at, word } => {
            let at = at % n;
            for (k, b) in word.to_le_bytes().into_iter().enumerate() {
                if let Some(slot) = bytes.get_mut(at + k) {
                    *slot = b;
                }
            }
        }
        Mutation::Truncate { at } => bytes.truncate(at % n),
        Mutation::Number { at, value } => {
            let is_number = |b: &u8| b.is_ascii_digit() || b"-+.eE".contains(b);
            let Some(start) = bytes[at % n..]
                .iter()
                .position(|b| b.is_ascii_digit())
                .map(|i| at % n + i)
            else {
                return;
            };
            let end = bytes[start..]
                .iter()
                .position(|b| !is_number(b))
                .map_or(n, |i| start + i);
            bytes.splice(start..end, value.bytes());
        }
    }
}
