//! The light buffer (Haines & Greenberg, "The Light Buffer: A Shadow-Testing Accelerator",
//! IEEE CG&A 1986): for a point light, a cube of directions around it, each face a grid of
//! cells, each cell what may be seen through it. A shadow ray looks up the cell of its
//! direction and tests only that.
//!
//! Here a cell holds the scene BVH's subtrees instead of a list of primitives (the issue
//! allows it): the deepest few subtrees (at most a node's width, 8 with AVX2) whose boxes
//! together hold every primitive that may be seen through the cell, as one *entry node* in
//! the tree's own layout. A query is the BVH's own walk started at the cell's entry node:
//! it skips the upper levels, whose boxes a shadow ray mostly passes through, and a cell
//! that sees much costs a partial walk rather than a long list. The paper's list, its
//! order by distance and the walk limit of the previous buffer fall away: the walk's box
//! tests cull what lies beyond the shaded point, nearest first.
//!
//! prism's buffer must answer exactly what the BVH answers, so it is built conservatively:
//!
//! - a subtree's footprint on a face comes from the eight corners of its bounding box
//!   (in f64), widened by `FOOTPRINT_SLACK` on every side, and a box that holds the light
//!   covers every cell;
//! - a shadow ray starts at an offset surface point, so its line passes the light at a
//!   small distance δ rather than through it; its points at distance r from the light are
//!   seen δ/r away from its cell's direction. The slack covers that for r ≥ 4δ/slack; a
//!   query for which some leaf lies nearer than that to the light (usually none) asks the
//!   whole BVH instead;
//! - each face's cells span only its *window*, the part of the face some leaf's footprint
//!   reaches (a far light sees the scene in a narrow cone); a direction outside every
//!   window meets no bounded primitive, and takes the nearest cell of its face (any
//!   superset of nothing will do);
//! - the lookup (in f32) and the footprints (in f64) share one monotone rule from face
//!   coordinate to cell; their difference, ~10⁻⁷ in face coordinates, is far inside the
//!   slack;
//! - the walk is the BVH's own (`Bvh::query_entry`): its box tests, leaf tests and tie
//!   rule, on a superset of the primitives the ray may meet.
//!
//! So every answer is the BVH's own over fewer subtrees: exactness rests only on the
//! footprints. Polygons facing away from the light are not left out (prism's shadow rays
//! are blocked by back faces too).
//!
//! A directional light gets one orthographic buffer instead of the cube (as in the paper):
//! all its shadow rays share one direction, so each ray's line is a single point on a
//! plane across that direction, and a cell holds the subtrees whose boxes, projected along
//! the direction, reach it. Its conservative rules are the same in other units: the
//! footprints (f64, the boxes' eight corners) are widened by `PARALLEL_SLACK` of the
//! scene's reach (the largest |x| + |y| + |z| of a leaf's corner), which covers the f32
//! lookup's rounding and the drift of a ray's projection along its length (the plane's
//! axes are f32, so not exactly across the direction) while the ray starts within four
//! reaches of the origin; a ray that starts farther, or whose direction is not the light's
//! bit for bit, asks the whole BVH.

use crate::accel::bvh::{Bvh, EntryNodes, Subtree};
use crate::accel::{Accel, Hit, HitSearch, PacketQuery, QueryMode, SceneIntersector, PACKET_MAX};
use crate::geometry::Geometry;
use crate::math::{Aabb, Ray, TraceRay, Vec3};
use crate::stats::Stats;
use arrayvec::ArrayVec;
use glam::DVec3;
use std::collections::HashMap;
use std::time::{Duration, Instant};

/// Widening of every footprint, in face coordinates (tangents, −1 to 1 across a face).
const FOOTPRINT_SLACK: f64 = 1e-3;
/// Relative error allowed for in distances from the light (f32 hit points and directions).
const DISTANCE_SLACK: f64 = 1e-5;
/// Widening of every footprint of a directional light's buffer, in units of the scene's
/// reach: 30 times the errors it covers (`LightBuffer::build_directional`).
const PARALLEL_SLACK: f64 = 1e-4;
/// How far from the origin, in reaches, a directional light's shadow ray may start and
/// still use the buffer.
const PARALLEL_START: f32 = 4.0;
/// The widest entry node (an 8-wide BVH's).
const MAX_WIDTH: usize = 8;

/// How a buffer is built.
#[derive(Clone, Copy, Debug)]
pub struct BufferParams {
    /// Cells along a face's window side.
    pub res: u32,
    /// The most its cells and entry nodes may take.
    pub budget_bytes: u64,
}

/// Why a light has no buffer (its shadow rays then use the accelerator).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Unbuilt {
    /// The cells and their entry nodes would pass the memory budget.
    OverBudget { bytes: u64, budget_bytes: u64 },
    /// The scene's accelerator is not a BVH of boxes, whose subtrees cells hold.
    NotBvh,
}

