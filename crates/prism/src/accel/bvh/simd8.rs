//! The 8-wide traversal with AVX2, chosen at run time: `available` asks the CPU once, when
//! a `Bvh` is built, and only then is the tree laid out as `Wide8Node`s (`wide.rs`); other
//! CPUs and other architectures keep the 4-wide SSE layout and `traverse.rs`.
//!
//! A visit tests a node's eight boxes with a handful of 256-bit operations, the same
//! closed-box test as `WideNode::hit` and `Aabb::hit` lane by lane (unit-tested below),
//! and the walk itself (nearest child first, the others pushed farthest first) is the one
//! `traverse.rs` shares between both widths.

// With `math/lanes/`, the one place outside the benchmark and CLI shims that allows unsafe
// code: `#[target_feature]` functions (and the cone kernel's std::arch intrinsics) can only
// be called in unsafe blocks (and only after `is_x86_feature_detected!` said yes; see
// `traverse`). Nothing else here is unsafe; the workspace's `unsafe_code = "deny"` lists
// this module as an exception.
#![allow(unsafe_code)]

use super::packet::{PacketBounds, PacketSearch, RaySoa};
use super::traverse::LeafQuery;
use super::wide::Wide8Node;
use crate::accel::query::HitSearch;
use crate::geometry::TrianglePack;
use crate::math::TraceRay;
use crate::stats::Stats;

/// The fewest rays of one axis permutation that a packet's leaf of triangle packs tests
/// in SIMD lanes (one triangle against several rays); fewer go ray by ray.
const LANES_FOR_PACKS: u32 = 4;

/// Whether this CPU can take the 8-wide AVX2 path (AVX2 and POPCNT).
pub(super) fn available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("popcnt")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// For the 8-wide path's tests: whether this CPU lacks AVX2, so that the path is never
/// taken here and the test has nothing to check (said on stderr).
#[cfg(test)]
fn skipped_without_avx2() -> bool {
    let skip = !available();
    if skip {
        eprintln!("skipped: this CPU lacks AVX2, so the 8-wide path is never taken");
    }
    skip
}

