//! A triangle cut by planes across one axis, for SBVH's spatial splits. The part of a
//! triangle between two planes is a convex polygon whose corners are the triangle's
//! corners between the planes and its sections by the two planes (each a segment, two
//! points on two edges), so the part's box is the box of at most seven points: no polygon
//! is clipped, and a section serves both slabs it borders. Walking a triangle's slabs
//! along an axis costs one section per plane crossed (Embree's spatial binning computes
//! its splits from the corners the same way).

use super::prim_ref::SimdBox;
use crate::math::robust::gamma;
use crate::math::Vec3;
use glam::Vec3A;

/// A triangle seen along axis `A`: its corners in the order of their coordinate there.
/// The axis is a constant so that every coordinate on it is a lane read, not an index.
#[derive(Clone, Copy)]
pub(super) struct AlongAxis<const A: usize> {
    corners: [Vec3A; 3],
}

impl<const A: usize> AlongAxis<A> {
    #[inline(always)]
    pub(super) fn new(triangle: &[Vec3; 3]) -> AlongAxis<A> {
        let [mut a, mut b, mut c] = triangle.map(Vec3A::from);
        if b[A] < a[A] {
            std::mem::swap(&mut a, &mut b);
        }
        if c[A] < b[A] {
            std::mem::swap(&mut b, &mut c);
            if b[A] < a[A] {
                std::mem::swap(&mut a, &mut b);
            }
        }
        AlongAxis { corners: [a, b, c] }
    }

    /// The triangle's least and greatest coordinate on the axis.
    #[inline(always)]
    pub(super) fn ends(&self) -> (f32, f32) {
        (self.corners[0][A], self.corners[2][A])
    }

    /// The box of the triangle's section by the plane at `at` where the plane cuts it
    /// strictly between its ends, else empty (corners on the plane count as corners). The
    /// section is a segment between two edges; its points lie on the plane exactly.
    #[inline(always)]
    pub(super) fn section(&self, at: f32) -> SimdBox {
        let [a, b, c] = self.corners;
        if !(a[A] < at && at < c[A]) {
            return SimdBox::EMPTY;
        }
        // Neither edge is parallel to the plane: each has one end on either side of it.
        let on_edge = |u: Vec3A, w: Vec3A| {
            let t = (at - u[A]) / (w[A] - u[A]);
            let mut p = u + t * (w - u);
            p[A] = at;
            p
        };
        let long = on_edge(a, c);
        let short = if at < b[A] {
            on_edge(a, b)
        } else {
            on_edge(b, c)
        };
        SimdBox {
            min: long.min(short),
            max: long.max(short),
        }
    }

    /// The box of the corners with a coordinate in `[lo, hi]` (empty if none).
    #[inline(always)]
    pub(super) fn corners_within(&self, lo: f32, hi: f32) -> SimdBox {
        let mut b = SimdBox::EMPTY;
        for p in self.corners {
            if lo <= p[A] && p[A] <= hi {
                b.grow_point(p);
            }
        }
        b
    }

    /// The margin a part's box grows by for the rounding of its sections: relative to the
    /// triangle's largest coordinate, which bounds every operand of `section`.
    #[inline(always)]
    pub(super) fn rounding_margin(&self) -> f32 {
        let [a, b, c] = self.corners;
        gamma(16) * a.abs().max(b.abs()).max(c.abs()).max_element()
    }
}

