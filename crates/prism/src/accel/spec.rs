//! `AccelSpec`: which accelerator to build and with which parameters, written as one
//! string so the command line (`--accel`) and the scene file (`accel = "…"`) say it the
//! same way: `METHOD[:KEY=VALUE,…]`, e.g. `bvh`, `bvh:leaf=4,bins=32`, `grid:lambda=2`,
//! `kdtree:isect=80`, `bvh:volume=dop14`. A key without a value means `true` for switches.

use super::volumes::{self, NodeVolume};
use super::{
    Accel, AccelKind, BruteForce, Bvh, BvhOptions, Grid, GridOptions, KdTree, KdTreeOptions,
    Octree, OctreeOptions,
};
use crate::geometry::Geometry;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// An accelerator and its build parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum AccelSpec {
    BruteForce,
    Bvh(BvhOptions),
    /// The same SAH tree with other node volumes than boxes (`bvh:volume=…`); boxes are
    /// `Bvh` itself.
    BvhVolume {
        options: BvhOptions,
        volume: NodeVolume,
    },
    Grid(GridOptions),
    KdTree(KdTreeOptions),
    Octree(OctreeOptions),
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
            AccelKind::BruteForce => AccelSpec::BruteForce,
            AccelKind::Bvh => AccelSpec::Bvh(BvhOptions::default()),
            AccelKind::Grid => AccelSpec::Grid(GridOptions::default()),
            AccelKind::KdTree => AccelSpec::KdTree(KdTreeOptions::default()),
            AccelKind::Octree => AccelSpec::Octree(OctreeOptions::default()),
        }
    }
}

impl AccelSpec {
    pub fn kind(&self) -> AccelKind {
        match self {
            AccelSpec::BruteForce => AccelKind::BruteForce,
            AccelSpec::Bvh(_) | AccelSpec::BvhVolume { .. } => AccelKind::Bvh,
            AccelSpec::Grid(_) => AccelKind::Grid,
            AccelSpec::KdTree(_) => AccelKind::KdTree,
            AccelSpec::Octree(_) => AccelKind::Octree,
        }
    }

    /// Builds over the given (bounded) primitive indices.
    pub fn build(&self, geometry: &Geometry, prims: Vec<u32>) -> Box<dyn Accel> {
        match self {
            AccelSpec::BruteForce => Box::new(BruteForce::new(prims)),
            AccelSpec::Bvh(o) => Box::new(Bvh::build(geometry, prims, o)),
            AccelSpec::BvhVolume { options, volume } => {
                volumes::build(geometry, prims, options, *volume)
            }
            AccelSpec::Grid(o) => Box::new(Grid::build(geometry, prims, o)),
            AccelSpec::KdTree(o) => Box::new(KdTree::build(geometry, prims, o)),
            AccelSpec::Octree(o) => Box::new(Octree::build(geometry, prims, o)),
        }
    }

    /// The parameters that differ from the method's defaults, as `key=value` pairs in the
    /// order the parser documents them.
    fn non_default_params(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut put = |key: &str, value: String, default: String| {
            if value != default {
                out.push(format!("{key}={value}"));
            }
        };
        match self {
            AccelSpec::BruteForce => {}
            AccelSpec::Bvh(o) | AccelSpec::BvhVolume { options: o, .. } => {
                let d = BvhOptions::default();
                put("bins", o.bins.to_string(), d.bins.to_string());
                put(
                    "leaf",
                    o.max_leaf_size.to_string(),
                    d.max_leaf_size.to_string(),
                );
                put(
                    "trav",
                    o.traversal_cost.to_string(),
                    d.traversal_cost.to_string(),
                );
                put("build", o.builder.to_string(), d.builder.to_string());
                put("split", o.presplit.to_string(), d.presplit.to_string());
                if let AccelSpec::BvhVolume { volume, .. } = self {
                    put("volume", volume.to_string(), NodeVolume::Aabb.to_string());
                }
                if o.reinsert {
                    out.push("reinsert".to_string());
                }
            }
            AccelSpec::Grid(o) => {
                let d = GridOptions::default();
                put("lambda", o.lambda.to_string(), d.lambda.to_string());
                put("cells", o.max_cells.to_string(), d.max_cells.to_string());
            }
            AccelSpec::KdTree(o) => {
                let d = KdTreeOptions::default();
                put(
                    "trav",
                    o.traversal_cost.to_string(),
                    d.traversal_cost.to_string(),
                );
                put(
                    "isect",
                    o.intersection_cost.to_string(),
                    d.intersection_cost.to_string(),
                );
                put(
                    "empty-bonus",
                    o.empty_bonus.to_string(),
                    d.empty_bonus.to_string(),
                );
                put("depth", o.max_depth.to_string(), d.max_depth.to_string());
            }
            AccelSpec::Octree(o) => {
                let d = OctreeOptions::default();
                put(
                    "leaf",
                    o.max_leaf_size.to_string(),
                    d.max_leaf_size.to_string(),
                );
                put("depth", o.max_depth.to_string(), d.max_depth.to_string());
            }
        }
        out
    }
}