impl std::fmt::Display for Unbuilt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unbuilt::OverBudget {
                bytes,
                budget_bytes,
            } => write!(
                f,
                "its cells would take {} MiB, past the budget of {} MiB for it",
                bytes.div_ceil(1 << 20),
                budget_bytes >> 20
            ),
            Unbuilt::NotBvh => write!(f, "the accelerator is not a BVH of boxes"),
        }
    }
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

    #[cfg(test)]
    fn contains(&self, a: usize, t: f64) -> bool {
        t >= self.lo[a] && t <= self.hi[a]
    }
}

#[cfg(test)]
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
    (axis, u, v, if face.is_multiple_of(2) { 1.0 } else { -1.0 })
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

/// Where a query walks (`LightBuffer::route`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Route {
    /// The entry node of its cell.
    Cell(u32),
    /// That and the near node.
    CellAndNear(u32),
    /// The whole BVH.
    Bvh,
}

impl PointLight {
    /// What a query along `ray` must walk besides its cell: its line passes the light at
    /// some distance δ, and points of it nearer than 4δ / slack to the light (and before
    /// the shaded point) may be seen from another cell. Usually no leaf is that near; if
    /// only leaves of the near node are, the query walks it too; otherwise it asks the BVH.
    #[inline(always)]
    fn near_light(&self, ray: &Ray) -> Near {
        // The usual case in f32: δ ≤ |q × dir| + 2·10⁻⁶ |q| (10⁻⁶ for the f32 direction as
        // below, and as much again for this f32 arithmetic, whose errors are relative to
        // |q|: q = origin − light is one correctly rounded subtraction), both terms below
        // half of near_first · slack / 4 (`self.quick`, rounded down).
        let q = ray.origin - self.light_f32;
        let cross2 = q.cross(ray.dir).length_squared();
        let reach2 = q.length_squared();
        if cross2 < self.quick && reach2 * 4e-12 < self.quick {
            return Near::None;
        }
        let q = ray.origin.as_dvec3() - self.light;
        let dir = ray.dir.as_dvec3();
        let reach = q.length();
        // How far the ray's line passes from the light, with room for the f32 direction.
        let delta = q.cross(dir).length() + reach * 1e-6;
        let near_limit = 4.0 * delta / FOOTPRINT_SLACK;
        let far_limit = reach * (1.0 + DISTANCE_SLACK) + delta;
        let limit = near_limit.min(far_limit);
        if self.near_first > limit {
            Near::None
        } else if self.near_rest > limit {
            Near::Node
        } else {
            Near::Bvh
        }
    }
}

/// What a query walks besides its cell (`PointLight::near_light`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Near {
    /// Nothing.
    None,
    /// The entry node of the leaves nearest the light.
    Node,
    /// The whole BVH instead.
    Bvh,
}

/// One face's cells as the lookup sees them, in f32: cell (iu, iv) of a face is
/// `base + iv · res + iu`, with iu = ⌊(u − lo) · scale⌋ clamped to the window.
#[derive(Clone, Copy, Debug)]
struct Face {
    lo: [f32; 2],
    scale: [f32; 2],
    /// The last cell index along a side (res − 1; 0 for a face without cells, whose one
    /// cell is the empty one at 0).
    last: i32,
    base: u32,
}

/// How a buffer's cells map the rays' directions or lines.
#[derive(Clone, Copy, Debug)]
enum Projection {
    /// A point light: the cube of directions around it.
    Point(PointLight),
    /// A directional light: one face across its direction.
    Parallel(ParallelGrid),
}

/// A point light's position and what `near_light` needs of the leaves nearest it.
#[derive(Clone, Copy, Debug)]
struct PointLight {
    light: DVec3,
    light_f32: Vec3,
    /// (nearest · slack / 8)², rounded down: `near_light`'s quick bound.
    quick: f32,
    /// The nearest distance of any leaf from the light: a query whose line passes the light
    /// so far off that points this near could be seen from another cell also walks
    /// `NEAR_ENTRY`, the entry node of the leaves nearest the light (a node's width of
    /// them: a light inside a room sees the leaf of its walls, whose box holds it, in
    /// every direction) ...
    near_first: f64,
    /// ... and one that passes it so far off that the nearest leaf left out of that node,
    /// this far away, could be seen from another cell asks the whole BVH.
    near_rest: f64,
}

/// A directional light's face, on which a shadow ray's line is the point
/// (origin · `axes[0]`, origin · `axes[1]`).
#[derive(Clone, Copy, Debug)]
struct ParallelGrid {
    /// The direction towards the light, as its shadow rays carry it.
    to_light: Vec3,
    axes: [Vec3; 2],
    /// Rays starting farther from the origin than this (|x| + |y| + |z|) ask the BVH.
    start_limit: f32,
}

/// The entry node of the leaves nearest a point light (empty for a directional light).
const NEAR_ENTRY: u32 = 1;

