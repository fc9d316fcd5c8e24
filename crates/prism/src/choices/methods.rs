//! `method_list!`: a choice whose methods carry settings of their own (the accelerators
//! today), declared as one list. Each line names a settings type that has a key table
//! (`Keyed`) and implements the choice's behaviour trait; the macro makes the kind (the
//! method alone) and the spec (the method with its settings), their names, parsing,
//! printing, documentation and the dispatch to the behaviour, so adding a method is its
//! file plus one line in the list.

/// Declares a choice's methods:
///
/// ```ignore
/// method_list! {
///     kind AccelKind, spec AccelSpec, what "accelerator", behaviour dyn accel::Method;
///     BruteForce(BruteForceOptions),
///     #[default]
///     Bvh(BvhOptions),
/// }
/// ```
///
/// `what` names the choice in errors ("unknown accelerator 'x', expected one of: …");
/// `spec.method()` is the method's settings as the behaviour trait. Exported so that a
/// test can declare a list with a toy method of its own.
#[macro_export]
macro_rules! method_list {
    (
        kind $kind:ident, spec $spec:ident, what $what:literal, behaviour dyn $behaviour:path;
        $($(#[$meta:meta])* $variant:ident($options:ty)),+ $(,)?
    ) => {
        #[doc = concat!("Which ", $what, ": the method alone.")]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        pub enum $kind {
            $($(#[$meta])* $variant,)+
        }

        impl $kind {
            /// Every method, in the order help texts list them.
            pub const ALL: [$kind; [$(stringify!($variant)),+].len()] = [$($kind::$variant),+];

            /// The method's name as written before the colon.
            pub fn name(self) -> &'static str {
                match self {
                    $($kind::$variant => <$options as $crate::choices::Keyed>::NAME,)+
                }
            }

            /// The position in `ALL`.
            pub fn index(self) -> usize {
                $kind::ALL
                    .iter()
                    .position(|&k| k == self)
                    .expect("ALL lists every method")
            }

            /// Every method's name, summary and keys, read from their tables.
            pub fn docs() -> Vec<$crate::choices::MethodDoc> {
                vec![$($crate::choices::method_doc::<$options>()),+]
            }
        }

        $crate::kind_text!($kind, $what);

        #[doc = concat!("A ", $what, " and its settings.")]
        #[derive(Clone, Debug, PartialEq)]
        pub enum $spec {
            $(
                #[doc = concat!("`", stringify!($variant), "` with its settings.")]
                $variant($options),
            )+
        }

        impl Default for $spec {
            fn default() -> Self {
                $spec::from($kind::default())
            }
        }

        impl From<$kind> for $spec {
            /// The method with its default settings.
            fn from(kind: $kind) -> Self {
                match kind {
                    $($kind::$variant => $spec::$variant(<$options>::default()),)+
                }
            }
        }

        impl $spec {
            /// The method without its settings.
            pub fn kind(&self) -> $kind {
                match self {
                    $($spec::$variant(_) => $kind::$variant,)+
                }
            }

            /// The method's settings as its behaviour.
            pub fn method(&self) -> &dyn $behaviour {
                match self {
                    $($spec::$variant(o) => o,)+
                }
            }

            /// Sets `key` from its text (`None`: the key given alone).
            pub fn set_param(&mut self, key: &str, value: Option<&str>) -> Result<(), String> {
                match self {
                    $($spec::$variant(o) => $crate::choices::Keyed::set_param(o, key, value),)+
                }
            }

            /// The keys that differ from the method's defaults, as `key=value`.
            pub fn non_default_params(&self) -> Vec<String> {
                match self {
                    $($spec::$variant(o) => $crate::choices::Keyed::non_default_params(o),)+
                }
            }

            /// Every method's name, summary and keys.
            pub fn docs() -> Vec<$crate::choices::MethodDoc> {
                $kind::docs()
            }

            /// The keys a method takes, for error messages and help.
            pub fn keys(kind: $kind) -> Vec<&'static str> {
                $kind::docs()[kind.index()].keys.iter().map(|k| k.name).collect()
            }
        }

        impl ::std::fmt::Display for $spec {
            /// The canonical spelling, which parses back to the same spec.
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                $crate::choices::write_spec(f, self.kind().name(), &self.non_default_params())
            }
        }

        impl ::std::str::FromStr for $spec {
            type Err = String;

            fn from_str(s: &str) -> Result<Self, String> {
                let (name, params) = match s.split_once(':') {
                    Some((name, params)) => (name.trim(), Some(params)),
                    None => (s.trim(), None),
                };
                let mut spec = $spec::from(name.parse::<$kind>()?);
                $crate::choices::parse_params(s, params, |key, value| spec.set_param(key, value))?;
                Ok(spec)
            }
        }

        $crate::serde_as_text!($spec);
    };
}

/// Serializes a type as its `Display` text and deserializes it through `FromStr`, so a
/// spec reads the same in a scene file as on the command line.
#[macro_export]
macro_rules! serde_as_text {
    ($type:ty) => {
        impl $crate::choices::serde::Serialize for $type {
            fn serialize<S: $crate::choices::serde::Serializer>(
                &self,
                serializer: S,
            ) -> Result<S::Ok, S::Error> {
                serializer.collect_str(self)
            }
        }

        impl<'de> $crate::choices::serde::Deserialize<'de> for $type {
            fn deserialize<D: $crate::choices::serde::Deserializer<'de>>(
                deserializer: D,
            ) -> Result<Self, D::Error> {
                let text =
                    <String as $crate::choices::serde::Deserialize>::deserialize(deserializer)?;
                text.parse()
                    .map_err($crate::choices::serde::de::Error::custom)
            }
        }
    };
}
