//! The one ray query every accelerator answers, and the rules all of them share: what a
//! hit is, when a query is answered, and which of two hits at the same distance wins.
//!
//! An accelerator decides only which primitives a ray meets and in what order; it hands
//! each one to a `HitSearch`, which tests it and keeps the answer. So the tie rule and the
//! way a hit is built exist once, here, and every method gives the same answer as the
//! brute-force list whatever order it walks in.

use crate::geometry::{DecidedHit, Geometry, PackRay, ShapeHit, ShapeKind, TrianglePack};
use crate::math::robust::next_up;
use crate::math::{Ray, TraceRay};
use crate::stats::Stats;

/// The nearest intersection found along a ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit point.
    pub t: f32,
    /// The primitive hit (an index into `Geometry::primitives`).
    pub prim: u32,
    /// Shape-specific hit parameters (see `ShapeHit`).
    pub u: f32,
    /// Shape-specific hit parameters (see `ShapeHit`).
    pub v: f32,
}

impl Hit {
    /// The hit of primitive `prim` that its shape reported.
    #[inline(always)]
    pub fn new(prim: u32, hit: ShapeHit) -> Hit {
        Hit {
            t: hit.t,
            prim,
            u: hit.u,
            v: hit.v,
        }
    }

    /// The shape's own view of the hit, for building the surface point.
    pub fn shape_hit(&self) -> ShapeHit {
        ShapeHit {
            t: self.t,
            u: self.u,
            v: self.v,
        }
    }
}

/// One ray's query, as every accelerator's `Accel::query` takes it: over which primitives,
/// along which ray, how far (hits with `0 < t < t_max`) and which answer.
#[derive(Clone, Copy)]
pub struct RayQuery<'a> {
    /// The primitives the accelerator was built over.
    pub geometry: &'a Geometry,
    /// The ray, with what its tests precompute.
    pub ray: &'a TraceRay,
    /// Hits at or beyond it do not count.
    pub t_max: f32,
    /// The nearest hit or any.
    pub mode: QueryMode,
}

impl<'a> RayQuery<'a> {
    /// The query of `ray` over `geometry` for hits with `0 < t < t_max`, in `mode`.
    #[inline(always)]
    pub fn new(geometry: &'a Geometry, ray: &'a TraceRay, t_max: f32, mode: QueryMode) -> Self {
        RayQuery {
            geometry,
            ray,
            t_max,
            mode,
        }
    }
}

/// A packet's query, as `Accel::query_packet` takes it: ray i with bound `t_max[i]`, all
/// in one mode.
#[derive(Clone, Copy)]
pub struct PacketQuery<'a> {
    /// The primitives the accelerator was built over.
    pub geometry: &'a Geometry,
    /// The rays (at most `PACKET_MAX`).
    pub rays: &'a [Ray],
    /// One bound per ray.
    pub t_max: &'a [f32],
    /// The nearest hit or any, for every ray.
    pub mode: QueryMode,
}

impl<'a> PacketQuery<'a> {
    /// The query of `rays` over `geometry`, ray i for hits with `0 < t < t_max[i]`, all
    /// in `mode`.
    pub fn new(geometry: &'a Geometry, rays: &'a [Ray], t_max: &'a [f32], mode: QueryMode) -> Self {
        PacketQuery {
            geometry,
            rays,
            t_max,
            mode,
        }
    }
}

/// What a query asks of the primitives a ray meets before `t_max`.
///
/// A query for a packet of rays (several rays walked together) would add a method beside
/// `Accel::query` taking the rays and one mode; the mode and `HitSearch` stay as they are,
/// one search per ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QueryMode {
    /// The nearest hit (camera, reflected and refracted rays).
    Nearest,
    /// Any hit: the query may stop at the first one found (shadow rays).
    Any,
}

/// The state of one query: the best hit so far and the distance a new one must beat.
///
/// **The tie rule.** Two primitives hit at exactly the same distance go to the lower
/// primitive id, as the brute-force list (which tests in id order and keeps only strictly
/// nearer hits) decides them. A primitive with a lower id than the best so far is therefore
/// tested against a bound one ulp farther, so that a hit exactly at the best distance is
/// reported and replaces it; any other primitive must be strictly nearer.
pub(crate) struct HitSearch {
    best: Option<Hit>,
    t_max: f32,
    mode: QueryMode,
}

