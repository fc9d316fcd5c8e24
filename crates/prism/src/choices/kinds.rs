//! `named_kinds!`: the names of a plain enum of choices (sampler, filter, BVH builder, …),
//! as the command line and scene files spell them, written once. It derives `ALL`,
//! `NAMES`, `name()`, `Display` and a `FromStr` whose error lists the choices, so every
//! choice is parsed, printed and reported the same way.

/// Implements the naming of a fieldless enum:
///
/// ```ignore
/// named_kinds! {
///     FilterKind, "filter" {
///         Box => "box",
///         Tent => "tent",
///     }
///     aliases { "boxcar" => "box" }   // optional: other accepted spellings
/// }
/// ```
///
/// `"filter"` names the kind in errors: "unknown filter 'x', expected one of: box, tent".
#[macro_export]
macro_rules! named_kinds {
    (
        $kind:ident, $what:literal {
            $($variant:ident => $name:literal),+ $(,)?
        }
        $(aliases { $($alias:literal => $target:literal),+ $(,)? })?
    ) => {
        impl $kind {
            /// Every choice, in the order help texts list them.
            pub const ALL: [$kind; [$($name),+].len()] = [$($kind::$variant),+];
            /// Their names, in the same order.
            pub const NAMES: [&'static str; [$($name),+].len()] = [$($name),+];

            /// The position in `ALL` (and `NAMES`).
            pub fn index(self) -> usize {
                $kind::ALL
                    .iter()
                    .position(|&k| k == self)
                    .expect("ALL lists every variant")
            }

            /// The name the command line and scene files use.
            pub fn name(self) -> &'static str {
                match self {
                    $($kind::$variant => $name),+
                }
            }
        }

        $crate::kind_text!($kind, $what $(, $($alias => $target),+)?);
    };
}

/// `Display` and `FromStr` for a kind that has `ALL` and `name()`, as `named_kinds!` and
/// `method_list!` make them: a choice prints as its name, and parses from it (or from an
/// alias) with an error that lists every name.
#[doc(hidden)]
#[macro_export]
macro_rules! kind_text {
    ($kind:ident, $what:literal $(, $($alias:literal => $target:literal),+)?) => {
        impl ::std::fmt::Display for $kind {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str(self.name())
            }
        }

        impl ::std::str::FromStr for $kind {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                let wanted = match s {
                    $($($alias => $target,)+)?
                    other => other,
                };
                $kind::ALL.into_iter().find(|k| k.name() == wanted).ok_or_else(|| {
                    let names: Vec<_> = $kind::ALL.iter().map(|k| k.name()).collect();
                    format!(
                        concat!("unknown ", $what, " '{}', expected one of: {}"),
                        s,
                        names.join(", ")
                    )
                })
            }
        }
    };
}
