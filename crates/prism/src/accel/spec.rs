//! `AccelSpec`: which accelerator to build and with which parameters, written as one
//! string so the command line (`--accel`) and the scene file (`accel = "…"`) say it the
//! same way: `METHOD[:KEY=VALUE,…]`, e.g. `bvh`, `bvh:leaf=4,bins=32`, `grid:lambda=2`,
//! `kdtree:isect=80`, `bvh:volume=dop14`. A key without a value means `true` for switches.
//!
//! The methods are one list (`accel_methods!` below); each method's keys are its own
//! table (`choices::Keyed::KEYS`, in the method's files), from which parsing, printing, help and
//! the documentation check are all derived.

use super::{BruteForceOptions, BvhOptions, GridOptions, KdTreeOptions, OctreeOptions};

/// Declares the acceleration methods: one line per method, `Variant(OptionsType)`, where
/// the options type has a key table (`choices::Keyed`) and builds (`accel::Method`). It
/// makes `AccelKind` (the method alone) and `AccelSpec` (the method with its parameters),
/// their names, parsing and printing (`method_list!`), and `build`. Exported so a test can
/// declare a list with a toy method of its own.
#[macro_export]
macro_rules! accel_methods {
    ($($(#[$meta:meta])* $variant:ident($options:ty)),+ $(,)?) => {
        $crate::method_list! {
            kind AccelKind, spec AccelSpec, what "accelerator", behaviour dyn $crate::accel::Method;
            $($(#[$meta])* $variant($options)),+
        }

        impl AccelKind {
            /// Builds over the given (bounded) primitive indices, with default parameters.
            pub fn build(
                self,
                geometry: &$crate::geometry::Geometry,
                prims: Vec<u32>,
            ) -> Box<dyn $crate::accel::Accel> {
                AccelSpec::from(self).build(geometry, prims)
            }
        }

        impl AccelSpec {
            /// Builds over the given (bounded) primitive indices.
            pub fn build(
                &self,
                geometry: &$crate::geometry::Geometry,
                prims: Vec<u32>,
            ) -> Box<dyn $crate::accel::Accel> {
                self.method().build(geometry, prims)
            }

            /// `--accel`'s help: the syntax, then every method with its keys, from their
            /// tables.
            pub fn help() -> String {
                format!(
                    "Acceleration structure and its parameters, METHOD[:KEY=VALUE,...] \
                     (e.g. bvh:build=sweep,reinsert):{}",
                    $crate::choices::help_text(&AccelKind::docs())
                )
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
    /// This spec with a BVH's `build=auto` told the rays the render will trace; every
    /// other spec as it is.
    pub fn with_expected_rays(&self, rays: f64) -> AccelSpec {
        match self {
            AccelSpec::Bvh(o) => AccelSpec::Bvh(o.with_expected_rays(rays)),
            other => other.clone(),
        }
    }

    /// This spec with a BVH's `rays=auto` settled as `origins` (what the integrator
    /// traces, `RenderOptions::accel_to_build`); every other spec as it is.
    pub fn with_auto_rays(&self, origins: super::RayOrigins) -> AccelSpec {
        match self {
            AccelSpec::Bvh(o) => AccelSpec::Bvh(o.with_auto_rays(origins)),
            other => other.clone(),
        }
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
