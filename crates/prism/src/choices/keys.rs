//! Key tables: every method of a choice (an accelerator, a shadow method, the adaptive
//! sampler's settings) declares its keys once, with the values each accepts, its default
//! and a line of help, and everything else is read from that table: parsing `KEY=VALUE`
//! (with errors that name the key and the accepted range), printing the keys that differ
//! from the defaults, the help texts and the check that keeps the documentation's key
//! lists true.

use std::fmt::Write;

/// The values a key accepts.
#[derive(Clone, Copy, Debug)]
pub enum Accepts {
    /// An integer in `lo..=hi`.
    Int {
        /// Smallest accepted value.
        lo: usize,
        /// Largest accepted value.
        hi: usize,
    },
    /// A finite number in `lo..=hi`.
    Number {
        /// Smallest accepted value.
        lo: f32,
        /// Largest accepted value.
        hi: f32,
    },
    /// On or off: the key alone or `=true` turns it on, `=false` off.
    Switch,
    /// One of these names.
    Choice(&'static [&'static str]),
}

impl Accepts {
    /// What the key expects, as error messages and help texts say it.
    pub fn expected(&self) -> String {
        match self {
            Accepts::Int { lo, hi } => format!("an integer from {lo} to {hi}"),
            Accepts::Number { lo, hi } => format!("a number from {lo} to {hi}"),
            Accepts::Switch => "true or false (or the key alone)".to_string(),
            Accepts::Choice(names) => format!("one of: {}", names.join(", ")),
        }
    }

    /// The accepted values in a few characters, for help texts: `2–256`, `a|b|c`, `switch`.
    pub fn short(&self) -> String {
        match self {
            Accepts::Int { lo, hi } => format!("{lo}–{hi}"),
            Accepts::Number { lo, hi } => format!("{lo}–{hi}"),
            Accepts::Switch => "switch".to_string(),
            Accepts::Choice(names) => names.join("|"),
        }
    }
}

/// A parsed value; `Choice` is an index into the key's names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// For `Accepts::Int`.
    Int(usize),
    /// For `Accepts::Number`.
    Number(f32),
    /// For `Accepts::Switch`.
    Switch(bool),
    /// For `Accepts::Choice`: the index of the name.
    Choice(usize),
}

impl Value {
    /// The integer of an `Int` key (a table whose setter reads the wrong kind is a bug).
    pub fn int(self) -> usize {
        match self {
            Value::Int(v) => v,
            other => panic!("parameter table: expected an integer, got {other:?}"),
        }
    }

    /// The number of a `Number` key.
    pub fn number(self) -> f32 {
        match self {
            Value::Number(v) => v,
            other => panic!("parameter table: expected a number, got {other:?}"),
        }
    }

    /// The state of a `Switch` key.
    pub fn switch(self) -> bool {
        match self {
            Value::Switch(v) => v,
            other => panic!("parameter table: expected a switch, got {other:?}"),
        }
    }

    /// The index of a `Choice` key's name.
    pub fn choice(self) -> usize {
        match self {
            Value::Choice(v) => v,
            other => panic!("parameter table: expected a choice, got {other:?}"),
        }
    }
}

/// A row of a key table that reads and writes one field of the options: `int lo..=hi`,
/// `number lo..=hi`, `switch`, or `choice Kind` (a `named_kinds!` type, stored as itself).
/// An integer field of another type than `usize` says so with `as` after its name.
///
/// ```
/// # use prism::choices::{Key, Value};
/// struct Options { leaf: usize, res: u32, fast: bool }
/// const KEYS: &[Key<Options>] = &[
///     prism::field_key!("leaf" => leaf, int 1..=64, "largest leaf"),
///     prism::field_key!("res" => res as u32, int 1..=1024, "cells per side"),
///     prism::field_key!("fast" => fast, switch, "take the fast path"),
/// ];
/// # let mut o = Options { leaf: 4, res: 8, fast: false };
/// # (KEYS[1].set)(&mut o, Value::Int(16));
/// # assert_eq!((KEYS[1].get)(&o), Value::Int(16));
/// ```
///
/// Exported so that a test's toy method can write its table the same way.
#[macro_export]
macro_rules! field_key {
    ($name:literal => $field:ident, int $lo:literal ..= $hi:expr, $help:expr) => {
        $crate::field_key!(@key $name, $help, $crate::choices::Accepts::Int { lo: $lo, hi: $hi },
            |o| $crate::choices::Value::Int(o.$field), |o, v| o.$field = v.int())
    };
    ($name:literal => $field:ident as $int:ty, int $lo:literal ..= $hi:expr, $help:expr) => {
        $crate::field_key!(@key $name, $help, $crate::choices::Accepts::Int { lo: $lo, hi: $hi },
            |o| $crate::choices::Value::Int(o.$field as usize), |o, v| o.$field = v.int() as $int)
    };
    ($name:literal => $field:ident, number $lo:literal ..= $hi:expr, $help:expr) => {
        $crate::field_key!(@key $name, $help,
            $crate::choices::Accepts::Number { lo: $lo, hi: $hi },
            |o| $crate::choices::Value::Number(o.$field), |o, v| o.$field = v.number())
    };
    ($name:literal => $field:ident, switch, $help:expr) => {
        $crate::field_key!(@key $name, $help, $crate::choices::Accepts::Switch,
            |o| $crate::choices::Value::Switch(o.$field), |o, v| o.$field = v.switch())
    };
    ($name:literal => $field:ident, choice $kind:ident, $help:expr) => {
        $crate::field_key!(@key $name, $help, $crate::choices::Accepts::Choice(&$kind::NAMES),
            |o| $crate::choices::Value::Choice(o.$field.index()),
            |o, v| o.$field = $kind::ALL[v.choice()])
    };
    (@key $name:literal, $help:expr, $accepts:expr, $get:expr, $set:expr) => {
        $crate::choices::Key {
            name: $name,
            help: $help,
            accepts: $accepts,
            get: $get,
            set: $set,
        }
    };
}

