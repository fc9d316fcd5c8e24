//! The packet walk's per-ray kernels, written once over `FloatLanes`: one box, triangle or
//! sphere against the packet's rays, `L::LANES` rays per step (eight with AVX2, sixteen
//! with AVX-512). Each is `#[inline(always)]` and takes the target features of the walk it
//! is inlined into (`x86::traverse_packet`'s instances).
//!
//! Lane by lane a kernel makes the operations of the scalar test in its order, at each
//! ray's `nested` bound; a hit so found is kept if it holds at the ray's own bound
//! (`PacketSearch::keep_decided`, `keep_shape_hit`), as the scalar test decides it, so the
//! answers are each ray's own test's on every width.

use super::{PacketSearch, RaySoa, TrianglePack, Wide8Node};
use crate::accel::bvh::packet::Packet4;
use crate::accel::bvh::traverse::CullBound;
use crate::geometry::{sphere_lanes, ShapeHit, ShapeKind, Sheared, Sphere};
use crate::math::lanes::{axes, FloatLanes};
use crate::stats::Stats;

/// The rays of a packet, `L::LANES` at a time: the start of each group and its rays of
/// `rays` (bits), for the groups that hold any.
#[inline(always)]
fn groups<L: FloatLanes>(rays: u64) -> impl Iterator<Item = (usize, u32)> {
    (0..64 / L::LANES).filter_map(move |group| {
        let at = group * L::LANES;
        let wanted = (rays >> at) as u32 & L::all_lanes();
        (wanted != 0).then_some((at, wanted))
    })
}

/// The rays of `rays_in` (a bit per ray) whose own box test enters child `lane` of `node`
/// before their bound (`bound`, a ray each): the slab test of the node's boxes
/// (`BoxRay::hit`), `L::LANES` rays per step instead of eight boxes. `near` and `far`
/// are the rows of `node.bounds` holding the packet's entry and exit planes.
#[inline(always)]
pub(super) fn rays_entering<L: FloatLanes>(
    node: &Wide8Node,
    (near, far): ([usize; 3], [usize; 3]),
    lane: usize,
    rays_in: u64,
    soa: &RaySoa,
    bound: &[f32; 64],
) -> u64 {
    // Written out rather than mapped through a closure, which one build left as a call
    // per child (balls 8 % slower).
    let b = &node.bounds;
    let near = [
        L::splat(b[near[0]][lane]),
        L::splat(b[near[1]][lane]),
        L::splat(b[near[2]][lane]),
    ];
    let far = [
        L::splat(b[far[0]][lane]),
        L::splat(b[far[1]][lane]),
        L::splat(b[far[2]][lane]),
    ];
    let exit_scale = L::splat(crate::accel::CULL_SLACK);
    let mut out = 0u64;
    for (at, wanted) in groups::<L>(rays_in) {
        let mut enter = L::splat(0.0);
        let mut exit = L::load(bound, at);
        for axis in 0..3 {
            let o = L::load(&soa.origin[axis], at);
            let inv = L::load(&soa.inv_dir[axis], at);
            // `max` and `min` return their second operand where either is NaN.
            enter = ((near[axis] - o) * inv).max(enter);
            exit = ((far[axis] - o) * inv).min(exit);
        }
        let hit = L::bits(enter.le(exit * exit_scale)) & wanted;
        out |= u64::from(hit) << at;
    }
    out
}

/// Tests the triangles of `pack` for the rays of `rays` still searching, which share the
/// axis permutation `k`: the triangles' boxes against the packet's interval first (a
/// triangle none of the rays can reach is skipped for all of them), then one triangle
/// against `L::LANES` rays at a time.
#[inline(always)]
pub(super) fn test_pack<L: FloatLanes>(
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
        test_triangle::<L>(pack, lane, k, rays & search.open(), soa, search);
    }
}

/// Triangle `lane` of `pack` against the rays of `rays` (a bit per ray), which share the
/// axis permutation `k`: the whole watertight test (`Sheared::hits`), as
/// `TrianglePack::hits` runs it for one ray and four triangles. Rays with an exact zero
/// edge function (which the scalar test re-evaluates in f64) or a value that is not finite
/// take the scalar test.
#[inline(always)]
fn test_triangle<L: FloatLanes>(
    pack: &TrianglePack,
    lane: usize,
    k: [usize; 3],
    rays: u64,
    soa: &RaySoa,
    search: &mut PacketSearch,
) {
    let v = pack.lanes_by_vertex();
    let vertex = |i: usize| axes(|a| L::splat(v[i][k[a]][lane]));
    let (pa, pb, pc) = (vertex(0), vertex(1), vertex(2));
    let prim = pack.ids[lane];
    for (at, wanted) in groups::<L>(rays) {
        let o = axes(|a| L::load(&soa.origin[k[a]], at));
        let shear = axes(|a| L::load(&soa.shear[a], at));
        let rel = |p: &[L; 3]| axes(|a| p[a] - o[a]);
        let sheared = Sheared::new([rel(&pa), rel(&pb), rel(&pc)], shear);
        let hits = sheared.hits(L::load(&search.nested, at), wanted);
        hits.each_hit(|j, decided| search.keep_decided(at + j, prim, decided));
        let mut undecided = hits.undecided;
        while undecided != 0 {
            let j = undecided.trailing_zeros() as usize;
            undecided &= undecided - 1;
            search.test_pack_lane(at + j, pack, lane, &soa.ray(at + j));
        }
    }
}

/// `sphere` (primitive `prim`) against the rays of `rays`: `sphere_lanes`, lane by lane
/// the operations of `Sphere::intersect`.
#[inline(always)]
pub(super) fn test_sphere<L: FloatLanes>(
    sphere: &Sphere,
    prim: u32,
    rays: u64,
    soa: &RaySoa,
    search: &mut PacketSearch,
    stats: &mut Stats,
) {
    stats.count_tests(ShapeKind::Sphere, u64::from(rays.count_ones()));
    let centre = axes(|a| L::splat(sphere.center[a]));
    let r2 = L::splat(sphere.radius * sphere.radius);
    for (at, wanted) in groups::<L>(rays) {
        let origin = axes(|a| L::load(&soa.origin[a], at));
        let dir = axes(|a| L::load(&soa.dir[a], at));
        let nested = L::load(&search.nested, at);
        let (hit, t) = sphere_lanes(origin, dir, centre, r2, nested);
        let mut hit = hit & wanted;
        if hit != 0 {
            let ts = t.to_array();
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
