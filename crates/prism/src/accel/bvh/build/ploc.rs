//! PLOC, parallel locally-ordered clustering (Meister & Bittner 2018): the primitives,
//! sorted by the Morton codes of their centroids, start as one cluster each; every round,
//! each cluster finds the cluster within `radius` places of it in that order whose union
//! with it has the smallest surface area, mutual nearest neighbours merge into a node, and
//! the survivors close ranks in order. Bottom up, so the SAH cost of leaving a subtree of
//! at most `max_leaf_size` primitives as one leaf is known when it is made (the leaves
//! are collapsed as LBVH's are).
//!
//! Every step is a function of the cluster order alone (the neighbours' distances, ties
//! to the lower position; the merges numbered by a prefix sum over fixed chunks), so the
//! tree does not depend on the thread count. Distances with ties broken by position order
//! the pairs totally, so the globally nearest pair is always mutual and every round merges.

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

pub(super) struct Ploc {
    pub radius: usize,
    pub max_leaf_size: usize,
    pub traversal_cost: f32,
    pub parallel_threshold: usize,
}

/// A node of the agglomerative tree. Nodes `0..n` are the primitives in Morton order;
/// each merge appends one whose children are earlier nodes.
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
        morton_order(prims, order);
        let sorted = order.to_vec();
        let clusters = self.cluster(prims, &sorted);
        let writer = Writer {
            ploc: self,
            prims,
            clusters: &clusters,
            sorted: &sorted,
        };
        let root = clusters.len() as u32 - 1;
        writer.block(root, 0, 1, order).into_nodes()
    }

    /// The agglomerative tree over the primitives in Morton order (`sorted`), its root last.
    fn cluster(&self, prims: &BuildPrims, sorted: &[u32]) -> Vec<Cluster> {
        let n = sorted.len();
        let mut clusters: Vec<Cluster> = Vec::with_capacity(2 * n - 1);
        clusters.par_extend(sorted.par_iter().map(|&i| {
            let b = &prims.bounds[i as usize];
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
        }));
        let mut active: Vec<u32> = (0..n as u32).collect();
        let mut boxes: Vec<SimdBox> = clusters.iter().map(|c| c.bounds).collect();
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
            // Per chunk: merges, survivors; then each chunk's first new node id.
            let merges: Vec<usize> = (nearest.par_chunks(CHUNK).enumerate())
                .map(|(k, chunk)| {
                    let base = k * CHUNK;
                    (chunk.iter().enumerate())
                        .filter(|&(i, &j)| is_merge(&nearest, base + i, j))
                        .count()
                })
                .collect();
            let mut next = clusters.len() as u32;
            let first_ids: Vec<u32> = merges
                .iter()
                .map(|&m| {
                    let id = next;
                    next += m as u32;
                    id
                })
                .collect();
            let rounds: Vec<Round> = (nearest
                .par_chunks(CHUNK)
                .zip(first_ids.par_iter())
                .enumerate())
            .map(|(k, (chunk, &first_id))| {
                let base = k * CHUNK;
                let mut made = Vec::new();
                let mut kept = Vec::with_capacity(chunk.len());
                for (offset, &j) in chunk.iter().enumerate() {
                    let i = base + offset;
                    if is_merge(&nearest, i, j) {
                        let (a, b) = (active[i], active[j as usize]);
                        let merged = self.merge(prims, &clusters, a, b);
                        kept.push((first_id + made.len() as u32, merged.bounds));
                        made.push(merged);
                    } else if nearest[j as usize] as usize != i {
                        kept.push((active[i], boxes[i]));
                    }
                }
                (made, kept)
            })
            .collect();
            let survivors: usize = rounds.iter().map(|r| r.1.len()).sum();
            let (mut next_active, mut next_boxes) =
                (Vec::with_capacity(survivors), Vec::with_capacity(survivors));
            for (made, kept) in rounds {
                clusters.extend(made);
                for (id, b) in kept {
                    next_active.push(id);
                    next_boxes.push(b);
                }
            }
            active = next_active;
            boxes = next_boxes;
        }
        clusters
    }

    /// The node over clusters `a` and `b`, a leaf where the SAH prefers one.
    fn merge(&self, prims: &BuildPrims, clusters: &[Cluster], a: u32, b: u32) -> Cluster {
        let (l, r) = (&clusters[a as usize], &clusters[b as usize]);
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

/// One chunk's share of a round: the nodes it merged, and its surviving clusters with
/// their boxes, in order.
type Round = (Vec<Cluster>, Vec<(u32, SimdBox)>);

/// Whether cluster `i`, whose nearest neighbour is `j`, is the first of a mutual pair
/// (and so becomes the merged node; `j` leaves the list).
fn is_merge(nearest: &[u32], i: usize, j: u32) -> bool {
    (i as u32) < j && nearest[j as usize] as usize == i
}

/// The distance between two clusters: the surface area of their union, `f32::MAX` where
/// it is not finite (so that every pair stays below the `INFINITY` of "no candidate").
#[inline(always)]
fn distance(a: &SimdBox, b: &SimdBox) -> f32 {
    let d = a.union(b).surface_area();
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
    // distances[(o - 1) * span + (i - first)]: from cluster i to cluster i + o.
    let mut distances = vec![f32::INFINITY; radius * span];
    for o in 1..=radius {
        let last = end.min(m.saturating_sub(o));
        if last <= first {
            continue;
        }
        let row = &mut distances[(o - 1) * span..][..last - first];
        for ((d, a), b) in row.iter_mut().zip(&boxes[first..]).zip(&boxes[first + o..]) {
            *d = distance(a, b);
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
    /// The subtree of cluster `c` at `depth`, its primitives written into `order` (its
    /// slice of the leaf order, which starts at `offset`).
    fn block(&self, c: u32, offset: u32, depth: usize, order: &mut [u32]) -> NodeBlock {
        let cluster = &self.clusters[c as usize];
        if cluster.count as usize <= self.ploc.parallel_threshold || self.ends_here(c, depth) {
            let mut nodes = Vec::with_capacity(cluster.count as usize / 2 + 1);
            nodes.push(Node::leaf(Aabb::EMPTY, 0, 0));
            self.write(&mut nodes, 0, c, offset, depth, order);
            return NodeBlock::Serial(nodes);
        }
        let [a, b] = cluster.children;
        let left_count = self.clusters[a as usize].count;
        let (lo, hi) = order.split_at_mut(left_count as usize);
        let (left, right) = rayon::join(
            || self.block(a, offset, depth + 1, lo),
            || self.block(b, offset + left_count, depth + 1, hi),
        );
        NodeBlock::split(Node::interior(cluster.bounds.to_aabb(), 0), left, right)
    }

    /// Whether cluster `c` at `depth` is written as a leaf or as a balanced subtree.
    fn ends_here(&self, c: u32, depth: usize) -> bool {
        let cluster = &self.clusters[c as usize];
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
        let cluster = &self.clusters[c as usize];
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
        let left_count = self.clusters[a as usize].count;
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
                let [a, b] = self.clusters[c as usize].children;
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
            let [a, b] = self.clusters[c as usize].children;
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