/// Whether this CPU can also take the 16-ray AVX-512 packet kernels (`per_ray.rs` in sixteen
/// lanes).
pub(super) fn avx512_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        available() && std::arch::is_x86_feature_detected!("avx512f")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Walks `nodes` for `ray` from `root` (`nodes[0]`, or an entry node of some of its
/// subtrees), testing leaves with `leaves` (`LeafQuery::test`'s answers, two triangle packs
/// at a time: `simd8/pair.rs`). `nodes` must come from a `Bvh` built while `available()`
/// was true (the only way `Bvh::wide8` is filled).
#[inline(always)]
pub(super) fn traverse<const ORDERED: bool>(
    nodes: &[Wide8Node],
    root: &Wide8Node,
    ray: &TraceRay,
    search: &mut HitSearch,
    stats: &mut Stats,
    leaves: &LeafQuery<'_>,
) {
    #[cfg(target_arch = "x86_64")]
    {
        debug_assert!(available());
        // SAFETY: `nodes` is non-empty only when AVX2 was detected (see above).
        unsafe { x86::traverse::<ORDERED>(nodes, root, ray, search, stats, leaves) }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (nodes, root, ray, search, stats, leaves);
        unreachable!("8-wide nodes are only built on x86-64 with AVX2")
    }
}

/// Walks `nodes` from `root` (`nodes[0]`, or an entry node of some of its subtrees) for a
/// packet of rays (`packet.rs`): each visit first tests the eight
/// boxes once for the whole packet against its interval `bounds`, then each box that
/// passes against the packet's rays eight at a time, so every child goes on with the rays
/// that enter it. Leaves of triangle packs are tested one triangle against eight rays of
/// one axis permutation at a time (`RaySoa::permutations`; a permutation's rays go to
/// `leaf` when fewer than `LANES_FOR_PACKS`), spheres and cones against several rays in
/// any leaf, other primitives ray by ray. With `avx512` (only where
/// `avx512_available()`), the per-ray kernels take sixteen rays per step; `any` walks for
/// any-hit queries (children unordered).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(super) fn traverse_packet(
    avx512: bool,
    any: bool,
    nodes: &[Wide8Node],
    root: &Wide8Node,
    bounds: &PacketBounds,
    soa: &RaySoa,
    leaves: &LeafQuery<'_>,
    search: &mut PacketSearch,
    stats: &mut Stats,
    leaf: impl FnMut(u32, u32, f32, u64, &mut PacketSearch, &mut Stats),
) {
    #[cfg(target_arch = "x86_64")]
    {
        debug_assert!(available());
        debug_assert!(!avx512 || avx512_available());
        // SAFETY: `nodes` is non-empty only when AVX2 was detected (see `traverse`), and
        // `avx512` is set only where AVX-512 was detected.
        unsafe {
            match (avx512, any) {
                (true, true) => x86::traverse_packet16::<false>(
                    nodes, root, bounds, soa, leaves, search, stats, leaf,
                ),
                (true, false) => x86::traverse_packet16::<true>(
                    nodes, root, bounds, soa, leaves, search, stats, leaf,
                ),
                (false, true) => x86::traverse_packet::<false>(
                    nodes, root, bounds, soa, leaves, search, stats, leaf,
                ),
                (false, false) => x86::traverse_packet::<true>(
                    nodes, root, bounds, soa, leaves, search, stats, leaf,
                ),
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (
            avx512, any, nodes, root, bounds, soa, leaves, search, stats, leaf,
        );
        unreachable!("8-wide nodes are only built on x86-64 with AVX2")
    }
}

#[cfg(target_arch = "x86_64")]
mod cones;
#[cfg(target_arch = "x86_64")]
mod pair;
#[cfg(target_arch = "x86_64")]
mod per_ray;
#[cfg(target_arch = "x86_64")]
mod spheres;

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::{per_ray, LeafQuery, PacketBounds, PacketSearch, RaySoa, Wide8Node};
    use crate::accel::bvh::leaves::PACKED;
    use crate::accel::bvh::packet::{Packet4, PacketBoxes};
    use crate::accel::bvh::traverse::{CullBound, Visit};
    use crate::accel::bvh::wide::BoxRay;
    use crate::accel::query::HitSearch;
    use crate::geometry::Shape;
    use crate::math::lanes::{F32x16, F32x8, FloatLanes};
    use crate::math::TraceRay;
    use crate::stats::Stats;

    /// A ray prepared for the slab test of an 8-wide node's boxes.
    type Ray8 = BoxRay<F32x8>;

    /// The children of `node` that `ray` enters within `t_max` (bits) and their entry
    /// distances (meaningful in the lanes hit): `BoxRay::hit` in eight lanes, inlined into
    /// the walk without fail (a call per visit cost single rays about 4 %).
    #[inline(always)]
    fn hit8(ray: &Ray8, node: &Wide8Node, t_max: f32) -> (u32, [f32; 8]) {
        let (hit, enter) = ray.hit(|row| F32x8::load(&node.bounds[row], 0), t_max);
        (F32x8::bits(hit), enter.to_array())
    }

    /// Children in use (unused lanes hold min = +∞).
    #[inline(always)]
    fn children8(node: &Wide8Node) -> u32 {
        let min_x = F32x8::load(&node.bounds[0], 0);
        F32x8::bits(min_x.lt(F32x8::splat(f32::INFINITY))).count_ones()
    }

    /// A packet prepared for the interval test of an 8-wide node's boxes.
    type Packet8 = PacketBoxes<F32x8>;

    /// The children some ray of the packet may enter before `t_max` (the farthest bound of
    /// its rays), per child a lower bound of every ray's entry distance, and the children
    /// that every ray enters before `t_min` (the nearest bound): `PacketBoxes::hit` in
    /// eight lanes (held to `Packet4` and to every ray's own box test below).
    #[inline(always)]
    fn packet_hit8(
        packet: &Packet8,
        node: &Wide8Node,
        t_max: f32,
        t_min: f32,
    ) -> (u32, [f32; 8], u32) {
        let row = |row: usize| F32x8::load(&node.bounds[row], 0);
        let (some, enter, every) = packet.hit::<true>(row, t_max, t_min);
        (some, enter.to_array(), every)
    }

    /// A visit of the packet walk, written once over the lanes of its per-ray kernels
    /// (`per_ray.rs`): the node's eight boxes once for the whole packet, then each box
    /// that some ray may enter against the rays, so each child goes on with the rays that
    /// do enter it.
    #[inline(always)]
    fn visit_packet<L: FloatLanes>(
        packet: &Packet8,
        soa: &RaySoa,
        node: &Wide8Node,
        s: &PacketSearch,
        rays: u64,
    ) -> Visit<u64> {
        let (mut some, entries, everyone) = packet_hit8(packet, node, s.t_max(), s.t_min());
        let (mut hit, mut entering) = (0u32, [0u64; 8]);
        while some != 0 {
            let k = some.trailing_zeros() as usize;
            some &= some - 1;
            entering[k] = if everyone >> k & 1 == 1 {
                rays
            } else {
                let planes = (packet.near, packet.far);
                per_ray::rays_entering::<L>(node, planes, k, rays, soa, &s.bound)
            };
            if entering[k] != 0 {
                hit |= 1 << k;
            }
        }
        Visit {
            children: children8(node),
            hit,
            entries,
            rays: entering,
        }
    }

    /// A leaf of the packet walk (`(first, count, enter)` as the walk hands it), written
    /// once over the lanes of its per-ray kernels; true when every ray is answered.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn leaf_packet<L: FloatLanes>(
        leaves: &LeafQuery<'_>,
        soa: &RaySoa,
        box_test: &Packet4,
        (child, count, enter): (u32, u32, f32),
        rays: u64,
        search: &mut PacketSearch,
        stats: &mut Stats,
        leaf: &mut impl FnMut(u32, u32, f32, u64, &mut PacketSearch, &mut Stats),
    ) -> bool {
        let rays = rays & search.open();
        let first = child as usize;
        if count & PACKED != 0 {
            // The rays of each axis permutation against the packs in turn (per ray the
            // order of `LeafQuery::test`); a few rays one by one, whose own test takes two
            // packs a step.
            let packs = &leaves.packs[first..][..(count & !PACKED) as usize];
            for &(k, group) in &soa.permutations {
                let rays = rays & group;
                if rays.count_ones() < super::LANES_FOR_PACKS {
                    if rays != 0 {
                        leaf(child, count, enter, rays, search, stats);
                    }
                    continue;
                }
                for pack in packs {
                    per_ray::test_pack::<L>(pack, k, rays, soa, box_test, search, stats);
                }
            }
        } else {
            // Primitive by primitive, each against the rays still searching: per ray the
            // order of `LeafQuery::test`.
            let reaching = search.reaching(rays, enter);
            let prims = &leaves.prims[first..first + count as usize];
            for &prim in prims {
                let rays = reaching & search.open();
                if rays == 0 {
                    break;
                }
                let geometry = leaves.geometry;
                match &geometry.primitives[prim as usize].shape {
                    Shape::Sphere(sphere) => {
                        per_ray::test_sphere::<L>(sphere, prim, rays, soa, search, stats)
                    }
                    // SAFETY: only inlined into the entry points below, compiled for AVX2,
                    // which their callers checked.
                    Shape::Cone(cone) => unsafe {
                        super::cones::test_cone(cone, prim, rays, soa, search, stats)
                    },
                    _ => search.test_per_ray(geometry, prim, rays, soa, stats),
                }
            }
        }
        search.finish_leaf()
    }

    /// The entry points of the packet walk, one per instruction set: the walk with
    /// `visit_packet` and `leaf_packet` in `$lanes`, compiled for `$features`. The closures
    /// are written here so that they take the entry point's target features (a closure
    /// defined in a generic function would not, and the walk leaves one uninlined).
    macro_rules! packet_entry {
        ($name:ident, $lanes:ty, $features:literal) => {
            /// `super::traverse_packet` compiled for this instruction set.
            ///
            /// # Safety
            /// The CPU must support the instruction set (`available`, and
            /// `avx512_available` for the AVX-512 variant).
            #[target_feature(enable = $features)]
            #[allow(clippy::too_many_arguments)]
            pub(super) unsafe fn $name<const ORDERED: bool>(
                nodes: &[Wide8Node],
                root: &Wide8Node,
                bounds: &PacketBounds,
                soa: &RaySoa,
                leaves: &LeafQuery<'_>,
                search: &mut PacketSearch,
                stats: &mut Stats,
                mut leaf: impl FnMut(u32, u32, f32, u64, &mut PacketSearch, &mut Stats),
            ) {
                let packet = Packet8::new(bounds);
                let box_test = Packet4::new(*bounds);
                crate::accel::bvh::traverse::walk::<_, _, ORDERED>(
                    nodes,
                    root,
                    |node: &Wide8Node, s: &PacketSearch, rays: u64| {
                        visit_packet::<$lanes>(&packet, soa, node, s, rays)
                    },
                    search,
                    stats,
                    |child, count, enter, rays, search: &mut PacketSearch, stats: &mut Stats| {
                        let at = (child, count, enter);
                        leaf_packet::<$lanes>(
                            leaves, soa, &box_test, at, rays, search, stats, &mut leaf,
                        )
                    },
                )
            }
        };
    }

    packet_entry!(traverse_packet, F32x8, "avx2,popcnt");
    packet_entry!(traverse_packet16, F32x16, "avx2,popcnt,avx512f");

    /// `super::traverse` compiled for AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2 and POPCNT.
    #[target_feature(enable = "avx2,popcnt")]
    pub(super) unsafe fn traverse<const ORDERED: bool>(
        nodes: &[Wide8Node],
        root: &Wide8Node,
        ray: &TraceRay,
        search: &mut HitSearch,
        stats: &mut Stats,
        leaves: &LeafQuery<'_>,
    ) {
        let ray8 = Ray8::new(ray);
        crate::accel::bvh::traverse::walk::<_, _, ORDERED>(
            nodes,
            root,
            |node: &Wide8Node, s: &HitSearch, ()| {
                let (hit, entries) = hit8(&ray8, node, s.t_max());
                Visit {
                    children: children8(node),
                    hit,
                    entries,
                    rays: [(); 8],
                }
            },
            search,
            stats,
            |first, count, _, (), search: &mut HitSearch, stats: &mut Stats| {
                super::pair::test_leaf(leaves, first, count, search, stats)
            },
        )
    }

    #[cfg(test)]
    mod tests {
        use super::*;
        use crate::accel::bvh::Node;
        use crate::math::{Aabb, Ray, Vec3};

        fn leaf(min: Vec3, max: Vec3) -> Node {
            Node {
                min,
                first: 0,
                max,
                count: 1,
            }
        }

        /// The packet test: its lanes and entry bounds are the 4-wide interval test's
        /// (`Packet4::hit_boxes`), it lets through every child that one of the packet's
        /// rays enters by its own box test, and a child it says every ray enters is entered
        /// by every ray's own test.
        #[test]
        #[cfg_attr(
            not(prism_host_avx2),
            ignore = "this CPU lacks AVX2: the 8-wide kernels never run here"
        )]
        fn packet_test_bounds_every_rays_own_test() {
            use crate::accel::bvh::packet::{Packet4, PacketBounds};
            use crate::math::hash::uniform;
            if super::super::skipped_without_avx2() {
                return;
            }
            let u = |k: u64| uniform(k as u32, 0, 0, 0, 7);
            let (mut some_seen, mut all_seen) = (0, 0);
            for packet in 0..300u64 {
                let k = packet * 1000;
                // A bundle of rays from a small patch toward a common region, some bounded.
                let eye = Vec3::new(u(k) * 4.0 - 2.0, u(k + 1) * 4.0 - 2.0, -6.0);
                let rays: Vec<TraceRay> = (0..16)
                    .map(|r| {
                        let j = k + 10 + 4 * r;
                        let o = eye + 0.3 * Vec3::new(u(j), u(j + 1), u(j + 2));
                        let target = Vec3::new(u(j + 3) - 0.5, u(j + 3) * 0.7 - 0.3, 0.5);
                        TraceRay::new(Ray::new(o, (target - o).normalize()))
                    })
                    .collect();
                let plain: Vec<Ray> = rays.iter().map(|r| r.ray).collect();
                let Some(bounds) = PacketBounds::of_rays(&plain) else {
                    continue;
                };
                let mut node = Wide8Node::EMPTY;
                let mut boxes = Vec::new();
                for lane in 0..7 {
                    let j = k + 200 + 6 * lane;
                    let lo = Vec3::new(u(j), u(j + 1), u(j + 2)) * 4.0 - 2.0;
                    let b = Aabb::new(lo, lo + Vec3::new(u(j + 3), u(j + 4), u(j + 5)) * 3.0);
                    node.set_box(lane as usize, &leaf(b.min, b.max));
                    boxes.push(b);
                }
                let bound = |r: usize| {
                    if r.is_multiple_of(3) {
                        20.0 + r as f32
                    } else {
                        f32::INFINITY
                    }
                };
                let t_max = (0..16).map(bound).fold(0.0, f32::max);
                let t_min = (0..16).map(bound).fold(f32::INFINITY, f32::min);
                let (some, entries, all) = packet_hit8(&Packet8::new(&bounds), &node, t_max, t_min);
                let four = Packet4::new(bounds);
                for (lane, b) in boxes.iter().enumerate() {
                    let row = |f: fn(&Aabb) -> Vec3| {
                        let v = f(b);
                        [v.x, v.y, v.z].map(glam::Vec4::splat)
                    };
                    let (mask4, t4) = four.hit_boxes(row(|b| b.min), row(|b| b.max), t_max);
                    let in_some = some >> lane & 1 == 1;
                    assert_eq!(in_some, mask4 & 1 == 1, "packet {packet} lane {lane}");
                    if in_some {
                        assert_eq!(entries[lane], t4.x, "packet {packet} lane {lane}");
                    }
                    let own: Vec<bool> = rays
                        .iter()
                        .enumerate()
                        .map(|(r, ray)| b.hit(ray.ray.origin, ray.inv_dir, bound(r)).is_some())
                        .collect();
                    if own.iter().any(|&h| h) {
                        assert!(in_some, "packet {packet} lane {lane}: a ray enters, culled");
                        some_seen += 1;
                    }
                    if all >> lane & 1 == 1 {
                        assert!(
                            own.iter().all(|&h| h),
                            "packet {packet} lane {lane}: not all"
                        );
                        all_seen += 1;
                    }
                }
                assert_eq!(some >> 7, 0, "an unused lane is let through");
            }
            // The workload must exercise both answers.
            assert!(
                some_seen > 100 && all_seen > 20,
                "{some_seen} entered, {all_seen} all"
            );
        }

        /// On random boxes at three scales and rays of every kind the walk meets (from
        /// afar, from inside, from a face or a corner, parallel to one or two axes, at
        /// bounds around the box), the AVX2 test never misses a box `Aabb::hit` enters nor
        /// enters it later, and where no slab distance can be NaN (no zero direction
        /// component) gives exactly its answer.
        #[test]
        #[cfg_attr(
            not(prism_host_avx2),
            ignore = "this CPU lacks AVX2: the 8-wide kernels never run here"
        )]
        fn avx2_test_is_the_box_test_or_more_conservative() {
            if super::super::skipped_without_avx2() {
                return;
            }
            use crate::accel::bvh::wide::tests::box_test_is_aabb_hit_or_more_conservative;
            box_test_is_aabb_hit_or_more_conservative(8, avx2_hit);
        }

        /// The AVX2 test's answers for a node holding `lanes` (AVX2 must be there).
        fn avx2_hit(lanes: &[Aabb], ray: &TraceRay, t_max: f32) -> Vec<Option<f32>> {
            let w: Wide8Node = crate::accel::bvh::wide::tests::node_of(lanes);
            let (mask, t) = hit8(&Ray8::new(ray), &w, t_max);
            (0..8)
                .map(|k| (mask >> k & 1 == 1).then_some(t[k]))
                .collect()
        }

        /// The AVX2 test against `Aabb::hit` on fixed boxes and rays (flat and point boxes,
        /// rays in face planes, from inside, axis-parallel of both signs); the unused lanes
        /// are never hit.
        #[test]
        #[cfg_attr(
            not(prism_host_avx2),
            ignore = "this CPU lacks AVX2: the 8-wide kernels never run here"
        )]
        fn avx2_test_matches_the_box_test() {
            if super::super::skipped_without_avx2() {
                return;
            }
            crate::accel::bvh::wide::tests::box_test_matches_aabb_hit(8, avx2_hit);
        }
    }
}