/// A light buffer around one point (res × res cells on each face some primitive is seen
/// on) or across one direction (res × res cells), each cell the index of its entry node.
pub struct LightBuffer {
    projection: Projection,
    res: u32,
    faces: [Face; 6],
    /// Per cell, its entry node (cells that see the same subtrees share one).
    cells: Vec<u32>,
    entries: EntryNodes,
    /// Mean subtrees per cell and the share of them that are leaves.
    mean_subtrees: f64,
    leaf_share: f64,
    build_time: Duration,
}

/// What `prism info` and the statistics say about a buffer.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LightBufferInfo {
    /// Cells along each side of a direction-cube face's window, or of the orthographic
    /// grid.
    pub resolution: u32,
    /// Whether the buffer is a directional light's orthographic grid (else a cube).
    pub orthographic: bool,
    /// Cells over all faces.
    pub cells: usize,
    /// Distinct entry nodes (cells seeing the same subtrees share one).
    pub entry_nodes: usize,
    /// Mean subtrees per cell.
    pub mean_subtrees: f64,
    /// Share of the cells' subtrees that are leaves.
    pub leaf_share: f64,
    /// Bytes the cells and entry nodes take.
    pub memory_bytes: usize,
    /// How long building it took.
    pub build_time: Duration,
}

/// The subtrees of a BVH, parents before children: what the cells choose from.
struct Tree {
    subtrees: Vec<Subtree>,
    /// Per subtree, where its children lie in `subtrees` (empty for a leaf).
    children: Vec<std::ops::Range<u32>>,
    /// Per subtree, its box's surface area: the larger, the more rays enter it.
    area: Vec<f32>,
    /// The root's subtrees.
    top: std::ops::Range<u32>,
}

impl Tree {
    fn of(bvh: &Bvh) -> Tree {
        let mut subtrees = bvh.root_subtrees();
        let top = 0..subtrees.len() as u32;
        let mut children = Vec::new();
        let mut i = 0;
        while i < subtrees.len() {
            let kids = bvh.subtrees_of(&subtrees[i]);
            let first = subtrees.len() as u32;
            children.push(first..first + kids.len() as u32);
            subtrees.extend(kids);
            i += 1;
        }
        let area = subtrees.iter().map(|s| s.bounds.surface_area()).collect();
        Tree {
            subtrees,
            children,
            area,
            top,
        }
    }
}

impl LightBuffer {
    /// The resolution the buffer takes when none is asked for: √n / 2 cells along a
    /// window's side, within 16 and 32. Finer cells hold deeper subtrees but cost memory
    /// the walk then misses in the CPU cache: on SPD gears (36,610 triangles) 24 cells
    /// gave 0.98× the BVH's speed and 96 (6.6 MiB) 0.87×; on the other SPD scenes 32 to
    /// 64 were best, 128 and 256 slower (prism bench, docs/shadows.md).
    pub fn auto_resolution(primitives: usize) -> u32 {
        ((primitives as f64).sqrt() * 0.5).round().clamp(16.0, 32.0) as u32
    }

    /// Builds the buffer of the light at `light` over the BVH of `intersector` (which its
    /// queries must be given), or says why not.
    pub fn build(
        intersector: &SceneIntersector,
        light: Vec3,
        params: &BufferParams,
    ) -> Result<LightBuffer, Unbuilt> {
        let l = light.as_dvec3();
        let print = |b| {
            let (lo, hi) = relative_box(b, l);
            let prints = std::array::from_fn(|face| footprint(face, lo, hi));
            (prints, Some(near_distance(lo, hi)))
        };
        Self::build_over(intersector, params, print, |near_first, near_rest| {
            let half = near_first * FOOTPRINT_SLACK / 8.0;
            Projection::Point(PointLight {
                light: l,
                light_f32: light,
                quick: (half * half * 0.99) as f32,
                near_first,
                near_rest,
            })
        })
    }

    /// Builds the orthographic buffer of a directional light whose shadow rays point along
    /// `to_light` (a unit vector), over the BVH of `intersector`, or says why not.
    pub fn build_directional(
        intersector: &SceneIntersector,
        to_light: Vec3,
        params: &BufferParams,
    ) -> Result<LightBuffer, Unbuilt> {
        let bvh = intersector.accel.as_bvh().ok_or(Unbuilt::NotBvh)?;
        let axes = plane_axes(to_light);
        let axes64 = axes.map(|a| a.as_dvec3());
        // The reach: no leaf corner lies farther from the origin (|x| + |y| + |z|).
        let root = (bvh.root_subtrees().iter()).fold(Aabb::EMPTY, |a, s| a.union(&s.bounds));
        let reach = if root.is_empty() {
            0.0
        } else {
            let far = root.min.abs().max(root.max.abs()).as_dvec3();
            far.x + far.y + far.z
        };
        let slack = PARALLEL_SLACK * reach;
        let grid = ParallelGrid {
            to_light,
            axes,
            start_limit: (PARALLEL_START as f64 * reach) as f32,
        };
        let print = |b| {
            let mut prints = [None; 6];
            prints[0] = Some(parallel_footprint(b, axes64, slack));
            (prints, None)
        };
        Self::build_over(intersector, params, print, |_, _| {
            Projection::Parallel(grid)
        })
    }

