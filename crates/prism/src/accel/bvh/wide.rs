//! The traversal layouts of a BVH: a 4-wide tree whose nodes hold up to four children's
//! boxes in SIMD lanes (128 bytes, two cache lines), so one visit tests four boxes with a
//! handful of 4-wide operations, and a ray takes half as many steps as in the binary tree.
//!
//! The builders keep producing the plain binary `Node` array, which the SAH cost, the
//! statistics and the tests speak about; `WideNode`s are derived from it after the build
//! by pulling grandchildren up (the child with the largest box is opened first), in
//! depth-first order so a subtree stays close in memory.
//!
//! `Wide8Node` is the same with eight children (256 bytes, four cache lines), collapsed
//! the same way; it is built instead of `WideNode` when the CPU has AVX2, and `simd8.rs`
//! tests its eight boxes at once.

use super::Node;
use crate::math::lanes::{axes, FloatLanes};
use crate::math::{Aabb, TraceRay, Vec3};
use arrayvec::ArrayVec;
use glam::Vec4;
use rayon::prelude::*;

/// Up to four children. Lane k of each vector holds child k's box; unused lanes hold an
/// empty box (min +∞, max −∞) that no ray hits.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct WideNode {
    /// `bounds[axis]` holds the children's minima on `axis`, `bounds[3 + axis]` their
    /// maxima, as `Wide8Node::bounds`.
    bounds: [Vec4; 6],
    /// A leaf child's first primitive (into `Bvh::prims`), or an interior child's
    /// `WideNode` index.
    pub child: [u32; 4],
    /// Primitives of a leaf child; 0 for an interior child or an unused lane.
    pub count: [u32; 4],
}

impl WideNode {
    const EMPTY: WideNode = WideNode {
        bounds: [
            Vec4::INFINITY,
            Vec4::INFINITY,
            Vec4::INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::NEG_INFINITY,
            Vec4::NEG_INFINITY,
        ],
        child: [0; 4],
        count: [0; 4],
    };

    /// Row `row` of the children's bounds, a lane per child: their minima on axis `row`
    /// for rows 0..3, their maxima on axis `row - 3` for rows 3..6.
    #[inline(always)]
    pub(super) fn row(&self, row: usize) -> Vec4 {
        self.bounds[row]
    }

    /// Children in use (boxes a visit tests).
    #[inline(always)]
    pub(super) fn children(&self) -> u32 {
        // Unused lanes hold min = +∞.
        self.bounds[0].cmplt(Vec4::INFINITY).bitmask().count_ones()
    }

    /// Wide nodes for the tree `nodes` (root at 0). A root that is a leaf has none; the
    /// traversal treats it on its own.
    pub(super) fn from_tree(nodes: &[Node]) -> Vec<WideNode> {
        collapse_tree(nodes)
    }

    /// Entry distances of the children's boxes along `ray` within `t_max`; +∞ for a
    /// child the ray misses (and for unused lanes): `BoxRay::hit` in four lanes.
    #[inline(always)]
    pub(super) fn hit(&self, ray: &WideRay, t_max: f32) -> Vec4 {
        let (hit, enter) = ray.hit(|row| self.row(row), t_max);
        Vec4::select(hit, enter, Vec4::INFINITY)
    }
}

/// The child slots of a wide node (`child`, `count`): read by the traversal's shared walk,
/// rewritten by `leaves.rs`.
pub(super) trait LeafSlots: Send {
    fn slots(&mut self) -> (&mut [u32], &mut [u32]);
    fn children_and_counts(&self) -> (&[u32], &[u32]);
}

/// A wide node's lanes one at a time, as (box, child, count) with `child` and `count` as in
/// the node: what `subtree.rs` reads subtrees from and builds entry nodes of.
pub(super) trait Lanes: Sized {
    /// Lanes per node.
    const WIDTH: usize;
    /// Lane `k`, None when unused.
    fn lane(&self, k: usize) -> Option<(Aabb, u32, u32)>;
    /// A node of `lanes` (at most `WIDTH`), the other lanes unused.
    fn of_lanes(lanes: &[(Aabb, u32, u32)]) -> Self;
}

