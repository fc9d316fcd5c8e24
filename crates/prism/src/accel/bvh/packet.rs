//! Packets: several coherent rays (a block of camera rays) walked through the tree
//! together. A node visit tests the children's boxes once for the whole packet, against
//! the interval of its origins and inverse directions (interval arithmetic, as Boulos et
//! al. 2006 cull whole packets): a child none of the rays can enter is skipped for all of
//! them with one SIMD test instead of one per ray. A leaf's primitives are tested against
//! the rays that reach it, several rays per SIMD step for triangle packs and spheres
//! (`simd8.rs`) and ray by ray otherwise, each ray with its own search, skipping rays whose
//! best hit already lies before the leaf, so every ray gets exactly the answer its own
//! query gives (the tie rule is per ray, the SIMD tests are the scalar tests' operations
//! lane by lane, and the interval test only ever lets through more than a ray's own test
//! would).
//!
//! The interval test is exact about rounding: subtraction and multiplication round
//! monotonically, so bounds computed from the extreme origins and inverse directions bound
//! every ray's own rounded slab distances. It needs every ray's direction to have the same
//! sign on each axis and no zero component (no infinite inverse); other packets are
//! answered one ray at a time.

use super::accel::Root;
use super::traverse::{walk, CullBound, LeafQuery, Visit};
use super::wide::{plane_rows, WideNode};
use super::Bvh;
use crate::accel::query::HitSearch;
use crate::accel::{Hit, PacketQuery, QueryMode, RayQuery, CULL_SLACK, PACKET_MAX};
use crate::geometry::{DecidedHit, Geometry, PackRay, ShapeHit, TrianglePack};
use crate::math::lanes::{axes, FloatLanes};
use crate::math::{permutation, watertight_axes, Ray, TraceRay, Vec3};
use crate::stats::Stats;
use arrayvec::ArrayVec;
use glam::Vec4;

/// The extremes of a packet's rays per axis, arranged for the box test: the origin bound
/// that gives the nearest entry into a box and the one that gives the farthest exit, and
/// the inverse directions' interval.
#[derive(Clone, Copy, Debug)]
pub(super) struct PacketBounds {
    /// Per axis, whether the rays run toward negative values (the box's max is entered).
    pub negative: [bool; 3],
    /// Per axis, the origin coordinate that makes `entry plane - origin` smallest (the
    /// largest origin for a positive direction, the smallest for a negative one).
    pub origin_near: [f32; 3],
    /// Per axis, the origin coordinate that makes `exit plane - origin` largest.
    pub origin_far: [f32; 3],
    /// Per axis, the smallest inverse direction.
    pub inv_lo: [f32; 3],
    /// Per axis, the largest inverse direction.
    pub inv_hi: [f32; 3],
}

impl PacketBounds {
    /// The bounds of `rays`, as `of` gives them (for tests of the box tests).
    #[cfg(test)]
    pub(super) fn of_rays(rays: &[Ray]) -> Option<PacketBounds> {
        PacketBounds::of(&RaySoa::new(rays))
    }

    /// The bounds of the rays of `soa`, or None when their directions disagree in sign
    /// on some axis, or an origin or inverse direction is not finite (a zero or NaN
    /// direction component): such packets are not coherent enough to share a walk.
    fn of(soa: &RaySoa) -> Option<PacketBounds> {
        let mut b = PacketBounds {
            negative: [false; 3],
            origin_near: [0.0; 3],
            origin_far: [0.0; 3],
            inv_lo: [0.0; 3],
            inv_hi: [0.0; 3],
        };
        // Over the filled lanes four at a time (the padding repeats the first ray).
        // `min`/`max` may drop a NaN, but a NaN fails the finiteness test, which rejects
        // the packet.
        let fold = |row: &[f32; PACKET_MAX]| {
            let (mut lo, mut hi, mut finite) = (Vec4::INFINITY, Vec4::NEG_INFINITY, true);
            for k in (0..soa.lanes).step_by(4) {
                let v = Vec4::from_slice(&row[k..k + 4]);
                (lo, hi) = (lo.min(v), hi.max(v));
                finite &= v.abs().cmplt(Vec4::INFINITY).all();
            }
            (lo.min_element(), hi.max_element(), finite)
        };
        for a in 0..3 {
            let (lo, hi, inv_finite) = fold(&soa.inv_dir[a]);
            let (o_lo, o_hi, o_finite) = fold(&soa.origin[a]);
            if !(inv_finite && o_finite && (lo > 0.0 || hi < 0.0)) {
                return None;
            }
            let negative = hi < 0.0;
            b.negative[a] = negative;
            (b.origin_near[a], b.origin_far[a]) =
                if negative { (o_lo, o_hi) } else { (o_hi, o_lo) };
            (b.inv_lo[a], b.inv_hi[a]) = (lo, hi);
        }
        Some(b)
    }
}