    /// The cells and entry nodes of a buffer whose subtree boxes `print` maps to their
    /// footprints on the six faces and, around a point light, their nearest distance from
    /// it; `projection` makes the lookup from the nearest leaf's distance and that of the
    /// first leaf left out of the near node (infinite without distances).
    fn build_over(
        intersector: &SceneIntersector,
        params: &BufferParams,
        print: impl Fn(Aabb) -> ([Option<[f64; 4]>; 6], Option<f32>),
        projection: impl FnOnce(f64, f64) -> Projection,
    ) -> Result<LightBuffer, Unbuilt> {
        let start = Instant::now();
        let bvh = intersector.accel.as_bvh().ok_or(Unbuilt::NotBvh)?;
        let res = params.res.clamp(1, u16::MAX as u32);
        let tree = Tree::of(bvh);
        let n = tree.subtrees.len();
        // Per face, each subtree's footprint; the windows span the leaves' footprints.
        let mut windows = [Window::EMPTY; 6];
        let mut prints: Vec<[Option<[f64; 4]>; 6]> = Vec::with_capacity(n);
        let mut near: Vec<(f32, u32)> = Vec::new();
        for (i, s) in tree.subtrees.iter().enumerate() {
            let (p, distance) = print(s.bounds);
            if s.is_leaf() {
                if let Some(distance) = distance {
                    near.push((distance, i as u32));
                }
                for (w, p) in windows.iter_mut().zip(&p) {
                    if let Some(p) = p {
                        w.include(*p);
                    }
                }
            }
            prints.push(p);
        }
        // Cell 0 is the one cell of every face without a window, and sees nothing; entry
        // node 0 is empty, 1 the near node.
        let mut cell_count = 1;
        for w in &mut windows {
            cell_count += w.finish(res, cell_count);
        }
        let cell_bytes = cell_count as u64 * 4;
        if cell_bytes > params.budget_bytes {
            return Err(Unbuilt::OverBudget {
                bytes: cell_bytes,
                budget_bytes: params.budget_bytes,
            });
        }
        let width = bvh.entry_width().min(MAX_WIDTH);
        // The leaves nearest the light, in an entry node of their own: `NEAR_ENTRY`.
        near.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let near_first = near.first().map_or(f64::INFINITY, |n| n.0 as f64);
        let near_rest = near.get(width).map_or(f64::INFINITY, |n| n.0 as f64);
        let mut near_list: ArrayVec<u32, MAX_WIDTH> =
            near.iter().take(width).map(|n| n.1).collect();
        near_list.sort_unstable();
        let mut cells = vec![0u32; cell_count];
        let mut lists: Vec<ArrayVec<u32, MAX_WIDTH>> = vec![ArrayVec::new(), near_list];
        let mut known: HashMap<ArrayVec<u32, MAX_WIDTH>, u32> = HashMap::new();
        known.insert(ArrayVec::new(), 0);
        let (mut subtree_sum, mut leaf_sum) = (0usize, 0usize);
        for (face, w) in windows.iter().enumerate() {
            if w.lo[0] > w.hi[0] {
                continue;
            }
            // Each subtree's rectangle of cells on this face (iu0, iu1, iv0, iv1), or None.
            let rects: Vec<Option<[u32; 4]>> = prints
                .iter()
                .map(|p| {
                    p[face].map(|p| {
                        [
                            w.index(0, p[0], res),
                            w.index(0, p[1], res),
                            w.index(1, p[2], res),
                            w.index(1, p[3], res),
                        ]
                    })
                })
                .collect();
            for iv in 0..res {
                for iu in 0..res {
                    let list = cut(&tree, &rects, iu, iv, width);
                    subtree_sum += list.len();
                    leaf_sum += list
                        .iter()
                        .filter(|&&s| tree.subtrees[s as usize].is_leaf())
                        .count();
                    let next = lists.len() as u32;
                    let id = *known.entry(list.clone()).or_insert(next);
                    if id == next {
                        lists.push(list);
                    }
                    cells[w.base + (iv * res + iu) as usize] = id;
                }
            }
        }
        let bytes = cell_bytes + (lists.len() * 32 * width) as u64;
        if bytes > params.budget_bytes {
            return Err(Unbuilt::OverBudget {
                bytes,
                budget_bytes: params.budget_bytes,
            });
        }
        let subtree_lists: Vec<Vec<Subtree>> = lists
            .iter()
            .map(|l| l.iter().map(|&s| tree.subtrees[s as usize]).collect())
            .collect();
        let entries = bvh.entry_nodes(subtree_lists.iter().map(Vec::as_slice));
        let faces = windows.map(|w| {
            if w.lo[0] > w.hi[0] {
                Face {
                    lo: [0.0; 2],
                    scale: [0.0; 2],
                    last: 0,
                    base: 0,
                }
            } else {
                Face {
                    lo: w.lo.map(|x| x as f32),
                    scale: w.scale.map(|x| x as f32),
                    last: res as i32 - 1,
                    base: w.base as u32,
                }
            }
        });
        let filled = (cell_count - 1).max(1) as f64;
        let projection = projection(near_first, near_rest);
        Ok(LightBuffer {
            projection,
            res,
            faces,
            cells,
            entries,
            mean_subtrees: subtree_sum as f64 / filled,
            leaf_share: leaf_sum as f64 / subtree_sum.max(1) as f64,
            build_time: start.elapsed(),
        })
    }