/// `LeafSlots` and `Lanes` for a wide node type of `$width` lanes: both layouts index
/// `bounds[row][lane]`, `child[lane]` and `count[lane]` alike.
macro_rules! wide_node_lanes {
    ($node:ident, $width:expr) => {
        impl LeafSlots for $node {
            fn slots(&mut self) -> (&mut [u32], &mut [u32]) {
                (&mut self.child, &mut self.count)
            }
            #[inline(always)]
            fn children_and_counts(&self) -> (&[u32], &[u32]) {
                (&self.child, &self.count)
            }
        }

        impl Lanes for $node {
            const WIDTH: usize = $width;
            fn lane(&self, k: usize) -> Option<(Aabb, u32, u32)> {
                let b = &self.bounds;
                let min = Vec3::new(b[0][k], b[1][k], b[2][k]);
                let max = Vec3::new(b[3][k], b[4][k], b[5][k]);
                (min.x < f32::INFINITY).then_some((Aabb { min, max }, self.child[k], self.count[k]))
            }
            fn of_lanes(lanes: &[(Aabb, u32, u32)]) -> Self {
                let mut w = $node::EMPTY;
                for (k, &(b, child, count)) in lanes.iter().enumerate() {
                    for axis in 0..3 {
                        w.bounds[axis][k] = b.min[axis];
                        w.bounds[3 + axis][k] = b.max[axis];
                    }
                    (w.child[k], w.count[k]) = (child, count);
                }
                w
            }
        }
    };
}

wide_node_lanes!(WideNode, 4);
wide_node_lanes!(Wide8Node, 8);

/// Up to eight children: `bounds[axis][k]` is child k's minimum on `axis` and
/// `bounds[3 + axis][k]` its maximum; unused lanes hold an empty box (min +∞, max −∞).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct Wide8Node {
    pub bounds: [[f32; 8]; 6],
    /// As in `WideNode`: a leaf child's first primitive or pack, or an interior child's
    /// `Wide8Node` index.
    pub child: [u32; 8],
    /// As in `WideNode`: a leaf child's primitives (or `PACKED | packs`), 0 otherwise.
    pub count: [u32; 8],
}

impl Wide8Node {
    pub(super) const EMPTY: Wide8Node = Wide8Node {
        bounds: [
            [f32::INFINITY; 8],
            [f32::INFINITY; 8],
            [f32::INFINITY; 8],
            [f32::NEG_INFINITY; 8],
            [f32::NEG_INFINITY; 8],
            [f32::NEG_INFINITY; 8],
        ],
        child: [0; 8],
        count: [0; 8],
    };

    /// Sets lane `k` to node `n`'s box (the SIMD tests' nodes).
    #[cfg(test)]
    pub(super) fn set_box(&mut self, k: usize, n: &Node) {
        for axis in 0..3 {
            self.bounds[axis][k] = n.min[axis];
            self.bounds[3 + axis][k] = n.max[axis];
        }
    }

    /// 8-wide nodes for the tree `nodes`, as `WideNode::from_tree` makes 4-wide ones.
    pub(super) fn from_tree(nodes: &[Node]) -> Vec<Wide8Node> {
        collapse_tree(nodes)
    }
}

/// Levels of wide nodes whose subtrees are laid out in parallel: the root's (up to 8
/// tasks). Each level below the first copies its subtrees once more into place.
const PARALLEL_LEVELS: usize = 1;

/// The wide nodes for the binary tree `nodes`, depth first: each node's interior children
/// side by side, then the first child's descendants, then the second's, and so on, so a
/// subtree stays close in memory. The root's subtrees are laid out in parallel, each with
/// indices from 0, and shifted into place: the same nodes in the same order as a serial
/// walk.
fn collapse_tree<W: Lanes + LeafSlots + Copy>(nodes: &[Node]) -> Vec<W> {
    if nodes.first().is_none_or(Node::is_leaf) {
        return Vec::new();
    }
    let (root, mut wide) = lay_out::<W>(nodes, 0, 0, 1);
    wide[0] = root;
    wide
}