/// A packet's bounds for the interval box test, broadcast per axis in lanes `L`, a box per
/// lane: four with glam's `Vec4` (`Packet4`: the 4-wide nodes' children, the boxes of a
/// triangle pack's four triangles), eight with AVX2 (the 8-wide nodes' children, `simd8.rs`).
pub(super) struct PacketBoxes<L> {
    origin_near: [L; 3],
    origin_far: [L; 3],
    inv_lo: [L; 3],
    inv_hi: [L; 3],
    /// Per axis, the row of a node's bounds (rows `axis` minima, rows `3 + axis` maxima)
    /// holding the boxes' entry planes for the packet's rays, and the exit planes.
    pub near: [usize; 3],
    pub far: [usize; 3],
}

impl<L: FloatLanes> PacketBoxes<L> {
    #[inline(always)]
    pub(super) fn new(bounds: &PacketBounds) -> PacketBoxes<L> {
        let (near, far) = plane_rows(bounds.negative);
        PacketBoxes {
            origin_near: axes(|a| L::splat(bounds.origin_near[a])),
            origin_far: axes(|a| L::splat(bounds.origin_far[a])),
            inv_lo: axes(|a| L::splat(bounds.inv_lo[a])),
            inv_hi: axes(|a| L::splat(bounds.inv_hi[a])),
            near,
            far,
        }
    }

    /// The boxes some ray of the packet may enter before `t_max` (the farthest bound of its
    /// rays, as bits) and per box a lower bound of every ray's entry distance, from the
    /// boxes' bounds `row` by row. With `EVERY`, also the boxes every ray enters before
    /// `t_min` (the nearest bound), for which no ray needs its own test: the same interval
    /// arithmetic from the other ends (held to every ray's own box test in `simd8.rs`'s
    /// tests); else no bits. The packet's inverse directions are finite and nonzero and its
    /// origins finite (`PacketBounds::of`), so no product is NaN.
    #[inline(always)]
    pub(super) fn hit<const EVERY: bool>(
        &self,
        row: impl Fn(usize) -> L,
        t_max: f32,
        t_min: f32,
    ) -> (u32, L, u32) {
        let zero = L::splat(0.0);
        // The interval products' low and high ends: which end of the inverse interval
        // depends on the sign of the distance.
        let product = |d: L, when_non_negative: L, when_negative: L| {
            d * L::select(d.ge(zero), when_non_negative, when_negative)
        };
        let (mut enter_lo, mut enter_hi) = (zero, zero);
        let (mut exit_hi, mut exit_lo) = (L::splat(t_max), L::splat(t_min));
        for axis in 0..3 {
            let (near_plane, far_plane) = (row(self.near[axis]), row(self.far[axis]));
            let (lo, hi) = (self.inv_lo[axis], self.inv_hi[axis]);
            let (origin_near, origin_far) = (self.origin_near[axis], self.origin_far[axis]);
            enter_lo = product(near_plane - origin_near, lo, hi).max(enter_lo);
            exit_hi = product(far_plane - origin_far, hi, lo).min(exit_hi);
            if EVERY {
                enter_hi = product(near_plane - origin_far, hi, lo).max(enter_hi);
                exit_lo = product(far_plane - origin_near, lo, hi).min(exit_lo);
            }
        }
        let slack = L::splat(CULL_SLACK);
        let some = L::bits(enter_lo.le(exit_hi * slack));
        let every = if EVERY {
            some & L::bits(enter_hi.le(exit_lo * slack))
        } else {
            0
        };
        (some, enter_lo, every)
    }
}

/// The 4-wide interval box test (`PacketBoxes` in glam's `Vec4`).
pub(super) struct Packet4(PacketBoxes<Vec4>);

impl Packet4 {
    pub(super) fn new(bounds: PacketBounds) -> Packet4 {
        Packet4(PacketBoxes::new(&bounds))
    }

