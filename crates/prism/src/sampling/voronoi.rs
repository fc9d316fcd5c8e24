//! Restricted Voronoi cells for Lloyd relaxation: a convex polygon (the cell so far) cut by
//! the bisector half-planes of neighbouring points, and its centroid. In f64 and relative
//! to the cell's own point, so positions far out in a tile lose no precision.

use glam::DVec2;

/// A convex polygon, counter-clockwise or clockwise, as its vertices.
#[derive(Clone, Debug, Default)]
pub(super) struct Cell {
    pub vertices: Vec<DVec2>,
    scratch: Vec<DVec2>,
}

impl Cell {
    /// The axis-aligned rectangle [min, max].
    pub(super) fn rect(&mut self, min: DVec2, max: DVec2) {
        self.vertices.clear();
        self.vertices
            .extend([min, DVec2::new(max.x, min.y), max, DVec2::new(min.x, max.y)]);
    }

    /// Keeps the part of the cell closer to the origin than to `q`: the half-plane
    /// x·q ≤ |q|²/2 (Sutherland–Hodgman against one edge).
    pub(super) fn clip_to_bisector(&mut self, q: DVec2) {
        let limit = 0.5 * q.length_squared();
        let side = |p: DVec2| p.dot(q) - limit;
        self.scratch.clear();
        let n = self.vertices.len();
        for i in 0..n {
            let a = self.vertices[i];
            let b = self.vertices[(i + 1) % n];
            let (sa, sb) = (side(a), side(b));
            if sa <= 0.0 {
                self.scratch.push(a);
            }
            if (sa < 0.0 && sb > 0.0) || (sa > 0.0 && sb < 0.0) {
                self.scratch.push(a + (b - a) * (sa / (sa - sb)));
            }
        }
        std::mem::swap(&mut self.vertices, &mut self.scratch);
    }

    /// Largest distance from the origin to a vertex: no point farther than twice this
    /// can cut the cell.
    pub(super) fn radius(&self) -> f64 {
        self.vertices.iter().map(|v| v.length()).fold(0.0, f64::max)
    }

    /// The centroid, or None for a degenerate (zero-area) cell.
    pub(super) fn centroid(&self) -> Option<DVec2> {
        let n = self.vertices.len();
        let (mut area2, mut c) = (0.0, DVec2::ZERO);
        for i in 0..n {
            let a = self.vertices[i];
            let b = self.vertices[(i + 1) % n];
            let cross = a.perp_dot(b);
            area2 += cross;
            c += (a + b) * cross;
        }
        (area2.abs() > 0.0).then(|| c / (3.0 * area2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_cut_by_a_bisector_keeps_the_near_half() {
        let mut cell = Cell::default();
        cell.rect(DVec2::new(-1.0, -1.0), DVec2::new(1.0, 1.0));
        cell.clip_to_bisector(DVec2::new(1.0, 0.0));
        // The half x ≤ 0.5 of the square: area 3, centroid at x = -0.25.
        let c = cell.centroid().unwrap();
        assert!((c.x + 0.25).abs() < 1e-12 && c.y.abs() < 1e-12, "{c}");
        assert!((cell.radius() - 2f64.sqrt()).abs() < 1e-12);
    }
}
