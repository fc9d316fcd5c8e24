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
//! The paper's other refinements (cells wholly covered by one opaque polygon answer without
//! a test; polygons facing away from the light left out) are not here: each needs a proof
//! that it gives the BVH's answer at the edges, which the tests could not yet hold it to.

use crate::accel::{Hit, HitSearch, QueryMode};
use crate::geometry::Geometry;
use crate::math::{Aabb, Ray, TraceRay, Vec3};
use crate::stats::Stats;
use glam::DVec3;
use std::time::{Duration, Instant};

/// Widening of every footprint, in face coordinates (tangents, −1 to 1 across a face).
const FOOTPRINT_SLACK: f64 = 1e-3;
/// Relative error allowed for in distances from the light (f32 hit points and directions).
const DISTANCE_SLACK: f64 = 1e-5;

/// One list entry: a primitive and its nearest distance from the light.
#[derive(Clone, Copy, Debug)]
struct Entry {
    prim: u32,
    near: f32,
}

/// Why a light has no buffer (its shadow rays then use the BVH).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Unbuilt {
    /// The cell lists would pass the memory budget.
    OverBudget { entries: u64, budget_bytes: u64 },
}

/// A light buffer around one point: 6 faces × res × res cells.
pub struct LightBuffer {
    light: DVec3,
    res: u32,
    /// Cell c's entries are `entries[offsets[c]..offsets[c + 1]]`, nearest first.
    offsets: Vec<u32>,
    entries: Vec<Entry>,
    /// Every bounded primitive, nearest first: the ones very near the light are tested for
    /// every query.
    by_distance: Vec<Entry>,
    /// Planes have no footprint: every query tests them, as `SceneIntersector` does.
    unbounded: Vec<u32>,
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
    /// Bytes the buffer's offsets and lists take.
    pub memory_bytes: usize,
    /// How long building it took.
    pub build_time: Duration,
}

/// The face and the cell of direction `d` (from the light), and its face coordinates.
fn cell_of(d: DVec3, res: u32) -> usize {
    let a = d.abs();
    let (face, w, u, v) = if a.x >= a.y && a.x >= a.z {
        (if d.x >= 0.0 { 0 } else { 1 }, a.x, d.y, d.z)
    } else if a.y >= a.z {
        (if d.y >= 0.0 { 2 } else { 3 }, a.y, d.z, d.x)
    } else {
        (if d.z >= 0.0 { 4 } else { 5 }, a.z, d.x, d.y)
    };
    (face * res * res) as usize + (cell_index(v / w, res) * res + cell_index(u / w, res)) as usize
}

/// The cell along one side of a face that face coordinate `t` (−1 to 1) falls in; beyond
/// the face's edges, the edge cell.
fn cell_index(t: f64, res: u32) -> u32 {
    (((t + 1.0) * 0.5 * res as f64).floor() as i64).clamp(0, res as i64 - 1) as u32
}

/// For face `face` (0..6: +x, −x, +y, −y, +z, −z), the (depth, u, v) ranges of box
/// `[lo, hi]` (relative to the light) in that face's coordinates.
fn face_ranges(face: usize, lo: DVec3, hi: DVec3) -> [(f64, f64); 3] {
    let (axis, u, v) = match face / 2 {
        0 => (0, 1, 2),
        1 => (1, 2, 0),
        _ => (2, 0, 1),
    };
    let w = if face % 2 == 0 {
        (lo[axis], hi[axis])
    } else {
        (-hi[axis], -lo[axis])
    };
    [w, (lo[u], hi[u]), (lo[v], hi[v])]
}