    /// Per child, a lower bound of the entry distance of every ray of the packet into its
    /// box, and whether some ray may enter it before `t_max`.
    #[inline(always)]
    fn hit(&self, node: &WideNode, t_max: f32) -> (u32, Vec4) {
        let (some, enter, _) = self.0.hit::<false>(|row| node.row(row), t_max, t_max);
        (some, enter)
    }

    /// `hit` for four boxes given by their minima and maxima per axis.
    #[inline(always)]
    pub(super) fn hit_boxes(&self, min: [Vec4; 3], max: [Vec4; 3], t_max: f32) -> (u32, Vec4) {
        let rows = [min[0], min[1], min[2], max[0], max[1], max[2]];
        let (some, enter, _) = self.0.hit::<false>(|row| rows[row], t_max, t_max);
        (some, enter)
    }
}

/// The rays of a packet in SoA form for the per-ray SIMD tests (`simd8.rs`): per axis,
/// ray i's origin, direction and inverse direction; the watertight test's shear and axis
/// permutation. Lanes past the packet's rays, up to a multiple of 16, repeat its first
/// ray, so that folds over them (`PacketBounds::of`) need no mask; the per-ray tests never
/// let them through, and lanes beyond are never read.
///
/// Built straight from the rays, lane by lane with the operations of `TraceRay::new`
/// (`watertight_axes`, so `ray(i)` is bit for bit `TraceRay::new(rays[i])`), in loops the
/// compiler vectorises:
/// preparing the rays one `TraceRay` at a time, then copying them into these arrays, took
/// a third or more of a primary packet's time on the bunny.
pub(super) struct RaySoa {
    pub(super) origin: [[f32; PACKET_MAX]; 3],
    pub(super) dir: [[f32; PACKET_MAX]; 3],
    pub(super) inv_dir: [[f32; PACKET_MAX]; 3],
    pub(super) shear: [[f32; PACKET_MAX]; 3],
    /// Per ray, its axis permutation as `kx | ky << 2 | kz << 4`.
    axes: [u32; PACKET_MAX],
    /// The rays' axis permutations (kx, ky, kz), each with a bit per ray that has it, so
    /// that one triangle can be tested against several rays exactly as each ray's own
    /// first pass tests it: a packet across the diagonal planes where the dominant axis
    /// changes has two or more.
    pub(super) permutations: ArrayVec<([usize; 3], u64), 6>,
    /// The lanes filled: the rays, and the padding that repeats the first.
    lanes: usize,
}

impl RaySoa {
    /// Ray i prepared for the scalar tests: what `TraceRay::new` gives it.
    #[inline(always)]
    pub(super) fn ray(&self, i: usize) -> TraceRay {
        let lane = |rows: &[[f32; PACKET_MAX]; 3]| [rows[0][i], rows[1][i], rows[2][i]];
        let ray = Ray::new(
            Vec3::from_array(lane(&self.origin)),
            Vec3::from_array(lane(&self.dir)),
        );
        TraceRay::with_constants(ray, lane(&self.inv_dir), self.axes[i], lane(&self.shear))
    }

    /// The rays of `rays` in SoA form (a packet's own copy; `query` reuses one per thread).
    #[cfg(test)]
    pub(super) fn new(rays: &[Ray]) -> RaySoa {
        let mut soa = RaySoa::empty();
        soa.fill(rays);
        soa.group_by_permutation(rays.len());
        soa
    }

    /// Room for a packet, no lanes filled.
    fn empty() -> RaySoa {
        RaySoa {
            origin: [[0.0; PACKET_MAX]; 3],
            dir: [[0.0; PACKET_MAX]; 3],
            inv_dir: [[0.0; PACKET_MAX]; 3],
            shear: [[0.0; PACKET_MAX]; 3],
            axes: [0; PACKET_MAX],
            permutations: ArrayVec::new(),
            lanes: 0,
        }
    }

