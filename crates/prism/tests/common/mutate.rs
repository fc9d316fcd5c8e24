//! The byte-mutation kit of the parser suites (TOML, glTF, OBJ/MTL, PLY): ways to damage a
//! file, how each is applied, the strategies that draw them and the suites' proptest
//! configuration. Each suite mixes its own strategy from these (which bytes and values are
//! likely to reach its parser's checks); the damage itself is defined once.

use proptest::prelude::*;

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

/// Deleting up to `max - 1` bytes somewhere.
pub(crate) fn deletions(max: usize) -> BoxedStrategy<Mutation> {
    (any::<usize>(), 1usize..max)
        .prop_map(|(at, len)| Mutation::Delete { at, len })
        .boxed()
}

/// Repeating up to `max - 1` bytes somewhere, right after themselves.
pub(crate) fn duplications(max: usize) -> BoxedStrategy<Mutation> {
    (any::<usize>(), 1usize..max)
        .prop_map(|(at, len)| Mutation::Duplicate { at, len })
        .boxed()
}

/// Replacing a byte with one of `bytes` (those the parser reads as syntax).
pub(crate) fn bytes_from(bytes: &'static [u8]) -> BoxedStrategy<Mutation> {
    (any::<usize>(), prop::sample::select(bytes))
        .prop_map(|(at, byte)| Mutation::Replace { at, byte })
        .boxed()
}

/// Replacing a byte with any byte.
pub(crate) fn any_bytes() -> BoxedStrategy<Mutation> {
    (any::<usize>(), any::<u8>())
        .prop_map(|(at, byte)| Mutation::Replace { at, byte })
        .boxed()
}

/// Replacing a number with one of `values` (limits, signs, overflows).
pub(crate) fn numbers_from(values: &'static [&'static str]) -> BoxedStrategy<Mutation> {
    (any::<usize>(), prop::sample::select(values))
        .prop_map(|(at, value)| Mutation::Number { at, value })
        .boxed()
}

/// Cutting the file short somewhere.
pub(crate) fn truncations() -> BoxedStrategy<Mutation> {
    any::<usize>()
        .prop_map(|at| Mutation::Truncate { at })
        .boxed()
}

/// The damages a text format's suite draws, each as likely: deletions and duplications
/// shorter than `delete` and `duplicate` bytes, a byte of `syntax`, any byte, a number of
/// `values`.
pub(crate) fn text_damage(
    delete: usize,
    duplicate: usize,
    syntax: &'static [u8],
    values: &'static [&'static str],
) -> BoxedStrategy<Mutation> {
    prop_oneof![
        deletions(delete),
        duplications(duplicate),
        bytes_from(syntax),
        any_bytes(),
        numbers_from(values),
    ]
    .boxed()
}

/// A parser suite's proptest configuration: `cases` cases, failing cases saved beside the
/// suite (its `.proptest-regressions` file) and replayed first.
pub(crate) fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::WithSource("proptest-regressions"),
        )),
        ..ProptestConfig::default()
    }
}