/// The cells of one face that box `[lo, hi]` may be seen through, as inclusive index
/// ranges (iu0, iu1, iv0, iv1); None when the box is not in that face's pyramid.
fn footprint(face: usize, lo: DVec3, hi: DVec3, res: u32) -> Option<[u32; 4]> {
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
    let all = [0, res - 1, 0, res - 1];
    if w_min <= 0.0 {
        // The box holds the light: it may be seen in every direction.
        return Some(all);
    }
    let range = |a: f64, b: f64| {
        let lo = (a / w_min).min(a / w1) - FOOTPRINT_SLACK;
        let hi = (b / w_min).max(b / w1) + FOOTPRINT_SLACK;
        (cell_index(lo, res), cell_index(hi, res))
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

impl LightBuffer {
    /// The resolution the buffer takes when none is asked for: 4·√n cells a side, within
    /// 32 and 512. A scene seen from its light fills only part of the cube, and a list is
    /// walked up to the shaded point, so cells must be much finer than one per primitive
    /// (on SPD balls and tetra the tests per shadow ray fall about as 1/res up to this).
    pub fn auto_resolution(primitives: usize) -> u32 {
        ((primitives as f64).sqrt() * 4.0)
            .round()
            .clamp(32.0, 512.0) as u32
    }

    /// Builds the buffer of the light at `light` over every primitive of `geometry`, or
    /// says why not: its lists would take more than `budget_bytes`.
    pub fn build(
        geometry: &Geometry,
        light: Vec3,
        res: u32,
        budget_bytes: u64,
    ) -> Result<LightBuffer, Unbuilt> {
        let start = Instant::now();
        let res = res.max(1);
        let l = light.as_dvec3();
        let mut by_distance = Vec::new();
        let mut unbounded = Vec::new();
        // (entry, face, footprint) per covered face.
        let mut prints: Vec<(Entry, usize, [u32; 4])> = Vec::new();
        let mut total: u64 = 0;
        let budget_entries = budget_bytes / std::mem::size_of::<Entry>() as u64;
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
            for face in 0..6 {
                if let Some(p) = footprint(face, lo, hi, res) {
                    total += (p[1] - p[0] + 1) as u64 * (p[3] - p[2] + 1) as u64;
                    prints.push((entry, face, p));
                }
            }
            if total > budget_entries {
                return Err(Unbuilt::OverBudget {
                    entries: total,
                    budget_bytes,
                });
            }
        }
        let cells = 6 * (res * res) as usize;
        let cell = |face: usize, iu: u32, iv: u32| {
            (face * (res * res) as usize) + (iv * res + iu) as usize
        };
        let mut offsets = vec![0u32; cells + 1];
        for &(_, face, [iu0, iu1, iv0, iv1]) in &prints {
            for iv in iv0..=iv1 {
                for iu in iu0..=iu1 {
                    offsets[cell(face, iu, iv) + 1] += 1;
                }
            }
        }
        for c in 0..cells {
            offsets[c + 1] += offsets[c];
        }
        let mut fill = offsets.clone();
        let mut entries = vec![Entry { prim: 0, near: 0.0 }; total as usize];
        for &(entry, face, [iu0, iu1, iv0, iv1]) in &prints {
            for iv in iv0..=iv1 {
                for iu in iu0..=iu1 {
                    let c = cell(face, iu, iv);
                    entries[fill[c] as usize] = entry;
                    fill[c] += 1;
                }
            }
        }
        let by_near = |a: &Entry, b: &Entry| a.near.total_cmp(&b.near).then(a.prim.cmp(&b.prim));
        for c in 0..cells {
            entries[offsets[c] as usize..offsets[c + 1] as usize].sort_unstable_by(by_near);
        }
        by_distance.sort_unstable_by(by_near);
        Ok(LightBuffer {
            light: l,
            res,
            offsets,
            entries,
            by_distance,
            unbounded,
            build_time: start.elapsed(),
        })
    }

    /// The hit a ray from `ray.origin` towards the light meets before `t_max`: the nearest
    /// (`QueryMode::Nearest`) or any (`QueryMode::Any`), exactly as `SceneIntersector`'s
    /// queries answer. The ray must point at this buffer's light.
    pub fn query(
        &self,
        geometry: &Geometry,
        ray: &Ray,
        t_max: f32,
        mode: QueryMode,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let tr = TraceRay::new(*ray);
        let mut search = HitSearch::new(t_max, mode);
        if mode == QueryMode::Any {
            // The planes first, as `SceneIntersector::occluded` does: a few tests that may
            // spare the lists.
            for &prim in &self.unbounded {
                if search.test_unbounded(geometry, &tr, prim, stats) {
                    return search.best();
                }
            }
        }
        let mut bounded = HitSearch::new(t_max, mode);
        self.candidates(ray, |prim| bounded.test(geometry, &tr, prim, stats));
        if mode == QueryMode::Any {
            return bounded.best();
        }
        if let Some(hit) = bounded.best() {
            search.offer(hit);
        }
        for &prim in &self.unbounded {
            search.test_unbounded(geometry, &tr, prim, stats);
        }
        search.best()
    }

    /// Hands every primitive the ray may meet to `test`, until it returns true.
    fn candidates(&self, ray: &Ray, mut test: impl FnMut(u32) -> bool) {
        let q = ray.origin.as_dvec3() - self.light;
        let dir = ray.dir.as_dvec3();
        let reach = q.length();
        // How far the ray's line passes from the light, with room for the f32 direction.
        let delta = q.cross(dir).length() + reach * 1e-6;
        // Nearer than this to the light, a point of the ray may be seen from another cell.
        let near_limit = (4.0 * delta / FOOTPRINT_SLACK) as f32;
        let far_limit = (reach * (1.0 + DISTANCE_SLACK) + delta) as f32;
        for e in &self.by_distance {
            if e.near > near_limit || e.near > far_limit {
                break;
            }
            if test(e.prim) {
                return;
            }
        }
        let c = cell_of(-dir, self.res);
        for e in &self.entries[self.offsets[c] as usize..self.offsets[c + 1] as usize] {
            if e.near > far_limit {
                break;
            }
            if test(e.prim) {
                return;
            }
        }
    }

    /// The buffer's figures, for `prism info` and the statistics.
    pub fn info(&self) -> LightBufferInfo {
        let cells = self.offsets.len() - 1;
        let max_list = self
            .offsets
            .windows(2)
            .map(|w| (w[1] - w[0]) as usize)
            .max()
            .unwrap_or(0);
        LightBufferInfo {
            resolution: self.res,
            cells,
            entries: self.entries.len(),
            mean_list: self.entries.len() as f64 / cells.max(1) as f64,
            max_list,
            memory_bytes: self.entries.len() * std::mem::size_of::<Entry>()
                + self.offsets.len() * 4
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
    fn a_direction_falls_in_the_cell_its_face_coordinates_name() {
        let res = 4;
        // +z face, u = x/z = 0.6 → column 3, v = y/z = −0.9 → row 0.
        assert_eq!(cell_of(DVec3::new(0.6, -0.9, 1.0), res), 4 * 16 + 3);
        // −x face: w = 1, u = z, v = x... the face's own axes.
        assert_eq!(cell_of(DVec3::new(-1.0, 0.0, 0.0), res) / 16, 1);
    }

    #[test]
    fn a_box_around_the_light_covers_every_cell_of_every_face() {
        let (lo, hi) = (DVec3::splat(-1.0), DVec3::splat(1.0));
        for face in 0..6 {
            assert_eq!(
                footprint(face, lo, hi, 8),
                Some([0, 7, 0, 7]),
                "face {face}"
            );
        }
    }

    #[test]
    fn a_distant_box_covers_the_cells_it_is_seen_through() {
        // A unit box 10 units up the +z axis, centred: u and v within ±0.05.
        let (lo, hi) = (DVec3::new(-0.5, -0.5, 10.0), DVec3::new(0.5, 0.5, 11.0));
        assert_eq!(footprint(4, lo, hi, 100), Some([47, 52, 47, 52]));
        for face in [0, 1, 2, 3, 5] {
            assert_eq!(footprint(face, lo, hi, 100), None, "face {face}");
        }
        assert!((near_distance(lo, hi) - 10.0).abs() < 1e-3);
    }
}
