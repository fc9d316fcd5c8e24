//! How a BVH is built: which builder, its SAH parameters, leaf size, the optional
//! reinsertion pass and when subtrees are built in parallel.

use std::fmt;
use std::str::FromStr;

/// The construction algorithm.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BvhBuilder {
    /// Object median along the longest axis of the centroid bounds: fast, SAH-blind.
    Median,
    /// Binned SAH (Wald 2007), `bins` candidate planes per axis.
    #[default]
    Binned,
    /// Full-sweep SAH: every split between sorted centroids on every axis is evaluated.
    Sweep,
    /// Linear BVH from sorted 63-bit Morton codes of the centroids (Lauterbach et al. 2009).
    Lbvh,
}

impl BvhBuilder {
    pub const ALL: [BvhBuilder; 4] = [
        BvhBuilder::Median,
        BvhBuilder::Binned,
        BvhBuilder::Sweep,
        BvhBuilder::Lbvh,
    ];

    pub fn name(self) -> &'static str {
        match self {
            BvhBuilder::Median => "median",
            BvhBuilder::Binned => "binned",
            BvhBuilder::Sweep => "sweep",
            BvhBuilder::Lbvh => "lbvh",
        }
    }

    /// The method as `prism info` names it, e.g. "full-sweep SAH".
    pub fn description(self) -> &'static str {
        match self {
            BvhBuilder::Median => "object median",
            BvhBuilder::Binned => "binned SAH",
            BvhBuilder::Sweep => "full-sweep SAH",
            BvhBuilder::Lbvh => "LBVH, 63-bit Morton",
        }
    }
}

impl fmt::Display for BvhBuilder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for BvhBuilder {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        BvhBuilder::ALL
            .into_iter()
            .find(|b| b.name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = BvhBuilder::ALL.iter().map(|b| b.name()).collect();
                format!(
                    "unknown BVH builder '{s}', expected one of: {}",
                    names.join(", ")
                )
            })
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct BvhOptions {
    pub builder: BvhBuilder,
    /// Bins per axis for the binned SAH sweep.
    pub bins: usize,
    /// Leaves never hold more primitives than this (unless they cannot be split).
    pub max_leaf_size: usize,
    /// Cost of a node visit relative to one primitive test.
    pub traversal_cost: f32,
    /// Improve the built tree by reinserting badly placed subtrees (Bittner et al. 2013).
    pub reinsert: bool,
    /// Pre-split triangles whose boxes are mostly empty into up to 16 references, this
    /// many extra references per primitive in all (0 = off; `build/presplit.rs`).
    pub presplit: f32,
    /// Subtrees with more primitives than this are built on separate threads. The tree does
    /// not depend on it (or on the thread count); `usize::MAX` builds on one thread.
    pub parallel_threshold: usize,
}

impl Default for BvhOptions {
    fn default() -> Self {
        BvhOptions {
            builder: BvhBuilder::Binned,
            bins: 16,
            max_leaf_size: 8,
            traversal_cost: 1.0,
            reinsert: false,
            presplit: 0.0,
            parallel_threshold: 4096,
        }
    }
}
