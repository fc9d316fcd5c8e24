//! PLOC, parallel locally-ordered clustering (Meister & Bittner 2018): the primitives,
//! sorted by the Morton codes of their centroids, start as clusters; every round, each
//! cluster finds the cluster within `radius` places of it in that order whose union with
//! it has the smallest surface area, mutual nearest neighbours merge into a node, and the
//! survivors close ranks in order. Bottom up, so the SAH cost of leaving a subtree of at
//! most `max_leaf_size` primitives as one leaf is known when it is made (the leaves are
//! collapsed as LBVH's are).
//!
//! As in PLOC++ (Benthin et al. 2022), the first clusters are not single primitives but
//! the LBVH's subtrees of at most as many primitives as a leaf tests in one step (four
//! triangles): the SAH makes each of them one leaf whatever their order, and the rounds
//! start from a third of the clusters (a million triangles: 1.06 M → 0.36 M).
//!
//! Every step is a function of the cluster order alone (the LBVH cut of the codes; the
//! neighbours' distances, ties to the lower position; the merges numbered by a prefix sum
//! over fixed chunks), so the tree does not depend on the thread count. Distances with
//! ties broken by position order the pairs totally, so the globally nearest pair is
//! always mutual and every round merges.

use super::lbvh::morton_order;
use super::prim_ref::SimdBox;
use super::stitch::NodeBlock;
use super::BuildPrims;
use crate::accel::bvh::{Node, MAX_DEPTH};
use crate::math::Aabb;
use rayon::prelude::*;

/// Clusters per parallel task: fixed, so the work split never shapes the tree, and large
/// against the radius, so a chunk rarely reads its neighbours' clusters.
const CHUNK: usize = 1 << 13;
const NONE: u32 = u32::MAX;
/// What a new node's slot holds until its round writes it.
const PLACEHOLDER: Cluster = Cluster {
    bounds: SimdBox::EMPTY,
    children: [NONE; 2],
    count: 0,
    height: 0,
    leaf: true,
    cost: 0.0,
};
/// Pre-clusters per task that makes their nodes.
const PRECLUSTER_CHUNK: usize = 1 << 12;

pub(super) struct Ploc {
    pub radius: usize,
    pub max_leaf_size: usize,
    pub traversal_cost: f32,
    pub parallel_threshold: usize,
}

/// A node of the agglomerative tree. Nodes `0..n` are the primitives in Morton order,
/// made when asked for (`primitive`); each merge appends one, numbered from `n`, whose
/// children are earlier nodes.
#[derive(Clone, Copy)]
struct Cluster {
    bounds: SimdBox,
    children: [u32; 2],
    /// Primitives below.
    count: u32,
    /// Levels of the tree as it will be written (a collapsed subtree is one level).
    height: u32,
    /// Whether the subtree becomes one leaf (the SAH prefers it, or it is one primitive).
    leaf: bool,
    /// The subtree's SAH cost, area-weighted and unnormalised, as written.
    cost: f32,
}

impl Ploc {
    /// Builds over all of `prims`, writing the leaf order into `order`.
    pub(super) fn build(&self, prims: &BuildPrims, order: &mut [u32]) -> Vec<Node> {
        let codes = morton_order(prims, order);
        let sorted = order.to_vec();
        let clusters = self.cluster(prims, &sorted, &codes);
        let writer = Writer {
            ploc: self,
            prims,
            clusters: &clusters,
            sorted: &sorted,
        };
        let root = (sorted.len() + clusters.len()) as u32 - 1;
        writer.block(root, 0, 1, order).into_nodes()
    }

