//! The light buffer (Haines & Greenberg, "The Light Buffer: A Shadow-Testing Accelerator",
//! IEEE CG&A 1986): for a point light, a cube of directions around it, each face a grid of
//! cells, each cell the list of primitives seen through it, nearest to the light first. A
//! shadow ray looks up the cell of its direction and tests only that list, stopping at the
//! first entry that begins beyond the shaded point.
//!
//! prism's buffer must answer exactly what the BVH answers, so it is built conservatively:
//!
//! - a primitive's footprint on a face comes from the eight corners of its bounding box
//!   (in f64), widened by `FOOTPRINT_SLACK` on every side, and a box that holds the light
//!   covers every cell;
//! - a shadow ray starts at an offset surface point, so its line passes the light at a
//!   small distance δ rather than through it; its points at distance r from the light are
//!   seen δ/r away from its cell's direction. The slack covers that for r ≥ 4δ/slack; the
//!   primitives nearer than that to the light (the `by_distance` prefix, usually none) are
//!   tested for every query;
//! - candidates are tested with the accelerators' own `HitSearch`, whose tie rule makes the
//!   nearest hit among any superset of the primitives a ray meets the brute-force one.
//!
//! - each face's cells span only its *window*, the part of the face some footprint reaches
//!   (a far light sees the scene in a narrow cone); directions outside every window meet no
//!   bounded primitive;
//! - a walk tests an entry's bounding box first (the BVH's own conservative slab test), so
//!   a flat receiver's box, wholly below its offset shadow rays, costs no primitive test.
//!
//! Three refinements trade the lists' work for the accelerator's or for one test:
//!
//! - **walk limit**: lists keep at most `max_walk` entries; a query that would walk more
//!   (its point lies beyond the last kept entry) asks the accelerator instead, so a grazing
//!   light over a terrain no longer walks hundreds of triangles;
//! - **covered cells** (the paper's refinement): a cell whose every direction, widened by
//!   the slack, meets one opaque triangle or sphere remembers the nearest such one. A point
//!   farther than it tests it *first*, and a hit answers the query. The paper answers such a
//!   point "in shadow" without a test; here the test stays, because the f32 ray–triangle and
//!   ray–sphere tests cannot be proven to hit near an outline, at every scale, from the
//!   geometry alone, and exactness comes first. Transparent primitives never cover.
//! - polygons facing away from the light are *not* left out: prism's shadow rays are
//!   blocked by back faces too, and leaving them out is exact only for closed meshes and a
//!   light outside them, which prism does not know.
//!
//! Every answer is therefore some primitive's own test or the accelerator's: exactness does
//! not rest on the cover or the limit being right, only on the footprints.

use crate::accel::{Hit, HitSearch, QueryMode, SceneIntersector};
use crate::geometry::{Geometry, Shape};
use crate::math::{Aabb, Ray, TraceRay, Vec3};
use crate::stats::Stats;
use glam::DVec3;
use std::time::{Duration, Instant};

/// Widening of every footprint, in face coordinates (tangents, −1 to 1 across a face).
const FOOTPRINT_SLACK: f64 = 1e-3;
/// Relative error allowed for in distances from the light (f32 hit points and directions).
const DISTANCE_SLACK: f64 = 1e-5;

/// One list entry: a primitive and its nearest distance from the light. A walk tests the
/// primitive's bounding box (`PrimBounds`) first, as a BVH tests a leaf's box (the same
/// conservative test): a flat receiver's own box, say, lies wholly below its offset shadow
/// rays.
#[derive(Clone, Copy, Debug)]
struct Entry {
    prim: u32,
    near: f32,
}

/// Every primitive's bounding box (empty for planes), by primitive id: one copy shared by
/// the buffers of all lights, small next to their lists.
pub(crate) type PrimBounds = std::sync::Arc<[Aabb]>;

/// The bounds `LightBuffer` tests entries with.
pub(crate) fn prim_bounds(geometry: &Geometry) -> PrimBounds {
    (0..geometry.primitives.len() as u32)
        .map(|p| geometry.bounds(p).unwrap_or(Aabb::EMPTY))
        .collect()
}