    /// The entry node of the direction from the light back along `tr`'s ray: its face is
    /// the ray's dominant axis (`TraceRay::kz`, chosen by the same comparisons as
    /// `face_coords`), and 1 / |dir[kz]| is already `shear.z`; no division, no branch
    /// but the face's.
    #[inline(always)]
    fn entry_of(&self, tr: &TraceRay) -> u32 {
        let d = tr.ray.dir;
        let kz = tr.kz;
        // Looking back at the ray's origin from the light: direction −dir.
        let face = 2 * kz + usize::from(d[kz] > 0.0);
        let (u_axis, v_axis) = [(1, 2), (2, 0), (0, 1)][kz];
        let inv = tr.shear.z.abs();
        self.cell(face, -d[u_axis] * inv, -d[v_axis] * inv)
    }

    /// The entry node of the cell at face coordinates (u, v) of face `face`.
    #[inline(always)]
    fn cell(&self, face: usize, u: f32, v: f32) -> u32 {
        let f = &self.faces[face];
        // `as` truncates towards zero and saturates (NaN to 0); below 0 is clamped anyway.
        let iu = (((u - f.lo[0]) * f.scale[0]) as i32).clamp(0, f.last);
        let iv = (((v - f.lo[1]) * f.scale[1]) as i32).clamp(0, f.last);
        let cell = f.base as usize + (iv * (f.last + 1) + iu) as usize;
        self.cells[cell]
    }

    /// `entry_of` for a ray without its traversal constants: the same dominant axis, by
    /// the same comparisons (`math::ray::watertight_axes`), and the same 1 / |dir[kz]|.
    #[inline(always)]
    fn entry_of_dir(&self, d: Vec3) -> u32 {
        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let face = 2 * kz + usize::from(d[kz] > 0.0);
        let (u_axis, v_axis) = [(1, 2), (2, 0), (0, 1)][kz];
        let inv = (1.0 / d[kz]).abs();
        self.cell(face, -d[u_axis] * inv, -d[v_axis] * inv)
    }

    /// Where a query along `tr` walks: its cell's entry node, with the near node for a
    /// point light's ray that passes the light far off (`near_light`), or the whole BVH.
    #[inline(always)]
    fn route(&self, tr: &TraceRay) -> Route {
        self.route_with(&tr.ray, || self.entry_of(tr))
    }

    /// `route` for a ray without its traversal constants.
    #[inline(always)]
    fn route_of_ray(&self, ray: &Ray) -> Route {
        self.route_with(ray, || self.entry_of_dir(ray.dir))
    }

    /// `route`, with `entry` the cell's entry node of the ray's direction.
    #[inline(always)]
    fn route_with(&self, ray: &Ray, entry: impl Fn() -> u32) -> Route {
        match self.projection {
            Projection::Point(point) => match point.near_light(ray) {
                Near::None => Route::Cell(entry()),
                Near::Node => Route::CellAndNear(entry()),
                Near::Bvh => Route::Bvh,
            },
            Projection::Parallel(ParallelGrid {
                to_light,
                axes,
                start_limit,
            }) => {
                let o = ray.origin;
                // Written so that a NaN origin asks the BVH too.
                let near_enough = o.abs().element_sum() <= start_limit;
                if ray.dir != to_light || !near_enough {
                    return Route::Bvh;
                }
                Route::Cell(self.cell(0, o.dot(axes[0]), o.dot(axes[1])))
            }
        }
    }

    /// The hit a ray from `ray.origin` towards the light meets before `t_max`: the nearest
    /// (`QueryMode::Nearest`) or any (`QueryMode::Any`), exactly as `accel`'s queries
    /// answer. The ray must point at this buffer's light, and `accel` be the one the buffer
    /// was built over.
    pub fn query(
        &self,
        geometry: &Geometry,
        accel: &SceneIntersector,
        ray: &Ray,
        t_max: f32,
        mode: QueryMode,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let bvh = accel.accel.as_bvh().expect("a buffer is built over a BVH");
        match mode {
            QueryMode::Any => self.any_hit(geometry, accel, bvh, ray, t_max, None, stats),
            QueryMode::Nearest => self.nearest(geometry, accel, bvh, ray, t_max, stats),
        }
    }