impl fmt::Display for AccelSpec {
    /// The canonical spelling, which parses back to the same spec.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.kind().name())?;
        let params = self.non_default_params();
        if !params.is_empty() {
            write!(f, ":{}", params.join(","))?;
        }
        Ok(())
    }
}

impl From<AccelSpec> for String {
    fn from(spec: AccelSpec) -> String {
        spec.to_string()
    }
}

impl TryFrom<String> for AccelSpec {
    type Error = String;
    fn try_from(s: String) -> Result<Self, String> {
        s.parse()
    }
}

impl FromStr for AccelSpec {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let (name, params) = match s.split_once(':') {
            Some((name, params)) => (name.trim(), Some(params)),
            None => (s.trim(), None),
        };
        let mut spec = AccelSpec::from(name.parse::<AccelKind>()?);
        let mut seen: Vec<&str> = Vec::new();
        for param in params.into_iter().flat_map(|p| p.split(',')) {
            let param = param.trim();
            if param.is_empty() {
                return Err(format!(
                    "empty parameter in '{s}': expected KEY=VALUE pairs separated by commas"
                ));
            }
            let (key, value) = match param.split_once('=') {
                Some((k, v)) => (k.trim(), Some(v.trim())),
                None => (param, None),
            };
            if seen.contains(&key) {
                return Err(format!("'{key}' is given twice in '{s}'"));
            }
            seen.push(key);
            spec.set(key, Param { key, value })?;
        }
        Ok(spec)
    }
}

/// One `key=value` pair being applied, with the parsing rules for its value.
struct Param<'a> {
    key: &'a str,
    value: Option<&'a str>,
}

impl Param<'_> {
    fn text(&self, expected: &str) -> Result<&str, String> {
        self.value
            .filter(|v| !v.is_empty())
            .ok_or_else(|| format!("'{}' needs a value: expected {expected}", self.key))
    }

    /// An integer in `lo..=hi`.
    fn int(&self, lo: usize, hi: usize) -> Result<usize, String> {
        let expected = format!("an integer from {lo} to {hi}");
        let text = self.text(&expected)?;
        match text.parse::<usize>() {
            Ok(v) if (lo..=hi).contains(&v) => Ok(v),
            _ => Err(format!(
                "bad value '{text}' for '{}': expected {expected}",
                self.key
            )),
        }
    }

    /// A switch: given alone or as `true` means on, `false` off.
    fn switch(&self) -> Result<bool, String> {
        match self.value {
            None | Some("true") => Ok(true),
            Some("false") => Ok(false),
            Some(text) => Err(format!(
                "bad value '{text}' for '{}': expected true or false (or the key alone)",
                self.key
            )),
        }
    }

    /// A name its type parses (whose error lists the choices).
    fn choice<T: FromStr<Err = String>>(&self) -> Result<T, String> {
        self.text("a name")?
            .parse()
            .map_err(|e| format!("bad value for '{}': {e}", self.key))
    }

    /// A node volume by name.
    fn volume(&self) -> Result<NodeVolume, String> {
        let names: Vec<&str> = NodeVolume::ALL.iter().map(|v| v.name()).collect();
        let expected = format!("one of {}", names.join(", "));
        let text = self.text(&expected)?;
        text.parse()
            .map_err(|_| format!("bad value '{text}' for '{}': expected {expected}", self.key))
    }

    /// A finite number in `lo..=hi`.
    fn number(&self, lo: f32, hi: f32) -> Result<f32, String> {
        let expected = format!("a number from {lo} to {hi}");
        let text = self.text(&expected)?;
        match text.parse::<f32>() {
            Ok(v) if v.is_finite() && (lo..=hi).contains(&v) => Ok(v),
            _ => Err(format!(
                "bad value '{text}' for '{}': expected {expected}",
                self.key
            )),
        }
    }
}