/// One cell: its list (`entries[start..start + len]`, nearest first, at most `max_walk`
/// long), the nearest distance of the first entry left out (a query reaching it would walk
/// too far, and asks the accelerator), and its covering primitive: an opaque triangle or
/// sphere that every direction of the cell (widened by the slack) meets, with its farthest
/// distance from the light (rounded up). A point farther than `cover_far` tests it first;
/// only a hint, the answer is that test's.
#[derive(Clone, Copy, Debug)]
struct Cell {
    start: u32,
    len: u32,
    limit: f32,
    cover_far: f32,
    cover: u32,
}

const EMPTY_CELL: Cell = Cell {
    start: 0,
    len: 0,
    limit: f32::INFINITY,
    cover_far: f32::INFINITY,
    cover: u32::MAX,
};

/// How a buffer is built.
pub struct BufferParams<'a> {
    /// Cells along a face's window side.
    pub res: u32,
    /// The most its lists may take.
    pub budget_bytes: u64,
    /// The longest walk a query takes; lists keep no more entries than this.
    pub max_walk: usize,
    /// The primitives that may cover a cell (transparent ones may not).
    pub opaque: &'a dyn Fn(u32) -> bool,
    /// The primitives' boxes, if already made (`prim_bounds`) for another light.
    pub bounds: Option<PrimBounds>,
}

/// Why a light has no buffer (its shadow rays then use the BVH).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Unbuilt {
    /// The cell lists would pass the memory budget.
    OverBudget { entries: u64, budget_bytes: u64 },
}

/// The part of one face, in face coordinates, that some footprint reaches: its res × res
/// cells span this window, not the whole face, so a light far from the scene (which sees it
/// in a narrow cone) still gets fine cells. Directions outside it meet no bounded primitive.
#[derive(Clone, Copy, Debug)]
struct Window {
    lo: [f64; 2],
    hi: [f64; 2],
    /// Cells per unit of face coordinate.
    scale: [f64; 2],
    /// Where the face's cells begin (faces no footprint reaches have none).
    base: usize,
}

impl Window {
    const EMPTY: Window = Window {
        lo: [f64::INFINITY; 2],
        hi: [f64::NEG_INFINITY; 2],
        scale: [0.0; 2],
        base: 0,
    };

    fn include(&mut self, r: [f64; 4]) {
        self.lo = [self.lo[0].min(r[0]), self.lo[1].min(r[2])];
        self.hi = [self.hi[0].max(r[1]), self.hi[1].max(r[3])];
    }

    /// Fixes the cells' size and where they begin; returns how many the face has.
    fn finish(&mut self, res: u32, base: usize) -> usize {
        self.base = base;
        if self.lo[0] > self.hi[0] {
            return 0;
        }
        for a in 0..2 {
            self.scale[a] = res as f64 / (self.hi[a] - self.lo[a]).max(1e-9);
        }
        (res * res) as usize
    }

    /// The cell along axis `a` that face coordinate `t` falls in (the edge cells take
    /// rounding at the window's ends): the one rule for lookups and footprints, monotone
    /// in `t`, so a footprint's cells hold every direction between its ends.
    fn index(&self, a: usize, t: f64, res: u32) -> u32 {
        (((t - self.lo[a]) * self.scale[a]).floor() as i64).clamp(0, res as i64 - 1) as u32
    }

    fn contains(&self, a: usize, t: f64) -> bool {
        t >= self.lo[a] && t <= self.hi[a]
    }

    /// Face coordinates of cell `i`'s ends along axis `a`.
    fn cell_span(&self, a: usize, i: u32) -> (f64, f64) {
        (
            self.lo[a] + i as f64 / self.scale[a],
            self.lo[a] + (i + 1) as f64 / self.scale[a],
        )
    }
}

/// A light buffer around one point: res × res cells on each face some primitive is seen on.
pub struct LightBuffer {
    light: DVec3,
    res: u32,
    windows: [Window; 6],
    bounds: PrimBounds,
    cells: Vec<Cell>,
    entries: Vec<Entry>,
    /// Every bounded primitive, nearest first: the ones very near the light are tested for
    /// every query.
    by_distance: Vec<Entry>,
    /// Planes have no footprint: every query tests them, as `SceneIntersector` does.
    unbounded: Vec<u32>,
    /// A query that would test more entries than this asks the accelerator instead.
    max_walk: usize,
    build_time: Duration,
}

