//! What an acceleration structure looks like once built: the figures `prism info`, the
//! statistics report and `prism bench` print, the same for every method.

use serde::Serialize;
use std::fmt;

/// What an accelerator built, for `prism info`, `--stats` and `prism bench`.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct AccelInfo {
    /// Method and its parameters, e.g. "bvh (binned SAH, 16 bins)".
    pub method: String,
    /// Distinct primitives the structure holds.
    pub primitives: usize,
    /// All nodes (cells, for grids), leaves included.
    pub nodes: usize,
    /// Leaves (non-empty or not; cells, for grids).
    pub leaves: usize,
    /// Deepest leaf; the root alone has depth 1.
    pub depth: usize,
    /// Primitive references per leaf (a primitive may sit in several leaves of a spatial
    /// subdivision): largest and mean over non-empty leaves.
    pub max_leaf_size: usize,
    /// Mean references per non-empty leaf.
    pub mean_leaf_size: f64,
    /// Expected cost of a random ray under the surface area heuristic, in units of one
    /// primitive test with a node visit costing 1 too; `None` where it does not apply.
    pub sah_cost: Option<f64>,
    /// Bytes of the structure itself (nodes and reference lists), not the geometry.
    pub memory_bytes: usize,
}

impl fmt::Display for AccelInfo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {} nodes ({} leaves), depth {}, leaf size mean {:.2} max {}, ",
            self.method,
            self.nodes,
            self.leaves,
            self.depth,
            self.mean_leaf_size,
            self.max_leaf_size
        )?;
        if let Some(c) = self.sah_cost {
            write!(f, "SAH cost {c:.2}, ")?;
        }
        write!(
            f,
            "{} primitives, {:.2} MiB",
            self.primitives,
            self.memory_bytes as f64 / (1024.0 * 1024.0)
        )
    }
}
