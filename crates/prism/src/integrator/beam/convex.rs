//! Convex polygons in image space (pixels, f64) and the one operation beam tracing builds
//! everything on: cutting a convex polygon by a line, which keeps it convex. Hidden-surface
//! removal, windows of secondary beams, pixel pieces and checker squares are all chains of
//! such cuts, so every visible fragment is an exact polygon, up to f64 rounding.

use glam::DVec2;

/// An affine function of image position, f(x, y) = a·x + b·y + c. Its zero set is a line;
/// `Convex::clip` keeps the side where it is positive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine2 {
    /// Coefficient of x.
    pub a: f64,
    /// Coefficient of y.
    pub b: f64,
    /// Constant term.
    pub c: f64,
}

impl Affine2 {
    /// The function's value at `p`.
    #[inline]
    pub fn at(&self, p: DVec2) -> f64 {
        self.a * p.x + self.b * p.y + self.c
    }

    /// `self − other`.
    pub fn minus(&self, o: &Affine2) -> Affine2 {
        Affine2 {
            a: self.a - o.a,
            b: self.b - o.b,
            c: self.c - o.c,
        }
    }

    /// `self − k·other`.
    pub fn minus_scaled(&self, k: f64, o: &Affine2) -> Affine2 {
        Affine2 {
            a: self.a - k * o.a,
            b: self.b - k * o.b,
            c: self.c - k * o.c,
        }
    }

    /// `−self`: the other side of the same line.
    pub fn flipped(&self) -> Affine2 {
        Affine2 {
            a: -self.a,
            b: -self.b,
            c: -self.c,
        }
    }

    /// The half-plane left of the directed edge p → q (counter-clockwise interior in a
    /// y-up frame; `Convex` keeps vertices in the order that makes this the inside).
    pub fn left_of(p: DVec2, q: DVec2) -> Affine2 {
        let d = q - p;
        Affine2 {
            a: -d.y,
            b: d.x,
            c: d.y * p.x - d.x * p.y,
        }
    }
}

/// A convex polygon, vertices in order with positive signed area (`Affine2::left_of` of
/// each edge is the inside).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Convex {
    /// The vertices.
    pub points: Vec<DVec2>,
}

/// Pieces whose area is below this many square pixels are dropped: slivers that rounding
/// leaves along cut lines. The unit is the image's pixel, whatever the scene's scale, so
/// this is not a tolerance of the geometry; what a pixel loses to it is far below the
/// coverage tolerance the tests state (1e-9 per pixel).
pub(crate) const SLIVER_AREA: f64 = 1e-14;

/// Edges shorter than this fraction of their polygon's extent are too short to have a
/// direction (see `Convex::edges`).
const SHORT_EDGE: f64 = 1e-9;

impl Convex {
    /// The rectangle [x0, x1] × [y0, y1].
    pub fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Convex {
        Convex {
            points: vec![
                DVec2::new(x0, y0),
                DVec2::new(x1, y0),
                DVec2::new(x1, y1),
                DVec2::new(x0, y1),
            ],
        }
    }

    /// A polygon from vertices in either order (reversed when clockwise); None when it has
    /// no area.
    pub fn from_points(mut points: Vec<DVec2>) -> Option<Convex> {
        if points.len() < 3 {
            return None;
        }
        let a = signed_area(&points);
        if a.is_nan() || a == 0.0 {
            return None;
        }
        if a < 0.0 {
            points.reverse();
        }
        Some(Convex { points })
    }

    /// Whether there is nothing left of it.
    pub fn is_empty(&self) -> bool {
        self.points.len() < 3
    }