/// What `prism info` and the statistics say about a buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LightBufferInfo {
    /// Cells along each side of a direction-cube face.
    pub resolution: u32,
    /// Cells over all six faces.
    pub cells: usize,
    /// Entries over all cells (a primitive counts once per cell it covers).
    pub entries: usize,
    /// Mean list length over all cells (`entries / cells`).
    pub mean_list: f64,
    /// Longest list of one cell.
    pub max_list: usize,
    /// Cells wholly covered by one opaque triangle or sphere.
    pub covered_cells: usize,
    /// Cells with at least one entry.
    pub occupied_cells: usize,
    /// Cells whose lists were cut at `max_walk` entries.
    pub cut_cells: usize,
    /// Longest walk before a query asks the accelerator instead.
    pub max_walk: usize,
    /// Bytes the buffer's offsets and lists take.
    pub memory_bytes: usize,
    /// How long building it took.
    pub build_time: Duration,
}

/// The face of direction `d` (from the light) and its face coordinates (u, v).
fn face_coords(d: DVec3) -> (usize, f64, f64) {
    let a = d.abs();
    let (face, w, u, v) = if a.x >= a.y && a.x >= a.z {
        (if d.x >= 0.0 { 0 } else { 1 }, a.x, d.y, d.z)
    } else if a.y >= a.z {
        (if d.y >= 0.0 { 2 } else { 3 }, a.y, d.z, d.x)
    } else {
        (if d.z >= 0.0 { 4 } else { 5 }, a.z, d.x, d.y)
    };
    (face, u / w, v / w)
}

/// The axes of face `face` (0..6: +x, −x, +y, −y, +z, −z): depth, u, v, and the depth's sign.
fn face_axes(face: usize) -> (usize, usize, usize, f64) {
    let (axis, u, v) = match face / 2 {
        0 => (0, 1, 2),
        1 => (1, 2, 0),
        _ => (2, 0, 1),
    };
    (axis, u, v, if face % 2 == 0 { 1.0 } else { -1.0 })
}

/// Point `p` (relative to the light) in face `face`'s frame: (depth, u, v).
fn in_face(face: usize, p: DVec3) -> (f64, f64, f64) {
    let (axis, u, v, sign) = face_axes(face);
    (sign * p[axis], p[u], p[v])
}

/// For face `face`, the (depth, u, v) ranges of box `[lo, hi]` (relative to the light) in
/// that face's coordinates.
fn face_ranges(face: usize, lo: DVec3, hi: DVec3) -> [(f64, f64); 3] {
    let (axis, u, v, sign) = face_axes(face);
    let w = if sign > 0.0 {
        (lo[axis], hi[axis])
    } else {
        (-hi[axis], -lo[axis])
    };
    [w, (lo[u], hi[u]), (lo[v], hi[v])]
}

/// The face coordinates box `[lo, hi]` may be seen through on face `face`, widened by the
/// slack and cut to the face: (u0, u1, v0, v1); None when the box is not in that face's
/// pyramid.
fn footprint(face: usize, lo: DVec3, hi: DVec3) -> Option<[f64; 4]> {
    let [(w0, w1), (u0, u1), (v0, v1)] = face_ranges(face, lo, hi);
    let k = 1.0 + FOOTPRINT_SLACK;
    let gap = |a: f64, b: f64| {
        if a > 0.0 {
            a
        } else if b < 0.0 {
            -b
        } else {
            0.0
        }
    };
    // In the (slightly widened) pyramid of the face, depth ≥ |u| / k and ≥ |v| / k.
    let w_min = w0.max(gap(u0, u1).max(gap(v0, v1)) / k);
    if w_min > w1 {
        return None;
    }
    if w_min <= 0.0 {
        // The box holds the light: it may be seen in every direction.
        return Some([-1.0, 1.0, -1.0, 1.0]);
    }
    let range = |a: f64, b: f64| {
        let lo = (a / w_min).min(a / w1) - FOOTPRINT_SLACK;
        let hi = (b / w_min).max(b / w1) + FOOTPRINT_SLACK;
        (lo.clamp(-1.0, 1.0), hi.clamp(-1.0, 1.0))
    };
    let (iu0, iu1) = range(u0, u1);
    let (iv0, iv1) = range(v0, v1);
    Some([iu0, iu1, iv0, iv1])
}

