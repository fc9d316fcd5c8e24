//! Linear BVH (Lauterbach et al. 2009): centroids quantised to 21 bits per axis in their
//! bounds, interleaved into 63-bit Morton codes and sorted; every node then splits its run
//! of codes where the highest differing bit flips, down to single primitives, and boxes
//! are fitted bottom-up. On the way up, a subtree of at most `max_leaf_size` primitives
//! becomes one leaf where the SAH says a leaf is cheaper (the usual LBVH leaf collapse),
//! a leaf costing a step per test block as in the binned builder, so that triangle packs
//! fill; a run that fits one block is a leaf at once. Fast and parallel, but the splits
//! themselves are blind to surface area.

use super::stitch::NodeBlock;
use super::BuildPrims;
use crate::accel::bvh::{Node, MAX_DEPTH};
use crate::math::{Aabb, Vec3};
use rayon::prelude::*;

const BITS_PER_AXIS: u32 = 21;

/// Builds over all of `prims`, writing the leaf order into `order`.
pub(super) fn build(
    prims: &BuildPrims,
    order: &mut [u32],
    max_leaf_size: usize,
    traversal_cost: f32,
    parallel_threshold: usize,
) -> Vec<Node> {
    let codes = morton_order(prims, order);
    let one_step_leaf = if traversal_cost >= 1.0 {
        prims.test_block.min(max_leaf_size)
    } else {
        0
    };
    let hierarchy = Hierarchy {
        prims,
        order,
        codes: &codes,
        max_leaf_size: max_leaf_size.max(1),
        traversal_cost,
        parallel_threshold: parallel_threshold.max(max_leaf_size),
        one_step_leaf,
    };
    hierarchy.block(0, codes.len(), 1).into_nodes()
}

/// Sorts `order` (build positions, `prims.bounds[order[i]]` the box of the i-th) by the
/// Morton codes of their centroids in the centroids' bounds, and returns the sorted codes.
pub(super) fn morton_order(prims: &BuildPrims, order: &mut [u32]) -> Vec<u64> {
    let centroids: Vec<Vec3> = (order.par_iter())
        .map(|&i| prims.bounds[i as usize].center())
        .collect();
    let centroid_bounds = centroids
        .par_iter()
        .fold(|| Aabb::EMPTY, |b, &c| b.union_point(c))
        .reduce(|| Aabb::EMPTY, |a, b| a.union(&b));
    let codes: Vec<u64> = (centroids.par_iter())
        .map(|&c| morton_code(c, &centroid_bounds))
        .collect();
    // A stable sort by code keeps equal codes in the order they came: the order does not
    // depend on threads.
    let (codes, sorted) = radix_sort(codes, order.to_vec());
    order.copy_from_slice(&sorted);
    codes
}

/// Sorts `keys` and their `values` alike by key, stably: least significant byte first,
/// one counting pass for all eight bytes, bytes where every key agrees skipped. About a
/// quarter of a comparison sort's time on a million codes.
fn radix_sort(mut keys: Vec<u64>, mut values: Vec<u32>) -> (Vec<u64>, Vec<u32>) {
    let n = keys.len();
    let mut counts = vec![[0usize; 256]; 8];
    for &k in &keys {
        for (byte, count) in counts.iter_mut().enumerate() {
            count[(k >> (8 * byte)) as usize & 0xff] += 1;
        }
    }
    let (mut keys_out, mut values_out) = (vec![0u64; n], vec![0u32; n]);
    for (byte, count) in counts.iter().enumerate() {
        if count.contains(&n) {
            continue;
        }
        let mut next = [0usize; 256];
        let mut sum = 0;
        for (slot, &c) in next.iter_mut().zip(count) {
            *slot = sum;
            sum += c;
        }
        for (&k, &v) in keys.iter().zip(&values) {
            let d = (k >> (8 * byte)) as usize & 0xff;
            keys_out[next[d]] = k;
            values_out[next[d]] = v;
            next[d] += 1;
        }
        std::mem::swap(&mut keys, &mut keys_out);
        std::mem::swap(&mut values, &mut values_out);
    }
    (keys, values)
}

/// The Morton code of `p`'s cell in a 2²¹-per-axis grid over `bounds`.
fn morton_code(p: Vec3, bounds: &Aabb) -> u64 {
    let cells = (1u32 << BITS_PER_AXIS) as f32;
    let extent = bounds.extent();
    let mut code = 0;
    for axis in 0..3 {
        let t = if extent[axis] > 0.0 {
            (p[axis] - bounds.min[axis]) / extent[axis]
        } else {
            0.0
        };
        // The float-to-int cast saturates (and maps NaN to 0), so every cell is in range.
        let q = ((t * cells) as u32).min((1 << BITS_PER_AXIS) - 1);
        code |= spread_bits(q) << (2 - axis);
    }
    code
}

