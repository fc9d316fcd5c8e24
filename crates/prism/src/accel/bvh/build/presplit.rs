//! Pre-splitting ("early split clipping", Ernst & Greiner 2007; budgeted as in Karras &
//! Aila 2013): before the build, a triangle whose box is mostly empty — long, thin and
//! diagonal — is entered several times, each reference bounded by the box of the part of
//! the triangle inside one half of its box (halved again, recursively). The builder then
//! sees small, tight boxes instead of one big one, which is what spatial splits (SBVH) buy,
//! at the price of duplicate references. Other shapes keep one reference.
//!
//! A reference's box is the clipped polygon's box grown by a relative margin, and the
//! boxes of a triangle's pieces always cover the whole triangle (each piece keeps the
//! split plane exactly), so no hit is lost; a ray that meets two pieces finds the same
//! primitive at the same distance twice, which changes nothing.

use crate::geometry::{Geometry, Shape};
use crate::math::robust::gamma;
use crate::math::{Aabb, Vec3};
use arrayvec::ArrayVec;

/// A triangle clipped by a few planes: each plane adds at most one vertex, and no caller
/// clips by more than seven.
pub(super) type Polygon = ArrayVec<Vec3, 10>;

/// At most this many references per triangle (four levels of halving).
const MAX_PIECES: usize = 16;

/// References for `prims` (whose boxes are `bounds`): triangles split into up to 16 pieces
/// where their boxes are emptiest, `budget × prims.len()` extra references in all.
pub(super) fn presplit(
    geometry: &Geometry,
    prims: Vec<u32>,
    bounds: Vec<Aabb>,
    budget: f32,
) -> (Vec<u32>, Vec<Aabb>) {
    let extra = (budget.max(0.0) as f64 * prims.len() as f64) as usize;
    let triangles: Vec<Option<[Vec3; 3]>> = prims.iter().map(|&p| triangle(geometry, p)).collect();
    // Priority: the box area the triangle does not use (Karras & Aila's measure), to the
    // power 1/3 so that the budget spreads over many triangles rather than a few.
    let priority: Vec<f64> = triangles
        .iter()
        .zip(&bounds)
        .map(|(t, b)| match t {
            Some([a, b2, c]) => {
                let area = 0.5 * (*b2 - *a).cross(*c - *a).length() as f64;
                (b.surface_area() as f64 - 2.0 * area).max(0.0).cbrt()
            }
            None => 0.0,
        })
        .collect();
    let total: f64 = priority.iter().sum();
    let scene = bounds.iter().fold(Aabb::EMPTY, |s, b| s.union(b));
    let mut out_prims = Vec::with_capacity(prims.len() + extra);
    let mut out_bounds = Vec::with_capacity(prims.len() + extra);
    for (i, (&prim, b)) in prims.iter().zip(&bounds).enumerate() {
        let pieces = if total > 0.0 {
            1 + (extra as f64 * priority[i] / total) as usize
        } else {
            1
        }
        .min(MAX_PIECES);
        match triangles[i] {
            Some(tri) if pieces > 1 => {
                split(&tri, *b, &scene, pieces, &mut |piece| {
                    out_prims.push(prim);
                    out_bounds.push(piece);
                });
            }
            _ => {
                out_prims.push(prim);
                out_bounds.push(*b);
            }
        }
    }
    (out_prims, out_bounds)
}

/// The corners of `prim` if it is a triangle.
pub(super) fn triangle(geometry: &Geometry, prim: u32) -> Option<[Vec3; 3]> {
    match geometry.primitives[prim as usize].shape {
        Shape::Triangle { mesh, index } => Some(geometry.meshes[mesh as usize].vertices(index)),
        _ => None,
    }
}

/// Emits boxes covering `polygon` (which lies within `bounds`) in `pieces` parts, cutting
/// `bounds` across its longest axis at the coarsest plane of the scene's power-of-two grid
/// that crosses it (Karras & Aila): pieces of different triangles then share their cut
/// planes, which the builder's own splits can follow.
fn split(polygon: &[Vec3], bounds: Aabb, scene: &Aabb, pieces: usize, emit: &mut impl FnMut(Aabb)) {
    if pieces <= 1 || polygon.len() < 3 {
        emit(bounds);
        return;
    }
    let axis = bounds.extent().max_position();
    let mid = grid_plane(
        scene.min[axis],
        scene.max[axis],
        bounds.min[axis],
        bounds.max[axis],
    );
    if !(mid > bounds.min[axis] && mid < bounds.max[axis]) {
        // Too thin to halve in f32: one piece.
        emit(bounds);
        return;
    }
    let below = clip(polygon, axis, mid, false);
    let above = clip(polygon, axis, mid, true);
    let (mut lo_box, mut hi_box) = (bounds, bounds);
    lo_box.max[axis] = mid;
    hi_box.min[axis] = mid;
    let lo_box = piece_bounds(&below, lo_box);
    let hi_box = piece_bounds(&above, hi_box);
    match (lo_box, hi_box) {
        (Some(lo), Some(hi)) => {
            split(&below, lo, scene, pieces / 2, emit);
            split(&above, hi, scene, pieces - pieces / 2, emit);
        }
        // The whole polygon on one side (up to rounding): keep the unsplit box.
        _ => emit(bounds),
    }
}