/// The nearest distance from the origin to box `[lo, hi]`, rounded down.
fn near_distance(lo: DVec3, hi: DVec3) -> f32 {
    let d = lo.max(-hi).max(DVec3::ZERO).length() * (1.0 - DISTANCE_SLACK);
    d as f32
}

/// The farthest distance from the origin to box `[lo, hi]`, rounded up.
fn far_distance(lo: DVec3, hi: DVec3) -> f32 {
    let d = lo.abs().max(hi.abs()).length() * (1.0 + DISTANCE_SLACK);
    d as f32
}

/// What one face-coordinate rectangle of directions must lie within to be covered by a
/// primitive, as seen from the light.
enum Silhouette {
    /// A triangle wholly in front of the face: its corners projected onto it.
    Triangle([[f64; 2]; 3]),
    /// A sphere not holding the light: its centre (relative to the light) and the cosine
    /// of its angular radius.
    Sphere(DVec3, f64),
}

impl Silhouette {
    fn of(geometry: &Geometry, prim: u32, light: DVec3, face: usize) -> Option<Silhouette> {
        match &geometry.primitives[prim as usize].shape {
            Shape::Triangle { mesh, index } => {
                let vs = geometry.meshes[*mesh as usize].vertices(*index);
                let mut p = [[0.0; 2]; 3];
                for (k, v) in vs.iter().enumerate() {
                    let (w, u, v) = in_face(face, v.as_dvec3() - light);
                    if w <= 0.0 {
                        return None;
                    }
                    p[k] = [u / w, v / w];
                }
                let area = cross2(p[0], p[1], p[2]);
                if area.is_nan() || area == 0.0 {
                    return None;
                }
                if area < 0.0 {
                    p.swap(1, 2);
                }
                Some(Silhouette::Triangle(p))
            }
            Shape::Sphere(s) => {
                let c = s.center.as_dvec3() - light;
                let r = s.radius.abs() as f64;
                let d = c.length();
                (d > r * 1.001).then(|| Silhouette::Sphere(c, (1.0 - (r / d).powi(2)).sqrt()))
            }
            _ => None,
        }
    }

    /// Whether every direction of the rectangle (u0, u1) × (v0, v1) on face `face` is
    /// within the silhouette (its four corners, both shapes being convex).
    fn covers(&self, face: usize, u: (f64, f64), v: (f64, f64)) -> bool {
        let corners = [[u.0, v.0], [u.1, v.0], [u.0, v.1], [u.1, v.1]];
        match self {
            Silhouette::Triangle(p) => corners.iter().all(|&c| {
                cross2(p[0], p[1], c) > 0.0
                    && cross2(p[1], p[2], c) > 0.0
                    && cross2(p[2], p[0], c) > 0.0
            }),
            Silhouette::Sphere(centre, cos_radius) => {
                let (axis, ua, va, sign) = face_axes(face);
                corners.iter().all(|&[cu, cv]| {
                    let mut d = DVec3::ZERO;
                    d[axis] = sign;
                    d[ua] = cu;
                    d[va] = cv;
                    d.normalize().dot(*centre) > cos_radius * centre.length()
                })
            }
        }
    }
}

/// Twice the signed area of triangle (a, b, c).
fn cross2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The work a shadow query would take, before any test.
struct Plan<'a> {
    /// The primitives near the light that every query tests.
    prefix: &'a [Entry],
    /// The cell's entries that begin before the shaded point.
    list: &'a [Entry],
    /// Whether the walk would pass the buffer's `max_walk`.
    too_long: bool,
    /// The cell's covering primitive, when the point lies beyond it.
    hint: Option<u32>,
}

