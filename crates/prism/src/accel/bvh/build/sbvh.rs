//! Spatial-split BVH (Stich, Friedrich & Dietrich 2009): top down, each node takes the
//! binned SAH's object split unless its two children overlap by more than `alpha` of the
//! root's area and either by at least `overlap` of the node's own (Embree's second test)
//! or with 0.3 of the node's references touching the overlap (slivers crossing it), in
//! nodes of at least 128 references; then a spatial split is also costed — the node's box
//! cut into slabs on each axis, every triangle cut into the slabs it crosses (chopped
//! binning), so that a plane between slabs sends each reference left, right, or, cut, to
//! both — and the cheaper one wins. Duplicated references are bounded by a budget, shared
//! out among the children by their reference counts (so the tree does not depend on which
//! side was built first or on which thread). Only triangles are cut; other primitives go
//! whole to the side of their centroid.
//!
//! The binning reads each reference once: a reference whose box lies in one slab goes
//! there whole; one that spans several is walked along the axis, each piece's box from
//! the triangle's corners in the slab and its sections by the slab's two planes, each
//! section computed once for the slabs on both sides (`triangle_cut.rs`; clipping the
//! triangle to every slab, twice per slab, was over half of the build).
//!
//! A cut reference's box is the box of the triangle's part within the slab, grown by the
//! sections' rounding and kept within the reference's box and the slab, whose face on the
//! plane stays exact, so the pieces of a triangle cover it: no hit is lost, and a ray
//! meeting two pieces finds the same primitive twice.

use super::binned::{truncate_lanes, BinnedSah};
use super::prim_ref::{PrimRef, SimdBox};
use super::stitch::NodeBlock;
use super::topdown::{extent_of, SplitRule, PARALLEL_PASS};
use super::triangle_cut::{bound_piece, AlongAxis};
use super::BuildPrims;
use crate::accel::bvh::{Node, MAX_DEPTH};
use crate::math::{Aabb, Vec3};
use glam::Vec3A;
use rayon::prelude::*;

pub(super) struct Sbvh {
    pub object: BinnedSah,
    pub bins: usize,
    pub traversal_cost: f32,
    /// The overlap of an object split's children, as a share of the root's area, above
    /// which a spatial split is costed too.
    pub alpha: f32,
    /// The overlap, as a share of the node's own area, below which no spatial split is
    /// costed even above `alpha` (Embree's second test), unless `CROWDED_OVERLAP` of the
    /// node's references touch the overlap: most nodes whose children overlap by a sliver
    /// gain little from a spatial split, and binning one costs as much as a worthwhile one.
    pub overlap: f32,
    pub parallel_threshold: usize,
}

/// The fewest references a node tries spatial splits at. Below, the greedy SAH's spatial
/// splits near the leaves gain nothing for the tree (the SAH cost of embree-bench's four
/// meshes fell 0.06–0.27 % without them, the sliver-crossed knot's stayed), while those
/// nodes were most of the ones binned spatially (10,523 of 11,046 on the bunny).
const MIN_SPATIAL_REFS: usize = 128;

/// Where a node's references go.
enum Decision {
    Leaf(Aabb, Vec<PrimRef>),
    Split {
        bounds: Aabb,
        sides: [(Vec<PrimRef>, usize); 2],
    },
}

/// A spatial split: the plane between slab `k - 1` and slab `k` on `axis`.
#[derive(Clone, Copy)]
struct SpatialSplit {
    axis: usize,
    k: usize,
    cost: f32,
}

/// The slabs of one node on the three axes: where slab borders lie, and which slab a
/// coordinate falls in (the one rule both binning and partitioning follow).
#[derive(Clone, Copy)]
struct Slabs {
    lo: Vec3A,
    width: Vec3A,
    /// Slabs per unit length; 0 on an axis the node is flat on (no slabs cut it).
    scale: Vec3A,
    /// The last slab's number, as a float.
    last: Vec3A,
    count: usize,
}

