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
use crate::math::{Aabb, TraceRay, Vec3};
use glam::Vec4;

/// Up to four children. Lane k of each vector holds child k's box; unused lanes hold an
/// empty box (min +∞, max −∞) that no ray hits.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(64))]
pub(super) struct WideNode {
    min: [Vec4; 3],
    max: [Vec4; 3],
    /// A leaf child's first primitive (into `Bvh::prims`), or an interior child's
    /// `WideNode` index.
    pub child: [u32; 4],
    /// Primitives of a leaf child; 0 for an interior child or an unused lane.
    pub count: [u32; 4],
}

impl WideNode {
    const EMPTY: WideNode = WideNode {
        min: [Vec4::INFINITY; 3],
        max: [Vec4::NEG_INFINITY; 3],
        child: [0; 4],
        count: [0; 4],
    };

    /// The children's minima on `axis`, a lane per child.
    #[inline(always)]
    pub(super) fn min_row(&self, axis: usize) -> Vec4 {
        self.min[axis]
    }

    /// The children's maxima on `axis`, a lane per child.
    #[inline(always)]
    pub(super) fn max_row(&self, axis: usize) -> Vec4 {
        self.max[axis]
    }

    /// Children in use (boxes a visit tests).
    #[inline(always)]
    pub(super) fn children(&self) -> u32 {
        // Unused lanes hold min = +∞.
        self.min[0].cmplt(Vec4::INFINITY).bitmask().count_ones()
    }

    /// Wide nodes for the tree `nodes` (root at 0). A root that is a leaf has none; the
    /// traversal treats it on its own.
    pub(super) fn from_tree(nodes: &[Node]) -> Vec<WideNode> {
        let mut wide = Vec::new();
        if nodes.first().is_none_or(Node::is_leaf) {
            return wide;
        }
        wide.push(WideNode::EMPTY);
        // (interior binary node, the wide slot its children go to)
        let mut stack = vec![(0usize, 0usize)];
        while let Some((node, slot)) = stack.pop() {
            let children = collapse(nodes, node, 4);
            let mut w = WideNode::EMPTY;
            let mut interior = Vec::new();
            for (k, &c) in children.iter().enumerate() {
                let n = &nodes[c];
                for axis in 0..3 {
                    w.min[axis][k] = n.min[axis];
                    w.max[axis][k] = n.max[axis];
                }
                if n.is_leaf() {
                    w.child[k] = n.first;
                    w.count[k] = n.count;
                } else {
                    w.child[k] = wide.len() as u32;
                    wide.push(WideNode::EMPTY);
                    interior.push((c, w.child[k] as usize));
                }
            }
            wide[slot] = w;
            // Reversed, so the first child's subtree is laid out right after this node.
            stack.extend(interior.into_iter().rev());
        }
        wide
    }

    /// Entry distances of the children's boxes along `ray` within `t_max`; +∞ for a
    /// child the ray misses (and for unused lanes). The same closed-box test as
    /// `Aabb::hit`: a slab whose distance is NaN (the origin lies in a face plane of a box
    /// the ray runs parallel to) does not constrain t.
    #[inline(always)]
    pub(super) fn hit(&self, ray: &WideRay, t_max: f32) -> Vec4 {
        let mut enter = Vec4::ZERO;
        let mut exit = Vec4::splat(t_max);
        for axis in 0..3 {
            let to_min = (self.min[axis] - ray.origin[axis]) * ray.inv_dir[axis];
            let to_max = (self.max[axis] - ray.origin[axis]) * ray.inv_dir[axis];
            let (near, far) = if ray.negative[axis] {
                (to_max, to_min)
            } else {
                (to_min, to_max)
            };
            // A NaN compares false and leaves the running bound alone, as f32::max/min do.
            enter = Vec4::select(near.cmpgt(enter), near, enter);
            exit = Vec4::select(far.cmplt(exit), far, exit);
        }
        let hit = enter.cmple(exit * ray.exit_scale);
        Vec4::select(hit, enter, Vec4::INFINITY)
    }
}