impl LightBuffer {
    /// The resolution the buffer takes when none is asked for: √n / 2 cells along a
    /// window's side, within 16 and 96. The windows put the cells where the scene is, lists
    /// are cut at the walk limit and their boxes filter the tests, so finer cells buy few
    /// tests and cost cache misses: on the SPD scenes 48 cells beat 96, which beat 362
    /// (the old 4·√n), everywhere (prism bench, docs/shadows.md).
    pub fn auto_resolution(primitives: usize) -> u32 {
        ((primitives as f64).sqrt() * 0.5).round().clamp(16.0, 96.0) as u32
    }

    /// The longest walk a query takes before it asks the accelerator instead, when none is
    /// asked for: ⌈log₂ n⌉ / 2 entries, at least 2, as an estimate of what a BVH's any-hit
    /// query costs in primitive tests (its node visits grow as log n, and on the SPD scenes
    /// about four node visits cost one entry's test; tuned on them).
    pub fn auto_max_walk(primitives: usize) -> usize {
        let log = usize::BITS - primitives.max(1).leading_zeros();
        (log as usize).div_ceil(2).max(2)
    }

    /// Builds the buffer of the light at `light` over every primitive of `geometry`, with
    /// whole lists (no walk limit) and every primitive taken as opaque, or says why not: its
    /// lists would take more than `budget_bytes`.
    pub fn build(
        geometry: &Geometry,
        light: Vec3,
        res: u32,
        budget_bytes: u64,
    ) -> Result<LightBuffer, Unbuilt> {
        let params = BufferParams {
            res,
            budget_bytes,
            max_walk: usize::MAX,
            opaque: &|_| true,
            bounds: None,
        };
        Self::build_with(geometry, light, &params)
    }

    /// Builds the buffer of the light at `light` as `params` say.
    pub fn build_with(
        geometry: &Geometry,
        light: Vec3,
        params: &BufferParams,
    ) -> Result<LightBuffer, Unbuilt> {
        let start = Instant::now();
        let res = params.res.max(1);
        let keep = params.max_walk.min(u32::MAX as usize) as u32;
        let l = light.as_dvec3();
        let mut by_distance = Vec::new();
        let mut unbounded = Vec::new();
        // (entry, far distance, face, footprint) per face a primitive may be seen on.
        let mut prints: Vec<(Entry, f32, usize, [f64; 4])> = Vec::new();
        let mut windows = [Window::EMPTY; 6];
        for prim in 0..geometry.primitives.len() as u32 {
            let Some(b) = geometry.bounds(prim) else {
                unbounded.push(prim);
                continue;
            };
            let (lo, hi) = relative_box(b, l);
            let entry = Entry {
                prim,
                near: near_distance(lo, hi),
            };
            by_distance.push(entry);
            for (face, window) in windows.iter_mut().enumerate() {
                if let Some(p) = footprint(face, lo, hi) {
                    window.include(p);
                    prints.push((entry, far_distance(lo, hi), face, p));
                }
            }
        }
        let mut cell_count = 0;
        for w in &mut windows {
            cell_count += w.finish(res, cell_count);
        }
        // Nearest first: each cell's list fills in order, and the first entry that finds
        // it full is the nearest one left out.
        let by_near = |a: &Entry, b: &Entry| a.near.total_cmp(&b.near).then(a.prim.cmp(&b.prim));
        prints.sort_unstable_by(|a, b| by_near(&a.0, &b.0).then(a.2.cmp(&b.2)));
        let cells_of = |face: usize, p: [f64; 4]| {
            let w = &windows[face];
            [
                w.index(0, p[0], res),
                w.index(0, p[1], res),
                w.index(1, p[2], res),
                w.index(1, p[3], res),
            ]
        };
        let cell_at = |face: usize, iu: u32, iv: u32| windows[face].base + (iv * res + iu) as usize;
        let mut cells = vec![EMPTY_CELL; cell_count];
        let mut total: u64 = 0;
        let budget_entries = params.budget_bytes / std::mem::size_of::<Entry>() as u64;
        for &(_, _, face, p) in &prints {
            let [iu0, iu1, iv0, iv1] = cells_of(face, p);
            for iv in iv0..=iv1 {
                for iu in iu0..=iu1 {
                    let cell = &mut cells[cell_at(face, iu, iv)];
                    if cell.len < keep {
                        cell.len += 1;
                        total += 1;
                    }
                }
            }
            if total > budget_entries {
                return Err(Unbuilt::OverBudget {
                    entries: total,
                    budget_bytes: params.budget_bytes,
                });
            }
        }
        let mut next = 0;
        for cell in &mut cells {
            cell.start = next;
            next += cell.len;
            cell.len = 0;
        }
        let mut entries = vec![Entry { prim: 0, near: 0.0 }; total as usize];
        for &(entry, far, face, p) in &prints {
            let [iu0, iu1, iv0, iv1] = cells_of(face, p);
            let silhouette = (params.opaque)(entry.prim)
                .then(|| Silhouette::of(geometry, entry.prim, l, face))
                .flatten();
            let w = &windows[face];
            for iv in iv0..=iv1 {
                for iu in iu0..=iu1 {
                    let cell = &mut cells[cell_at(face, iu, iv)];
                    if cell.len < keep {
                        entries[(cell.start + cell.len) as usize] = entry;
                        cell.len += 1;
                    } else if cell.limit == f32::INFINITY {
                        cell.limit = entry.near;
                    }
                    if let Some(s) = &silhouette {
                        if far < cell.cover_far {
                            let (u0, u1) = w.cell_span(0, iu);
                            let (v0, v1) = w.cell_span(1, iv);
                            let e = FOOTPRINT_SLACK;
                            if s.covers(face, (u0 - e, u1 + e), (v0 - e, v1 + e)) {
                                cell.cover_far = far;
                                cell.cover = entry.prim;
                            }
                        }
                    }
                }
            }
        }
        by_distance.sort_unstable_by(by_near);
        Ok(LightBuffer {
            light: l,
            res,
            windows,
            bounds: params
                .bounds
                .clone()
                .unwrap_or_else(|| prim_bounds(geometry)),
            cells,
            entries,
            by_distance,
            unbounded,
            max_walk: params.max_walk,
            build_time: start.elapsed(),
        })
    }