impl AccelSpec {
    /// The keys each method takes, for error messages and `--help`.
    pub fn keys(kind: AccelKind) -> &'static [&'static str] {
        match kind {
            AccelKind::BruteForce => &[],
            AccelKind::Bvh => &[
                "bins", "leaf", "trav", "build", "reinsert", "split", "volume",
            ],
            AccelKind::Grid => &["lambda", "cells"],
            AccelKind::KdTree => &["trav", "isect", "empty-bonus", "depth"],
            AccelKind::Octree => &["leaf", "depth"],
        }
    }

    fn set(&mut self, key: &str, p: Param) -> Result<(), String> {
        if let (AccelSpec::Bvh(o) | AccelSpec::BvhVolume { options: o, .. }, "volume") =
            (&*self, key)
        {
            let options = o.clone();
            let volume = p.volume()?;
            *self = match volume {
                NodeVolume::Aabb => AccelSpec::Bvh(options),
                volume => AccelSpec::BvhVolume { options, volume },
            };
            return Ok(());
        }
        match (self, key) {
            (AccelSpec::Bvh(o) | AccelSpec::BvhVolume { options: o, .. }, "bins") => {
                o.bins = p.int(2, 256)?
            }
            (AccelSpec::Bvh(o) | AccelSpec::BvhVolume { options: o, .. }, "leaf") => {
                o.max_leaf_size = p.int(1, 1024)?
            }
            (AccelSpec::Bvh(o) | AccelSpec::BvhVolume { options: o, .. }, "trav") => {
                o.traversal_cost = p.number(0.0, 1000.0)?
            }
            (AccelSpec::Bvh(o) | AccelSpec::BvhVolume { options: o, .. }, "build") => {
                o.builder = p.choice()?
            }
            (AccelSpec::Bvh(o) | AccelSpec::BvhVolume { options: o, .. }, "reinsert") => {
                o.reinsert = p.switch()?
            }
            (AccelSpec::Bvh(o) | AccelSpec::BvhVolume { options: o, .. }, "split") => {
                o.presplit = p.number(0.0, 4.0)?
            }
            (AccelSpec::Grid(o), "lambda") => o.lambda = p.number(0.01, 100.0)?,
            (AccelSpec::Grid(o), "cells") => o.max_cells = p.int(1, 1 << 24)?,
            (AccelSpec::KdTree(o), "trav") => o.traversal_cost = p.number(0.0, 1000.0)?,
            (AccelSpec::KdTree(o), "isect") => o.intersection_cost = p.number(0.001, 1000.0)?,
            (AccelSpec::KdTree(o), "empty-bonus") => o.empty_bonus = p.number(0.0, 1.0)?,
            (AccelSpec::KdTree(o), "depth") => o.max_depth = p.int(0, 60)?,
            (AccelSpec::Octree(o), "leaf") => o.max_leaf_size = p.int(1, 1024)?,
            (AccelSpec::Octree(o), "depth") => o.max_depth = p.int(1, 20)?,
            (spec, _) => {
                let kind = spec.kind();
                let keys = AccelSpec::keys(kind);
                return Err(if keys.is_empty() {
                    format!("{} takes no parameters, got '{key}'", kind.name())
                } else {
                    format!(
                        "unknown parameter '{key}' for {}, expected one of: {}",
                        kind.name(),
                        keys.join(", ")
                    )
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
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
                "unknown BVH builder 'octopus', expected one of: median, binned, sweep, lbvh",
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
                "expected one of aabb, sphere, obb, dop14, dop26, hull",
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