    /// Area in square pixels.
    pub fn area(&self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            signed_area(&self.points).max(0.0)
        }
    }

    /// The centroid (area-weighted), or the vertex mean for a degenerate polygon.
    pub fn centroid(&self) -> DVec2 {
        let n = self.points.len();
        if n == 0 {
            return DVec2::ZERO;
        }
        // Relative to the first vertex, so large coordinates lose nothing.
        let o = self.points[0];
        let (mut sum, mut twice_area) = (DVec2::ZERO, 0.0);
        for i in 1..n.saturating_sub(1) {
            let (p, q) = (self.points[i] - o, self.points[i + 1] - o);
            let cross = p.perp_dot(q);
            twice_area += cross;
            sum += (p + q) * cross;
        }
        if twice_area > 0.0 {
            o + sum / (3.0 * twice_area)
        } else {
            self.points.iter().copied().sum::<DVec2>() / n as f64
        }
    }

    /// Bounding box: (min, max).
    pub fn bounds(&self) -> (DVec2, DVec2) {
        let mut lo = DVec2::splat(f64::INFINITY);
        let mut hi = DVec2::splat(f64::NEG_INFINITY);
        for &p in &self.points {
            lo = lo.min(p);
            hi = hi.max(p);
        }
        (lo, hi)
    }

    /// The part where `f ≥ 0` (Sutherland–Hodgman against one line). Crossing points are
    /// interpolated from the two values, so a vertex exactly on the line stays exact.
    pub fn clip(&self, f: &Affine2) -> Convex {
        let n = self.points.len();
        if n < 3 {
            return Convex::default();
        }
        let values: Vec<f64> = self.points.iter().map(|&p| f.at(p)).collect();
        if values.iter().all(|&v| v >= 0.0) {
            return self.clone();
        }
        if values.iter().all(|&v| v <= 0.0) {
            return Convex::default();
        }
        let mut out = Vec::with_capacity(n + 1);
        for i in 0..n {
            let j = (i + 1) % n;
            let (p, q, fp, fq) = (self.points[i], self.points[j], values[i], values[j]);
            if fp >= 0.0 {
                out.push(p);
            }
            if (fp > 0.0 && fq < 0.0) || (fp < 0.0 && fq > 0.0) {
                let s = fp / (fp - fq);
                out.push(p + (q - p) * s);
            }
        }
        Convex { points: out }
    }

    /// The part inside every half-plane of `lines`.
    pub fn clip_all(&self, lines: &[Affine2]) -> Convex {
        let mut out = self.clone();
        for l in lines {
            if out.is_empty() {
                break;
            }
            out = out.clip(l);
        }
        out
    }

    /// The inside edges' half-planes. Clipping leaves vertices that rounding has put a
    /// hair apart; the direction of such an edge is noise, and its line could cut away
    /// anything, so edges shorter than `SHORT_EDGE` of the polygon's extent are left out
    /// (the polygon they bound is then larger by at most that much, far below a pixel).
    pub fn edges(&self) -> Vec<Affine2> {
        let n = self.points.len();
        let (lo, hi) = self.bounds();
        let short = SHORT_EDGE * (hi - lo).length();
        (0..n)
            .filter(|&i| (self.points[(i + 1) % n] - self.points[i]).length() > short)
            .map(|i| Affine2::left_of(self.points[i], self.points[(i + 1) % n]))
            .collect()
    }

    /// Cuts `self` into the part inside every line (returned first) and convex pieces of
    /// the rest (each outside one line and inside the ones before it). Pieces smaller than
    /// `SLIVER_AREA` are dropped.
    pub fn split(&self, lines: &[Affine2]) -> (Convex, Vec<Convex>) {
        let mut inside = self.clone();
        let mut rest = Vec::new();
        for l in lines {
            if inside.is_empty() {
                break;
            }
            // A line of a zero-length edge is no line: everything is on it, and cutting by
            // it and by its flip would keep the whole polygon twice.
            if l.a == 0.0 && l.b == 0.0 {
                continue;
            }
            let out = inside.clip(&l.flipped());
            if out.area() > SLIVER_AREA {
                rest.push(out);
            }
            inside = inside.clip(l);
        }
        (inside, rest)
    }
}

fn signed_area(points: &[DVec2]) -> f64 {
    let o = points[0];
    let mut twice = 0.0;
    for i in 1..points.len().saturating_sub(1) {
        twice += (points[i] - o).perp_dot(points[i + 1] - o);
    }
    0.5 * twice
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_cut_by_its_diagonal_is_two_halves() {
        let sq = Convex::rect(0.0, 0.0, 2.0, 2.0);
        let diag = Affine2::left_of(DVec2::new(0.0, 0.0), DVec2::new(2.0, 2.0));
        let (inside, rest) = sq.split(&[diag]);
        assert_eq!(inside.area(), 2.0);
        assert_eq!(rest.len(), 1);
        assert_eq!(rest[0].area(), 2.0);
        // The left of the diagonal (going up-right) is the upper-left triangle.
        assert!((inside.centroid() - DVec2::new(2.0 / 3.0, 4.0 / 3.0)).length() < 1e-12);
    }

    #[test]
    fn splitting_keeps_the_area() {
        let sq = Convex::rect(-1.0, -1.0, 3.0, 2.0);
        let tri = Convex::from_points(vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 5.0),
            DVec2::new(4.0, -2.0),
        ])
        .unwrap();
        let (inside, rest) = sq.split(&tri.edges());
        let total: f64 = inside.area() + rest.iter().map(Convex::area).sum::<f64>();
        assert!((total - sq.area()).abs() < 1e-12, "{total}");
        assert!(inside.area() > 0.0 && inside.area() < tri.area());
    }

    #[test]
    fn a_repeated_vertex_cuts_nothing_twice() {
        let sq = Convex::rect(0.0, 0.0, 1.0, 1.0);
        let p = DVec2::new(0.5, 0.5);
        let (inside, rest) = sq.split(&[Affine2::left_of(p, p)]);
        assert_eq!(
            inside.area() + rest.iter().map(Convex::area).sum::<f64>(),
            1.0
        );
    }

    #[test]
    fn clockwise_input_is_turned_round() {
        let c = Convex::from_points(vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(0.0, 1.0),
            DVec2::new(1.0, 0.0),
        ])
        .unwrap();
        assert_eq!(c.area(), 0.5);
        assert!(Convex::from_points(vec![DVec2::ZERO, DVec2::X, DVec2::X * 2.0]).is_none());
    }
}