/// The wide node for interior binary node `node`, and after `reserved` empty slots its
/// descendants: the node's interior children and the descendants index into that vector.
fn lay_out<W: Lanes + LeafSlots + Copy>(
    nodes: &[Node],
    node: usize,
    level: usize,
    reserved: usize,
) -> (W, Vec<W>) {
    if level >= PARALLEL_LEVELS {
        return lay_out_serially(nodes, node, reserved);
    }
    let mut interior: ArrayVec<usize, 8> = ArrayVec::new();
    let first = reserved as u32;
    let w = wide_node::<W>(nodes, node, |c| {
        interior.push(c);
        first + interior.len() as u32 - 1
    });
    let parts: Vec<(W, Vec<W>)> = interior
        .par_iter()
        .map(|&c| lay_out(nodes, c, level + 1, 0))
        .collect();
    let total = reserved + parts.len() + parts.iter().map(|(_, d)| d.len()).sum::<usize>();
    let mut below = Vec::with_capacity(total);
    below.resize(reserved, W::of_lanes(&[]));
    // Each part's descendants land after the children and the parts before it.
    let mut offsets = Vec::with_capacity(parts.len());
    let mut offset = (reserved + parts.len()) as u32;
    for (_, descendants) in &parts {
        offsets.push(offset);
        offset += descendants.len() as u32;
    }
    for ((child, _), &at) in parts.iter().zip(&offsets) {
        below.push(shifted(*child, at));
    }
    for ((_, descendants), &at) in parts.iter().zip(&offsets) {
        below.extend(descendants.iter().map(|&d| shifted(d, at)));
    }
    (w, below)
}

/// `lay_out` on one thread: a stack of (binary node, its slot among the descendants).
fn lay_out_serially<W: Lanes + LeafSlots + Copy>(
    nodes: &[Node],
    node: usize,
    reserved: usize,
) -> (W, Vec<W>) {
    let mut below: Vec<W> = vec![W::of_lanes(&[]); reserved];
    let mut stack: Vec<(usize, usize)> = Vec::new();
    let visit = |node: usize, below: &mut Vec<W>, stack: &mut Vec<(usize, usize)>| {
        let mut interior: ArrayVec<(usize, usize), 8> = ArrayVec::new();
        let w = wide_node::<W>(nodes, node, |c| {
            below.push(W::of_lanes(&[]));
            interior.push((c, below.len() - 1));
            below.len() as u32 - 1
        });
        // Reversed, so the first child's subtree is laid out right after this node's.
        stack.extend(interior.into_iter().rev());
        w
    };
    let w = visit(node, &mut below, &mut stack);
    while let Some((node, slot)) = stack.pop() {
        below[slot] = visit(node, &mut below, &mut stack);
    }
    (w, below)
}

/// The wide node over `collapse`'s children of `node`: leaves keep their primitive range,
/// and `place` gives each interior child (a binary node) its wide node's index.
fn wide_node<W: Lanes>(nodes: &[Node], node: usize, mut place: impl FnMut(usize) -> u32) -> W {
    let children = collapse(nodes, node, W::WIDTH);
    let lanes: ArrayVec<(Aabb, u32, u32), 8> = children
        .iter()
        .map(|&c| {
            let n = &nodes[c];
            if n.is_leaf() {
                (n.bounds(), n.first, n.count)
            } else {
                (n.bounds(), place(c), 0)
            }
        })
        .collect();
    W::of_lanes(&lanes)
}

/// `w` with its interior children's indices `by` places further on.
fn shifted<W: Lanes + LeafSlots>(mut w: W, by: u32) -> W {
    let used: ArrayVec<bool, 8> = (0..W::WIDTH).map(|k| w.lane(k).is_some()).collect();
    let (child, count) = w.slots();
    for k in 0..child.len() {
        if used[k] && count[k] == 0 {
            child[k] += by;
        }
    }
    w
}

/// The binary nodes that become the children of the wide node for `root`: its two
/// children, then repeatedly the interior one with the largest box replaced by its own two
/// children, until there are `width` or only leaves. Order is kept left to right; of equal
/// areas the rightmost opens first. Each child's area is computed once, and nothing is
/// allocated: this runs for every wide node of every build.
fn collapse(nodes: &[Node], root: usize, width: usize) -> ArrayVec<usize, 8> {
    debug_assert!(width <= 8);
    // Interior children carry their area; leaves carry -∞ and are never opened.
    let area = |i: usize| {
        let n = &nodes[i];
        if n.is_leaf() {
            f32::NEG_INFINITY
        } else {
            Aabb::new(n.min, n.max).surface_area()
        }
    };
    let first = nodes[root].first as usize;
    let mut children: ArrayVec<(usize, f32), 8> = ArrayVec::new();
    children.extend([(first, area(first)), (first + 1, area(first + 1))]);
    while children.len() < width {
        let mut open: Option<usize> = None;
        for (k, &(_, a)) in children.iter().enumerate() {
            if a == f32::NEG_INFINITY {
                continue;
            }
            if open.is_none_or(|o| a.total_cmp(&children[o].1).is_ge()) {
                open = Some(k);
            }
        }
        let Some(k) = open else { break };
        let f = nodes[children[k].0].first as usize;
        children[k] = (f, area(f));
        children.insert(k + 1, (f + 1, area(f + 1)));
    }
    children.iter().map(|&(c, _)| c).collect()
}