    /// Fills the lanes of `rays` and their padding; lanes past those keep what an earlier
    /// packet left there, which nothing reads. `permutations` is left empty until
    /// `group_by_permutation`.
    #[inline(always)]
    pub(super) fn fill(&mut self, rays: &[Ray]) {
        assert!(rays.len() <= PACKET_MAX);
        let soa = self;
        soa.lanes = rays.len().next_multiple_of(16);
        soa.permutations.clear();
        let Some(first) = rays.first() else {
            return;
        };
        for (i, r) in rays.iter().enumerate() {
            (soa.origin[0][i], soa.origin[1][i], soa.origin[2][i]) =
                (r.origin.x, r.origin.y, r.origin.z);
            (soa.dir[0][i], soa.dir[1][i], soa.dir[2][i]) = (r.dir.x, r.dir.y, r.dir.z);
        }
        let (n, lanes) = (rays.len(), soa.lanes);
        let first_lanes = first
            .origin
            .to_array()
            .into_iter()
            .zip(first.dir.to_array());
        for (a, (o, d)) in first_lanes.enumerate() {
            soa.origin[a][n..lanes].fill(o);
            soa.dir[a][n..lanes].fill(d);
        }
        // `TraceRay::new`'s operations lane by lane, in a loop without a branch.
        for i in 0..lanes {
            let d = [soa.dir[0][i], soa.dir[1][i], soa.dir[2][i]];
            let inv = d.map(|v| 1.0 / v);
            let (axes, shear) = watertight_axes(d, inv);
            for a in 0..3 {
                soa.inv_dir[a][i] = inv[a];
                soa.shear[a][i] = shear[a];
            }
            soa.axes[i] = axes;
        }
    }

    /// Groups the first `n` rays (those `fill` was given) by axis permutation into
    /// `permutations`. Only a packet that walks needs the groups; one that is answered ray
    /// by ray (directions in several octants, as most of a path tracer's are after the
    /// first bounce) skips the search for each ray's group, which `perf` put at about a
    /// tenth of the packet query's own samples on `cornell-light`'s paths.
    fn group_by_permutation(&mut self, n: usize) {
        let soa = self;
        soa.permutations.clear();
        if n == 0 {
            return;
        }
        let lanes = soa.lanes;
        // Whether the rays share one permutation, folded with `&` rather than left early,
        // so the loop has no dependent branch per ray; only where they do not are they
        // sorted into groups.
        let first = soa.axes[0];
        let every_ray = u64::MAX >> (PACKET_MAX - n);
        if soa.axes[..lanes]
            .iter()
            .fold(true, |all, &c| all & (c == first))
        {
            soa.permutations.push((permutation(first), every_ray));
        } else {
            let mut codes: ArrayVec<(u32, u64), 6> = ArrayVec::new();
            for (i, &code) in soa.axes[..n].iter().enumerate() {
                match codes.iter_mut().find(|(c, _)| *c == code) {
                    Some((_, rays)) => *rays |= 1 << i,
                    None => codes.push((code, 1 << i)),
                }
            }
            (soa.permutations).extend(codes.into_iter().map(|(c, r)| (permutation(c), r)));
        }
    }
}

/// One search per ray of the packet, and the farthest bound any of them still has.
pub(super) struct PacketSearch {
    searches: ArrayVec<HitSearch, PACKET_MAX>,
    /// Rays whose query is answered (any-hit rays that found a blocker), a bit per ray.
    done: u64,
    all: u64,
    t_max: f32,
    /// The nearest bound of the rays still searching: a box every ray enters before it is
    /// entered by all of them.
    t_min: f32,
    /// Per ray, its search's bound (−∞ once answered, and past the packet's rays), read
    /// by the per-ray box tests.
    pub(super) bound: [f32; PACKET_MAX],
    /// Per ray, its search's bound for a first pass over triangles (`nested_limit`).
    pub(super) nested: [f32; PACKET_MAX],
    /// `bound` with +∞ instead of −∞ where a ray is answered or past the packet's rays:
    /// the lanes `finish_leaf` takes the nearest bound of.
    open_bound: [f32; PACKET_MAX],
}

impl CullBound for PacketSearch {
    type Rays = u64;
    const BY_BRANCHES: bool = false;
    #[inline(always)]
    fn t_max(&self) -> f32 {
        self.t_max
    }
    #[inline(always)]
    fn all_rays(&self) -> u64 {
        self.open()
    }
    #[inline(always)]
    fn resume(&self, rays: u64, t_enter: f32) -> Option<u64> {
        let rays = rays & self.open();
        (rays != 0 && t_enter <= self.t_max * CULL_SLACK).then_some(rays)
    }
}

impl PacketSearch {
    /// Room for a packet's searches, none started.
    fn empty() -> PacketSearch {
        PacketSearch {
            searches: ArrayVec::new(),
            done: 0,
            all: 0,
            t_max: 0.0,
            t_min: f32::INFINITY,
            bound: [f32::NEG_INFINITY; PACKET_MAX],
            nested: [f32::NEG_INFINITY; PACKET_MAX],
            open_bound: [f32::INFINITY; PACKET_MAX],
        }
    }