impl Slabs {
    fn new(bounds: &Aabb, count: usize) -> Slabs {
        let extent = Vec3A::from(bounds.extent());
        let scale = count as f32 / extent;
        Slabs {
            lo: bounds.min.into(),
            width: extent / count as f32,
            // Not NaN, not infinite, not for a flat extent.
            scale: Vec3A::select(
                extent.cmpgt(Vec3A::ZERO) & scale.is_finite_mask(),
                scale,
                Vec3A::ZERO,
            ),
            last: Vec3A::splat((count - 1) as f32),
            count,
        }
    }

    /// The slabs of a point on the three axes. The clamp keeps the maximum in the last
    /// slab and sends NaN to slab 0 (`max` returns its argument when a lane is NaN).
    #[inline(always)]
    fn of(&self, p: Vec3A) -> [usize; 3] {
        truncate_lanes(((p - self.lo) * self.scale).max(Vec3A::ZERO).min(self.last))
    }

    /// Whether the slabs cut `axis` at all.
    fn cuts(&self, axis: usize) -> bool {
        self.scale[axis] > 0.0
    }

    /// The border below slab `k`.
    #[inline(always)]
    fn plane(&self, axis: usize, k: usize) -> f32 {
        self.lo[axis] + k as f32 * self.width[axis]
    }
}

/// The spatial bins of one node: per axis and slab, the box of the pieces in it and how
/// many references start and end there.
#[derive(Clone)]
struct SlabBins {
    boxes: Vec<SimdBox>,
    entries: Vec<u32>,
    exits: Vec<u32>,
}

impl SlabBins {
    fn new(slabs: usize) -> SlabBins {
        SlabBins {
            boxes: vec![SimdBox::EMPTY; 3 * slabs],
            entries: vec![0; 3 * slabs],
            exits: vec![0; 3 * slabs],
        }
    }

    /// Unions and counts are exact, so chunks merge into the same bins in any order.
    fn merge(mut self, other: SlabBins) -> SlabBins {
        for (a, b) in self.boxes.iter_mut().zip(&other.boxes) {
            *a = a.union(b);
        }
        for (a, b) in self.entries.iter_mut().zip(&other.entries) {
            *a += b;
        }
        for (a, b) in self.exits.iter_mut().zip(&other.exits) {
            *a += b;
        }
        self
    }
}

/// A reference's triangle cut across axis `A` within the reference's box.
struct Cut<const A: usize> {
    along: AlongAxis<A>,
    within: SimdBox,
    margin: f32,
}

impl<const A: usize> Cut<A> {
    #[inline(always)]
    fn new(tri: &[Vec3; 3], r: &PrimRef) -> Cut<A> {
        let along = AlongAxis::new(tri);
        Cut {
            along,
            within: SimdBox {
                min: r.min(),
                max: r.max(),
            },
            margin: along.rounding_margin(),
        }
    }

    /// The piece of the reference between `lo` and `hi` on the axis (both within its box),
    /// given the triangle's sections there: the box of the triangle's part there, grown by
    /// the sections' rounding and kept within the reference's box and `[lo, hi]`, whose
    /// borders stay exact. `None` where the part is empty, or where it only touches a
    /// border that the reference crosses (`crossed`: the lower, the upper). Such a part (a
    /// corner or an edge of the triangle lying on the plane) is also the neighbouring
    /// part's, which keeps the plane exactly; bounded on its own it is a point or a segment
    /// that can sit far from everything else in its leaf and stretch the leaf's box across
    /// the scene (a quad split on its diagonal, cut through the diagonal's end, left its
    /// corner beside the far stands of a stadium, under the camera).
    #[inline(always)]
    fn piece(
        &self,
        (lo, hi): (f32, f32),
        (at_lo, at_hi): (SimdBox, SimdBox),
        (crossed_lo, crossed_hi): (bool, bool),
    ) -> Option<SimdBox> {
        // The part's extent on the axis (empty where `top < bottom`).
        let (first, last) = self.along.ends();
        let (bottom, top) = (first.max(lo), last.min(hi));
        let reaches_lo = if crossed_lo { top > lo } else { top >= lo };
        let reaches_hi = if crossed_hi {
            bottom < hi
        } else {
            bottom <= hi
        };
        if !(lo <= hi && reaches_lo && reaches_hi) {
            return None;
        }
        let raw = at_lo
            .union(&at_hi)
            .union(&self.along.corners_within(lo, hi));
        bound_piece::<A>(raw, &self.within, lo, hi, self.margin)
    }

