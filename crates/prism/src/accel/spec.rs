//! `AccelSpec`: which accelerator to build and with which parameters, written as one
//! string so the command line (`--accel`) and the scene file (`accel = "…"`) say it the
//! same way: `METHOD[:KEY=VALUE,…]`, e.g. `bvh`, `bvh:leaf=4,bins=32`, `grid:lambda=2`,
//! `kdtree:isect=80`, `bvh:volume=dop14`. A key without a value means `true` for switches.
//!
//! The methods are one list (`accel_methods!` below); each method's keys are its own
//! table (`Method::KEYS`, in the method's files), from which parsing, printing, help and
//! the documentation check are all derived.

use super::params::{help_text, MethodDoc};
use super::{BruteForceOptions, BvhOptions, GridOptions, KdTreeOptions, OctreeOptions};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Declares the acceleration methods: one line per method, `Variant(OptionsType)`, where
/// the options type implements `Method`. It makes `AccelKind` (the method alone) and
/// `AccelSpec` (the method with its parameters), their names, parsing and printing, and
/// `build`. Exported so a test can declare a list with a toy method of its own.
#[macro_export]
macro_rules! accel_methods {
    ($($(#[$meta:meta])* $variant:ident($options:ty)),+ $(,)?) => {
        /// Which accelerator to build.
        #[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
        pub enum AccelKind {
            $($(#[$meta])* $variant,)+
        }

        impl AccelKind {
            /// Every method, in the order help texts list them.
            pub const ALL: [AccelKind; [$(stringify!($variant)),+].len()] =
                [$(AccelKind::$variant),+];

            /// The method's name as `--accel` writes it.
            pub fn name(self) -> &'static str {
                match self {
                    $(AccelKind::$variant => <$options as $crate::accel::Method>::NAME,)+
                }
            }

            /// Builds over the given (bounded) primitive indices, with default parameters.
            pub fn build(
                self,
                geometry: &$crate::geometry::Geometry,
                prims: Vec<u32>,
            ) -> Box<dyn $crate::accel::Accel> {
                AccelSpec::from(self).build(geometry, prims)
            }

            /// Every method's name, summary and keys, read from their tables.
            pub fn docs() -> Vec<$crate::accel::MethodDoc> {
                vec![$($crate::accel::method_doc::<$options>()),+]
            }
        }

        impl ::std::fmt::Display for AccelKind {
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str(self.name())
            }
        }

        impl ::std::str::FromStr for AccelKind {
            type Err = String;
            fn from_str(s: &str) -> Result<Self, String> {
                AccelKind::ALL
                    .into_iter()
                    .find(|k| k.name() == s)
                    .ok_or_else(|| {
                        let names: Vec<_> = AccelKind::ALL.iter().map(|k| k.name()).collect();
                        format!(
                            "unknown accelerator '{s}', expected one of: {}",
                            names.join(", ")
                        )
                    })
            }
        }

        /// An accelerator and its build parameters.
        #[derive(Clone, Debug, PartialEq)]
        pub enum AccelSpec {
            $(
                #[doc = concat!("`", stringify!($variant), "` with its parameters.")]
                $variant($options),
            )+
        }

        impl Default for AccelSpec {
            fn default() -> Self {
                AccelSpec::from(AccelKind::default())
            }
        }

        impl From<AccelKind> for AccelSpec {
            /// The method with its default parameters.
            fn from(kind: AccelKind) -> Self {
                match kind {
                    $(AccelKind::$variant => AccelSpec::$variant(<$options>::default()),)+
                }
            }
        }

        impl AccelSpec {
            /// The method without its parameters.
            pub fn kind(&self) -> AccelKind {
                match self {
                    $(AccelSpec::$variant(_) => AccelKind::$variant,)+
                }
            }

            /// Builds over the given (bounded) primitive indices.
            pub fn build(
                &self,
                geometry: &$crate::geometry::Geometry,
                prims: Vec<u32>,
            ) -> Box<dyn $crate::accel::Accel> {
                match self {
                    $(AccelSpec::$variant(o) => $crate::accel::Method::build(o, geometry, prims),)+
                }
            }

            fn set_param(&mut self, key: &str, value: Option<&str>) -> Result<(), String> {
                match self {
                    $(AccelSpec::$variant(o) => $crate::accel::Method::set_param(o, key, value),)+
                }
            }

            fn non_default_params(&self) -> Vec<String> {
                match self {
                    $(AccelSpec::$variant(o) => $crate::accel::Method::non_default_params(o),)+
                }
            }
        }

        impl ::std::fmt::Display for AccelSpec {
            /// The canonical spelling, which parses back to the same spec.
            fn fmt(&self, f: &mut ::std::fmt::Formatter<'_>) -> ::std::fmt::Result {
                f.write_str(self.kind().name())?;
                let params = self.non_default_params();
                if !params.is_empty() {
                    write!(f, ":{}", params.join(","))?;
                }
                Ok(())
            }
        }

        impl ::std::str::FromStr for AccelSpec {
            type Err = String;

            fn from_str(s: &str) -> Result<Self, String> {
                let (name, params) = match s.split_once(':') {
                    Some((name, params)) => (name.trim(), Some(params)),
                    None => (s.trim(), None),
                };
                let mut spec = AccelSpec::from(name.parse::<AccelKind>()?);
                $crate::accel::parse_params(s, params, |key, value| spec.set_param(key, value))?;
                Ok(spec)
            }
        }
    };
}

accel_methods! {
    /// Test every primitive: the reference.
    BruteForce(BruteForceOptions),
    /// Bounding volume hierarchy, binned SAH build.
    #[default]
    Bvh(BvhOptions),
    /// Uniform grid walked by 3D-DDA, with mailboxing.
    Grid(GridOptions),
    /// kd-tree, SAH event-sweep build.
    KdTree(KdTreeOptions),
    /// Adaptive octree.
    Octree(OctreeOptions),
}

impl AccelSpec {
    /// This spec with a BVH's `rays=auto` settled as `origins` (what the integrator
    /// traces, `RenderOptions::accel_to_build`); every other spec as it is.
    pub fn with_auto_rays(&self, origins: super::RayOrigins) -> AccelSpec {
        match self {
            AccelSpec::Bvh(o) => AccelSpec::Bvh(o.with_auto_rays(origins)),
            other => other.clone(),
        }
    }
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

impl AccelSpec {
    /// The keys each method takes, for error messages and `--help`.
    pub fn keys(kind: AccelKind) -> Vec<&'static str> {
        AccelKind::docs()[kind.index()]
            .keys
            .iter()
            .map(|k| k.name)
            .collect()
    }

    /// `--accel`'s help: the syntax, then every method with its keys, from their tables.
    pub fn help() -> String {
        format!(
            "Acceleration structure and its parameters, METHOD[:KEY=VALUE,...] \
             (e.g. bvh:build=sweep,reinsert):{}",
            help_text(&AccelKind::docs())
        )
    }

    /// Every method's name, summary and keys.
    pub fn docs() -> Vec<MethodDoc> {
        AccelKind::docs()
    }
}

impl AccelKind {
    /// The position in `ALL`.
    pub fn index(self) -> usize {
        AccelKind::ALL
            .iter()
            .position(|&k| k == self)
            .expect("ALL lists every method")
    }
}

impl Serialize for AccelSpec {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(&self.to_string())
    }
}

impl<'de> Deserialize<'de> for AccelSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = String::deserialize(deserializer)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::volumes::{self, NodeVolume};
    use crate::accel::BvhBuilder;

    #[test]
    fn plain_names_give_the_defaults() {
        for kind in AccelKind::ALL {
            let spec: AccelSpec = kind.name().parse().unwrap();
            assert_eq!(spec, AccelSpec::from(kind));
            assert_eq!(spec.to_string(), kind.name());
        }
    }

    #[test]
    fn parameters_parse_and_print_back() {
        for text in [
            "bvh:bins=32,leaf=4",
            "bvh:trav=2.5",
            "bvh:build=sweep,reinsert,leaf=4",
            "bvh:build=lbvh,reinsert=false",
            "bvh:split=0.5,build=sweep",
            "bvh:build=median,reinsert=true",
            "bvh:leaf=4,volume=obb",
            "bvh:volume=dop26",
            "bvh:volume=hull,bins=8",
            "grid:lambda=2,cells=1000",
            "kdtree:trav=1,isect=80,empty-bonus=0.5,depth=20",
            "octree:leaf=2,depth=6",
        ] {
            let spec: AccelSpec = text.parse().unwrap();
            let again: AccelSpec = spec.to_string().parse().unwrap();
            assert_eq!(spec, again, "{text}");
        }
        let AccelSpec::Bvh(o) = "bvh: leaf = 4 , bins=32".parse().unwrap() else {
            panic!("not a bvh");
        };
        assert_eq!((o.max_leaf_size, o.bins), (4, 32));
        let AccelSpec::Bvh(o) = "bvh:build=sweep,reinsert,leaf=4".parse().unwrap() else {
            panic!("not a bvh");
        };
        assert_eq!(
            (o.builder, o.reinsert, o.max_leaf_size),
            (BvhBuilder::Sweep, true, 4)
        );
        assert_eq!(
            AccelSpec::Bvh(o).to_string(),
            "bvh:leaf=4,build=sweep,reinsert"
        );
        for v in volumes::NodeVolume::ALL {
            let spec: AccelSpec = format!("bvh:volume={v}").parse().unwrap();
            assert_eq!(spec.kind(), AccelKind::Bvh);
            if v == NodeVolume::Aabb {
                assert_eq!(spec, AccelSpec::default(), "boxes are the plain BVH");
            } else {
                assert_eq!(spec.to_string(), format!("bvh:volume={v}"));
            }
        }
        // A default value is not printed.
        assert_eq!(
            "bvh:bins=16".parse::<AccelSpec>().unwrap().to_string(),
            "bvh"
        );
    }

    #[test]
    fn bad_specs_say_what_was_expected() {
        for (text, phrase) in [
            ("bvhh", "expected one of: brute-force, bvh"),
            ("bvh:leaf=0", "expected an integer from 1 to 1024"),
            ("bvh:leaf=x", "bad value 'x' for 'leaf'"),
            ("bvh:leaf", "'leaf' needs a value"),
            (
                "bvh:build=octopus",
                "bad value 'octopus' for 'build': expected one of: median, binned, sweep, lbvh",
            ),
            ("bvh:build", "'build' needs a value"),
            ("bvh:reinsert=yes", "expected true or false"),
            (
                "bvh:lambda=2",
                "unknown parameter 'lambda' for bvh, expected one of: bins",
            ),
            ("grid:lambda=nan", "expected a number from"),
            (
                "bvh:volume=cube",
                "bad value 'cube' for 'volume': expected one of: aabb, sphere, obb, dop14, dop26, \
                 hull",
            ),
            ("bvh:volume", "'volume' needs a value"),
            ("grid:volume=obb", "unknown parameter 'volume' for grid"),
            ("grid:lambda=inf", "expected a number from"),
            ("brute-force:leaf=1", "brute-force takes no parameters"),
            ("bvh:leaf=4,,bins=2", "empty parameter"),
            ("bvh:leaf=4,leaf=8", "'leaf' is given twice"),
            ("grid:cells=16777217", "from 1 to 16777216"),
            ("octree:depth=21", "from 1 to 20"),
        ] {
            let err = text.parse::<AccelSpec>().unwrap_err();
            assert!(err.contains(phrase), "{text}: {err}");
        }
    }
}