    /// The agglomerative tree over the primitives in Morton order (`sorted`, their codes
    /// `codes`), its root last.
    fn cluster(&self, prims: &BuildPrims, sorted: &[u32], codes: &[u64]) -> Vec<Cluster> {
        let n = sorted.len();
        // The merged nodes, n on (the primitives are the nodes below n, made on demand).
        let mut clusters: Vec<Cluster> = Vec::with_capacity(n - 1);
        // Pre-clusters: the LBVH subtrees of at most `group` primitives, each of which
        // the SAH makes one leaf anyway (a leaf tests `group` of them in one step), so the
        // rounds start from them rather than from single primitives.
        let group = self.precluster_size(prims);
        let ranges = lbvh_cut(codes, group);
        // Range r over [lo, hi) makes hi - lo - 1 nodes, so its first is n + lo - r.
        let made: Vec<Vec<Cluster>> = (ranges.par_chunks(PRECLUSTER_CHUNK).enumerate())
            .map(|(k, chunk)| {
                let (lo, hi) = (chunk[0].0, chunk[chunk.len() - 1].1);
                let mut nodes = Vec::with_capacity((hi - lo) as usize - chunk.len());
                let first = n as u32 + lo - (k * PRECLUSTER_CHUNK) as u32;
                for &(lo, hi) in chunk {
                    self.small_tree(prims, sorted, codes, lo, hi, first, &mut nodes);
                }
                nodes
            })
            .collect();
        for nodes in made {
            clusters.extend(nodes);
        }
        let mut active: Vec<u32> = (ranges.par_iter().enumerate())
            .map(|(r, &(lo, hi))| {
                if hi - lo == 1 {
                    lo
                } else {
                    n as u32 + hi - 2 - r as u32
                }
            })
            .collect();
        let mut boxes: Vec<SimdBox> = (active.par_iter())
            .map(|&c| node(prims, sorted, &clusters, c).bounds)
            .collect();
        let radius = self.radius.max(1);
        while active.len() > 1 {
            let mut nearest = vec![NONE; active.len()];
            (nearest.par_chunks_mut(NEAREST_CHUNK).enumerate())
                .for_each(|(k, out)| nearest_in_chunk(&boxes, radius, k * NEAREST_CHUNK, out));
            if !nearest
                .iter()
                .enumerate()
                .any(|(i, &j)| is_merge(&nearest, i, j))
            {
                // Only a NaN box can make the distances asymmetric; merge the first two
                // clusters so that every round makes progress.
                (nearest[0], nearest[1]) = (1, 0);
            }
            // Per chunk: merges and survivors; their prefix sums place each chunk's new
            // nodes and survivors, which the chunks then write in parallel.
            let counts: Vec<(usize, usize)> = (nearest.par_chunks(CHUNK).enumerate())
                .map(|(k, chunk)| {
                    let base = k * CHUNK;
                    let (mut merges, mut survivors) = (0, 0);
                    for (offset, &j) in chunk.iter().enumerate() {
                        let i = base + offset;
                        if is_merge(&nearest, i, j) {
                            merges += 1;
                            survivors += 1;
                        } else if nearest[j as usize] as usize != i {
                            survivors += 1;
                        }
                    }
                    (merges, survivors)
                })
                .collect();
            let merges: usize = counts.iter().map(|c| c.0).sum();
            let survivors: usize = counts.iter().map(|c| c.1).sum();
            let old = clusters.len();
            clusters.par_extend(rayon::iter::repeat_n(PLACEHOLDER, merges));
            let (before, made) = clusters.split_at_mut(old);
            let mut next_active = vec![0u32; survivors];
            let mut next_boxes = vec![SimdBox::EMPTY; survivors];
            let made = split_by(made, counts.iter().map(|c| c.0));
            let kept_ids = split_by(&mut next_active, counts.iter().map(|c| c.1));
            let kept_boxes = split_by(&mut next_boxes, counts.iter().map(|c| c.1));
            let mut first_id = (n + old) as u32;
            let first_ids: Vec<u32> = (counts.iter())
                .map(|c| {
                    let id = first_id;
                    first_id += c.0 as u32;
                    id
                })
                .collect();
            let before = &*before;
            (made
                .into_par_iter()
                .zip(kept_ids)
                .zip(kept_boxes)
                .zip(first_ids))
            .enumerate()
            .for_each(|(k, (((made, ids), kept_boxes), first_id))| {
                let base = k * CHUNK;
                let end = (base + CHUNK).min(nearest.len());
                let (mut m, mut kept) = (0, 0);
                for i in base..end {
                    let j = nearest[i];
                    if is_merge(&nearest, i, j) {
                        let (a, b) = (active[i], active[j as usize]);
                        let l = node(prims, sorted, before, a);
                        let r = node(prims, sorted, before, b);
                        made[m] = self.merge(prims, &l, &r, a, b);
                        ids[kept] = first_id + m as u32;
                        kept_boxes[kept] = made[m].bounds;
                        m += 1;
                        kept += 1;
                    } else if nearest[j as usize] as usize != i {
                        ids[kept] = active[i];
                        kept_boxes[kept] = boxes[i];
                        kept += 1;
                    }
                }
            });
            active = next_active;
            boxes = next_boxes;
        }
        clusters
    }