/// One key of a method's parameter table, over the method's options type `P`.
pub struct Key<P> {
    /// As written after the method's colon.
    pub name: &'static str,
    /// What it sets, in a few words.
    pub help: &'static str,
    /// The values it accepts.
    pub accepts: Accepts,
    /// Reads the key's value from the options.
    pub get: fn(&P) -> Value,
    /// Writes a value (already checked against `accepts`) into the options.
    pub set: fn(&mut P, Value),
}

impl<P> Key<P> {
    /// The key's value in `options` as it is written after `=`.
    pub fn text(&self, options: &P) -> String {
        match ((self.get)(options), self.accepts) {
            (Value::Choice(i), Accepts::Choice(names)) => names[i].to_string(),
            (Value::Int(v), _) => v.to_string(),
            (Value::Number(v), _) => v.to_string(),
            (Value::Switch(v), _) => v.to_string(),
            (Value::Choice(i), _) => i.to_string(),
        }
    }

    /// Parses `value` (None when the key is given alone).
    fn parse(&self, value: Option<&str>) -> Result<Value, String> {
        let key = self.name;
        let expected = self.accepts.expected();
        if let Accepts::Switch = self.accepts {
            return match value {
                None | Some("true") => Ok(Value::Switch(true)),
                Some("false") => Ok(Value::Switch(false)),
                Some(text) => Err(format!(
                    "bad value '{text}' for '{key}': expected {expected}"
                )),
            };
        }
        let text = value
            .filter(|v| !v.is_empty())
            .ok_or_else(|| format!("'{key}' needs a value: expected {expected}"))?;
        let bad = || format!("bad value '{text}' for '{key}': expected {expected}");
        match self.accepts {
            Accepts::Int { lo, hi } => match text.parse::<usize>() {
                Ok(v) if (lo..=hi).contains(&v) => Ok(Value::Int(v)),
                _ => Err(bad()),
            },
            Accepts::Number { lo, hi } => match text.parse::<f32>() {
                Ok(v) if v.is_finite() && (lo..=hi).contains(&v) => Ok(Value::Number(v)),
                _ => Err(bad()),
            },
            Accepts::Choice(names) => names
                .iter()
                .position(|n| *n == text)
                .map(Value::Choice)
                .ok_or_else(bad),
            Accepts::Switch => unreachable!("handled above"),
        }
    }
}