    /// The cell of direction `d` (from the light); None outside every face's window, where
    /// no bounded primitive may be seen.
    fn cell_of(&self, d: DVec3) -> Option<usize> {
        let (face, u, v) = face_coords(d);
        let w = &self.windows[face];
        if !(w.contains(0, u) && w.contains(1, v)) {
            return None;
        }
        let res = self.res;
        Some(w.base + (w.index(1, v, res) * res + w.index(0, u, res)) as usize)
    }

    /// What a query along `ray` (towards the light) would test.
    fn plan(&self, ray: &Ray) -> Plan<'_> {
        let q = ray.origin.as_dvec3() - self.light;
        let dir = ray.dir.as_dvec3();
        let reach = q.length();
        // How far the ray's line passes from the light, with room for the f32 direction.
        let delta = q.cross(dir).length() + reach * 1e-6;
        // Nearer than this to the light, a point of the ray may be seen from another cell.
        let near_limit = (4.0 * delta / FOOTPRINT_SLACK) as f32;
        let far_limit = (reach * (1.0 + DISTANCE_SLACK) + delta) as f32;
        let prefix = match self.by_distance.first() {
            Some(e) if e.near <= near_limit && e.near <= far_limit => {
                let limit = near_limit.min(far_limit);
                let n = self.by_distance.partition_point(|e| e.near <= limit);
                &self.by_distance[..n]
            }
            _ => &[],
        };
        let (list, cut, hint) = match self.cell_of(-dir) {
            Some(c) => {
                let cell = &self.cells[c];
                let kept = &self.entries[cell.start as usize..(cell.start + cell.len) as usize];
                let n = kept.partition_point(|e| e.near <= far_limit);
                let hint = ((cell.cover_far as f64) < reach).then_some(cell.cover);
                (&kept[..n], cell.limit <= far_limit, hint)
            }
            None => (&[][..], false, None),
        };
        Plan {
            prefix,
            list,
            too_long: cut || prefix.len() + list.len() > self.max_walk,
            hint,
        }
    }

    /// The hit a ray from `ray.origin` towards the light meets before `t_max`: the nearest
    /// (`QueryMode::Nearest`) or any (`QueryMode::Any`), exactly as `accel`'s queries
    /// answer. The ray must point at this buffer's light.
    pub fn query(
        &self,
        geometry: &Geometry,
        accel: &SceneIntersector,
        ray: &Ray,
        t_max: f32,
        mode: QueryMode,
        stats: &mut Stats,
    ) -> Option<Hit> {
        match mode {
            QueryMode::Any => self.any_hit(geometry, accel, ray, t_max, None, stats),
            QueryMode::Nearest => self.nearest(geometry, accel, ray, t_max, stats),
        }
    }

    /// An any-hit query, as `accel.any_hit` answers it: first the cell's covering primitive
    /// (if the point lies beyond it), then `remembered` (the shadow cache's blocker; a hit
    /// counts as a cache hit), then the walk, or the accelerator when the walk would be
    /// longer than `max_walk`. Every answer is some primitive's own test.
    pub(crate) fn any_hit(
        &self,
        geometry: &Geometry,
        accel: &SceneIntersector,
        ray: &Ray,
        t_max: f32,
        remembered: Option<u32>,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let tr = TraceRay::new(*ray);
        let plan = self.plan(ray);
        let mut search = HitSearch::new(t_max, QueryMode::Any);
        if let Some(prim) = plan.hint {
            if search.test(geometry, &tr, prim, stats) {
                stats.light_buffer_covered += 1;
                return search.best();
            }
        }
        if let Some(prim) = remembered.filter(|&p| Some(p) != plan.hint) {
            if search.test(geometry, &tr, prim, stats) {
                stats.shadow_cache_hits += 1;
                return search.best();
            }
        }
        if plan.too_long {
            stats.light_buffer_fallbacks += 1;
            return accel.any_hit(geometry, ray, t_max, stats);
        }
        // The planes first, as `SceneIntersector::any_hit` does: a few tests that may spare
        // the lists.
        for &prim in &self.unbounded {
            if search.test_unbounded(geometry, &tr, prim, stats) {
                return search.best();
            }
        }
        for e in plan.prefix.iter().chain(plan.list) {
            stats.node_visits += 1;
            if self.bounds[e.prim as usize]
                .hit(tr.ray.origin, tr.inv_dir, t_max)
                .is_some()
                && search.test(geometry, &tr, e.prim, stats)
            {
                return search.best();
            }
        }
        None
    }

    /// The nearest hit, as `accel.intersect` answers it.
    fn nearest(
        &self,
        geometry: &Geometry,
        accel: &SceneIntersector,
        ray: &Ray,
        t_max: f32,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let plan = self.plan(ray);
        if plan.too_long {
            stats.light_buffer_fallbacks += 1;
            return accel.intersect(geometry, ray, t_max, stats);
        }
        let tr = TraceRay::new(*ray);
        let mut bounded = HitSearch::new(t_max, QueryMode::Nearest);
        for e in plan.prefix.iter().chain(plan.list) {
            stats.node_visits += 1;
            let limit = bounded.nested_limit();
            if self.bounds[e.prim as usize]
                .hit(tr.ray.origin, tr.inv_dir, limit)
                .is_some()
            {
                bounded.test(geometry, &tr, e.prim, stats);
            }
        }
        let mut search = HitSearch::new(t_max, QueryMode::Nearest);
        if let Some(hit) = bounded.best() {
            search.offer(hit);
        }
        for &prim in &self.unbounded {
            search.test_unbounded(geometry, &tr, prim, stats);
        }
        search.best()
    }

    /// The buffer's figures, for `prism info` and the statistics.
    pub fn info(&self) -> LightBufferInfo {
        let cells = self.cells.len();
        LightBufferInfo {
            resolution: self.res,
            cells,
            entries: self.entries.len(),
            mean_list: self.entries.len() as f64 / cells.max(1) as f64,
            max_list: self.cells.iter().map(|c| c.len as usize).max().unwrap_or(0),
            covered_cells: self.cells.iter().filter(|c| c.cover != u32::MAX).count(),
            occupied_cells: self.cells.iter().filter(|c| c.len > 0).count(),
            cut_cells: self
                .cells
                .iter()
                .filter(|c| c.limit < f32::INFINITY)
                .count(),
            max_walk: self.max_walk,
            memory_bytes: self.entries.len() * std::mem::size_of::<Entry>()
                + self.cells.len() * std::mem::size_of::<Cell>()
                + self.by_distance.len() * std::mem::size_of::<Entry>(),
            build_time: self.build_time,
        }
    }
}