    /// Primitives per pre-cluster at most: as many as a leaf tests in one step (and no
    /// more than a leaf holds), so that the SAH would make each of them one leaf.
    fn precluster_size(&self, prims: &BuildPrims) -> u32 {
        prims.test_block.min(self.max_leaf_size).max(1) as u32
    }

    /// The LBVH subtree over the primitives `lo..hi` (at most a few), its nodes appended
    /// to `out` in post order, numbered from `first`; returns its root.
    #[allow(clippy::too_many_arguments)]
    fn small_tree(
        &self,
        prims: &BuildPrims,
        sorted: &[u32],
        codes: &[u64],
        lo: u32,
        hi: u32,
        first: u32,
        out: &mut Vec<Cluster>,
    ) -> u32 {
        if hi - lo == 1 {
            return lo;
        }
        let mid = lbvh_split(codes, lo, hi);
        let a = self.small_tree(prims, sorted, codes, lo, mid, first, out);
        let b = self.small_tree(prims, sorted, codes, mid, hi, first, out);
        let get = |c: u32| {
            if (c as usize) < sorted.len() {
                primitive(prims, sorted, c)
            } else {
                out[(c - first) as usize]
            }
        };
        let node = self.merge(prims, &get(a), &get(b), a, b);
        out.push(node);
        first + out.len() as u32 - 1
    }

    /// The node over clusters `a` (`l`) and `b` (`r`), a leaf where the SAH prefers one.
    fn merge(&self, prims: &BuildPrims, l: &Cluster, r: &Cluster, a: u32, b: u32) -> Cluster {
        let bounds = l.bounds.union(&r.bounds);
        let count = l.count + r.count;
        let a_area = bounds.surface_area();
        let split_cost = self.traversal_cost * a_area + l.cost + r.cost;
        let leaf_cost = a_area * prims.leaf_cost(count as usize);
        let leaf = count as usize <= self.max_leaf_size && leaf_cost <= split_cost;
        Cluster {
            bounds,
            children: [a, b],
            count,
            height: if leaf { 1 } else { 1 + l.height.max(r.height) },
            leaf,
            cost: if leaf { leaf_cost } else { split_cost },
        }
    }
}

/// Node `c` of the agglomerative tree: primitive `sorted[c]` below `sorted.len()`, then
/// the merged nodes.
#[inline(always)]
fn node(prims: &BuildPrims, sorted: &[u32], merged: &[Cluster], c: u32) -> Cluster {
    match (c as usize).checked_sub(sorted.len()) {
        None => primitive(prims, sorted, c),
        Some(k) => merged[k],
    }
}

/// The leaf over the primitive at Morton position `c`.
#[inline(always)]
fn primitive(prims: &BuildPrims, sorted: &[u32], c: u32) -> Cluster {
    let b = &prims.bounds[sorted[c as usize] as usize];
    let bounds = SimdBox {
        min: b.min.into(),
        max: b.max.into(),
    };
    Cluster {
        bounds,
        children: [NONE; 2],
        count: 1,
        height: 1,
        leaf: true,
        cost: bounds.surface_area() * prims.leaf_cost(1),
    }
}

/// Where LBVH splits the run of codes `lo..hi` (at least two): where the highest bit in
/// which its first and last codes differ flips, or in the middle of equal codes.
fn lbvh_split(codes: &[u64], lo: u32, hi: u32) -> u32 {
    let (first, last) = (codes[lo as usize], codes[hi as usize - 1]);
    if first == last {
        return lo + (hi - lo) / 2;
    }
    let bit = 63 - (first ^ last).leading_zeros();
    lo + codes[lo as usize..hi as usize].partition_point(|c| c >> bit & 1 == 0) as u32
}