    /// The pieces below and above the plane at `at`, which lies within the box.
    fn halves(&self, at: f32) -> (Option<SimdBox>, Option<SimdBox>) {
        let (min, max) = (self.within.min[A], self.within.max[A]);
        let (below, above) = (at.min(max), at.max(min));
        let section = |p: f32| self.along.section(p);
        let lower = self.piece(
            (min, below),
            (section(min), section(below)),
            (false, max > at),
        );
        let upper = self.piece(
            (above, max),
            (section(above), section(max)),
            (min < at, false),
        );
        (lower, upper)
    }

    /// Adds the pieces in slabs `first..=last` (those the reference's box spans) to the
    /// axis's bins; returns the first and last slab that got one. Each plane's section
    /// serves the slabs on both sides of it.
    #[inline(always)]
    fn bin(
        &self,
        slabs: &Slabs,
        (first, last): (usize, usize),
        bins: &mut [SimdBox],
    ) -> Option<(usize, usize)> {
        let (lo, hi) = (self.within.min[A], self.within.max[A]);
        let mut pieces: Option<(usize, usize)> = None;
        // The last section computed and where.
        let (mut at, mut section) = (lo, self.along.section(lo));
        let (mut plane_below, mut plane_above) = (lo, slabs.plane(A, first + 1));
        for (k, bin) in bins.iter_mut().enumerate().take(last + 1).skip(first) {
            let lower = if k == first { lo } else { plane_below.max(lo) };
            let upper = if k == last { hi } else { plane_above.min(hi) };
            let at_lower = if lower.to_bits() == at.to_bits() {
                section
            } else {
                self.along.section(lower)
            };
            let at_upper = self.along.section(upper);
            let crossed = (k > first && lo < plane_below, k < last && hi > plane_above);
            if let Some(p) = self.piece((lower, upper), (at_lower, at_upper), crossed) {
                *bin = bin.union(&p);
                pieces = Some((pieces.map_or(k, |(f, _)| f), k));
            }
            (at, section) = (upper, at_upper);
            plane_below = plane_above;
            plane_above = slabs.plane(A, k + 2);
        }
        pieces
    }
}

impl Sbvh {
    /// Builds over `refs` with at most `budget` duplicates; returns the nodes and the
    /// references in leaf order.
    pub(super) fn build(
        &self,
        prims: &BuildPrims,
        refs: Vec<PrimRef>,
        budget: usize,
    ) -> (Vec<Node>, Vec<PrimRef>) {
        let root_area = extent_of(&refs).0.surface_area();
        let builder = Builder {
            sbvh: self,
            prims,
            min_overlap: self.alpha * root_area,
        };
        let (block, leaf_order) = builder.block(refs, budget, 1);
        let mut nodes = block.into_nodes();
        number_leaves(&mut nodes);
        (nodes, leaf_order)
    }
}

/// Sets every leaf's `first` to its place in the leaf order: leaves left to right, each
/// after the references of the ones before it (the order the builder collects them in).
fn number_leaves(nodes: &mut [Node]) {
    if nodes.is_empty() {
        return;
    }
    let mut next = 0;
    let mut stack = vec![0usize];
    while let Some(i) = stack.pop() {
        if nodes[i].is_leaf() {
            nodes[i].first = next;
            next += nodes[i].count;
        } else {
            let first = nodes[i].first as usize;
            stack.extend([first + 1, first]);
        }
    }
}