/// Box `b` relative to the light, in f64.
fn relative_box(b: Aabb, light: DVec3) -> (DVec3, DVec3) {
    (b.min.as_dvec3() - light, b.max.as_dvec3() - light)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_direction_has_the_face_coordinates_of_its_face() {
        // +z face: u = x/z, v = y/z.
        assert_eq!(face_coords(DVec3::new(0.6, -0.9, 1.0)), (4, 0.6, -0.9));
        // −x face: u = y/|x|, v = z/|x|.
        assert_eq!(face_coords(DVec3::new(-2.0, 1.0, 0.5)), (1, 0.5, 0.25));
    }

    #[test]
    fn a_box_around_the_light_is_seen_on_all_of_every_face() {
        let (lo, hi) = (DVec3::splat(-1.0), DVec3::splat(1.0));
        for face in 0..6 {
            assert_eq!(
                footprint(face, lo, hi),
                Some([-1.0, 1.0, -1.0, 1.0]),
                "face {face}"
            );
        }
    }

    #[test]
    fn a_distant_box_is_seen_through_its_own_window() {
        // A unit box 10 units up the +z axis, centred: u and v within ±0.05.
        let (lo, hi) = (DVec3::new(-0.5, -0.5, 10.0), DVec3::new(0.5, 0.5, 11.0));
        let p = footprint(4, lo, hi).unwrap();
        let e = FOOTPRINT_SLACK;
        for (got, want) in p.iter().zip([-0.05 - e, 0.05 + e, -0.05 - e, 0.05 + e]) {
            assert!((got - want).abs() < 1e-12, "{p:?}");
        }
        for face in [0, 1, 2, 3, 5] {
            assert_eq!(footprint(face, lo, hi), None, "face {face}");
        }
        assert!((near_distance(lo, hi) - 10.0).abs() < 1e-3);
        // The window is the footprint: its 100 cells span ±0.051, not the face's ±1.
        let mut w = Window::EMPTY;
        w.include(p);
        assert_eq!(w.finish(100, 7), 100 * 100);
        let mut empty = Window::EMPTY;
        assert_eq!(empty.finish(100, 7), 0);
        assert_eq!((w.index(0, p[0], 100), w.index(0, p[1], 100)), (0, 99));
        assert!(w.contains(0, 0.0) && !w.contains(0, 0.06));
    }

    #[test]
    fn a_triangle_covers_the_cells_inside_its_outline_only() {
        // A big triangle at z = 1 over the light: covers the centre of the +z face, not a
        // rectangle that pokes out of its hypotenuse.
        let mut g = Geometry::default();
        let positions = vec![
            Vec3::new(-1.0, -1.0, 1.0),
            Vec3::new(1.0, -1.0, 1.0),
            Vec3::new(-1.0, 1.0, 1.0),
        ];
        let mesh = crate::geometry::TriangleMesh::new(positions, vec![[0, 1, 2]], None, None);
        g.add_mesh(mesh.unwrap(), 0);
        let s = Silhouette::of(&g, 0, DVec3::ZERO, 4).unwrap();
        assert!(s.covers(4, (-0.5, -0.1), (-0.5, -0.1)));
        assert!(!s.covers(4, (-0.5, 0.1), (-0.5, 0.1)));
        // Seen from the other side of its plane, it is on no face in front of the light.
        assert!(Silhouette::of(&g, 0, DVec3::new(0.0, 0.0, 2.0), 4).is_none());
    }
}