/// The maximal subtrees of the LBVH over `codes` that hold at most `group` primitives,
/// as ranges in order: a function of the codes alone.
fn lbvh_cut(codes: &[u64], group: u32) -> Vec<(u32, u32)> {
    fn cut(codes: &[u64], lo: u32, hi: u32, group: u32, out: &mut Vec<(u32, u32)>) {
        if hi - lo <= group {
            out.push((lo, hi));
        } else {
            let mid = lbvh_split(codes, lo, hi);
            cut(codes, lo, mid, group, out);
            cut(codes, mid, hi, group, out);
        }
    }
    fn parallel(codes: &[u64], lo: u32, hi: u32, group: u32) -> Vec<(u32, u32)> {
        if hi - lo <= 1 << 16 {
            let mut out = Vec::with_capacity(((hi - lo) / group.max(2)) as usize * 2);
            cut(codes, lo, hi, group, &mut out);
            return out;
        }
        let mid = lbvh_split(codes, lo, hi);
        let (mut left, right) = rayon::join(
            || parallel(codes, lo, mid, group),
            || parallel(codes, mid, hi, group),
        );
        left.extend(right);
        left
    }
    parallel(codes, 0, codes.len() as u32, group.max(1))
}

/// `slice` cut into consecutive pieces of the given lengths.
fn split_by<T>(mut slice: &mut [T], lengths: impl Iterator<Item = usize>) -> Vec<&mut [T]> {
    let mut pieces = Vec::new();
    for length in lengths {
        let (piece, rest) = std::mem::take(&mut slice).split_at_mut(length);
        pieces.push(piece);
        slice = rest;
    }
    pieces
}

/// Whether cluster `i`, whose nearest neighbour is `j`, is the first of a mutual pair
/// (and so becomes the merged node; `j` leaves the list).
fn is_merge(nearest: &[u32], i: usize, j: u32) -> bool {
    (i as u32) < j && nearest[j as usize] as usize == i
}

/// The distance between two clusters: the surface area of their union, `f32::MAX` where
/// it is not finite (so that every pair stays below the `INFINITY` of "no candidate").
#[cfg(test)]
fn distance(a: &SimdBox, b: &SimdBox) -> f32 {
    union_area(
        a.min.to_array(),
        a.max.to_array(),
        b.min.to_array(),
        b.max.to_array(),
    )
}

/// `distance` of the boxes `a_min..a_max` and `b_min..b_max`, as the SIMD boxes compute
/// it (their `min`, `max` and `surface_area`, lane for lane), in plain arithmetic.
#[inline(always)]
fn union_area(a_min: [f32; 3], a_max: [f32; 3], b_min: [f32; 3], b_max: [f32; 3]) -> f32 {
    let e = |k: usize| {
        let lo = if a_min[k] < b_min[k] {
            a_min[k]
        } else {
            b_min[k]
        };
        let hi = if a_max[k] > b_max[k] {
            a_max[k]
        } else {
            b_max[k]
        };
        hi - lo
    };
    let (x, y, z) = (e(0), e(1), e(2));
    let d = 2.0 * (x * y + y * z + z * x);
    if d < f32::INFINITY {
        d
    } else {
        f32::MAX
    }
}

/// Clusters per nearest-neighbour task: the pair distances of one task fit in L2.
const NEAREST_CHUNK: usize = 1 << 10;