/// The coarsest plane `lo + j·(hi − lo)/2^k` strictly inside `(a, b)`, or the midpoint of
/// `(a, b)` when the grid is finer than f32 can tell.
fn grid_plane(lo: f32, hi: f32, a: f32, b: f32) -> f32 {
    let extent = hi - lo;
    if extent > 0.0 {
        let mut cell = extent;
        for _ in 0..24 {
            cell *= 0.5;
            let plane = lo + ((a - lo) / cell).floor() * cell + cell;
            if plane > a && plane < b {
                return plane;
            }
        }
    }
    0.5 * (a + b)
}

/// The box of a clipped piece: its vertices' box grown by a margin relative to the
/// coordinates (the clipping rounds), kept within the half it belongs to, whose split face
/// stays exact so that the two halves' boxes meet without a crack.
pub(super) fn piece_bounds(piece: &[Vec3], half: Aabb) -> Option<Aabb> {
    if piece.len() < 3 {
        return None;
    }
    let b = piece.iter().fold(Aabb::EMPTY, |b, &p| b.union_point(p));
    let margin = gamma(8) * (half.min.abs().max(half.max.abs())).max_element();
    let grown = Aabb::new(b.min - Vec3::splat(margin), b.max + Vec3::splat(margin));
    let tight = Aabb::new(grown.min.max(half.min), grown.max.min(half.max));
    (tight.min.cmple(tight.max).all()).then_some(tight)
}

/// Sutherland–Hodgman clip of a convex polygon to `p[axis] ≥ at` (`keep_above`) or
/// `p[axis] ≤ at`. Points on the plane belong to both sides.
pub(super) fn clip(polygon: &[Vec3], axis: usize, at: f32, keep_above: bool) -> Polygon {
    let inside = |p: Vec3| {
        if keep_above {
            p[axis] >= at
        } else {
            p[axis] <= at
        }
    };
    let mut out = Polygon::new();
    for (i, &a) in polygon.iter().enumerate() {
        let b = polygon[(i + 1) % polygon.len()];
        if inside(a) {
            out.push(a);
        }
        if inside(a) != inside(b) {
            let t = (at - a[axis]) / (b[axis] - a[axis]);
            let mut p = a + t * (b - a);
            p[axis] = at;
            out.push(p);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pieces' boxes cover every point of the triangle, and are smaller than its box.
    #[test]
    fn pieces_cover_the_triangle_and_are_tighter() {
        let tri = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(10.0, 10.0, 10.0),
            Vec3::new(10.1, 10.0, 10.0),
        ];
        let bounds = tri.iter().fold(Aabb::EMPTY, |b, &p| b.union_point(p));
        let mut boxes = Vec::new();
        split(&tri, bounds, &bounds, 16, &mut |b| boxes.push(b));
        assert_eq!(boxes.len(), 16);
        let area: f32 = boxes.iter().map(Aabb::surface_area).sum();
        assert!(
            area < 0.3 * bounds.surface_area(),
            "{area} vs {}",
            bounds.surface_area()
        );
        // Points spread over the triangle, edges and corners included, computed in f64 so
        // that they lie on the triangle itself (an f32 point may round out of its box).
        let t = tri.map(|v| v.as_dvec3());
        let n = 60;
        for i in 0..=n {
            for j in 0..=n - i {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let p = t[0] + u * (t[1] - t[0]) + v * (t[2] - t[0]);
                // f64 rounding of p itself (~1e-15) is not a gap between pieces.
                let slack = glam::DVec3::splat(1e-12);
                assert!(
                    boxes.iter().any(|b| p.cmpge(b.min.as_dvec3() - slack).all()
                        && p.cmple(b.max.as_dvec3() + slack).all()),
                    "{p} is in no piece"
                );
            }
        }
    }

    #[test]
    fn clipping_keeps_points_on_the_plane_on_both_sides() {
        let square = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        ];
        let left = clip(&square, 0, 1.0, false);
        let right = clip(&square, 0, 1.0, true);
        assert!(left.iter().all(|p| p.x <= 1.0) && left.len() == 4);
        assert!(right.iter().all(|p| p.x >= 1.0) && right.len() == 4);
    }
}