    /// An any-hit query, as `accel.any_hit` answers it: first `remembered` (the shadow
    /// cache's blocker; a hit counts as a cache hit), the planes, then the walk from the
    /// cell's entry node of `bvh` (`accel`'s).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn any_hit(
        &self,
        geometry: &Geometry,
        accel: &SceneIntersector,
        bvh: &Bvh,
        ray: &Ray,
        t_max: f32,
        remembered: Option<u32>,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let tr = TraceRay::new(*ray);
        let mut search = HitSearch::new(t_max, QueryMode::Any);
        if let Some(prim) = remembered {
            if search.test(geometry, &tr, prim, stats) {
                stats.shadow_cache_hits += 1;
                return search.best();
            }
        }
        let route = self.route(&tr);
        if route == Route::Bvh {
            stats.light_buffer_fallbacks += 1;
            return accel.any_hit(geometry, ray, t_max, stats);
        }
        if let Some(plane) = accel.plane_blocker(geometry, &tr, t_max, stats) {
            return Some(plane);
        }
        let mut walk = |entry| {
            bvh.query_entry(
                self.entries.get(entry),
                geometry,
                &tr,
                t_max,
                QueryMode::Any,
                stats,
            )
        };
        match route {
            Route::CellAndNear(entry) => walk(NEAR_ENTRY).or_else(|| walk(entry)),
            Route::Cell(entry) => walk(entry),
            Route::Bvh => unreachable!("answered above"),
        }
    }

    /// `any_hit` (without a remembered blocker) for a packet of shadow rays towards this
    /// buffer's light (at most `PACKET_MAX`): `answers[i]` is a hit for `rays[i]` exactly
    /// where `any_hit` finds one (the planes' where a plane blocks, as they are tested
    /// first). A packet whose rays all look up one cell walks as one packet from the
    /// cell's entry node; any other walks from the BVH's root as one packet (after the
    /// near node for rays that pass the light close by). Split by cell, the packets of rays
    /// of neighbouring pixels came apart into packets of a few rays (teapot: 2.8 a packet
    /// of 58), whose fixed costs outweighed the levels each skipped.
    /// `accel` must be the one the buffer was built over, and every ray point at its light.
    pub fn any_hit_packet(
        &self,
        geometry: &Geometry,
        accel: &SceneIntersector,
        rays: &[Ray],
        t_max: &[f32],
        answers: &mut [Option<Hit>],
        stats: &mut Stats,
    ) {
        let bvh = Self::packet_bvh(accel, rays, t_max, answers, stats);
        let n = rays.len();
        if n == 0 {
            return;
        }
        // Planes first, as `any_hit` and `SceneIntersector::any_hit` test them.
        let planes = !accel.unbounded().is_empty();
        for (i, ray) in rays.iter().enumerate() {
            answers[i] = None;
            if planes {
                let tr = TraceRay::new(*ray);
                answers[i] = accel.plane_blocker(geometry, &tr, t_max[i], stats);
            }
        }
        let mut near = ArrayVec::new();
        let cell = self.packet_cell(rays, &mut near, stats);
        near.retain(|i| answers[usize::from(*i)].is_none());
        // The near node first, as `any_hit` asks it first.
        self.walk_packet(
            geometry,
            bvh,
            Some(NEAR_ENTRY),
            &near,
            rays,
            t_max,
            answers,
            stats,
        );
        let open: ArrayVec<u8, PACKET_MAX> = (0..n as u8)
            .filter(|&i| answers[usize::from(i)].is_none())
            .collect();
        self.walk_packet(geometry, bvh, cell, &open, rays, t_max, answers, stats);
    }

    /// The BVH a packet query walks (`accel`'s), after checking the packet's lengths and
    /// counting its rays as the buffer's queries.
    fn packet_bvh<'b>(
        accel: &'b SceneIntersector,
        rays: &[Ray],
        t_max: &[f32],
        answers: &[Option<Hit>],
        stats: &mut Stats,
    ) -> &'b Bvh {
        let n = rays.len();
        assert!(n <= PACKET_MAX && t_max.len() == n && answers.len() == n);
        stats.light_buffer_queries += n as u64;
        accel.accel.as_bvh().expect("a buffer is built over a BVH")
    }

    /// `nearest` for a packet of rays towards this buffer's light (at most `PACKET_MAX`):
    /// `answers[i]` is exactly what `nearest` gives `rays[i]`. A packet whose rays all look
    /// up one cell (and pass the light far off) walks as one packet from the cell's entry
    /// node; any other walks from the BVH's root, as `accel`'s packets do.
    pub fn nearest_packet(
        &self,
        geometry: &Geometry,
        accel: &SceneIntersector,
        rays: &[Ray],
        t_max: &[f32],
        answers: &mut [Option<Hit>],
        stats: &mut Stats,
    ) {
        let bvh = Self::packet_bvh(accel, rays, t_max, answers, stats);
        let mut near = ArrayVec::new();
        let cell = self.packet_cell(rays, &mut near, stats);
        let packet = PacketQuery::new(geometry, rays, t_max, QueryMode::Nearest);
        // A ray that passes the light close by needs the near node's walk and its cell's,
        // the nearer hit of the two: the packet walks from the root instead.
        let Some(entry) = cell.filter(|_| near.is_empty()) else {
            accel.query_packet(&packet, answers, stats);
            return;
        };
        bvh.query_entry_packet(self.entries.get(entry), &packet, answers, stats);
        // The planes, as `nearest` offers them after the walk.
        accel.add_planes(&packet, answers, stats);
    }

    /// The entry node of the cell every ray of a packet looks up, where they all look up
    /// one and none asks the whole BVH (those count as fallbacks); the rays that also pass
    /// the light close by (`Route::CellAndNear`) go to `near`.
    fn packet_cell(
        &self,
        rays: &[Ray],
        near: &mut ArrayVec<u8, PACKET_MAX>,
        stats: &mut Stats,
    ) -> Option<u32> {
        let mut common = None;
        let mut shared = true;
        for (i, ray) in rays.iter().enumerate() {
            let entry = match self.route_of_ray(ray) {
                Route::Bvh => {
                    stats.light_buffer_fallbacks += 1;
                    shared = false;
                    continue;
                }
                Route::Cell(entry) => entry,
                Route::CellAndNear(entry) => {
                    near.push(i as u8);
                    entry
                }
            };
            shared &= *common.get_or_insert(entry) == entry;
        }
        common.filter(|_| shared)
    }

    /// The rays `lanes` of a packet walked together from entry node `entry` (from the
    /// BVH's root without one); the hits they meet go to `answers`.
    #[allow(clippy::too_many_arguments)]
    fn walk_packet(
        &self,
        geometry: &Geometry,
        bvh: &Bvh,
        entry: Option<u32>,
        lanes: &[u8],
        rays: &[Ray],
        t_max: &[f32],
        answers: &mut [Option<Hit>],
        stats: &mut Stats,
    ) {
        let m = lanes.len();
        if m == 0 {
            return;
        }
        let mut walk = |rays: &[Ray], t_max: &[f32], answers: &mut [Option<Hit>]| {
            let mode = QueryMode::Any;
            let packet = PacketQuery::new(geometry, rays, t_max, mode);
            match entry {
                Some(e) => bvh.query_entry_packet(self.entries.get(e), &packet, answers, stats),
                None => bvh.query_packet(&packet, answers, stats),
            }
        };
        if m == rays.len() {
            // The whole packet, as it came.
            walk(rays, t_max, answers);
            return;
        }
        let group: ArrayVec<Ray, PACKET_MAX> =
            lanes.iter().map(|&i| rays[usize::from(i)]).collect();
        let bounds: ArrayVec<f32, PACKET_MAX> =
            lanes.iter().map(|&i| t_max[usize::from(i)]).collect();
        let mut found = [None; PACKET_MAX];
        walk(&group, &bounds, &mut found[..m]);
        for (&i, &hit) in lanes.iter().zip(&found[..m]) {
            answers[usize::from(i)] = hit;
        }
    }

    /// The nearest hit, as `accel.intersect` answers it.
    pub(crate) fn nearest(
        &self,
        geometry: &Geometry,
        accel: &SceneIntersector,
        bvh: &Bvh,
        ray: &Ray,
        t_max: f32,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let tr = TraceRay::new(*ray);
        let mut entries = ArrayVec::<u32, 2>::new();
        match self.route(&tr) {
            Route::Bvh => {
                stats.light_buffer_fallbacks += 1;
                return accel.intersect(geometry, ray, t_max, stats);
            }
            Route::Cell(entry) => entries.push(entry),
            Route::CellAndNear(entry) => entries.extend([entry, NEAR_ENTRY]),
        }
        let mut search = HitSearch::new(t_max, QueryMode::Nearest);
        for entry in entries {
            let bounded = bvh.query_entry(
                self.entries.get(entry),
                geometry,
                &tr,
                search.nested_limit(),
                QueryMode::Nearest,
                stats,
            );
            // The nearer of the two walks' hits, ties to the lower id (`offer`).
            if let Some(hit) = bounded {
                search.offer(hit);
            }
        }
        // The walks' hit against the planes (offered to a fresh search, it leaves the
        // search as it is here).
        accel.nearest_with_planes(geometry, &tr, t_max, search.best(), stats)
    }

    /// The buffer's figures, for `prism info` and the statistics.
    pub fn info(&self) -> LightBufferInfo {
        LightBufferInfo {
            resolution: self.res,
            orthographic: matches!(self.projection, Projection::Parallel(_)),
            cells: self.cells.len(),
            entry_nodes: self.entries.len(),
            mean_subtrees: self.mean_subtrees,
            leaf_share: self.leaf_share,
            memory_bytes: self.cells.len() * 4 + self.entries.memory_bytes(),
            build_time: self.build_time,
        }
    }
}