/// Moves bit i of the 21-bit `x` to bit 3i.
fn spread_bits(x: u32) -> u64 {
    let mut x = x as u64 & 0x1f_ffff;
    x = (x | x << 32) & 0x001f_0000_0000_ffff;
    x = (x | x << 16) & 0x001f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}

struct Hierarchy<'a> {
    prims: &'a BuildPrims,
    order: &'a [u32],
    codes: &'a [u64],
    max_leaf_size: usize,
    traversal_cost: f32,
    /// At least `max_leaf_size`, so collapsing never crosses a parallel split.
    parallel_threshold: usize,
    /// Runs of at most this many primitives are leaves without a look at their subtree:
    /// those that fit one test step, where a node costs at least a step (else 0).
    one_step_leaf: usize,
}

impl Hierarchy<'_> {
    /// Where the run `codes[lo..hi]` splits, or `None` for a leaf.
    fn split(&self, lo: usize, hi: usize, depth: usize) -> Option<usize> {
        let n = hi - lo;
        if n == 1 || depth >= MAX_DEPTH - 1 {
            return None;
        }
        let (first, last) = (self.codes[lo], self.codes[hi - 1]);
        if first == last {
            // One cell: no bit tells them apart, so halve the run.
            return Some(lo + n / 2);
        }
        // The codes share every bit above the highest differing one, and are sorted, so
        // those with that bit clear come first.
        let bit = 63 - (first ^ last).leading_zeros();
        Some(lo + self.codes[lo..hi].partition_point(|c| c >> bit & 1 == 0))
    }

    fn leaf(&self, lo: usize, hi: usize) -> Node {
        let bounds = self.order[lo..hi]
            .iter()
            .fold(Aabb::EMPTY, |b, &i| b.union(&self.prims.bounds[i as usize]));
        Node::leaf(bounds, lo as u32, hi - lo)
    }

    fn block(&self, lo: usize, hi: usize, depth: usize) -> NodeBlock {
        if hi - lo <= self.parallel_threshold {
            let mut nodes = Vec::with_capacity(2 * (hi - lo));
            nodes.push(Node::leaf(Aabb::EMPTY, 0, 0));
            self.subdivide(&mut nodes, 0, lo, hi, depth);
            nodes.shrink_to_fit();
            return NodeBlock::Serial(nodes);
        }
        let Some(mid) = self.split(lo, hi, depth) else {
            return NodeBlock::leaf(self.leaf(lo, hi));
        };
        let (left, right) = rayon::join(
            || self.block(lo, mid, depth + 1),
            || self.block(mid, hi, depth + 1),
        );
        let bounds = left.root().bounds().union(&right.root().bounds());
        NodeBlock::split(Node::interior(bounds, 0), left, right)
    }

    /// Fills `nodes[index]` for `lo..hi`, children first, and returns its box and SAH cost
    /// (unnormalised: area-weighted, in units of one primitive test).
    fn subdivide(
        &self,
        nodes: &mut Vec<Node>,
        index: usize,
        lo: usize,
        hi: usize,
        depth: usize,
    ) -> (Aabb, f32) {
        let n = hi - lo;
        let leaf = |nodes: &mut Vec<Node>| {
            nodes[index] = self.leaf(lo, hi);
            let bounds = nodes[index].bounds();
            (bounds, bounds.surface_area() * self.prims.leaf_cost(n))
        };
        // A run that fits one test step is the collapse's answer without its subtree:
        // the leaf costs its area once, a split at least the node's area again.
        if n <= self.one_step_leaf {
            return leaf(nodes);
        }
        let Some(mid) = self.split(lo, hi, depth) else {
            return leaf(nodes);
        };
        let left = nodes.len();
        let placeholder = Node::leaf(Aabb::EMPTY, 0, 0);
        nodes.extend([placeholder, placeholder]);
        let (bl, cl) = self.subdivide(nodes, left, lo, mid, depth + 1);
        let (br, cr) = self.subdivide(nodes, left + 1, mid, hi, depth + 1);
        let bounds = bl.union(&br);
        let area = bounds.surface_area();
        let cost = self.traversal_cost * area + cl + cr;
        if n <= self.max_leaf_size && area * self.prims.leaf_cost(n) <= cost {
            // The subtree is everything appended since its children: drop it for one leaf.
            nodes.truncate(left);
            return leaf(nodes);
        }
        nodes[index] = Node::interior(bounds, left as u32);
        (bounds, cost)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Boxes of a few thousand small triangles scattered in clumps, a tenth of them
    /// flat or points (zero-area boxes), for `test_block` primitives a step.
    fn clumped_boxes(test_block: usize) -> BuildPrims {
        let mut state = 11u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let bounds = (0..3000)
            .map(|i| {
                let clump = Vec3::new((i % 7) as f32, (i % 5) as f32, (i % 3) as f32) * 10.0;
                let min = clump + Vec3::new(next(), next(), next()) * 3.0;
                let size = if i % 10 == 0 {
                    Vec3::ZERO
                } else {
                    Vec3::new(next(), next(), next()) * 0.2
                };
                Aabb::new(min, min + size)
            })
            .collect();
        BuildPrims {
            bounds,
            test_block,
            triangles: Vec::new(),
        }
    }

    fn nodes_with(prims: &BuildPrims, one_step_leaf: usize) -> Vec<Node> {
        let mut order: Vec<u32> = (0..prims.bounds.len() as u32).collect();
        let codes = morton_order(prims, &mut order);
        let hierarchy = Hierarchy {
            prims,
            order: &order,
            codes: &codes,
            max_leaf_size: 8,
            traversal_cost: 1.0,
            parallel_threshold: usize::MAX,
            one_step_leaf,
        };
        hierarchy.block(0, codes.len(), 1).into_nodes()
    }

    /// The shortcut for runs that fit one test step makes the leaves the SAH collapse
    /// makes of their subtrees, node for node.
    #[test]
    fn one_step_runs_are_the_collapses_own_leaves() {
        let prims = clumped_boxes(4);
        assert_eq!(nodes_with(&prims, 4), nodes_with(&prims, 0));
    }

    /// Leaves cost a step per test block, so triangle packs of four fill: the mean leaf
    /// holds well over two triangles (1.6 when the collapse counted every triangle as a
    /// step), and a primitive a step keeps smaller leaves.
    #[test]
    fn triangle_packs_fill() {
        let mean_leaf = |prims: &BuildPrims| {
            let nodes = nodes_with(prims, prims.test_block);
            let leaves = nodes.iter().filter(|n| n.is_leaf()).count();
            prims.bounds.len() as f64 / leaves as f64
        };
        let (packs, singles) = (mean_leaf(&clumped_boxes(4)), mean_leaf(&clumped_boxes(1)));
        assert!(packs > 3.0, "mean leaf {packs:.2} with packs of four");
        assert!(singles < packs - 1.0, "mean leaf {singles:.2} one a step");
    }

    /// The radix sort orders as a stable comparison sort does, equal keys included.
    #[test]
    fn radix_sort_is_a_stable_sort() {
        let mut state = 7u64;
        let keys: Vec<u64> = (0..5000)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                // Few distinct values in the high bytes, so ties and skipped bytes occur.
                (state >> 61) << 40 | (state >> 33) & 0xff_ff
            })
            .collect();
        let values: Vec<u32> = (0..keys.len() as u32).rev().collect();
        let mut expected: Vec<(u64, u32)> =
            keys.iter().copied().zip(values.iter().copied()).collect();
        expected.sort_by_key(|p| p.0);
        let (k, v) = radix_sort(keys, values);
        let got: Vec<(u64, u32)> = k.into_iter().zip(v).collect();
        assert_eq!(got, expected);
        assert_eq!(radix_sort(vec![], vec![]), (vec![], vec![]));
    }

    #[test]
    fn spread_bits_interleaves() {
        for x in [0u32, 1, 2, 0x15_5555, 0x1f_ffff, 12345] {
            let spread = spread_bits(x);
            for bit in 0..21 {
                assert_eq!(
                    spread >> (3 * bit) & 1,
                    (x >> bit & 1) as u64,
                    "{x:#x} bit {bit}"
                );
            }
            assert_eq!(spread.count_ones(), x.count_ones());
        }
    }

    #[test]
    fn morton_codes_order_cells_along_a_z_curve() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        assert_eq!(morton_code(Vec3::ZERO, &b), 0);
        assert_eq!(morton_code(Vec3::ONE, &b), (1 << 63) - 1);
        // x is the highest bit of each triple.
        assert!(
            morton_code(Vec3::new(0.6, 0.0, 0.0), &b) > morton_code(Vec3::new(0.4, 0.9, 0.9), &b)
        );
    }
}