    /// Starts a search per ray, ray i's up to `t_max[i]`.
    #[inline(always)]
    fn reset(&mut self, t_max: &[f32], mode: QueryMode) {
        let n = t_max.len();
        self.searches.clear();
        self.searches
            .extend(t_max.iter().map(|&t| HitSearch::new(t, mode)));
        self.all = if n == 64 { u64::MAX } else { (1u64 << n) - 1 };
        self.done = 0;
        self.bound[..n].copy_from_slice(t_max);
        self.nested[..n].copy_from_slice(t_max);
        self.open_bound[..n].copy_from_slice(t_max);
        self.bound[n..].fill(f32::NEG_INFINITY);
        self.nested[n..].fill(f32::NEG_INFINITY);
        self.open_bound[n..].fill(f32::INFINITY);
        self.t_max = t_max.iter().copied().fold(0.0, f32::max);
        self.t_min = t_max.iter().copied().fold(f32::INFINITY, f32::min);
    }

    /// The nearest bound of the rays still searching.
    #[inline(always)]
    pub(super) fn t_min(&self) -> f32 {
        self.t_min
    }

    /// The rays still searching, a bit per ray.
    #[inline(always)]
    pub(super) fn open(&self) -> u64 {
        !self.done & self.all
    }

    /// Ray i's search after a test: its bounds for the SIMD tests, and whether it is
    /// answered.
    #[inline(always)]
    fn settle(&mut self, i: usize, answered: bool) {
        if answered {
            self.done |= 1 << i;
            self.bound[i] = f32::NEG_INFINITY;
            self.nested[i] = f32::NEG_INFINITY;
            self.open_bound[i] = f32::INFINITY;
        } else {
            self.bound[i] = self.searches[i].t_max();
            self.nested[i] = self.searches[i].nested_limit();
            self.open_bound[i] = self.bound[i];
        }
    }

    /// After a leaf: the packet's bound is the farthest of its open rays'; true when every
    /// ray is answered.
    #[inline(always)]
    pub(super) fn finish_leaf(&mut self) -> bool {
        // Over all lanes, four at a time: answered rays and lanes past the packet hold −∞
        // in `bound` and +∞ in `open_bound`, so they change neither extreme (a loop over
        // the open rays' bits cost several percent of a render).
        let (mut far, mut near) = (Vec4::NEG_INFINITY, Vec4::INFINITY);
        for k in (0..PACKET_MAX).step_by(4) {
            far = Vec4::from_slice(&self.bound[k..k + 4]).max(far);
            near = Vec4::from_slice(&self.open_bound[k..k + 4]).min(near);
        }
        (self.t_max, self.t_min) = (far.max_element(), near.min_element());
        self.done == self.all
    }

    /// Ray i keeps triangle `prim`'s hit if it holds at its own bound: `decided` by a SIMD
    /// pass at `nested[i]`.
    #[inline(always)]
    pub(super) fn keep_decided(&mut self, i: usize, prim: u32, decided: &DecidedHit) {
        let answered = self.searches[i].keep_decided(prim, decided);
        self.settle(i, answered);
    }

    /// The scalar test of triangle `lane` of `pack` for ray i, which a first pass kept.
    #[inline(always)]
    pub(super) fn test_pack_lane(
        &mut self,
        i: usize,
        pack: &TrianglePack,
        lane: usize,
        ray: &TraceRay,
    ) {
        let answered = self.searches[i].test_pack_lane(pack, lane, ray);
        self.settle(i, answered);
    }

    /// The rays of `rays` still searching that may meet something in a leaf whose box
    /// they enter no nearer than `enter` (with the slack the box tests give exits).
    #[inline(always)]
    pub(super) fn reaching(&self, rays: u64, enter: f32) -> u64 {
        let (mut open, mut out) = (rays & self.open(), 0u64);
        while open != 0 {
            let i = open.trailing_zeros() as usize;
            open &= open - 1;
            if enter <= self.bound[i] * CULL_SLACK {
                out |= 1 << i;
            }
        }
        out
    }

    /// Primitive `prim` for each ray of `rays`, one at a time (shapes without a packet test).
    #[inline(always)]
    pub(super) fn test_per_ray(
        &mut self,
        geometry: &Geometry,
        prim: u32,
        rays: u64,
        soa: &RaySoa,
        stats: &mut Stats,
    ) {
        let mut open = rays;
        while open != 0 {
            let i = open.trailing_zeros() as usize;
            open &= open - 1;
            let answered = self.searches[i].test(geometry, &soa.ray(i), prim, stats);
            self.settle(i, answered);
        }
    }