/// The subtrees cell (iu, iv) of a face holds, at most `width`: from the root's, each
/// replaced by those of its children whose footprints (`rects`) reach the cell, the one
/// with the largest box first, while they fit. Sorted, so equal cells share an entry node.
fn cut(
    tree: &Tree,
    rects: &[Option<[u32; 4]>],
    iu: u32,
    iv: u32,
    width: usize,
) -> ArrayVec<u32, MAX_WIDTH> {
    let meets = |s: u32| {
        rects[s as usize]
            .is_some_and(|[u0, u1, v0, v1]| u0 <= iu && iu <= u1 && v0 <= iv && iv <= v1)
    };
    let mut list: ArrayVec<u32, MAX_WIDTH> = tree.top.clone().filter(|&s| meets(s)).collect();
    loop {
        // The interior subtree with the largest box whose children in the cell fit.
        let mut best: Option<(usize, f32)> = None;
        for (k, &s) in list.iter().enumerate() {
            let kids = tree.children[s as usize].clone();
            if kids.is_empty() || best.is_some_and(|(_, a)| a >= tree.area[s as usize]) {
                continue;
            }
            let n = kids.filter(|&c| meets(c)).count();
            if list.len() - 1 + n <= width {
                best = Some((k, tree.area[s as usize]));
            }
        }
        let Some((k, _)) = best else { break };
        let s = list.swap_remove(k);
        for c in tree.children[s as usize].clone() {
            if meets(c) {
                list.push(c);
            }
        }
    }
    list.sort_unstable();
    list
}