/// The nearest neighbours of clusters `start .. start + out.len()` within `radius`
/// places. Each pair's distance is computed once, a row per offset (straight-line code),
/// then every cluster takes the least of its candidates, in increasing position so that
/// a strict `<` keeps the lower one on a tie.
fn nearest_in_chunk(boxes: &[SimdBox], radius: usize, start: usize, out: &mut [u32]) {
    let m = boxes.len();
    let end = start + out.len();
    let first = start.saturating_sub(radius);
    let span = end - first;
    // The boxes this chunk reads, one array per bound and axis, so that a row of
    // distances is the same arithmetic on consecutive lanes (vectorised by the compiler).
    let read_end = (end + radius).min(m);
    let width = read_end - first;
    let mut soa = vec![0.0f32; 6 * width];
    {
        let (min, max) = soa.split_at_mut(3 * width);
        for (k, b) in boxes[first..read_end].iter().enumerate() {
            for axis in 0..3 {
                min[axis * width + k] = b.min[axis];
                max[axis * width + k] = b.max[axis];
            }
        }
    }
    let axis = |bound: usize, axis: usize| &soa[(3 * bound + axis) * width..][..width];
    let (min_x, min_y, min_z) = (axis(0, 0), axis(0, 1), axis(0, 2));
    let (max_x, max_y, max_z) = (axis(1, 0), axis(1, 1), axis(1, 2));
    // distances[(o - 1) * span + (i - first)]: from cluster i to cluster i + o.
    let mut distances = vec![f32::INFINITY; radius * span];
    for o in 1..=radius {
        let last = end.min(m.saturating_sub(o));
        if last <= first {
            continue;
        }
        let len = last - first;
        let row = &mut distances[(o - 1) * span..][..len];
        let (ax, bx) = (&min_x[..len], &min_x[o..][..len]);
        let (ay, by) = (&min_y[..len], &min_y[o..][..len]);
        let (az, bz) = (&min_z[..len], &min_z[o..][..len]);
        let (cx, dx) = (&max_x[..len], &max_x[o..][..len]);
        let (cy, dy) = (&max_y[..len], &max_y[o..][..len]);
        let (cz, dz) = (&max_z[..len], &max_z[o..][..len]);
        for k in 0..len {
            row[k] = union_area(
                [ax[k], ay[k], az[k]],
                [cx[k], cy[k], cz[k]],
                [bx[k], by[k], bz[k]],
                [dx[k], dy[k], dz[k]],
            );
        }
    }
    let len = out.len();
    let mut best = vec![f32::INFINITY; len];
    out.fill(NONE);
    // From `k_from` on, cluster `start + k` meets the candidate `j_from + (k - k_from)`,
    // whose distance is `row_from + (k - k_from)` in offset `o`'s row.
    let mut take = |o: usize, k_from: usize, row_from: usize, j_from: usize| {
        let row = &distances[(o - 1) * span + row_from..];
        let (best, out) = (&mut best[k_from..], &mut out[k_from..]);
        for (k, ((&d, b), n)) in row.iter().zip(best).zip(out).enumerate() {
            if d < *b {
                *b = d;
                *n = (j_from + k) as u32;
            }
        }
    };
    // Left candidates j = i - o (ascending j: o from radius down), where j >= first.
    for o in (1..=radius).rev() {
        let k_from = (first + o).saturating_sub(start).min(len);
        let j_from = start + k_from - o;
        take(o, k_from, j_from - first, j_from);
    }
    // Right candidates j = i + o; rows past the last cluster hold INFINITY.
    for o in 1..=radius {
        take(o, 0, start - first, start + o);
    }
}
/// Writes the agglomerative tree as the builders' node array, depth first as a serial
/// top-down build would, large subtrees on separate threads and stitched.
struct Writer<'a> {
    ploc: &'a Ploc,
    prims: &'a BuildPrims,
    clusters: &'a [Cluster],
    /// Build positions in Morton order: cluster `i < n` is primitive `sorted[i]`.
    sorted: &'a [u32],
}

