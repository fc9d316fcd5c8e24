//! The traversal layout of a BVH: each interior node stores its two children's boxes side
//! by side in SIMD lanes (64 bytes, one cache line), so one visit tests both children with
//! a handful of 4-wide operations instead of two scalar slab tests.
//!
//! The builders keep producing the plain binary `Node` array; `PairNode`s are derived from
//! it after the build, in depth-first order so a subtree stays close in memory.

use super::Node;
use crate::math::robust::gamma;
use crate::math::TraceRay;
use glam::{BVec4A, Vec4, Vec4Swizzles};

/// Both children of an interior node. Per axis, lanes hold
/// `[min of child 0, min of child 1, max of child 0, max of child 1]`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct PairNode {
    x: Vec4,
    y: Vec4,
    z: Vec4,
    /// A leaf child's first primitive (into `Bvh::prims`), or an interior child's
    /// `PairNode` index.
    pub child: [u32; 2],
    /// Primitives of a leaf child; 0 for an interior child.
    pub count: [u32; 2],
}

impl PairNode {
    /// Pair nodes for every interior node of `nodes` (a tree rooted at 0), depth-first.
    /// A root that is a leaf has no pair node; the traversal treats it on its own.
    pub fn from_tree(nodes: &[Node]) -> Vec<PairNode> {
        let mut pairs = Vec::new();
        if nodes.first().is_none_or(Node::is_leaf) {
            return pairs;
        }
        // (interior node in `nodes`, the pair slot its children go to)
        let mut stack = vec![(0usize, 0usize)];
        pairs.push(PairNode::EMPTY);
        while let Some((node, slot)) = stack.pop() {
            let first = nodes[node].first as usize;
            let children = [&nodes[first], &nodes[first + 1]];
            let mut pair = PairNode::EMPTY;
            for (k, c) in children.iter().enumerate() {
                pair.set_bounds(k, c);
                if c.is_leaf() {
                    pair.child[k] = c.first;
                    pair.count[k] = c.count;
                } else {
                    pair.child[k] = pairs.len() as u32;
                    pair.count[k] = 0;
                    pairs.push(PairNode::EMPTY);
                }
            }
            pairs[slot] = pair;
            // Right first, so the left subtree is laid out right after its parent.
            for k in [1, 0] {
                if pair.count[k] == 0 {
                    stack.push((first + k, pair.child[k] as usize));
                }
            }
        }
        pairs
    }

    const EMPTY: PairNode = PairNode {
        x: Vec4::ZERO,
        y: Vec4::ZERO,
        z: Vec4::ZERO,
        child: [0; 2],
        count: [0; 2],
    };

    fn set_bounds(&mut self, k: usize, node: &Node) {
        for (axis, lanes) in [&mut self.x, &mut self.y, &mut self.z]
            .into_iter()
            .enumerate()
        {
            lanes[k] = node.min[axis];
            lanes[k + 2] = node.max[axis];
        }
    }

    /// Entry distances of the two child boxes along `ray` within `t_max`, `None` for a
    /// child the ray misses. The same closed-box test as `Aabb::hit`: a slab whose distance
    /// is NaN (the origin lies in a face plane of a box the ray runs parallel to) does not
    /// constrain t.
    #[inline(always)]
    pub fn hit(&self, ray: &PairRay, t_max: f32) -> [Option<f32>; 2] {
        let tx = ray.order(0, (self.x - ray.origin[0]) * ray.inv_dir[0]);
        let ty = ray.order(1, (self.y - ray.origin[1]) * ray.inv_dir[1]);
        let tz = ray.order(2, (self.z - ray.origin[2]) * ray.inv_dir[2]);
        // Lanes 0, 1 reduce to the entry distances (a max starting at 0), lanes 2, 3 to the
        // exits (a min starting at t_max). `keep_larger`/`keep_smaller` leave the
        // accumulator alone when the candidate is NaN, as f32::max/min do.
        let start = Vec4::new(0.0, 0.0, t_max, t_max);
        let mut t = start;
        for slab in [tx, ty, tz] {
            let better = slab.cmpgt(t) ^ EXIT_LANES;
            let better = better & !slab.is_nan_mask();
            t = Vec4::select(better, slab, t);
        }
        let exit_scale = 1.0 + 2.0 * gamma(3);
        let enter = [t.x, t.y];
        let exit = [t.z * exit_scale, t.w * exit_scale];
        [0, 1].map(|k| (enter[k] <= exit[k]).then_some(enter[k]))
    }
}

/// Lanes that hold exit distances, where the reduction keeps the smaller value.
const EXIT_LANES: BVec4A = BVec4A::new(false, false, true, true);

/// A ray prepared for `PairNode::hit`: origin and inverse direction splatted per axis, and
/// per axis whether the ray runs toward negative values (its entry plane is then the max).
pub(super) struct PairRay {
    origin: [Vec4; 3],
    inv_dir: [Vec4; 3],
    negative: [bool; 3],
}

impl PairRay {
    pub fn new(ray: &TraceRay) -> Self {
        let o = ray.ray.origin;
        let inv = ray.inv_dir;
        PairRay {
            origin: [o.x, o.y, o.z].map(Vec4::splat),
            inv_dir: [inv.x, inv.y, inv.z].map(Vec4::splat),
            negative: [inv.x < 0.0, inv.y < 0.0, inv.z < 0.0],
        }
    }

    /// Puts the entry distances of both children in lanes 0, 1 and the exits in 2, 3.
    #[inline(always)]
    fn order(&self, axis: usize, t: Vec4) -> Vec4 {
        if self.negative[axis] {
            t.zwxy()
        } else {
            t
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

    /// The pair test agrees with `Aabb::hit` on each child, including rays lying in a face
    /// plane, rays starting inside and axis-parallel rays of both signs.
    #[test]
    fn pair_test_matches_the_box_test() {
        let a = leaf(Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0));
        let b = leaf(Vec3::new(2.0, -1.0, 0.5), Vec3::new(3.0, 0.5, 4.0));
        let mut pair = PairNode::EMPTY;
        pair.set_bounds(0, &a);
        pair.set_bounds(1, &b);
        let origins = [
            Vec3::new(-1.0, 0.5, 0.5),
            Vec3::new(0.5, 0.5, 0.5),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 2.0),
            Vec3::new(5.0, 0.5, 0.5),
            Vec3::new(2.0, 0.5, 1.0),
        ];
        let mut dirs = vec![
            Vec3::X,
            -Vec3::X,
            Vec3::Y,
            -Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(1.0, 0.2, -0.1),
            Vec3::new(-1.0, -0.0, 0.0),
        ];
        dirs.extend([Vec3::new(0.0, -0.0, 1.0), Vec3::new(3.0, -2.0, 1.0)]);
        for o in origins {
            for d in &dirs {
                let ray = TraceRay::new(Ray::new(o, *d));
                let pr = PairRay::new(&ray);
                for t_max in [f32::INFINITY, 1.5] {
                    let got = pair.hit(&pr, t_max);
                    for (k, n) in [a, b].iter().enumerate() {
                        let expected = Aabb::new(n.min, n.max).hit(o, ray.inv_dir, t_max);
                        assert_eq!(got[k], expected, "o {o} d {d} t_max {t_max} child {k}");
                    }
                }
            }
        }
    }
}
