//! Uniform grid: the scene box cut into equal cells, each listing the primitives whose
//! (padded) bounds overlap it; the resolution heuristic and build are in `build.rs`, the
//! 3D-DDA walk of Amanatides & Woo (1987) with mailboxing in `traverse.rs`.

mod build;
mod traverse;

use crate::accel::AccelInfo;
use crate::math::{Aabb, Vec3};

pub use build::GridOptions;

/// A uniform grid over the scene box: cells listing the primitives they overlap.
pub struct Grid {
    bounds: Aabb,
    /// Cells per axis.
    res: [u32; 3],
    cell_size: Vec3,
    /// Compressed cell lists: cell `c` holds `refs[starts[c] .. starts[c + 1]]`, cells
    /// numbered x fastest, then y, then z.
    starts: Vec<u32>,
    refs: Vec<u32>,
    primitives: usize,
    lambda: f32,
}

impl Grid {
    fn cell_index(&self, c: [u32; 3]) -> usize {
        (c[0] + self.res[0] * (c[1] + self.res[1] * c[2])) as usize
    }

    fn cell_prims(&self, c: [u32; 3]) -> &[u32] {
        let i = self.cell_index(c);
        &self.refs[self.starts[i] as usize..self.starts[i + 1] as usize]
    }

    /// Lower corner of cell `i` along `axis` (`i` may be `res`, the far side).
    #[inline(always)]
    fn plane(&self, axis: usize, i: u32) -> f32 {
        if i >= self.res[axis] {
            self.bounds.max[axis]
        } else {
            self.bounds.min[axis] + i as f32 * self.cell_size[axis]
        }
    }

    /// Bytes of the cell lists.
    pub fn memory_bytes(&self) -> usize {
        (self.starts.len() + self.refs.len()) * 4
    }

    /// Resolution, cell occupancy and memory.
    pub fn info(&self) -> AccelInfo {
        let cells = self.starts.len().saturating_sub(1);
        let sizes = self.starts.windows(2).map(|w| (w[1] - w[0]) as usize);
        let non_empty = sizes.clone().filter(|&n| n > 0).count();
        AccelInfo {
            method: format!(
                "grid ({}×{}×{} cells, λ = {})",
                self.res[0], self.res[1], self.res[2], self.lambda
            ),
            primitives: self.primitives,
            nodes: cells,
            leaves: cells,
            depth: 1,
            max_leaf_size: sizes.max().unwrap_or(0),
            mean_leaf_size: self.refs.len() as f64 / non_empty.max(1) as f64,
            sah_cost: None,
            memory_bytes: self.memory_bytes(),
        }
    }
}