    /// Ray i keeps `hit` on primitive `prim` if it holds at its own bound: found by a SIMD
    /// pass at `nested[i]` with the scalar test's operations.
    #[inline(always)]
    pub(super) fn keep_shape_hit(&mut self, i: usize, prim: u32, hit: ShapeHit) {
        let answered = self.searches[i].keep_within(prim, hit);
        self.settle(i, answered);
    }

    /// Tests a leaf for the rays of `rays_in` (a bit per ray) that are still searching, one
    /// ray at a time; `enter` is a lower bound of their entry distances.
    #[inline(always)]
    pub(super) fn test_leaf_per_ray(
        &mut self,
        leaf: &LeafQuery,
        soa: &RaySoa,
        (first, count, enter): (u32, u32, f32),
        rays_in: u64,
        stats: &mut Stats,
    ) {
        // A ray's bound changes only with its own tests, so the rays reaching the leaf
        // can be found before any of them is tested.
        let mut open = self.reaching(rays_in, enter);
        while open != 0 {
            let i = open.trailing_zeros() as usize;
            open &= open - 1;
            let ray = soa.ray(i);
            let pack_ray = PackRay::new(&ray);
            let ray_leaf = LeafQuery {
                ray: &ray,
                pack_ray: &pack_ray,
                ..*leaf
            };
            let answered = ray_leaf.test(first, count, &mut self.searches[i], stats);
            self.settle(i, answered);
        }
    }
}

/// Answers `rays` (at most `PACKET_MAX`, each with its own bound) as a packet where they
/// are coherent, as a packet per octant where they are not but an octant holds enough
/// of them (`Octants`), one by one otherwise, over the subtrees below `root` (an entry node,
/// `subtree.rs`) or the whole tree without one: `answers[i]` is what `Accel::query` (or
/// `Bvh::walk_from` from `root`) gives `rays[i]`.
#[inline(always)]
pub(super) fn query(
    bvh: &Bvh,
    root: Option<Root<'_>>,
    packet: &PacketQuery,
    answers: &mut [Option<Hit>],
    stats: &mut Stats,
) {
    let PacketQuery {
        geometry,
        rays,
        t_max,
        mode,
    } = *packet;
    assert!(rays.len() <= PACKET_MAX && t_max.len() == rays.len() && answers.len() == rays.len());
    let mut run = |scratch: &mut Scratch| {
        query_in(
            scratch, bvh, root, geometry, rays, t_max, mode, answers, stats,
        );
    };
    SCRATCH.with(|cell| match cell.try_borrow_mut() {
        Ok(mut scratch) => run(&mut scratch),
        // A query inside a query (none today) gets room of its own.
        Err(_) => run(&mut Box::new(Scratch::new())),
    });
}

/// The octants of a packet's rays, and those that hold enough of them to walk as a
/// packet of their own.
struct Octants {
    /// Per ray, its octant (a bit per axis whose direction is negative), or `NONE` for a
    /// ray with a zero or non-finite direction component or origin.
    of_ray: [u8; PACKET_MAX],
    /// A bit per octant walked as a packet.
    together: u8,
}

impl Octants {
    const NONE: u8 = 8;
    /// The fewest rays of one octant walked as a packet. A packet across an axis plane
    /// of a camera's view, or of shadow rays toward a light amid their hits, splits into
    /// coherent parts; the rays a packet of reflected rays holds in one octant come from
    /// all over its hits, and walked together from 4 of them they were slower than one
    /// by one on SPD balls, lattice and rings, from 16 level (docs/journal/performance.md,
    /// seventeenth and eighteenth steps).
    const MIN_RAYS: usize = 16;

    fn none() -> Octants {
        Octants {
            of_ray: [Octants::NONE; PACKET_MAX],
            together: 0,
        }
    }

    /// The octants of the first `n` rays of `soa`.
    fn of(soa: &RaySoa, n: usize) -> Octants {
        let mut octants = Octants::none();
        let mut count = [0usize; 9];
        for (i, octant) in octants.of_ray[..n].iter_mut().enumerate() {
            let finite =
                (0..3).all(|a| soa.inv_dir[a][i].is_finite() && soa.origin[a][i].is_finite());
            *octant = if finite {
                (0..3).fold(0, |bits, a| bits | u8::from(soa.inv_dir[a][i] < 0.0) << a)
            } else {
                Octants::NONE
            };
            count[usize::from(*octant)] += 1;
        }
        for (octant, &c) in count[..8].iter().enumerate() {
            if c >= Octants::MIN_RAYS {
                octants.together |= 1 << octant;
            }
        }
        octants
    }