struct Builder<'a> {
    sbvh: &'a Sbvh,
    prims: &'a BuildPrims,
    /// `alpha` times the root's area.
    min_overlap: f32,
}

impl Builder<'_> {
    /// The subtree over `refs` (leaves numbered in its own leaf order) and that order.
    fn block(&self, refs: Vec<PrimRef>, budget: usize, depth: usize) -> (NodeBlock, Vec<PrimRef>) {
        if refs.len() <= self.sbvh.parallel_threshold {
            let mut nodes = Vec::with_capacity(refs.len() / 2 + 1);
            nodes.push(Node::leaf(Aabb::EMPTY, 0, 0));
            let mut order = Vec::with_capacity(refs.len());
            let mut scratch = self.sbvh.object.scratch();
            self.subdivide(&mut nodes, 0, refs, budget, depth, &mut order, &mut scratch);
            return (NodeBlock::Serial(nodes), order);
        }
        match self.decide(refs, budget, depth, &mut self.sbvh.object.scratch()) {
            Decision::Leaf(bounds, refs) => {
                (NodeBlock::leaf(Node::leaf(bounds, 0, refs.len())), refs)
            }
            Decision::Split {
                bounds,
                sides: [(lo, lo_budget), (hi, hi_budget)],
            } => {
                let ((left, mut order), (right, hi_order)) = rayon::join(
                    || self.block(lo, lo_budget, depth + 1),
                    || self.block(hi, hi_budget, depth + 1),
                );
                order.extend(hi_order);
                (
                    NodeBlock::split(Node::interior(bounds, 0), left, right),
                    order,
                )
            }
        }
    }

    /// Builds the subtree over `refs` at `nodes[index]`, its references appended to
    /// `order`.
    #[allow(clippy::too_many_arguments)]
    fn subdivide(
        &self,
        nodes: &mut Vec<Node>,
        index: usize,
        refs: Vec<PrimRef>,
        budget: usize,
        depth: usize,
        order: &mut Vec<PrimRef>,
        scratch: &mut <BinnedSah as SplitRule>::Scratch,
    ) {
        match self.decide(refs, budget, depth, scratch) {
            Decision::Leaf(bounds, refs) => {
                nodes[index] = Node::leaf(bounds, order.len() as u32, refs.len());
                order.extend(refs);
            }
            Decision::Split {
                bounds,
                sides: [(lo, lo_budget), (hi, hi_budget)],
            } => {
                let left = nodes.len();
                nodes[index] = Node::interior(bounds, left as u32);
                let placeholder = Node::leaf(Aabb::EMPTY, 0, 0);
                nodes.extend([placeholder, placeholder]);
                self.subdivide(nodes, left, lo, lo_budget, depth + 1, order, scratch);
                self.subdivide(nodes, left + 1, hi, hi_budget, depth + 1, order, scratch);
            }
        }
    }

    fn decide(
        &self,
        mut refs: Vec<PrimRef>,
        budget: usize,
        depth: usize,
        scratch: &mut <BinnedSah as SplitRule>::Scratch,
    ) -> Decision {
        let (bounds, centroid_bounds) = extent_of(&refs);
        let n = refs.len();
        if n == 1 || depth >= MAX_DEPTH - 1 {
            return Decision::Leaf(bounds, refs);
        }
        let object =
            self.sbvh
                .object
                .split(self.prims, scratch, &mut refs, &bounds, &centroid_bounds);
        let Some(object) = object else {
            return Decision::Leaf(bounds, refs);
        };
        let mid = object.mid;
        let [(lo_box, _), (hi_box, _)] = object
            .sides
            .unwrap_or_else(|| [extent_of(&refs[..mid]), extent_of(&refs[mid..])]);
        let parent_area = bounds.surface_area().max(f32::MIN_POSITIVE);
        let leaf_cost = |count: usize| self.prims.leaf_cost(count);
        let object_cost = self.sbvh.traversal_cost
            + (lo_box.surface_area() * leaf_cost(mid) + hi_box.surface_area() * leaf_cost(n - mid))
                / parent_area;
        let overlap = overlap_area(&lo_box, &hi_box);
        if budget > 0
            && n >= MIN_SPATIAL_REFS
            && overlap > self.min_overlap
            && (overlap >= self.sbvh.overlap * bounds.surface_area()
                || straddling(&refs, &lo_box, &hi_box) as f32 >= CROWDED_OVERLAP * n as f32)
        {
            if let Some(spatial) = self.spatial_split(&refs, &bounds, budget) {
                if spatial.cost < object_cost {
                    if let Some(sides) = self.spatial_partition(&refs, &bounds, spatial) {
                        let extra = sides[0].len() + sides[1].len() - n;
                        let left_share = share(budget - extra, sides[0].len(), sides[1].len());
                        let [lo, hi] = sides;
                        return Decision::Split {
                            bounds,
                            sides: [(lo, left_share), (hi, budget - extra - left_share)],
                        };
                    }
                }
            }
        }
        let hi = refs.split_off(mid);
        let left_share = share(budget, mid, n - mid);
        Decision::Split {
            bounds,
            sides: [(refs, left_share), (hi, budget - left_share)],
        }
    }

    fn slabs(&self, bounds: &Aabb, n: usize) -> Slabs {
        Slabs::new(bounds, self.sbvh.bins.min((n / 8).max(4)))
    }

    /// The cheapest spatial split whose duplicates fit in `budget`, if any.
    fn spatial_split(
        &self,
        refs: &[PrimRef],
        bounds: &Aabb,
        budget: usize,
    ) -> Option<SpatialSplit> {
        let slabs = self.slabs(bounds, refs.len());
        let fill = |chunk: &[PrimRef]| {
            let mut bins = SlabBins::new(slabs.count);
            for r in chunk {
                self.bin(r, &slabs, &mut bins);
            }
            bins
        };
        let bins = if refs.len() < PARALLEL_PASS {
            fill(refs)
        } else {
            (refs.par_chunks(PARALLEL_PASS / 2).map(fill))
                .reduce(|| SlabBins::new(slabs.count), SlabBins::merge)
        };
        let n = refs.len();
        let parent_area = bounds.surface_area().max(f32::MIN_POSITIVE);
        let mut best: Option<SpatialSplit> = None;
        let m = slabs.count;
        for axis in (0..3).filter(|&a| slabs.cuts(a)) {
            let boxes = &bins.boxes[axis * m..][..m];
            let (entries, exits) = (&bins.entries[axis * m..][..m], &bins.exits[axis * m..][..m]);
            let mut right_area = vec![0.0f32; m];
            let mut right_count = vec![0usize; m];
            let (mut acc, mut count) = (SimdBox::EMPTY, 0);
            for k in (1..m).rev() {
                acc = acc.union(&boxes[k]);
                count += exits[k] as usize;
                right_area[k] = acc.surface_area();
                right_count[k] = count;
            }
            let (mut acc, mut count) = (SimdBox::EMPTY, 0);
            for k in 1..m {
                acc = acc.union(&boxes[k - 1]);
                count += entries[k - 1] as usize;
                let right = right_count[k];
                if count == 0 || right == 0 || count + right - n > budget {
                    continue;
                }
                let cost = self.sbvh.traversal_cost
                    + (acc.surface_area() * self.prims.leaf_cost(count)
                        + right_area[k] * self.prims.leaf_cost(right))
                        / parent_area;
                if best.is_none_or(|b| cost < b.cost) {
                    best = Some(SpatialSplit { axis, k, cost });
                }
            }
        }
        best
    }

    /// Adds reference `r` to the slabs it crosses on every axis: a triangle as its pieces
    /// (`Cut::bin`), anything else whole in the slab of its centroid. A reference within
    /// one slab on every axis goes there whole, whatever its shape (its centroid is there
    /// too), without reading its corners: most references of a large node, whose corners,
    /// read in the references' order, are a cache miss each on a large mesh.
    #[inline(always)]
    fn bin(&self, r: &PrimRef, slabs: &Slabs, bins: &mut SlabBins) {
        let m = slabs.count;
        let (min, max) = (r.min(), r.max());
        let (mut firsts, mut lasts) = (slabs.of(min), slabs.of(max));
        let triangle = if firsts == lasts {
            None
        } else {
            let triangle = self.prims.triangle(r.index());
            if triangle.is_none() {
                let c = slabs.of(r.centroid());
                (firsts, lasts) = (c, c);
            }
            triangle
        };
        for axis in (0..3).filter(|&a| slabs.cuts(a)) {
            let (first, last) = (firsts[axis], lasts[axis]);
            let boxes = &mut bins.boxes[axis * m..][..m];
            // The slabs that got a piece: a part that only touches a slab's border is
            // the neighbour's (`Cut::piece`), so the reference counts on the sides that
            // `spatial_partition` sends it to.
            let pieces = match triangle {
                Some(tri) if first < last => match axis {
                    0 => Cut::<0>::new(&tri, r).bin(slabs, (first, last), boxes),
                    1 => Cut::<1>::new(&tri, r).bin(slabs, (first, last), boxes),
                    _ => Cut::<2>::new(&tri, r).bin(slabs, (first, last), boxes),
                },
                _ => None,
            };
            let (first, last) = pieces.unwrap_or_else(|| {
                boxes[first].grow(min, max);
                (first, first)
            });
            bins.entries[axis * m + first] += 1;
            bins.exits[axis * m + last] += 1;
        }
    }

    /// The two sides of `split`, or `None` where clipping left one side empty (the
    /// object split is taken instead).
    fn spatial_partition(
        &self,
        refs: &[PrimRef],
        bounds: &Aabb,
        split: SpatialSplit,
    ) -> Option<[Vec<PrimRef>; 2]> {
        let slabs = self.slabs(bounds, refs.len());
        let SpatialSplit { axis, k, .. } = split;
        let plane = slabs.plane(axis, k);
        let (mut left, mut right) = (Vec::new(), Vec::new());
        for r in refs {
            // A reference wholly on one side goes there, whatever its shape (its centroid
            // is on that side too); only one that crosses the plane is read.
            let (first, last) = (slabs.of(r.min())[axis], slabs.of(r.max())[axis]);
            if last < k {
                left.push(*r);
            } else if first >= k {
                right.push(*r);
            } else {
                let Some(tri) = self.prims.triangle(r.index()) else {
                    if slabs.of(r.centroid())[axis] < k {
                        left.push(*r);
                    } else {
                        right.push(*r);
                    }
                    continue;
                };
                let halves = match axis {
                    0 => Cut::<0>::new(&tri, r).halves(plane),
                    1 => Cut::<1>::new(&tri, r).halves(plane),
                    _ => Cut::<2>::new(&tri, r).halves(plane),
                };
                match halves {
                    (Some(lo), Some(hi)) => {
                        left.push(PrimRef::new(r.index(), &lo.to_aabb()));
                        right.push(PrimRef::new(r.index(), &hi.to_aabb()));
                    }
                    // One side holds the triangle's part but where it touches the plane,
                    // which the other side's box keeps (points on the plane belong to
                    // both); the whole reference goes there, as `bin` counted it.
                    (_, None) => left.push(*r),
                    (None, Some(_)) => right.push(*r),
                }
            }
        }
        (!left.is_empty() && !right.is_empty()).then_some([left, right])
    }
}