/// Two unit axes across `to_light` (in f32, the lookup's; the footprints use the same
/// values in f64): the first across its smallest component, the second across both.
fn plane_axes(to_light: Vec3) -> [Vec3; 2] {
    let d = to_light.as_dvec3();
    let a = d.abs();
    let across = if a.x <= a.y && a.x <= a.z {
        DVec3::X
    } else if a.y <= a.z {
        DVec3::Y
    } else {
        DVec3::Z
    };
    let u = d.cross(across).normalize();
    let v = d.cross(u).normalize();
    [u.as_vec3(), v.as_vec3()]
}

/// Where box `b` projects along a directional light's rays onto the plane of `axes`:
/// (u0, u1, v0, v1) over its eight corners, widened by `slack`.
fn parallel_footprint(b: Aabb, axes: [DVec3; 2], slack: f64) -> [f64; 4] {
    let (lo, hi) = (b.min.as_dvec3(), b.max.as_dvec3());
    let range = |axis: DVec3| {
        // Per coordinate, the corner's smaller and larger contribution.
        let (a, c) = (lo * axis, hi * axis);
        let (small, large) = (a.min(c), a.max(c));
        (small.element_sum() - slack, large.element_sum() + slack)
    };
    let (u0, u1) = range(axes[0]);
    let (v0, v1) = range(axes[1]);
    [u0, u1, v0, v1]
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

    /// The packets' lookup without traversal constants finds the cell of the single rays'
    /// lookup, for every direction: random ones, axis-aligned ones, and ties between axes
    /// (where the dominant axis is chosen by the same comparisons).
    #[test]
    fn a_rays_cell_is_the_same_with_and_without_its_traversal_constants() {
        use crate::geometry::{Shape, Sphere};
        use crate::math::hash::uniform;
        let mut geometry = Geometry::default();
        for k in 0..40 {
            let c = Vec3::new(
                uniform(k, 1, 0, 0, 3) * 8.0 - 4.0,
                uniform(k, 2, 0, 0, 3) * 8.0 - 4.0,
                uniform(k, 3, 0, 0, 3) * 8.0 - 4.0,
            );
            geometry.add(Shape::Sphere(Sphere::new(c, 0.3)), 0);
        }
        let accel = SceneIntersector::build(&geometry, &crate::accel::AccelSpec::default());
        let params = BufferParams {
            res: 16,
            budget_bytes: 1 << 30,
        };
        let buffer = LightBuffer::build(&accel, Vec3::new(0.5, 0.2, -0.1), &params).unwrap();
        let mut dirs: Vec<Vec3> = (0..20_000)
            .map(|k| {
                Vec3::new(
                    uniform(k, 4, 0, 0, 3) * 2.0 - 1.0,
                    uniform(k, 5, 0, 0, 3) * 2.0 - 1.0,
                    uniform(k, 6, 0, 0, 3) * 2.0 - 1.0,
                )
                .normalize()
            })
            .collect();
        for a in [-1.0f32, 1.0] {
            for b in [-1.0f32, 0.0, 1.0] {
                for c in [-1.0f32, 0.0, 1.0] {
                    dirs.extend([Vec3::new(a, b, c), Vec3::new(b, a, c), Vec3::new(c, b, a)]);
                }
            }
        }
        for d in dirs.into_iter().filter(|d| *d != Vec3::ZERO) {
            let d = d.normalize();
            let tr = TraceRay::new(Ray::new(Vec3::ZERO, d));
            assert_eq!(
                buffer.entry_of_dir(d),
                buffer.entry_of(&tr),
                "direction {d}"
            );
        }
    }
}