impl HitSearch {
    /// A query for hits with `0 < t < t_max`.
    #[inline(always)]
    pub(crate) fn new(t_max: f32, mode: QueryMode) -> Self {
        HitSearch {
            best: None,
            t_max,
            mode,
        }
    }

    /// The distance a hit must come before (the best hit's, once there is one).
    #[inline(always)]
    pub(crate) fn t_max(&self) -> f32 {
        self.t_max
    }

    /// The answer so far.
    #[inline(always)]
    pub(crate) fn best(&self) -> Option<Hit> {
        self.best
    }

    /// Tests primitive `prim` and keeps its hit if it wins; true when the query is
    /// answered (an any-hit query found something).
    #[inline(always)]
    pub(crate) fn test(
        &mut self,
        geometry: &Geometry,
        ray: &TraceRay,
        prim: u32,
        stats: &mut Stats,
    ) -> bool {
        match counted_test(geometry, prim, ray, self.limit_for(prim), stats) {
            Some(h) => self.keep(Hit::new(prim, h)),
            None => false,
        }
    }

    /// Tests the triangles of `pack`, whose ids are primitive ids, in lane order; true when
    /// the query is answered. Every lane counts as a test. The 4-wide test finds the lanes
    /// hit at the loosest bound any of them gets (the bound only shrinks as hits are kept);
    /// each is then held to the tie rule's bound for its id, with the comparisons of the
    /// scalar test on the lane's own values, and the lanes only the scalar test can decide
    /// go to it: the answer is the one `test` gives lane by lane.
    #[inline(always)]
    pub(crate) fn test_pack(
        &mut self,
        pack: &TrianglePack,
        pack_ray: &PackRay,
        ray: &TraceRay,
        stats: &mut Stats,
    ) -> bool {
        stats.count_tests(ShapeKind::Triangle, pack.len() as u64);
        let hits = pack.hits(pack_ray, self.nested_limit());
        self.take_pack_lanes(
            pack,
            hits.hit,
            hits.undecided,
            |lane| hits.decided(lane),
            ray,
        )
    }

    /// What a first pass of the watertight test over `pack` found, handled in lane order:
    /// the lanes of `hit` (values from `decided`) are held to the tie rule's bound for
    /// their ids, the lanes of `undecided` go to the scalar test; true when the query is
    /// answered. The pass must have run at a bound no tighter than `nested_limit` is now
    /// (it only shrinks), so that it dropped only lanes no bound of this search can keep.
    /// Shared by `test_pack` and the 8-wide pass over two packs (`simd8/pair.rs`), so both
    /// handle lanes alike.
    #[inline(always)]
    pub(crate) fn take_pack_lanes(
        &mut self,
        pack: &TrianglePack,
        hit: u32,
        undecided: u32,
        decided: impl Fn(usize) -> DecidedHit,
        ray: &TraceRay,
    ) -> bool {
        let mut lanes = hit | undecided;
        while lanes != 0 {
            let lane = lanes.trailing_zeros() as usize;
            lanes &= lanes - 1;
            let answered = if undecided & (1 << lane) != 0 {
                self.test_pack_lane(pack, lane, ray)
            } else {
                self.keep_decided(pack.ids[lane], &decided(lane))
            };
            if answered {
                return true;
            }
        }
        false
    }

    /// Keeps `hit` on primitive `prim`, found by a SIMD pass at `nested_limit` with the
    /// shape's own operations, if it holds at this search's bound for `prim` (what `test`
    /// would find); true when the query is answered.
    #[inline(always)]
    pub(crate) fn keep_within(&mut self, prim: u32, hit: ShapeHit) -> bool {
        hit.t < self.limit_for(prim) && self.keep(Hit::new(prim, hit))
    }