/// Per axis, the row of a wide node's bounds holding a box's entry plane and the one
/// holding its exit plane (rows `axis` hold minima, rows `3 + axis` maxima), for rays
/// running toward negative values on the axes marked.
pub(super) fn plane_rows(negative: [bool; 3]) -> ([usize; 3], [usize; 3]) {
    let near = [0, 1, 2].map(|a| if negative[a] { 3 + a } else { a });
    let far = [0, 1, 2].map(|a| if negative[a] { a } else { 3 + a });
    (near, far)
}

/// A ray prepared for the slab test of a wide node's boxes, a child per lane of `L` (four
/// with glam's `Vec4`, `WideNode`; eight with AVX2, `Wide8Node`): origin and inverse
/// direction broadcast per axis, and per axis the row of the node's bounds holding the
/// entry plane (the max for a ray running toward negative values) and the exit plane.
pub(super) struct BoxRay<L> {
    origin: [L; 3],
    inv_dir: [L; 3],
    /// The inverse direction times `CULL_SLACK`, for the exits: pushed out so that neither
    /// the box test's rounding nor a primitive's error in its reported distance loses a
    /// box; applied before the exits are combined rather than after, one multiplication
    /// fewer on the visit's critical path.
    inv_exit: [L; 3],
    near: [usize; 3],
    far: [usize; 3],
}

/// The 4-wide layout's ray.
pub(super) type WideRay = BoxRay<Vec4>;

impl<L: FloatLanes> BoxRay<L> {
    #[inline(always)]
    pub(super) fn new(ray: &TraceRay) -> Self {
        let o = ray.ray.origin;
        let inv = ray.inv_dir.to_array();
        let (near, far) = plane_rows(inv.map(|v| v < 0.0));
        BoxRay {
            origin: axes(|a| L::splat(o[a])),
            inv_dir: axes(|a| L::splat(inv[a])),
            inv_exit: axes(|a| L::splat(inv[a] * crate::accel::CULL_SLACK)),
            near,
            far,
        }
    }

