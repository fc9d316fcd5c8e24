//! The 8-wide traversal with AVX2, chosen at run time: `available` asks the CPU once, when
//! a `Bvh` is built, and only then is the tree laid out as `Wide8Node`s (`wide.rs`); other
//! CPUs and other architectures keep the 4-wide SSE layout and `traverse.rs`.
//!
//! A visit tests a node's eight boxes with a handful of 256-bit operations, the same
//! closed-box test as `WideNode::hit` and `Aabb::hit` lane by lane (unit-tested below),
//! and the walk itself (nearest child first, the others pushed farthest first) is the one
//! `traverse.rs` shares between both widths.

// The one place outside the benchmark and CLI shims that allows unsafe code: std::arch
// intrinsics and `#[target_feature]` functions can only be called in unsafe blocks (and
// only after `is_x86_feature_detected!` said yes; see `traverse`). Nothing else here is
// unsafe; the workspace's `unsafe_code = "deny"` lists this module as an exception.
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

/// Whether this CPU can also take the 16-ray AVX-512 packet kernels (`simd8/avx512.rs`).
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
pub(super) mod avx512;

#[cfg(target_arch = "x86_64")]
mod cones;
#[cfg(target_arch = "x86_64")]
mod pair;
#[cfg(target_arch = "x86_64")]
mod spheres;

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::{LeafQuery, PacketBounds, PacketSearch, RaySoa, TrianglePack, Wide8Node};
    use crate::accel::bvh::leaves::PACKED;
    use crate::accel::bvh::packet::Packet4;
    use crate::accel::bvh::traverse::{CullBound, Visit};
    use crate::accel::query::HitSearch;
    use crate::geometry::{DecidedHit, Shape, ShapeHit, ShapeKind, Sphere};
    use crate::math::robust::gamma;
    use crate::math::TraceRay;
    use crate::stats::Stats;
    use std::arch::x86_64::*;

    /// Per axis, the row of `Wide8Node::bounds` holding a box's entry plane and the one
    /// holding its exit plane, for rays running toward negative values on the axes marked.
    fn plane_rows(negative: [bool; 3]) -> ([usize; 3], [usize; 3]) {
        let near = [0, 1, 2].map(|a| if negative[a] { 3 + a } else { a });
        let far = [0, 1, 2].map(|a| if negative[a] { a } else { 3 + a });
        (near, far)
    }

    /// A ray prepared for `Ray8::hit`: origin and inverse direction broadcast per axis, and
    /// per axis the row of `Wide8Node::bounds` holding the entry plane (the max for a ray
    /// running toward negative values) and the exit plane.
    pub(super) struct Ray8 {
        origin: [__m256; 3],
        inv_dir: [__m256; 3],
        /// `inv_dir` times `CULL_SLACK`, for the exit planes: the slack applied before
        /// the exits are combined rather than after, one multiplication fewer on the
        /// visit's critical path.
        inv_exit: [__m256; 3],
        near: [usize; 3],
        far: [usize; 3],
    }

    impl Ray8 {
        #[target_feature(enable = "avx2,popcnt")]
        pub(super) fn new(ray: &TraceRay) -> Ray8 {
            let o = ray.ray.origin;
            let inv = ray.inv_dir;
            let (near, far) = plane_rows([inv.x < 0.0, inv.y < 0.0, inv.z < 0.0]);
            let slack = crate::accel::CULL_SLACK;
            Ray8 {
                origin: [o.x, o.y, o.z].map(|v| _mm256_set1_ps(v)),
                inv_dir: [inv.x, inv.y, inv.z].map(|v| _mm256_set1_ps(v)),
                inv_exit: [inv.x, inv.y, inv.z].map(|v| _mm256_set1_ps(v * slack)),
                near,
                far,
            }
        }

        /// The children hit within `t_max`: a bit mask of lanes and their entry distances
        /// (meaningful in the lanes of the mask). The slab test of `Aabb::hit` with the
        /// walk's slack (`CULL_SLACK`) on the exits, its operations arranged for a short
        /// chain of dependent steps, since a single ray's walk waits on each visit's
        /// answer: the slack is in the exit planes' inverse direction and the bound, and
        /// the three axes are combined as a tree (two steps) rather than one after the
        /// other (three). Where a slab distance is NaN (a ray parallel to an axis that
        /// starts on a box's face plane, 0 × ∞), `max`/`min` return their second operand,
        /// so the NaN drops that axis and maybe one beside it from the bound: the box may
        /// be entered where `Aabb::hit` says it is not, never the other way round. The
        /// answers do not change: a box test only decides which primitives are tested.
        ///
        /// Inlined into the walk without fail (a call per visit cost single rays about 4 %);
        /// `#[inline(always)]` cannot go with `#[target_feature]`, so the function has no
        /// target feature of its own and takes its caller's.
        ///
        /// # Safety
        /// The CPU must support AVX2 (`available`): only the AVX2-compiled walk calls it.
        #[inline(always)]
        pub(super) unsafe fn hit(&self, node: &Wide8Node, t_max: f32) -> (u32, [f32; 8]) {
            // SAFETY: AVX2 is there (the caller's contract); each row of `bounds` and `t`
            // are eight f32s (unaligned loads and store).
            unsafe {
                let load = |row: usize| _mm256_loadu_ps(node.bounds[row].as_ptr());
                let near = |axis: usize| {
                    let d = _mm256_sub_ps(load(self.near[axis]), self.origin[axis]);
                    _mm256_mul_ps(d, self.inv_dir[axis])
                };
                let far = |axis: usize| {
                    let d = _mm256_sub_ps(load(self.far[axis]), self.origin[axis]);
                    _mm256_mul_ps(d, self.inv_exit[axis])
                };
                let (near, far) = ([near(0), near(1), near(2)], [far(0), far(1), far(2)]);
                let bound = _mm256_set1_ps(t_max * crate::accel::CULL_SLACK);
                let enter = _mm256_max_ps(
                    _mm256_max_ps(near[0], near[1]),
                    _mm256_max_ps(near[2], _mm256_setzero_ps()),
                );
                let exit =
                    _mm256_min_ps(_mm256_min_ps(far[0], far[1]), _mm256_min_ps(far[2], bound));
                let hit = _mm256_cmp_ps::<_CMP_LE_OQ>(enter, exit);
                let mut t = [0.0f32; 8];
                _mm256_storeu_ps(t.as_mut_ptr(), enter);
                (_mm256_movemask_ps(hit) as u32, t)
            }
        }

        /// Children in use (unused lanes hold min = +∞).
        #[target_feature(enable = "avx2,popcnt")]
        #[inline]
        pub(super) fn children(node: &Wide8Node) -> u32 {
            // SAFETY: a row of eight f32s; unaligned load.
            let min_x = unsafe { _mm256_loadu_ps(node.bounds[0].as_ptr()) };
            let used = _mm256_cmp_ps::<_CMP_LT_OQ>(min_x, _mm256_set1_ps(f32::INFINITY));
            (_mm256_movemask_ps(used) as u32).count_ones()
        }
    }

    /// A packet prepared for `Packet8::hit`: its interval bounds broadcast per axis.
    pub(super) struct Packet8 {
        origin_near: [__m256; 3],
        origin_far: [__m256; 3],
        inv_lo: [__m256; 3],
        inv_hi: [__m256; 3],
        pub(super) near: [usize; 3],
        pub(super) far: [usize; 3],
        exit_scale: __m256,
    }

    impl Packet8 {
        #[target_feature(enable = "avx2,popcnt")]
        pub(super) fn new(b: &PacketBounds) -> Packet8 {
            let (near, far) = plane_rows(b.negative);
            Packet8 {
                origin_near: b.origin_near.map(|v| _mm256_set1_ps(v)),
                origin_far: b.origin_far.map(|v| _mm256_set1_ps(v)),
                inv_lo: b.inv_lo.map(|v| _mm256_set1_ps(v)),
                inv_hi: b.inv_hi.map(|v| _mm256_set1_ps(v)),
                near,
                far,
                exit_scale: _mm256_set1_ps(crate::accel::CULL_SLACK),
            }
        }

        /// The children some ray of the packet may enter before `t_max` (the farthest bound
        /// of its rays), per child a lower bound of every ray's entry distance, and the
        /// children that every ray enters before `t_min` (the nearest bound), for which no
        /// ray needs its own test: `packet.rs`'s interval test, eight lanes at once, and the
        /// same interval arithmetic from the other ends (held to `Packet4` and to every ray's
        /// own box test below).
        #[target_feature(enable = "avx2,popcnt")]
        #[inline]
        pub(super) fn hit(&self, node: &Wide8Node, t_max: f32, t_min: f32) -> (u32, [f32; 8], u32) {
            let load = |row: usize| {
                // SAFETY: each row of `bounds` is eight f32s; unaligned load.
                unsafe { _mm256_loadu_ps(node.bounds[row].as_ptr()) }
            };
            let zero = _mm256_setzero_ps();
            let (mut enter_lo, mut enter_hi) = (zero, zero);
            let mut exit_hi = _mm256_set1_ps(t_max);
            let mut exit_lo = _mm256_set1_ps(t_min);
            for axis in 0..3 {
                // The interval products' low and high ends: which end of the inverse
                // interval depends on the sign of the distance.
                let near_plane = load(self.near[axis]);
                let far_plane = load(self.far[axis]);
                let (lo, hi) = (self.inv_lo[axis], self.inv_hi[axis]);
                let product = |d: __m256, when_non_negative: __m256, when_negative: __m256| {
                    let non_negative = _mm256_cmp_ps::<_CMP_GE_OQ>(d, zero);
                    _mm256_mul_ps(
                        d,
                        _mm256_blendv_ps(when_negative, when_non_negative, non_negative),
                    )
                };
                let d = _mm256_sub_ps(near_plane, self.origin_near[axis]);
                enter_lo = _mm256_max_ps(product(d, lo, hi), enter_lo);
                let d = _mm256_sub_ps(far_plane, self.origin_far[axis]);
                exit_hi = _mm256_min_ps(product(d, hi, lo), exit_hi);
                let d = _mm256_sub_ps(near_plane, self.origin_far[axis]);
                enter_hi = _mm256_max_ps(product(d, hi, lo), enter_hi);
                let d = _mm256_sub_ps(far_plane, self.origin_near[axis]);
                exit_lo = _mm256_min_ps(product(d, lo, hi), exit_lo);
            }
            let some =
                _mm256_cmp_ps::<_CMP_LE_OQ>(enter_lo, _mm256_mul_ps(exit_hi, self.exit_scale));
            let all =
                _mm256_cmp_ps::<_CMP_LE_OQ>(enter_hi, _mm256_mul_ps(exit_lo, self.exit_scale));
            let mut t = [0.0f32; 8];
            // SAFETY: `t` holds eight f32s; unaligned store.
            unsafe { _mm256_storeu_ps(t.as_mut_ptr(), enter_lo) };
            let some = _mm256_movemask_ps(some) as u32;
            (some, t, some & _mm256_movemask_ps(all) as u32)
        }
    }

    /// The rays of `rays_in` (a bit per ray) whose own box test enters child `lane` of
    /// `node` before their bound: `Ray8::hit`'s test, eight rays per step instead of eight
    /// boxes.
    #[target_feature(enable = "avx2,popcnt")]
    #[inline]
    fn rays_entering(
        packet: &Packet8,
        node: &Wide8Node,
        lane: usize,
        rays_in: u64,
        soa: &RaySoa,
        bound: &[f32; 64],
    ) -> u64 {
        // Written out, as in `avx512::rays_entering`.
        let (b, n, f) = (&node.bounds, packet.near, packet.far);
        let near = [
            _mm256_set1_ps(b[n[0]][lane]),
            _mm256_set1_ps(b[n[1]][lane]),
            _mm256_set1_ps(b[n[2]][lane]),
        ];
        let far = [
            _mm256_set1_ps(b[f[0]][lane]),
            _mm256_set1_ps(b[f[1]][lane]),
            _mm256_set1_ps(b[f[2]][lane]),
        ];
        let load = |v: &[f32; 64], at: usize| {
            // SAFETY: `at + 8 <= 64`; unaligned load.
            unsafe { _mm256_loadu_ps(v.as_ptr().add(at)) }
        };
        let mut out = 0u64;
        for group in 0..8 {
            let at = 8 * group;
            let wanted = (rays_in >> at) & 0xff;
            if wanted == 0 {
                continue;
            }
            let mut enter = _mm256_setzero_ps();
            let mut exit = load(bound, at);
            for axis in 0..3 {
                let o = load(&soa.origin[axis], at);
                let inv = load(&soa.inv_dir[axis], at);
                let t_near = _mm256_mul_ps(_mm256_sub_ps(near[axis], o), inv);
                let t_far = _mm256_mul_ps(_mm256_sub_ps(far[axis], o), inv);
                enter = _mm256_max_ps(t_near, enter);
                exit = _mm256_min_ps(t_far, exit);
            }
            let hit = _mm256_cmp_ps::<_CMP_LE_OQ>(enter, _mm256_mul_ps(exit, packet.exit_scale));
            out |= ((_mm256_movemask_ps(hit) as u64) & wanted) << at;
        }
        out
    }

    /// pbrt-v4's bound on the rounding of the watertight test's t in eight lanes, from the
    /// sheared vertices' x, y and z, the edge functions and 1 / det: the scalar test's
    /// operations in its order, shared by the 8-lane kernels (one triangle against eight
    /// rays here, eight triangles against one ray in `pair.rs`).
    #[target_feature(enable = "avx2,popcnt")]
    #[inline]
    pub(super) fn t_rounding_bound(
        x: [__m256; 3],
        y: [__m256; 3],
        z: [__m256; 3],
        edges: [__m256; 3],
        inv: __m256,
    ) -> __m256 {
        let (add, mul, splat) = (_mm256_add_ps, _mm256_mul_ps, |x: f32| _mm256_set1_ps(x));
        let abs = |x: __m256| _mm256_andnot_ps(splat(-0.0), x);
        let abs_max =
            |v: [__m256; 3]| _mm256_max_ps(_mm256_max_ps(abs(v[0]), abs(v[1])), abs(v[2]));
        let (max_x, max_y, max_z) = (abs_max(x), abs_max(y), abs_max(z));
        let delta_z = mul(splat(gamma(3)), max_z);
        let delta_x = mul(splat(gamma(5)), add(max_x, max_z));
        let delta_y = mul(splat(gamma(5)), add(max_y, max_z));
        let delta_e = mul(
            splat(2.0),
            add(
                add(mul(mul(splat(gamma(2)), max_x), max_y), mul(delta_y, max_x)),
                mul(delta_x, max_y),
            ),
        );
        let max_e = abs_max(edges);
        mul(
            mul(
                splat(3.0),
                add(
                    add(mul(mul(splat(gamma(3)), max_e), max_z), mul(delta_e, max_z)),
                    mul(delta_z, max_e),
                ),
            ),
            abs(inv),
        )
    }

    /// Triangle `lane` of `pack` against the rays of `rays` (a bit per ray), which share
    /// the axis permutation `k`, eight rays per step: the whole watertight test as
    /// `TrianglePack::hits` runs it for one ray and four triangles (the same operations in
    /// the same order, the division and pbrt's bound on t included) at each ray's
    /// `nested` bound. A hit so decided is kept if it holds at the ray's own bound
    /// (`HitSearch::keep_decided`); rays with an exact zero edge function (which the
    /// scalar test re-evaluates in f64) or a value that is not finite take the scalar test.
    #[target_feature(enable = "avx2,popcnt")]
    #[inline]
    fn test_triangle(
        pack: &TrianglePack,
        lane: usize,
        k: [usize; 3],
        rays: u64,
        soa: &RaySoa,
        search: &mut PacketSearch,
    ) {
        let v = pack.lanes_by_vertex();
        let vertex = |i: usize| k.map(|axis| _mm256_set1_ps(v[i][axis][lane]));
        let (pa, pb, pc) = (vertex(0), vertex(1), vertex(2));
        let load = |v: &[f32; 64], at: usize| {
            // SAFETY: `at + 8 <= 64`; unaligned load.
            unsafe { _mm256_loadu_ps(v.as_ptr().add(at)) }
        };
        let store = |v: __m256| {
            let mut out = [0.0f32; 8];
            // SAFETY: `out` holds eight f32s; unaligned store.
            unsafe { _mm256_storeu_ps(out.as_mut_ptr(), v) };
            out
        };
        let zero = _mm256_setzero_ps();
        let sign = _mm256_set1_ps(-0.0);
        let abs = |x| _mm256_andnot_ps(sign, x);
        let splat = |x: f32| _mm256_set1_ps(x);
        let (add, sub, mul) = (_mm256_add_ps, _mm256_sub_ps, _mm256_mul_ps);
        let eq = |x| _mm256_cmp_ps::<_CMP_EQ_OQ>(x, zero);
        let lt = |x| _mm256_cmp_ps::<_CMP_LT_OQ>(x, zero);
        let gt = |x| _mm256_cmp_ps::<_CMP_GT_OQ>(x, zero);
        let or = |x, y| _mm256_or_ps(x, y);
        let and = |x, y| _mm256_and_ps(x, y);
        let prim = pack.ids[lane];
        for group in 0..8 {
            let at = 8 * group;
            let wanted = (rays >> at) & 0xff;
            if wanted == 0 {
                continue;
            }
            let o = k.map(|axis| load(&soa.origin[axis], at));
            let (sx, sy, sz) = (
                load(&soa.shear[0], at),
                load(&soa.shear[1], at),
                load(&soa.shear[2], at),
            );
            let rel = |p: &[__m256; 3]| [0, 1, 2].map(|a| sub(p[a], o[a]));
            let (a, b, c) = (rel(&pa), rel(&pb), rel(&pc));
            let sheared = |p: &[__m256; 3]| (sub(p[0], mul(sx, p[2])), sub(p[1], mul(sy, p[2])));
            let (ax, ay) = sheared(&a);
            let (bx, by) = sheared(&b);
            let (cx, cy) = sheared(&c);
            let u = sub(mul(cx, by), mul(cy, bx));
            let v = sub(mul(ax, cy), mul(ay, cx));
            let w = sub(mul(bx, ay), mul(by, ax));
            let exact_zero = or(or(eq(u), eq(v)), eq(w));
            let outside = and(or(or(lt(u), lt(v)), lt(w)), or(or(gt(u), gt(v)), gt(w)));
            let det = add(add(u, v), w);
            let (az, bz, cz) = (mul(sz, a[2]), mul(sz, b[2]), mul(sz, c[2]));
            let t_scaled = add(add(mul(u, az), mul(v, bz)), mul(w, cz));
            let nested = load(&search.nested, at);
            let limit = mul(nested, det);
            let behind_or_beyond = or(
                and(
                    lt(det),
                    or(
                        _mm256_cmp_ps::<_CMP_GE_OQ>(t_scaled, zero),
                        _mm256_cmp_ps::<_CMP_LT_OQ>(t_scaled, limit),
                    ),
                ),
                and(
                    gt(det),
                    or(
                        _mm256_cmp_ps::<_CMP_LE_OQ>(t_scaled, zero),
                        _mm256_cmp_ps::<_CMP_GT_OQ>(t_scaled, limit),
                    ),
                ),
            );
            let rejected = _mm256_movemask_ps(or(or(outside, behind_or_beyond), eq(det))) as u64;
            let exact_zero = _mm256_movemask_ps(exact_zero) as u64 & wanted;
            let open = !rejected & !exact_zero & wanted;
            let mut undecided = exact_zero;
            if open != 0 {
                // The division and pbrt-v4's bound on the rounding of t, as the scalar test.
                let inv = _mm256_div_ps(splat(1.0), det);
                let t = mul(t_scaled, inv);
                let delta_t =
                    t_rounding_bound([ax, bx, cx], [ay, by, cy], [az, bz, cz], [u, v, w], inv);
                let infinity = splat(f32::INFINITY);
                let finite = and(
                    _mm256_cmp_ps::<_CMP_LT_OQ>(abs(t), infinity),
                    _mm256_cmp_ps::<_CMP_LT_OQ>(abs(delta_t), infinity),
                );
                let within = and(
                    _mm256_cmp_ps::<_CMP_LT_OQ>(t, nested),
                    _mm256_cmp_ps::<_CMP_GT_OQ>(t, delta_t),
                );
                let finite = _mm256_movemask_ps(finite) as u64;
                let mut hit = open & finite & _mm256_movemask_ps(within) as u64;
                undecided |= open & !finite;
                if hit != 0 {
                    let (det, t_scaled, t) = (store(det), store(t_scaled), store(t));
                    let (b1, b2) = (store(mul(v, inv)), store(mul(w, inv)));
                    while hit != 0 {
                        let j = hit.trailing_zeros() as usize;
                        hit &= hit - 1;
                        let decided = DecidedHit {
                            det: det[j],
                            t_scaled: t_scaled[j],
                            t: t[j],
                            b1: b1[j],
                            b2: b2[j],
                        };
                        search.keep_decided(at + j, prim, &decided);
                    }
                }
            }
            while undecided != 0 {
                let j = undecided.trailing_zeros() as usize;
                undecided &= undecided - 1;
                search.test_pack_lane(at + j, pack, lane, &soa.ray(at + j));
            }
        }
    }

    /// `sphere` (primitive `prim`) against the rays of `rays`, eight per step: lane by lane
    /// the operations of `Sphere::intersect` in its order (`Vec3::dot` sums x, y, then z),
    /// at each ray's `nested` bound; a hit so found is kept if it holds at the ray's own
    /// bound for `prim` (`PacketSearch::keep_shape_hit`), as the scalar test decides it.
    #[target_feature(enable = "avx2,popcnt")]
    #[inline]
    fn test_sphere(
        sphere: &Sphere,
        prim: u32,
        rays: u64,
        soa: &RaySoa,
        search: &mut PacketSearch,
        stats: &mut Stats,
    ) {
        stats.count_tests(ShapeKind::Sphere, u64::from(rays.count_ones()));
        let load = |v: &[f32; 64], at: usize| {
            // SAFETY: `at + 8 <= 64`; unaligned load.
            unsafe { _mm256_loadu_ps(v.as_ptr().add(at)) }
        };
        let centre = sphere.center.to_array().map(|v| _mm256_set1_ps(v));
        let r2 = _mm256_set1_ps(sphere.radius * sphere.radius);
        for group in 0..8 {
            let at = 8 * group;
            let wanted = (rays >> at) & 0xff;
            if wanted == 0 {
                continue;
            }
            let origin = [0, 1, 2].map(|a| load(&soa.origin[a], at));
            let dir = [0, 1, 2].map(|a| load(&soa.dir[a], at));
            let nested = load(&search.nested, at);
            let (hit, t) = super::spheres::sphere_lanes(origin, dir, centre, r2, nested);
            let mut hit = wanted & u64::from(hit);
            if hit != 0 {
                let mut ts = [0.0f32; 8];
                // SAFETY: `ts` holds eight f32s; unaligned store.
                unsafe { _mm256_storeu_ps(ts.as_mut_ptr(), t) };
                while hit != 0 {
                    let j = hit.trailing_zeros() as usize;
                    hit &= hit - 1;
                    let shape_hit = ShapeHit {
                        t: ts[j],
                        u: 0.0,
                        v: 0.0,
                    };
                    search.keep_shape_hit(at + j, prim, shape_hit);
                }
            }
        }
    }

    /// The packet walk and its leaf tests, made once per instruction set: `$entering`,
    /// `$triangle` and `$sphere` are the per-ray kernels (eight rays per step with AVX2,
    /// sixteen with AVX-512), the rest is the same code compiled with `$features`.
    macro_rules! packet_traversal {
        (
            $traverse:ident,
            $test_pack:ident,
            $features:literal,
            $entering:path,
            $triangle:path,
            $sphere:path
        ) => {
            /// `super::traverse_packet` compiled for this instruction set.
            ///
            /// # Safety
            /// The CPU must support the instruction set (`available`, and
            /// `avx512_available` for the AVX-512 variant).
            #[target_feature(enable = $features)]
            #[allow(clippy::too_many_arguments)]
            pub(super) unsafe fn $traverse<const ORDERED: bool>(
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
                    // Each child the packet may enter goes on with the rays that do enter it.
                    |node: &Wide8Node, s: &PacketSearch, rays: u64| {
                        let (mut some, entries, everyone) = packet.hit(node, s.t_max(), s.t_min());
                        let (mut hit, mut entering) = (0u32, [0u64; 8]);
                        while some != 0 {
                            let k = some.trailing_zeros() as usize;
                            some &= some - 1;
                            entering[k] = if everyone >> k & 1 == 1 {
                                rays
                            } else {
                                $entering(&packet, node, k, rays, soa, &s.bound)
                            };
                            if entering[k] != 0 {
                                hit |= 1 << k;
                            }
                        }
                        Visit {
                            children: Ray8::children(node),
                            hit,
                            entries,
                            rays: entering,
                        }
                    },
                    search,
                    stats,
                    |child, count, enter, rays, search: &mut PacketSearch, stats: &mut Stats| {
                        let rays = rays & search.open();
                        let first = child as usize;
                        if count & PACKED != 0 {
                            // The rays of each axis permutation against the packs in
                            // turn (per ray the order of `LeafQuery::test`); a few rays
                            // one by one, whose own test takes two packs a step.
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
                                    $test_pack(pack, k, rays, soa, &box_test, search, stats);
                                }
                            }
                        } else {
                            // Primitive by primitive, each against the rays still
                            // searching: per ray the order of `LeafQuery::test`.
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
                                        $sphere(sphere, prim, rays, soa, search, stats)
                                    }
                                    Shape::Cone(cone) => super::cones::test_cone(
                                        cone, prim, rays, soa, search, stats,
                                    ),
                                    _ => search.test_per_ray(geometry, prim, rays, soa, stats),
                                }
                            }
                        }
                        search.finish_leaf()
                    },
                )
            }

            /// Tests the triangles of `pack` for the rays of `rays` still searching, which
            /// share the axis permutation `k`: the triangles' boxes against the packet's
            /// interval first (a triangle none of the rays can reach is skipped for all of
            /// them), then one triangle against several rays at a time (`$triangle`).
            #[target_feature(enable = $features)]
            #[inline]
            fn $test_pack(
                pack: &TrianglePack,
                k: [usize; 3],
                rays: u64,
                soa: &RaySoa,
                box_test: &Packet4,
                search: &mut PacketSearch,
                stats: &mut Stats,
            ) {
                let open = rays & search.open();
                if open == 0 {
                    return;
                }
                let v = pack.lanes_by_vertex();
                let min = [0, 1, 2].map(|a| v[0][a].min(v[1][a]).min(v[2][a]));
                let max = [0, 1, 2].map(|a| v[0][a].max(v[1][a]).max(v[2][a]));
                let (mut lanes, _) = box_test.hit_boxes(min, max, search.t_max());
                lanes &= (1 << pack.len()) - 1;
                stats.count_tests(
                    ShapeKind::Triangle,
                    u64::from(lanes.count_ones()) * u64::from(open.count_ones()),
                );
                while lanes != 0 {
                    let lane = lanes.trailing_zeros() as usize;
                    lanes &= lanes - 1;
                    $triangle(pack, lane, k, rays & search.open(), soa, search);
                }
            }
        };
    }

    packet_traversal!(
        traverse_packet,
        test_pack,
        "avx2,popcnt",
        rays_entering,
        test_triangle,
        test_sphere
    );
    packet_traversal!(
        traverse_packet16,
        test_pack16,
        "avx2,popcnt,avx512f",
        super::avx512::rays_entering,
        super::avx512::test_triangle,
        super::avx512::test_sphere
    );

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
                // SAFETY: this walk is compiled for AVX2, which the caller checked.
                let (hit, entries) = unsafe { ray8.hit(node, s.t_max()) };
                Visit {
                    children: Ray8::children(node),
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
                // SAFETY: AVX2 was detected above.
                let (some, entries, all) =
                    unsafe { Packet8::new(&bounds).hit(&node, t_max, t_min) };
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
            // SAFETY: the callers skip without AVX2.
            let (mask, t) = unsafe { Ray8::new(ray).hit(&w, t_max) };
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