/// The child slots of a wide node (`child`, `count`): read by the traversal's shared walk,
/// rewritten by `leaves.rs`.
pub(super) trait LeafSlots: Send {
    fn slots(&mut self) -> (&mut [u32], &mut [u32]);
    fn children_and_counts(&self) -> (&[u32], &[u32]);
}

impl LeafSlots for WideNode {
    fn slots(&mut self) -> (&mut [u32], &mut [u32]) {
        (&mut self.child, &mut self.count)
    }
    #[inline(always)]
    fn children_and_counts(&self) -> (&[u32], &[u32]) {
        (&self.child, &self.count)
    }
}

impl LeafSlots for Wide8Node {
    fn slots(&mut self) -> (&mut [u32], &mut [u32]) {
        (&mut self.child, &mut self.count)
    }
    #[inline(always)]
    fn children_and_counts(&self) -> (&[u32], &[u32]) {
        (&self.child, &self.count)
    }
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

impl Lanes for WideNode {
    const WIDTH: usize = 4;
    fn lane(&self, k: usize) -> Option<(Aabb, u32, u32)> {
        let min = Vec3::new(self.min[0][k], self.min[1][k], self.min[2][k]);
        let max = Vec3::new(self.max[0][k], self.max[1][k], self.max[2][k]);
        (min.x < f32::INFINITY).then_some((Aabb { min, max }, self.child[k], self.count[k]))
    }
    fn of_lanes(lanes: &[(Aabb, u32, u32)]) -> Self {
        let mut w = WideNode::EMPTY;
        for (k, &(b, child, count)) in lanes.iter().enumerate() {
            for axis in 0..3 {
                w.min[axis][k] = b.min[axis];
                w.max[axis][k] = b.max[axis];
            }
            (w.child[k], w.count[k]) = (child, count);
        }
        w
    }
}

impl Lanes for Wide8Node {
    const WIDTH: usize = 8;
    fn lane(&self, k: usize) -> Option<(Aabb, u32, u32)> {
        let b = &self.bounds;
        let min = Vec3::new(b[0][k], b[1][k], b[2][k]);
        let max = Vec3::new(b[3][k], b[4][k], b[5][k]);
        (min.x < f32::INFINITY).then_some((Aabb { min, max }, self.child[k], self.count[k]))
    }
    fn of_lanes(lanes: &[(Aabb, u32, u32)]) -> Self {
        let mut w = Wide8Node::EMPTY;
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

    /// Sets lane `k` to node `n`'s box.
    pub(super) fn set_box(&mut self, k: usize, n: &Node) {
        for axis in 0..3 {
            self.bounds[axis][k] = n.min[axis];
            self.bounds[3 + axis][k] = n.max[axis];
        }
    }

    /// 8-wide nodes for the tree `nodes`, as `WideNode::from_tree` makes 4-wide ones.
    pub(super) fn from_tree(nodes: &[Node]) -> Vec<Wide8Node> {
        let mut wide = Vec::new();
        if nodes.first().is_none_or(Node::is_leaf) {
            return wide;
        }
        wide.push(Wide8Node::EMPTY);
        let mut stack = vec![(0usize, 0usize)];
        while let Some((node, slot)) = stack.pop() {
            let children = collapse(nodes, node, 8);
            let mut w = Wide8Node::EMPTY;
            let mut interior = Vec::new();
            for (k, &c) in children.iter().enumerate() {
                let n = &nodes[c];
                w.set_box(k, n);
                if n.is_leaf() {
                    w.child[k] = n.first;
                    w.count[k] = n.count;
                } else {
                    w.child[k] = wide.len() as u32;
                    wide.push(Wide8Node::EMPTY);
                    interior.push((c, w.child[k] as usize));
                }
            }
            wide[slot] = w;
            stack.extend(interior.into_iter().rev());
        }
        wide
    }
}

/// The binary nodes that become the children of the wide node for `root`: its two
/// children, then repeatedly the interior one with the largest box replaced by its own two
/// children, until there are `width` or only leaves. Order is kept left to right.
fn collapse(nodes: &[Node], root: usize, width: usize) -> Vec<usize> {
    let first = nodes[root].first as usize;
    let mut children = vec![first, first + 1];
    while children.len() < width {
        let area = |i: usize| {
            let n = &nodes[i];
            crate::math::Aabb::new(n.min, n.max).surface_area()
        };
        let open = children
            .iter()
            .enumerate()
            .filter(|(_, &c)| !nodes[c].is_leaf())
            .max_by(|a, b| area(*a.1).total_cmp(&area(*b.1)))
            .map(|(k, _)| k);
        let Some(k) = open else { break };
        let f = nodes[children[k]].first as usize;
        children.splice(k..=k, [f, f + 1]);
    }
    children
}

/// A ray prepared for `WideNode::hit`: origin and inverse direction splatted per axis,
/// and per axis whether the ray runs toward negative values (its entry plane is the max).
pub(super) struct WideRay {
    origin: [Vec4; 3],
    inv_dir: [Vec4; 3],
    negative: [bool; 3],
    /// Exits are pushed out by this factor (`CULL_SLACK`), so that neither the box test's
    /// rounding nor a primitive's error in its reported distance loses a box.
    exit_scale: Vec4,
}

impl WideRay {
    pub(super) fn new(ray: &TraceRay) -> Self {
        let o = ray.ray.origin;
        let inv = ray.inv_dir;
        WideRay {
            origin: [o.x, o.y, o.z].map(Vec4::splat),
            inv_dir: [inv.x, inv.y, inv.z].map(Vec4::splat),
            negative: [inv.x < 0.0, inv.y < 0.0, inv.z < 0.0],
            exit_scale: Vec4::splat(crate::accel::CULL_SLACK),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Aabb, Ray, Vec3};

    fn leaf(min: Vec3, max: Vec3) -> Node {
        Node {
            min,
            first: 0,
            max,
            count: 1,
        }
    }

    /// The wide test agrees with `Aabb::hit` on each child, including rays lying in a face
    /// plane, rays starting inside and axis-parallel rays of both signs; the unused lane is
    /// never hit.
    #[test]
    fn wide_test_matches_the_box_test() {
        let boxes = [
            leaf(Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0)),
            leaf(Vec3::new(2.0, -1.0, 0.5), Vec3::new(3.0, 0.5, 4.0)),
            leaf(Vec3::new(-2.0, 1.0, 1.0), Vec3::new(-1.0, 1.0, 2.0)),
        ];
        let mut w = WideNode::EMPTY;
        for (k, n) in boxes.iter().enumerate() {
            for axis in 0..3 {
                w.min[axis][k] = n.min[axis];
                w.max[axis][k] = n.max[axis];
            }
        }
        let origins = [
            Vec3::new(-1.0, 0.5, 0.5),
            Vec3::new(0.5, 0.5, 0.5),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 2.0),
            Vec3::new(5.0, 0.5, 0.5),
            Vec3::new(2.0, 0.5, 1.0),
            Vec3::new(-1.5, 1.0, 0.0),
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
        ];
        for o in origins {
            for d in dirs {
                let ray = TraceRay::new(Ray::new(o, d));
                let wr = WideRay::new(&ray);
                for t_max in [f32::INFINITY, 1.5] {
                    let got = w.hit(&wr, t_max);
                    for (k, n) in boxes.iter().enumerate() {
                        let expected = Aabb::new(n.min, n.max).hit(o, ray.inv_dir, t_max);
                        let got = Some(got[k]).filter(|t| t.is_finite());
                        assert_eq!(got, expected, "o {o} d {d} t_max {t_max} child {k}");
                    }
                    assert_eq!(got[3], f32::INFINITY, "the unused lane is hit");
                }
            }
        }
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