/// A box cut to `[lo, hi]` on axis `A`: the part's box `raw` grown by `margin` and kept
/// within `within` and `[lo, hi]`, or `None` where nothing is left.
#[inline(always)]
pub(super) fn bound_piece<const A: usize>(
    raw: SimdBox,
    within: &SimdBox,
    lo: f32,
    hi: f32,
    margin: f32,
) -> Option<SimdBox> {
    let (mut min, mut max) = (within.min, within.max);
    min[A] = lo;
    max[A] = hi;
    let m = Vec3A::splat(margin);
    let tight = SimdBox {
        min: (raw.min - m).max(min),
        max: (raw.max + m).min(max),
    };
    tight.min.cmple(tight.max).all().then_some(tight)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::hash::uniform;
    use glam::DVec3;

    /// The exact box (in f64) of the part of `tri` with `lo <= p[axis] <= hi`: the
    /// triangle clipped by both planes, Sutherland–Hodgman, corners on a plane kept.
    fn exact_part(tri: &[Vec3; 3], axis: usize, lo: f32, hi: f32) -> Option<(DVec3, DVec3)> {
        let clip = |poly: Vec<DVec3>, at: f64, above: bool| {
            let inside = |p: DVec3| if above { p[axis] >= at } else { p[axis] <= at };
            let mut out = Vec::new();
            for (i, &a) in poly.iter().enumerate() {
                let b = poly[(i + 1) % poly.len()];
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
        };
        let poly = tri.iter().map(|p| p.as_dvec3()).collect();
        let poly = clip(clip(poly, lo as f64, true), hi as f64, false);
        let first = *poly.first()?;
        Some(
            poly.iter()
                .fold((first, first), |(a, b), &p| (a.min(p), b.max(p))),
        )
    }

    /// The box of a triangle's part between two planes, from its corners and its
    /// sections, is the exact part's box up to the rounding margin, and grown by that
    /// margin it holds the part: for triangles at three scales, planes through them,
    /// beside them and through their corners.
    #[test]
    fn parts_are_bounded_as_clipping_bounds_them() {
        let mut cut_between = 0;
        for (scale, offset) in [(1e-3f32, -2e-3f32), (1.0, 0.5), (1e3, 3e3)] {
            for i in 0..300u32 {
                let u = |d: u32| uniform(i, d, 0, 0, 11);
                let tri: [Vec3; 3] = std::array::from_fn(|c| {
                    Vec3::from_array(std::array::from_fn(|a| {
                        offset + scale * u(3 * c as u32 + a as u32)
                    }))
                });
                // Planes inside and outside the triangle's extent, and at its corners.
                let planes = |axis: usize, first: f32, last: f32| {
                    let at = |d: u32| match (i + d) % 4 {
                        0 => tri[(d % 3) as usize][axis],
                        _ => first + (last - first) * (1.5 * u(9 + axis as u32 + d) - 0.25),
                    };
                    (at(0).min(at(1)), at(0).max(at(1)))
                };
                let case = format!("scale {scale}, triangle {i}");
                cut_between += check::<0>(&tri, planes, &case)
                    + check::<1>(&tri, planes, &case)
                    + check::<2>(&tri, planes, &case);
            }
        }
        assert!(
            cut_between > 300,
            "only {cut_between} parts cut on both sides"
        );
    }

    /// `parts_are_bounded_as_clipping_bounds_them` on axis `A`: 1 where the part was cut
    /// on both sides, else 0.
    fn check<const A: usize>(
        tri: &[Vec3; 3],
        planes: impl Fn(usize, f32, f32) -> (f32, f32),
        case: &str,
    ) -> usize {
        let along = AlongAxis::<A>::new(tri);
        let (first, last) = along.ends();
        assert!(tri.iter().all(|p| first <= p[A] && p[A] <= last));
        let (lo, hi) = planes(A, first, last);
        let case = format!("{case}, axis {A}, [{lo}, {hi}]");
        let raw = (along.section(lo))
            .union(&along.section(hi))
            .union(&along.corners_within(lo, hi));
        let Some((min, max)) = exact_part(tri, A, lo, hi) else {
            assert!(raw.min.cmpgt(raw.max).any(), "{case}: not empty");
            return 0;
        };
        let margin = along.rounding_margin();
        let (rmin, rmax) = (raw.min.as_dvec3(), raw.max.as_dvec3());
        assert!(
            (rmin - min).abs().max_element() <= margin as f64
                && (rmax - max).abs().max_element() <= margin as f64,
            "{case}: {raw:?} against {min} {max}"
        );
        let within = tri.iter().fold(SimdBox::EMPTY, |mut b, &p| {
            b.grow_point(p.into());
            b
        });
        let piece = bound_piece::<A>(raw, &within, lo.max(first), hi.min(last), margin);
        let piece = piece.expect("a part with a box");
        let (pmin, pmax) = (piece.min.as_dvec3(), piece.max.as_dvec3());
        let (min, max) = (
            min.max(within.min.as_dvec3()),
            max.min(within.max.as_dvec3()),
        );
        assert!(pmin.cmple(min).all() && pmax.cmpge(max).all(), "{case}");
        assert!(pmin[A] >= lo as f64 && pmax[A] <= hi as f64, "{case}");
        usize::from(first < lo && hi < last)
    }
}