impl Writer<'_> {
    fn node(&self, c: u32) -> Cluster {
        node(self.prims, self.sorted, self.clusters, c)
    }

    /// The subtree of cluster `c` at `depth`, its primitives written into `order` (its
    /// slice of the leaf order, which starts at `offset`).
    fn block(&self, c: u32, offset: u32, depth: usize, order: &mut [u32]) -> NodeBlock {
        let cluster = &self.node(c);
        if cluster.count as usize <= self.ploc.parallel_threshold || self.ends_here(c, depth) {
            let mut nodes = Vec::with_capacity(cluster.count as usize / 2 + 1);
            nodes.push(Node::leaf(Aabb::EMPTY, 0, 0));
            self.write(&mut nodes, 0, c, offset, depth, order);
            return NodeBlock::Serial(nodes);
        }
        let [a, b] = cluster.children;
        let left_count = self.node(a).count;
        let (lo, hi) = order.split_at_mut(left_count as usize);
        let (left, right) = rayon::join(
            || self.block(a, offset, depth + 1, lo),
            || self.block(b, offset + left_count, depth + 1, hi),
        );
        NodeBlock::split(Node::interior(cluster.bounds.to_aabb(), 0), left, right)
    }

    /// Whether cluster `c` at `depth` is written as a leaf or as a balanced subtree.
    fn ends_here(&self, c: u32, depth: usize) -> bool {
        let cluster = &self.node(c);
        cluster.leaf || self.must_balance(cluster, depth)
    }

    /// Whether the subtree is too tall for the levels left below `depth` and must be
    /// rewritten balanced now, while a balanced tree still fits. The balanced tree needs
    /// fewer levels than the parent's had, so it always fits where this first says so,
    /// and at the root (at most 33 levels for 2³² primitives) it never does.
    fn must_balance(&self, cluster: &Cluster, depth: usize) -> bool {
        let levels_left = MAX_DEPTH - depth;
        cluster.height as usize > levels_left
            && balanced_levels(cluster.count as usize, self.ploc.max_leaf_size) + 1 >= levels_left
    }

    /// Fills `nodes[index]` with the subtree of cluster `c`, its descendants appended.
    fn write(
        &self,
        nodes: &mut Vec<Node>,
        index: usize,
        c: u32,
        offset: u32,
        depth: usize,
        order: &mut [u32],
    ) {
        let cluster = &self.node(c);
        if cluster.leaf {
            self.gather(c, order);
            nodes[index] = Node::leaf(cluster.bounds.to_aabb(), offset, order.len());
            return;
        }
        if self.must_balance(cluster, depth) {
            self.gather(c, order);
            self.balanced(nodes, index, offset, order);
            return;
        }
        let [a, b] = cluster.children;
        let left = nodes.len();
        nodes[index] = Node::interior(cluster.bounds.to_aabb(), left as u32);
        let placeholder = Node::leaf(Aabb::EMPTY, 0, 0);
        nodes.extend([placeholder, placeholder]);
        let left_count = self.node(a).count;
        let (lo, hi) = order.split_at_mut(left_count as usize);
        self.write(nodes, left, a, offset, depth + 1, lo);
        self.write(nodes, left + 1, b, offset + left_count, depth + 1, hi);
    }

    /// Writes the primitives below cluster `c`, left to right, into `order`.
    fn gather(&self, c: u32, order: &mut [u32]) {
        if order.len() <= self.ploc.max_leaf_size.max(1) {
            // A leaf's: recursion as deep as its few primitives at most.
            let mut k = 0;
            self.gather_small(c, order, &mut k);
            return;
        }
        // A subtree rewritten balanced may be a chain as long as its primitives.
        let n = self.sorted.len() as u32;
        let mut stack = vec![c];
        let mut k = 0;
        while let Some(c) = stack.pop() {
            if c < n {
                order[k] = self.sorted[c as usize];
                k += 1;
            } else {
                let [a, b] = self.node(c).children;
                stack.extend([b, a]);
            }
        }
        debug_assert_eq!(k, order.len());
    }

    fn gather_small(&self, c: u32, order: &mut [u32], k: &mut usize) {
        if (c as usize) < self.sorted.len() {
            order[*k] = self.sorted[c as usize];
            *k += 1;
        } else {
            let [a, b] = self.node(c).children;
            self.gather_small(a, order, k);
            self.gather_small(b, order, k);
        }
    }

    /// A balanced subtree over `order` in its order: halves down to leaves of at most
    /// `max_leaf_size`.
    fn balanced(&self, nodes: &mut Vec<Node>, index: usize, offset: u32, order: &[u32]) {
        let bounds =
            (order.iter()).fold(Aabb::EMPTY, |b, &i| b.union(&self.prims.bounds[i as usize]));
        if order.len() <= self.ploc.max_leaf_size.max(1) {
            nodes[index] = Node::leaf(bounds, offset, order.len());
            return;
        }
        let left = nodes.len();
        nodes[index] = Node::interior(bounds, left as u32);
        let placeholder = Node::leaf(Aabb::EMPTY, 0, 0);
        nodes.extend([placeholder, placeholder]);
        let mid = order.len().div_ceil(2);
        self.balanced(nodes, left, offset, &order[..mid]);
        self.balanced(nodes, left + 1, offset + mid as u32, &order[mid..]);
    }
}