/// A method of some choice with its settings: its name, and its table of keys over its
/// settings type. The kind of method adds its behaviour as a trait of its own (an
/// accelerator's `accel::Method` builds, a sampler's `render::SamplerMethod` renders).
pub trait Keyed: Default + Clone + PartialEq + std::fmt::Debug + Send + Sync + 'static {
    /// As written before the colon, e.g. `kdtree`.
    const NAME: &'static str;
    /// What it is, in a few words, for the help texts.
    const SUMMARY: &'static str;
    /// Its keys, in the order they are documented and printed.
    const KEYS: &'static [Key<Self>];

    /// Sets `key` from its text (`None`: the key given alone).
    fn set_param(&mut self, key: &str, value: Option<&str>) -> Result<(), String> {
        match Self::KEYS.iter().find(|k| k.name == key) {
            Some(k) => {
                let v = k.parse(value)?;
                (k.set)(self, v);
                Ok(())
            }
            None if Self::KEYS.is_empty() => {
                Err(format!("{} takes no parameters, got '{key}'", Self::NAME))
            }
            None => Err(format!(
                "unknown parameter '{key}' for {}, expected one of: {}",
                Self::NAME,
                Self::KEYS
                    .iter()
                    .map(|k| k.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
    }

    /// The keys that differ from the defaults, as `key=value` (a switch that is on as the
    /// key alone), in table order.
    fn non_default_params(&self) -> Vec<String> {
        let default = Self::default();
        Self::KEYS
            .iter()
            .filter(|k| (k.get)(self) != (k.get)(&default))
            .map(|k| match (k.get)(self) {
                Value::Switch(true) => k.name.to_string(),
                _ => format!("{}={}", k.name, k.text(self)),
            })
            .collect()
    }
}

/// A method's keys as documentation: name, accepted values, default and help.
#[derive(Clone, Debug, PartialEq)]
pub struct KeyDoc {
    /// The key.
    pub name: &'static str,
    /// The accepted values, short (`2–256`, `a|b`, `switch`).
    pub accepts: String,
    /// The default value as written after `=`.
    pub default: String,
    /// What it sets.
    pub help: &'static str,
}

/// A method's documentation, read from its table.
#[derive(Clone, Debug, PartialEq)]
pub struct MethodDoc {
    /// As written before the colon.
    pub name: &'static str,
    /// What it is.
    pub summary: &'static str,
    /// Its keys in table order.
    pub keys: Vec<KeyDoc>,
}

/// The documentation of method `M`.
pub fn method_doc<M: Keyed>() -> MethodDoc {
    let default = M::default();
    MethodDoc {
        name: M::NAME,
        summary: M::SUMMARY,
        keys: M::KEYS
            .iter()
            .map(|k| KeyDoc {
                name: k.name,
                accepts: k.accepts.short(),
                default: k.text(&default),
                help: k.help,
            })
            .collect(),
    }
}

/// The help of a list of methods, one line each: `kdtree: SAH kd-tree; trav (0–1000,
/// default 1) cost of a traversal step, …`.
pub fn help_text(methods: &[MethodDoc]) -> String {
    let mut out = String::new();
    for m in methods {
        let _ = write!(out, "\n  {}: {}", m.name, m.summary);
        for (i, k) in m.keys.iter().enumerate() {
            let sep = if i == 0 { "; keys " } else { ", " };
            let _ = write!(
                out,
                "{sep}{} ({}, default {}) {}",
                k.name, k.accepts, k.default, k.help
            );
        }
    }
    out
}

/// The methods and their keys as one Markdown sentence, as docs/scene-format.md lists them
/// under `accel` (a test holds the document to it): `` `"grid"` (uniform grid …; keys
/// `lambda` 0.01–100, default 3: cells along …) ``.
pub fn markdown(methods: &[MethodDoc]) -> String {
    let items: Vec<String> = methods
        .iter()
        .map(|m| {
            let keys: Vec<String> = m
                .keys
                .iter()
                // A `|` would end the Markdown table cell the list stands in.
                .map(|k| {
                    let accepts = k.accepts.replace('|', " / ");
                    format!("`{}` {accepts}, default {}: {}", k.name, k.default, k.help)
                })
                .collect();
            if keys.is_empty() {
                format!("`\"{}\"` ({})", m.name, m.summary)
            } else {
                format!("`\"{}\"` ({}; keys {})", m.name, m.summary, keys.join("; "))
            }
        })
        .collect();
    items.join(", ")
}

/// Writes a spec as it is spelt: `name`, then `:` and the keys that differ from the
/// defaults (`params`), if any.
pub fn write_spec(
    f: &mut std::fmt::Formatter<'_>,
    name: &str,
    params: &[String],
) -> std::fmt::Result {
    f.write_str(name)?;
    if !params.is_empty() {
        write!(f, ":{}", params.join(","))?;
    }
    Ok(())
}

/// Splits `params` (the text after the method's colon, if any) into `KEY[=VALUE]` pairs
/// and hands each to `set`, rejecting empty and repeated keys; `whole` is the full spec,
/// for messages.
pub fn parse_params(
    whole: &str,
    params: Option<&str>,
    mut set: impl FnMut(&str, Option<&str>) -> Result<(), String>,
) -> Result<(), String> {
    let mut seen: Vec<&str> = Vec::new();
    for param in params.into_iter().flat_map(|p| p.split(',')) {
        let param = param.trim();
        if param.is_empty() {
            return Err(format!(
                "empty parameter in '{whole}': expected KEY=VALUE pairs separated by commas"
            ));
        }
        let (key, value) = match param.split_once('=') {
            Some((k, v)) => (k.trim(), Some(v.trim())),
            None => (param, None),
        };
        if seen.contains(&key) {
            return Err(format!("'{key}' is given twice in '{whole}'"));
        }
        seen.push(key);
        set(key, value)?;
    }
    Ok(())
}