    /// Keeps triangle `prim`'s hit, decided by a SIMD pass at `nested_limit`, if it holds
    /// at this search's bound for `prim` (what `test_pack_lane` would find); true when the
    /// query is answered.
    #[inline(always)]
    pub(crate) fn keep_decided(&mut self, prim: u32, decided: &DecidedHit) -> bool {
        match decided.within(self.limit_for(prim)) {
            Some(h) => self.keep(Hit::new(
                prim,
                ShapeHit {
                    t: h.t,
                    u: h.b1,
                    v: h.b2,
                },
            )),
            None => false,
        }
    }

    /// The scalar test of triangle `lane` of `pack`, which a first pass kept (uncounted:
    /// the caller counts the pack's lanes); true when the query is answered.
    #[inline(always)]
    pub(crate) fn test_pack_lane(
        &mut self,
        pack: &TrianglePack,
        lane: usize,
        ray: &TraceRay,
    ) -> bool {
        let prim = pack.ids[lane];
        match pack.intersect(lane, ray, self.limit_for(prim)) {
            Some(h) => {
                let hit = ShapeHit {
                    t: h.t,
                    u: h.b1,
                    v: h.b2,
                };
                self.keep(Hit::new(prim, hit))
            }
            None => false,
        }
    }

    /// Tests an unbounded primitive (a plane) after the accelerator has answered: its hit
    /// must be strictly nearer, whatever the ids. The exception to the tie rule is
    /// deliberate: a plane is typically the floor that objects stand on, and where an
    /// object's face lies exactly in it (the glass pyramid of scenes/shapes.toml) the
    /// object's face is the surface the ray meets.
    #[inline(always)]
    pub(crate) fn test_unbounded(
        &mut self,
        geometry: &Geometry,
        ray: &TraceRay,
        prim: u32,
        stats: &mut Stats,
    ) -> bool {
        match counted_test(geometry, prim, ray, self.t_max, stats) {
            Some(h) => self.keep(Hit::new(prim, h)),
            None => false,
        }
    }

    /// The bound for a nested query over a group of primitives whose ids are not known in
    /// advance (a sub-tree): one ulp beyond the best distance once there is a best hit, so
    /// that a tie reaches `offer`, which decides it.
    #[inline(always)]
    pub(crate) fn nested_limit(&self) -> f32 {
        if self.best.is_some() {
            next_up(self.t_max)
        } else {
            self.t_max
        }
    }

    /// Offers the answer of a nested query made with `nested_limit`, keeping it if it is
    /// nearer or ties with a lower id; true when the query is answered.
    #[inline(always)]
    pub(crate) fn offer(&mut self, hit: Hit) -> bool {
        let wins = hit.t < self.t_max || self.best.is_none_or(|b| hit.prim < b.prim);
        wins && self.keep(hit)
    }

    /// Whether the nearest hit is settled once everything up to `t` has been tested: there
    /// is a best hit and it lies no farther than `t`.
    #[inline(always)]
    pub(crate) fn settled_by(&self, t: f32) -> bool {
        self.best.is_some() && self.t_max <= t
    }

    /// The bound primitive `prim`'s hit must come before: one ulp beyond the best distance
    /// for an id lower than the best hit's (the tie rule), the best distance otherwise.
    #[inline(always)]
    fn limit_for(&self, prim: u32) -> f32 {
        match self.best {
            Some(b) if prim < b.prim => next_up(self.t_max),
            _ => self.t_max,
        }
    }

    #[inline(always)]
    fn keep(&mut self, hit: Hit) -> bool {
        self.t_max = hit.t;
        self.best = Some(hit);
        self.mode == QueryMode::Any
    }
}

/// Primitive `prim`'s intersection test, counted in `stats` by shape kind: every test an
/// accelerator makes goes through here, so the statistics and cost views see them all.
/// `#[inline]`, not `always`: forcing the shape tests into every walk cost the BVH ~7 % of
/// its primary-ray speed (prism bench, sphereflake, CPU time).
#[inline]
fn counted_test(
    geometry: &Geometry,
    prim: u32,
    ray: &TraceRay,
    t_max: f32,
    stats: &mut Stats,
) -> Option<ShapeHit> {
    let shape = &geometry.primitives[prim as usize].shape;
    stats.count_test(shape.kind());
    shape.intersect(&geometry.meshes, ray, t_max)
}