/// The levels of the balanced tree `Writer::balanced` makes over `n` primitives.
fn balanced_levels(n: usize, max_leaf_size: usize) -> usize {
    let (mut n, mut levels) = (n, 1);
    while n > max_leaf_size.max(1) {
        n = n.div_ceil(2);
        levels += 1;
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    fn unit_box(x: f32) -> SimdBox {
        SimdBox {
            min: Vec3::new(x, 0.0, 0.0).into(),
            max: Vec3::new(x + 1.0, 1.0, 1.0).into(),
        }
    }

    /// Chunked pair-once search = every cluster scanning its window on its own.
    #[test]
    fn chunks_find_the_nearest_neighbours_of_a_plain_scan() {
        let xs = [
            0.0, 1.5, 1.6, 9.0, 9.0, 9.0, 20.0, 21.0, 40.0, 40.5, 41.0, 60.0, 61.0,
        ];
        let boxes: Vec<SimdBox> = xs.iter().map(|&x| unit_box(x)).collect();
        for radius in [1, 2, 3, 16] {
            let mut whole = vec![NONE; boxes.len()];
            nearest_in_chunk(&boxes, radius, 0, &mut whole);
            for chunk in [1, 2, 5] {
                let mut pieces = vec![NONE; boxes.len()];
                for (k, out) in pieces.chunks_mut(chunk).enumerate() {
                    nearest_in_chunk(&boxes, radius, k * chunk, out);
                }
                assert_eq!(pieces, whole, "radius {radius}, chunks of {chunk}");
            }
            for (i, &j) in whole.iter().enumerate() {
                let window = i.saturating_sub(radius)..=(i + radius).min(boxes.len() - 1);
                let best = (window.filter(|&k| k != i))
                    .min_by(|&a, &b| {
                        let d = |k: usize| distance(&boxes[i], &boxes[k]);
                        d(a).total_cmp(&d(b)).then(a.cmp(&b))
                    })
                    .unwrap();
                assert_eq!(j as usize, best, "radius {radius}, cluster {i}");
            }
        }
    }

    /// The plain arithmetic of the search is the SIMD boxes' own, NaN lanes included.
    #[test]
    fn union_area_is_the_simd_boxes_union_area() {
        let values = [
            -2.0,
            0.0,
            0.5,
            3.0,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        let mut k = 0usize;
        let mut next = || {
            k = (k * 7 + 3) % 1009;
            values[k % values.len()]
        };
        for _ in 0..500 {
            let mut v = [0.0f32; 12];
            v.iter_mut().for_each(|x| *x = next());
            let a = SimdBox {
                min: Vec3::new(v[0], v[1], v[2]).into(),
                max: Vec3::new(v[3], v[4], v[5]).into(),
            };
            let b = SimdBox {
                min: Vec3::new(v[6], v[7], v[8]).into(),
                max: Vec3::new(v[9], v[10], v[11]).into(),
            };
            let simd = a.union(&b).surface_area();
            let simd = if simd < f32::INFINITY { simd } else { f32::MAX };
            assert_eq!(distance(&a, &b).to_bits(), simd.to_bits(), "{v:?}");
        }
    }

    /// The cut covers the codes in order with LBVH subtrees of at most `group`, each as
    /// large as it can be: its parent subtree holds more than `group`.
    #[test]
    fn the_lbvh_cut_is_its_maximal_small_subtrees() {
        let mut state = 11u64;
        let mut codes: Vec<u64> = (0..3000)
            .map(|_| {
                state = (state.wrapping_mul(6364136223846793005)).wrapping_add(1);
                state >> 40
            })
            .collect();
        codes.extend([5, 5, 5, 5, 5, 5, 5]);
        codes.sort_unstable();
        // The LBVH's nodes, top down.
        fn nodes(codes: &[u64], lo: u32, hi: u32, out: &mut Vec<(u32, u32)>) {
            out.push((lo, hi));
            if hi - lo > 1 {
                let mid = lbvh_split(codes, lo, hi);
                nodes(codes, lo, mid, out);
                nodes(codes, mid, hi, out);
            }
        }
        let mut all = Vec::new();
        nodes(&codes, 0, codes.len() as u32, &mut all);
        for group in [1, 2, 4, 8] {
            let cut = lbvh_cut(&codes, group);
            assert_eq!(cut[0].0, 0);
            assert_eq!(cut[cut.len() - 1].1, codes.len() as u32);
            for pair in cut.windows(2) {
                assert_eq!(pair[0].1, pair[1].0, "group {group}: the ranges abut");
            }
            for &(lo, hi) in &cut {
                assert!(hi - lo <= group && all.contains(&(lo, hi)), "group {group}");
                let parent = all
                    .iter()
                    .filter(|&&(a, b)| a <= lo && hi <= b && b - a > hi - lo);
                assert!(parent
                    .map(|&(a, b)| b - a)
                    .min()
                    .is_none_or(|size| size > group));
            }
        }
    }

    #[test]
    fn balanced_levels_count_halvings() {
        assert_eq!(balanced_levels(1, 1), 1);
        assert_eq!(balanced_levels(2, 1), 2);
        assert_eq!(balanced_levels(5, 1), 4);
        assert_eq!(balanced_levels(8, 8), 1);
        assert_eq!(balanced_levels(9, 8), 2);
        assert_eq!(balanced_levels(1 << 32, 1), 33);
    }
}