/// The left child's part of `budget`, in proportion to its references.
fn share(budget: usize, left: usize, right: usize) -> usize {
    (budget as u128 * left as u128 / (left + right).max(1) as u128) as usize
}

/// The share of a node's references that, touching its children's overlap, tries a
/// spatial split however small that overlap is against the node's area: slivers crossing a
/// node put many of its references there, a smooth mesh's thin overlap holds few. The
/// builder suite's two sliver scenes: the knot crossed by parallel slivers keeps all its
/// splits up to 0.5 (0.6 loses them), the torus crossed by random chords up to 0.3 (0.4
/// loses them).
const CROWDED_OVERLAP: f32 = 0.3;

/// How many references touch the overlap of the two children's boxes.
fn straddling(refs: &[PrimRef], a: &Aabb, b: &Aabb) -> usize {
    let (lo, hi) = (Vec3A::from(a.min.max(b.min)), Vec3A::from(a.max.min(b.max)));
    refs.iter()
        .filter(|r| r.min().cmple(hi).all() && r.max().cmpge(lo).all())
        .count()
}

/// The surface area of the intersection of two boxes (0 when they are disjoint).
fn overlap_area(a: &Aabb, b: &Aabb) -> f32 {
    let lo = a.min.max(b.min);
    let hi = a.max.min(b.max);
    if lo.cmple(hi).all() {
        Aabb::new(lo, hi).surface_area()
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The piece of `tri` within `within` between `lo` and `hi` on x, as the binning and
    /// the partition cut it: an infinite border is the box's own, not crossed.
    fn piece(tri: &[Vec3; 3], within: &Aabb, lo: f32, hi: f32) -> Option<Aabb> {
        let cut = Cut::<0>::new(tri, &PrimRef::new(0, within));
        let (min, max) = (within.min.x, within.max.x);
        let (lo_in, hi_in) = (lo.max(min), hi.min(max));
        let sections = (cut.along.section(lo_in), cut.along.section(hi_in));
        let crossed = (min < lo, max > hi);
        (cut.piece((lo_in, hi_in), sections, crossed)).map(SimdBox::to_aabb)
    }

    /// The pieces of a long diagonal triangle in the slabs it crosses cover it, and are
    /// much smaller than its box.
    #[test]
    fn slab_pieces_cover_the_triangle() {
        let tri = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(8.0, 8.0, 8.0),
            Vec3::new(8.1, 8.0, 8.0),
        ];
        let bounds = tri.iter().fold(Aabb::EMPTY, |b, &p| b.union_point(p));
        let slabs = Slabs::new(&bounds, 8);
        let mut pieces = Vec::new();
        for k in 0..8 {
            let lo = if k == 0 {
                f32::NEG_INFINITY
            } else {
                slabs.plane(0, k)
            };
            let hi = if k == 7 {
                f32::INFINITY
            } else {
                slabs.plane(0, k + 1)
            };
            pieces.extend(piece(&tri, &bounds, lo, hi));
        }
        assert_eq!(pieces.len(), 8);
        let area: f32 = pieces.iter().map(Aabb::surface_area).sum();
        assert!(area < 0.3 * bounds.surface_area());
        for i in 0..=40 {
            for j in 0..=40 - i {
                let (u, v) = (i as f32 / 40.0, j as f32 / 40.0);
                let p = tri[0] + u * (tri[1] - tri[0]) + v * (tri[2] - tri[0]);
                let slack = 1e-5 * 8.0;
                assert!(
                    pieces
                        .iter()
                        .any(|b| p.cmpge(b.min - slack).all() && p.cmple(b.max + slack).all()),
                    "{p} is in no piece"
                );
            }
        }
    }

    /// A triangle that reaches a plane only with a corner has no part beyond it: the
    /// corner is the part on this side's, not a point-sized reference of its own.
    #[test]
    fn a_corner_on_the_plane_is_no_piece() {
        let tri = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(-4.0, 1.0, 0.5),
            Vec3::new(-4.0, -1.0, 0.0),
        ];
        let bounds = tri.iter().fold(Aabb::EMPTY, |b, &p| b.union_point(p));
        assert!(piece(&tri, &bounds, 0.0, f32::INFINITY).is_none());
        let below = piece(&tri, &bounds, f32::NEG_INFINITY, 0.0).unwrap();
        assert_eq!(below, bounds);
        // The same within a reference cut from a larger triangle, whose box ends on the
        // plane while the triangle goes on beyond it.
        let big = [
            Vec3::new(-4.0, -4.0, 0.0),
            Vec3::new(4.0, 4.0, 0.0),
            Vec3::new(-4.0, 4.0, 0.0),
        ];
        let within = Aabb::new(Vec3::new(-4.0, -4.0, 0.0), Vec3::new(0.0, 0.0, 0.0));
        assert!(piece(&big, &within, 0.0, 1.0).is_none());
        // A triangle lying in a slab's border plane is all there is of it: kept.
        let flat = tri.map(|p| Vec3::new(0.0, p.y, p.z + p.x));
        let flat_box = flat.iter().fold(Aabb::EMPTY, |b, &p| b.union_point(p));
        assert_eq!(piece(&flat, &flat_box, 0.0, 1.0), Some(flat_box));
    }

    /// How many references the tree over `count` slivers crossing one another (as across
    /// the builder test's knot) holds, built with a budget of one duplicate per sliver.
    fn crossed_slivers_references(count: u32) -> usize {
        let triangles: Vec<[Vec3; 3]> = (0..count)
            .map(|i| {
                let t = i as f32 / count as f32;
                let a = Vec3::new(-3.0, -3.0 + 6.0 * t, -3.0);
                let b = Vec3::new(3.0, 3.0 - 6.0 * t, 3.0);
                [a, b, b + Vec3::new(0.0, 0.05, 0.0)]
            })
            .collect();
        let bounds: Vec<Aabb> = (triangles.iter())
            .map(|t| t.iter().fold(Aabb::EMPTY, |b, &p| b.union_point(p)))
            .collect();
        let refs = (bounds.iter().enumerate())
            .map(|(i, b)| PrimRef::new(i as u32, b))
            .collect();
        let prims = BuildPrims {
            bounds,
            test_block: 4,
            triangles: triangles.into_iter().map(Some).collect(),
        };
        let options = crate::accel::bvh::BvhOptions::default();
        let sbvh = Sbvh {
            object: BinnedSah::new(&options),
            bins: options.bins,
            traversal_cost: options.node_cost(),
            alpha: options.alpha,
            overlap: options.overlap,
            parallel_threshold: usize::MAX,
        };
        sbvh.build(&prims, refs, count as usize).1.len()
    }

    /// Spatial splits are tried only at nodes of at least `MIN_SPATIAL_REFS` references:
    /// crossing slivers get none below that count and are cut above it.
    #[test]
    fn small_nodes_take_no_spatial_split() {
        let few = MIN_SPATIAL_REFS as u32 - 1;
        assert_eq!(crossed_slivers_references(few), few as usize);
        let many = 4 * MIN_SPATIAL_REFS as u32;
        assert!(crossed_slivers_references(many) > many as usize);
    }

    #[test]
    fn budgets_are_shared_by_reference_counts() {
        assert_eq!(share(10, 1, 1), 5);
        assert_eq!(share(10, 3, 1), 7);
        assert_eq!(share(0, 3, 1), 0);
        assert_eq!(share(usize::MAX, 1, 1), usize::MAX / 2);
    }

    #[test]
    fn leaves_are_numbered_left_to_right() {
        let b = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let mut nodes = vec![
            Node::interior(b, 1),
            Node::interior(b, 3),
            Node::leaf(b, 99, 2),
            Node::leaf(b, 99, 3),
            Node::leaf(b, 99, 1),
        ];
        number_leaves(&mut nodes);
        assert_eq!([nodes[3].first, nodes[4].first, nodes[2].first], [0, 3, 4]);
    }
}