    /// The children hit within `t_max` (a mask) and their entry distances (meaningful in
    /// the lanes of the mask), from the node's bounds `row` by row. The slab test of
    /// `Aabb::hit` with the walk's slack (`CULL_SLACK`) on the exits, its operations
    /// arranged for a short chain of dependent steps, since a single ray's walk waits on
    /// each visit's answer: the slack is in the exit planes' inverse direction and the
    /// bound, and the three axes are combined as a tree (two steps) rather than one after
    /// the other (three). Where a slab distance is NaN (a ray parallel to an axis that
    /// starts on a box's face plane, 0 × ∞), `max`/`min` return their second operand, and
    /// the bound and 0 come second: the NaN drops that axis and maybe one beside it from
    /// the bound, so the box may be entered where `Aabb::hit` says it is not, never the
    /// other way round. The answers do not change: a box test only decides which
    /// primitives are tested. Exactly `Aabb::hit`'s entry where no direction component is
    /// zero.
    #[inline(always)]
    pub(super) fn hit(&self, row: impl Fn(usize) -> L, t_max: f32) -> (L::Mask, L) {
        let near = |axis: usize| (row(self.near[axis]) - self.origin[axis]) * self.inv_dir[axis];
        let far = |axis: usize| (row(self.far[axis]) - self.origin[axis]) * self.inv_exit[axis];
        let (near, far) = ([near(0), near(1), near(2)], [far(0), far(1), far(2)]);
        let bound = L::splat(t_max * crate::accel::CULL_SLACK);
        let enter = near[0].max(near[1]).max(near[2].max(L::splat(0.0)));
        let exit = far[0].min(far[1]).min(far[2].min(bound));
        (enter.le(exit), enter)
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::math::{Aabb, Ray, Vec3};

    /// The root's subtrees laid out in parallel and shifted into place give the nodes a
    /// serial walk gives, in the same order.
    #[test]
    fn the_parallel_layout_is_the_serial_one() {
        let u = |i: u32, k: u32| crate::math::hash::uniform(i, k, 0, 0, 3);
        let bounds: Vec<Aabb> = (0..3000)
            .map(|i| {
                let lo = Vec3::new(u(i, 0), u(i, 1), u(i, 2)) * 100.0;
                Aabb::new(lo, lo + Vec3::new(u(i, 3), u(i, 4), u(i, 5)))
            })
            .collect();
        let bvh = crate::accel::bvh::Bvh::build_over_bounds(
            (0..3000).collect(),
            bounds,
            &crate::accel::bvh::BvhOptions::default(),
        );
        fn serial<W: Lanes + LeafSlots + Copy>(nodes: &[Node]) -> Vec<W> {
            let (root, mut wide) = lay_out_serially::<W>(nodes, 0, 1);
            wide[0] = root;
            wide
        }
        let parallel8: Vec<Wide8Node> = collapse_tree(&bvh.nodes);
        assert!(parallel8.len() > 100);
        assert_eq!(parallel8, serial::<Wide8Node>(&bvh.nodes));
        let parallel4: Vec<WideNode> = collapse_tree(&bvh.nodes);
        assert_eq!(parallel4, serial::<WideNode>(&bvh.nodes));
    }

    /// A box test's answers, `hit(lanes, ray, t_max)` (the entry of each lane of a node
    /// holding `lanes[k]` in lane k and nothing in the rest; None where not entered), for
    /// a node whose only box is `b`, held to `Aabb::hit` on
    /// random boxes at three scales and rays of every kind a walk meets (from afar, from
    /// inside, from a face or a corner, through a corner exactly, parallel to one or two
    /// axes, at bounds around the box): never a box missed or entered later, exactly its
    /// answer where no slab distance can be NaN (no zero direction component), an entry
    /// `Aabb::hit` refuses only within the walk's slack, no other lane entered. For the
    /// 4-wide test here and the 8-wide AVX2 test (`simd8.rs`).
    pub(in crate::accel::bvh) fn box_test_is_aabb_hit_or_more_conservative(
        width: usize,
        hit: impl Fn(&[Aabb], &TraceRay, f32) -> Vec<Option<f32>>,
    ) {
        use crate::math::hash::uniform;
        let u = |k: u32, d: u32| uniform(k, d, 0, 0, 21);
        let (mut entered, mut exact) = (0, 0);
        for scale in [1e-3f32, 1.0, 1e3] {
            for case in 0..4000u32 {
                let corner = |d: u32| Vec3::new(u(case, d), u(case, d + 1), u(case, d + 2));
                let lo = (corner(0) * 2.0 - 1.0) * scale;
                let b = Aabb::new(lo, lo + corner(3) * scale);
                let lane = case as usize % width;
                // Lanes before it hold empty boxes, as a node's unused lanes do.
                let mut lanes = vec![Aabb::EMPTY; lane];
                lanes.push(b);
                // The origin: anywhere, or on a face plane or corner of the box.
                let mut o = (corner(6) * 4.0 - 2.0) * scale;
                for axis in 0..3 {
                    match (case >> (2 * axis)) % 4 {
                        0 => o[axis] = b.min[axis],
                        1 => o[axis] = b.max[axis],
                        _ => {}
                    }
                }
                // The direction: toward the box, now and then through one of its corners
                // exactly (where rounding decides whether the ray enters, and the walk's
                // slack must keep it in), with zero components now and then.
                let mut target = b.min + (b.max - b.min) * corner(9);
                if case % 3 == 0 {
                    let bit = |axis: u32| (case / 3) >> axis & 1 == 1;
                    target = Vec3::select(glam::BVec3::new(bit(0), bit(1), bit(2)), b.max, b.min);
                }
                let mut d = target - o;
                for axis in 0..3 {
                    if (case / 64 + axis as u32).is_multiple_of(5) {
                        d[axis] = 0.0;
                    }
                }
                if d == Vec3::ZERO {
                    continue;
                }
                let ray = TraceRay::new(Ray::new(o, d));
                let reach = d.length().recip() * scale;
                for t_max in [f32::INFINITY, 0.5 * reach, 2.0 * reach, 4.0 * reach] {
                    let expected = b.hit(o, ray.inv_dir, t_max);
                    let answers = hit(&lanes, &ray, t_max);
                    let got = answers[lane];
                    let at = format!("scale {scale} case {case} o {o} d {d} t_max {t_max}");
                    for (k, other) in answers.iter().enumerate() {
                        assert!(k == lane || other.is_none(), "an unused lane is hit, {at}");
                    }
                    let no_nan = d.cmpne(Vec3::ZERO).all();
                    match (expected, got) {
                        (Some(want), Some(t)) => {
                            assert!(t <= want, "entered at {t}, not by {want}, {at}");
                            if no_nan {
                                assert_eq!(t, want, "{at}");
                                exact += 1;
                            }
                            entered += 1;
                        }
                        (Some(_), None) => panic!("missed, {at}"),
                        // Entered where `Aabb::hit` says not: only within the walk's slack
                        // beyond the bound, or where a NaN dropped an axis.
                        (None, Some(_)) if no_nan => {
                            // The slabs in f64: the ray misses by less than the slack.
                            let (mut enter, mut exit) = (0.0f64, f64::from(t_max));
                            for axis in 0..3 {
                                let inv = 1.0 / f64::from(d[axis]);
                                let to = |p: f32| (f64::from(p) - f64::from(o[axis])) * inv;
                                let (t0, t1) = (to(b.min[axis]), to(b.max[axis]));
                                enter = enter.max(t0.min(t1));
                                exit = exit.min(t0.max(t1));
                            }
                            let slack = 2.0 * f64::from(crate::accel::CULL_SLACK - 1.0);
                            assert!(
                                enter <= exit * (1.0 + slack),
                                "entered beyond the slack, {at}"
                            );
                        }
                        _ => {}
                    }
                }
            }
        }
        assert!(
            entered > 10_000 && exact > 5_000,
            "{entered} entered, {exact} exact"
        );
    }

    #[test]
    fn wide_test_is_the_box_test_or_more_conservative() {
        box_test_is_aabb_hit_or_more_conservative(4, wide_hit);
    }

    /// A box test's answers (`hit` as for `box_test_is_aabb_hit_or_more_conservative`)
    /// against `Aabb::hit` on fixed boxes (flat and point boxes among them, packed into
    /// nodes with at least one lane left unused) and rays lying in their face planes,
    /// starting inside them, parallel to axes with both signs of zero: exactly its answer
    /// where no slab distance can be NaN (no zero direction component, or no face plane
    /// through the origin), else never missed nor entered later; unused lanes never hit.
    /// For the 4-wide test here and the 8-wide AVX2 test (`simd8.rs`).
    pub(in crate::accel::bvh) fn box_test_matches_aabb_hit(
        width: usize,
        hit: impl Fn(&[Aabb], &TraceRay, f32) -> Vec<Option<f32>>,
    ) {
        let boxes = [
            Aabb::new(Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0)),
            Aabb::new(Vec3::new(2.0, -1.0, 0.5), Vec3::new(3.0, 0.5, 4.0)),
            Aabb::new(Vec3::new(-2.0, 1.0, 1.0), Vec3::new(-1.0, 1.0, 2.0)),
            Aabb::new(Vec3::new(0.0, 0.0, 2.0), Vec3::new(0.0, 1.0, 2.0)),
            Aabb::new(Vec3::new(-1.0, -1.0, -1.0), Vec3::new(5.0, 5.0, 5.0)),
            Aabb::new(Vec3::new(0.5, 0.5, 0.5), Vec3::new(0.5, 0.5, 0.5)),
        ];
        let origins = [
            Vec3::new(-1.0, 0.5, 0.5),
            Vec3::new(0.5, 0.5, 0.5),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 2.0),
            Vec3::new(5.0, 0.5, 0.5),
            Vec3::new(2.0, 0.5, 1.0),
            Vec3::new(-1.5, 1.0, 0.0),
            Vec3::new(-1.0, -1.0, -1.0),
        ];
        let dirs = [
            Vec3::X,
            -Vec3::X,
            Vec3::Y,
            -Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(1.0, 0.2, -0.1),
            Vec3::new(-1.0, -0.0, 0.0),
            Vec3::new(0.0, -0.0, 1.0),
            Vec3::new(3.0, -2.0, 1.0),
            Vec3::new(1.0, 1.0, 1.0),
        ];
        for node in boxes.chunks(width - 1) {
            for o in origins {
                for d in dirs {
                    let ray = TraceRay::new(Ray::new(o, d));
                    for t_max in [f32::INFINITY, 1.5] {
                        let got = hit(node, &ray, t_max);
                        for (k, b) in node.iter().enumerate() {
                            let expected = b.hit(o, ray.inv_dir, t_max);
                            let at = format!("o {o} d {d} t_max {t_max} box {b:?}");
                            if d.cmpne(Vec3::ZERO).all()
                                || (o.cmpne(b.min).all() && o.cmpne(b.max).all())
                            {
                                // No slab distance can be NaN: exactly `Aabb::hit`.
                                assert_eq!(got[k], expected, "{at}");
                            } else if let Some(want) = expected {
                                // A ray parallel to an axis may meet 0 × ∞ on a face
                                // plane: then the box may be entered early, never missed.
                                let t = got[k].unwrap_or_else(|| panic!("missed, {at}"));
                                assert!(t <= want, "entered at {t}, not by {want}, {at}");
                            }
                        }
                        assert_eq!(got.len(), width);
                        assert!(
                            got[node.len()..].iter().all(Option::is_none),
                            "an unused lane is hit, o {o} d {d} t_max {t_max}"
                        );
                    }
                }
            }
        }
    }

    /// A node of either width holding `lanes[k]` in lane k (leaf children of one
    /// primitive), the rest unused: what the box tests' checks test.
    pub(in crate::accel::bvh) fn node_of<W: Lanes>(lanes: &[Aabb]) -> W {
        let lanes: Vec<(Aabb, u32, u32)> = lanes.iter().map(|&b| (b, 0, 1)).collect();
        W::of_lanes(&lanes)
    }

    /// The 4-wide test's answers for a node holding `lanes`.
    fn wide_hit(lanes: &[Aabb], ray: &TraceRay, t_max: f32) -> Vec<Option<f32>> {
        let w: WideNode = node_of(lanes);
        let t = w.hit(&WideRay::new(ray), t_max).to_array();
        t.iter()
            .map(|&t| Some(t).filter(|t| t.is_finite()))
            .collect()
    }

    #[test]
    fn wide_test_matches_the_box_test() {
        box_test_matches_aabb_hit(4, wide_hit);
    }

    /// `NodeWidth::Auto` takes the 8-wide layout exactly when the CPU has AVX2, `Four`
    /// never; both layouts reference the same leaves, each once.
    #[test]
    fn the_width_is_chosen_at_run_time_and_keeps_the_leaves() {
        use super::super::{simd8, Bvh, BvhOptions, NodeWidth};
        let bounds: Vec<Aabb> = (0..500)
            .map(|i| {
                let x = (i * 37 % 101) as f32;
                let y = (i * 53 % 89) as f32;
                let z = (i * 11 % 97) as f32;
                Aabb::new(Vec3::new(x, y, z), Vec3::new(x + 1.5, y + 0.5, z + 2.0))
            })
            .collect();
        let build = |width| {
            let options = BvhOptions {
                width,
                ..BvhOptions::default()
            };
            Bvh::build_over_bounds((0..500).collect(), bounds.clone(), &options)
        };
        let four = build(NodeWidth::Four);
        assert!(!four.wide.is_empty() && four.wide8.is_empty());
        let auto = build(NodeWidth::Auto);
        assert_eq!(auto.wide8.is_empty(), !simd8::available());
        assert_eq!(auto.wide.is_empty(), simd8::available());
        let leaves = |slots: Vec<(u32, u32)>| {
            let mut l: Vec<_> = slots.into_iter().filter(|s| s.1 > 0).collect();
            l.sort_unstable();
            l
        };
        let of4 = leaves(
            four.wide
                .iter()
                .flat_map(|n| n.child.into_iter().zip(n.count))
                .collect(),
        );
        let of8 = leaves(
            Wide8Node::from_tree(&four.nodes)
                .iter()
                .flat_map(|n| n.child.into_iter().zip(n.count))
                .collect(),
        );
        assert_eq!(of4, of8);
        assert_eq!(of4.iter().map(|l| l.1).sum::<u32>(), 500);
    }
}