    fn walks_together(&self, ray: usize) -> bool {
        let octant = self.of_ray[ray];
        octant != Octants::NONE && self.together >> octant & 1 == 1
    }

    fn together(&self) -> impl Iterator<Item = u8> + '_ {
        (0..8u8).filter(|&o| self.together >> o & 1 == 1)
    }
}

/// What a packet query works in: its rays in SIMD lanes and its per-ray searches, about
/// 6 KiB. Built afresh for every packet, zeroed and then copied into place, they cost a
/// few percent of a frame of the viewer's default scene; one per thread is refilled
/// instead (`RaySoa::fill`, `PacketSearch::reset`).
struct Scratch {
    soa: RaySoa,
    search: PacketSearch,
}

impl Scratch {
    fn new() -> Scratch {
        Scratch {
            soa: RaySoa::empty(),
            search: PacketSearch::empty(),
        }
    }
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Box<Scratch>> = std::cell::RefCell::new(Box::new(Scratch::new()));
}

/// `query` in `scratch`.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn query_in(
    scratch: &mut Scratch,
    bvh: &Bvh,
    root: Option<Root<'_>>,
    geometry: &Geometry,
    rays: &[Ray],
    t_max: &[f32],
    mode: QueryMode,
    answers: &mut [Option<Hit>],
    stats: &mut Stats,
) {
    use crate::accel::Accel;
    scratch.soa.fill(rays);
    let walkable = rays.len() > 1 && !bvh.nodes.first().is_none_or(|n| n.is_leaf());
    let bounds = PacketBounds::of(&scratch.soa).filter(|_| walkable);
    if bounds.is_some() {
        scratch.soa.group_by_permutation(rays.len());
    }
    let Some(bounds) = bounds else {
        let soa = &scratch.soa;
        // Rays in several octants: those of an octant that holds enough of them (a
        // camera packet across an axis plane of the view) walk as a packet of their own,
        // the others one by one.
        let octants = if walkable {
            Octants::of(soa, rays.len())
        } else {
            Octants::none()
        };
        for (i, (&t, answer)) in t_max.iter().zip(answers.iter_mut()).enumerate() {
            if !octants.walks_together(i) {
                *answer = match root {
                    None => bvh.query(&RayQuery::new(geometry, &soa.ray(i), t, mode), stats),
                    Some(root) => bvh.walk_from(root, geometry, &soa.ray(i), t, mode, stats),
                };
            }
        }
        for octant in octants.together() {
            let lanes: ArrayVec<usize, PACKET_MAX> = (0..rays.len())
                .filter(|&i| octants.of_ray[i] == octant)
                .collect();
            let group: ArrayVec<Ray, PACKET_MAX> = lanes.iter().map(|&i| rays[i]).collect();
            let bounds: ArrayVec<f32, PACKET_MAX> = lanes.iter().map(|&i| t_max[i]).collect();
            let mut found = [None; PACKET_MAX];
            let found = &mut found[..lanes.len()];
            // Their directions agree in sign and are finite, so `PacketBounds::of` takes
            // them and this query walks them: it never comes back here.
            query_in(
                scratch, bvh, root, geometry, &group, &bounds, mode, found, stats,
            );
            for (&i, &hit) in lanes.iter().zip(found.iter()) {
                answers[i] = hit;
            }
        }
        return;
    };
    let Scratch { soa, search } = scratch;
    let soa = &*soa;
    // The leaf tests' shared parts; the walk hands each leaf its rays.
    let first = soa.ray(0);
    let first_pack_ray = PackRay::new(&first);
    let leaf = bvh.leaf_query(geometry, &first, &first_pack_ray);
    search.reset(t_max, mode);
    if !bvh.wide8.is_empty() {
        let root = match root {
            Some(Root::Eight(node)) => node,
            _ => &bvh.wide8[0],
        };
        super::simd8::traverse_packet(
            bvh.packet_avx512,
            mode == QueryMode::Any,
            &bvh.wide8,
            root,
            &bounds,
            soa,
            &leaf,
            search,
            stats,
            |c, n, enter, rays_in, s: &mut PacketSearch, st: &mut Stats| {
                s.test_leaf_per_ray(&leaf, soa, (c, n, enter), rays_in, st)
            },
        );
    } else {
        let packet = Packet4::new(bounds);
        let root = match root {
            Some(Root::Four(node)) => node,
            _ => &bvh.wide[0],
        };
        walk::<_, _, true>(
            &bvh.wide,
            root,
            // Interval culling only: every child goes on with all the rays that reached it.
            |node: &WideNode, s: &PacketSearch, entering: u64| {
                let (hit, t) = packet.hit(node, s.t_max());
                let mut entries = [0.0; 8];
                entries[..4].copy_from_slice(&t.to_array());
                Visit {
                    children: node.children(),
                    hit,
                    entries,
                    rays: [entering; 8],
                }
            },
            search,
            stats,
            |c, n, enter, entering, s: &mut PacketSearch, st: &mut Stats| {
                s.test_leaf_per_ray(&leaf, soa, (c, n, enter), entering, st);
                s.finish_leaf()
            },
        );
    }
    for (answer, s) in answers.iter_mut().zip(&search.searches) {
        *answer = s.best();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::hash::uniform;

    /// Bit for bit, so that a packet's SIMD tests and its scalar fallbacks see each ray
    /// exactly as its own query does.
    fn same(a: &TraceRay, b: &TraceRay) -> bool {
        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
        bits(a.ray.origin) == bits(b.ray.origin)
            && bits(a.ray.dir) == bits(b.ray.dir)
            && bits(a.inv_dir) == bits(b.inv_dir)
            && bits(a.shear) == bits(b.shear)
            && (a.kx, a.ky, a.kz) == (b.kx, b.ky, b.kz)
    }

    #[test]
    fn soa_lanes_are_what_trace_ray_new_gives() {
        let u = |k: u32| uniform(k, 0, 0, 0, 11) * 2.0 - 1.0;
        // Random directions, then the awkward ones: zero components (infinite inverses),
        // ties between the largest components in every sign, a NaN.
        let mut dirs: Vec<Vec3> = (0..200)
            .map(|k| Vec3::new(u(3 * k), u(3 * k + 1), u(3 * k + 2)).normalize())
            .collect();
        for x in [-1.0f32, 0.0, 1.0] {
            for y in [-1.0f32, 0.0, 1.0] {
                for z in [-1.0f32, 0.0, 1.0] {
                    dirs.push(Vec3::new(x, y, z));
                }
            }
        }
        dirs.push(Vec3::new(f32::NAN, 0.5, -0.5));
        for (p, chunk) in dirs.chunks(PACKET_MAX - 3).enumerate() {
            for scale in [1e-3f32, 1.0, 1e3] {
                let rays: Vec<Ray> = chunk
                    .iter()
                    .enumerate()
                    .map(|(i, &d)| {
                        let k = (1000 * p + i) as u32;
                        Ray::new(Vec3::new(u(k), u(k + 7), u(k + 13)) * scale, d)
                    })
                    .collect();
                let soa = RaySoa::new(&rays);
                for (i, r) in rays.iter().enumerate() {
                    assert!(same(&soa.ray(i), &TraceRay::new(*r)), "ray {i}: {r:?}");
                }
                let axes: Vec<[usize; 3]> = rays
                    .iter()
                    .map(|&r| TraceRay::new(r))
                    .map(|t| [t.kx, t.ky, t.kz])
                    .collect();
                // Each ray in the group of its own permutation, and only there.
                for (i, k) in axes.iter().enumerate() {
                    let groups: Vec<[usize; 3]> = (soa.permutations.iter())
                        .filter(|(_, rays)| rays >> i & 1 == 1)
                        .map(|&(p, _)| p)
                        .collect();
                    assert_eq!(groups, [*k], "ray {i}");
                }
                let distinct: std::collections::HashSet<_> = axes.iter().collect();
                assert_eq!(soa.permutations.len(), distinct.len());
            }
        }
        // Lanes past the rays, to a multiple of 16, repeat the first.
        let rays: Vec<Ray> = (0..20)
            .map(|k| {
                Ray::new(
                    Vec3::new(u(k), u(k + 1), u(k + 2)),
                    Vec3::new(0.1, -0.9, 0.2),
                )
            })
            .collect();
        let soa = RaySoa::new(&rays);
        for i in rays.len()..32 {
            assert!(same(&soa.ray(i), &TraceRay::new(rays[0])), "lane {i}");
        }
    }
}
