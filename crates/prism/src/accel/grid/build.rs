//! Grid resolution and construction.
//!
//! Resolution follows Cleary & Wyvill's rule of thumb as popularised by pbrt: about
//! `λ·∛N` cells along the longest axis of the box, the other axes in proportion to their
//! extent, so cells are near-cubes and hold O(1) primitives on average when primitives are
//! evenly spread. The total is capped so a huge scene cannot exhaust memory.

use super::Grid;
use crate::accel::cells::padded_bounds;
use crate::accel::Accel;
use crate::accel::Method;
use crate::choices::{Key, Keyed};
use crate::field_key;
use crate::geometry::Geometry;
use crate::math::{Aabb, Vec3};

/// How the grid resolution is chosen; also the `grid:` keys of `--accel`.
#[derive(Clone, Debug, PartialEq)]
pub struct GridOptions {
    /// Cells along the longest axis per cube root of the primitive count.
    pub lambda: f32,
    /// Upper bound on the number of cells.
    pub max_cells: usize,
}

impl Default for GridOptions {
    fn default() -> Self {
        GridOptions {
            lambda: 3.0,
            max_cells: 1 << 24,
        }
    }
}

impl Keyed for GridOptions {
    const NAME: &'static str = "grid";
    const SUMMARY: &'static str = "uniform grid walked by 3D-DDA";
    const KEYS: &'static [Key<Self>] = &[
        field_key!("lambda" => lambda, number 0.01..=100.0,
            "cells along the longest axis per cube root of the primitive count"),
        field_key!("cells" => max_cells, int 1..=1 << 24, "upper bound on the number of cells"),
    ];
}

impl Method for GridOptions {
    fn build(&self, geometry: &Geometry, prims: Vec<u32>) -> Box<dyn Accel> {
        Box::new(Grid::build(geometry, prims, self))
    }
}

/// Cells per axis for `n` primitives in a box of `extent`.
fn resolution(extent: Vec3, n: usize, options: &GridOptions, shrink: f32) -> [u32; 3] {
    let longest = extent.max_element();
    if n == 0 || longest.is_nan() || longest <= 0.0 {
        return [1; 3];
    }
    let mut per_unit = shrink * options.lambda.max(0.0) * (n as f32).cbrt() / longest;
    loop {
        let res = [0, 1, 2].map(|k| ((extent[k] * per_unit).round() as u32).clamp(1, 1 << 12));
        let cells = res.iter().map(|&r| r as usize).product::<usize>();
        if cells <= options.max_cells.max(1) || res == [1; 3] {
            return res;
        }
        per_unit *= 0.9;
    }
}

/// References a grid may hold (256 MiB of ids); past this the resolution is lowered.
const MAX_REFERENCES: u64 = 1 << 26;

/// The cell range each primitive's box covers, clamped: the same floor() the traversal
/// uses to find its entry cell, and the padding absorbs the rounding.
fn cell_ranges(
    boxes: &[Aabb],
    bounds: &Aabb,
    res: [u32; 3],
    cell_size: Vec3,
) -> Vec<([u32; 3], [u32; 3])> {
    let cell_of = |p: Vec3| -> [u32; 3] {
        [0, 1, 2].map(|k| {
            let f = ((p[k] - bounds.min[k]) / cell_size[k]).floor();
            (f.max(0.0) as u32).min(res[k] - 1)
        })
    };
    boxes
        .iter()
        .map(|b| (cell_of(b.min), cell_of(b.max)))
        .collect()
}

impl Grid {
    /// Builds the grid over `prims` (indices into `geometry.primitives`).
    pub fn build(geometry: &Geometry, prims: Vec<u32>, options: &GridOptions) -> Grid {
        let (boxes, bounds) = padded_bounds(geometry, &prims);
        // Big primitives in fine cells are listed in every cell they touch; coarsen the
        // grid until the references fit the budget rather than run out of memory.
        let mut shrink = 1.0;
        let (res, cell_size, ranges) = loop {
            let res = resolution(bounds.extent(), prims.len(), options, shrink);
            let cell_size =
                bounds.extent() / Vec3::new(res[0] as f32, res[1] as f32, res[2] as f32);
            let ranges = cell_ranges(&boxes, &bounds, res, cell_size);
            let total: u64 = ranges
                .iter()
                .map(|(lo, hi)| {
                    (0..3)
                        .map(|k| u64::from(hi[k] - lo[k] + 1))
                        .product::<u64>()
                })
                .sum();
            if total <= MAX_REFERENCES || res == [1; 3] {
                break (res, cell_size, ranges);
            }
            shrink *= 0.8;
        };
        let mut grid = Grid {
            bounds,
            res,
            cell_size,
            starts: Vec::new(),
            refs: Vec::new(),
            primitives: prims.len(),
            lambda: options.lambda,
        };
        if prims.is_empty() {
            grid.starts = vec![0, 0];
            return grid;
        }
        let cells = res.iter().map(|&r| r as usize).product::<usize>();
        let mut counts = vec![0u32; cells + 1];
        let each_cell = |(lo, hi): &([u32; 3], [u32; 3]), f: &mut dyn FnMut(usize)| {
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    let row = (res[0] * (y + res[1] * z)) as usize;
                    for x in lo[0]..=hi[0] {
                        f(row + x as usize);
                    }
                }
            }
        };
        for r in &ranges {
            each_cell(r, &mut |c| counts[c] += 1);
        }
        // Exclusive prefix sum: counts becomes starts.
        let mut total = 0u32;
        for c in counts.iter_mut() {
            let n = *c;
            *c = total;
            total += n;
        }
        let mut fill = counts.clone();
        let mut refs = vec![0u32; total as usize];
        for (r, &prim) in ranges.iter().zip(&prims) {
            each_cell(r, &mut |c| {
                refs[fill[c] as usize] = prim;
                fill[c] += 1;
            });
        }
        grid.starts = counts;
        grid.refs = refs;
        grid
    }
}
