//! Exact hidden-surface removal inside one beam. The beam's cross-section starts as its
//! window: convex cells that see nothing yet. Each facet, as a convex polygon on the film
//! with its inverse depth w(x, y) (affine on the film, larger = nearer), is inserted: in
//! every cell it overlaps, the part where it is nearer than what the cell shows is cut out
//! and given to it, and the rest of the cell is cut into convex pieces that keep their old
//! owner. Where two facets' planes cross, w₁ = w₂ is a straight line on the film, so
//! interpenetrating facets are resolved exactly too; the result does not depend on the
//! insertion order (front to back only saves work: a hidden facet cuts nothing).

use super::convex::{Affine2, Convex, SLIVER_AREA};
use glam::DVec2;

/// A convex piece of a beam's cross-section and what it shows.
#[derive(Clone, Debug)]
pub(crate) struct Cell {
    /// The piece.
    pub(crate) poly: Convex,
    lo: DVec2,
    hi: DVec2,
    /// What it shows: an index into the beam's visible surfaces, None for what lies
    /// beyond everything (the background).
    pub(crate) owner: Option<u32>,
    /// The owner's inverse depth on the film.
    depth: Affine2,
}

/// The cells of one beam's cross-section.
#[derive(Default)]
pub(crate) struct Cells {
    /// The cells, covering the window without overlap.
    pub(crate) cells: Vec<Cell>,
}

impl Cells {
    /// A window that sees nothing yet.
    pub(crate) fn new(window: &[Convex]) -> Cells {
        Cells {
            cells: window
                .iter()
                .filter(|c| !c.is_empty())
                .map(|c| {
                    let (lo, hi) = c.bounds();
                    Cell {
                        poly: c.clone(),
                        lo,
                        hi,
                        owner: None,
                        depth: Affine2 {
                            a: 0.0,
                            b: 0.0,
                            c: 0.0,
                        },
                    }
                })
                .collect(),
        }
    }

    /// Gives `owner` (a convex polygon with inverse depth `depth`) every part of the cells
    /// where it is the nearest. Returns whether it won any area.
    pub(crate) fn insert(&mut self, poly: &Convex, depth: Affine2, owner: u32) -> bool {
        let (lo, hi) = poly.bounds();
        let edges = poly.edges();
        let mut lines = edges.clone();
        let mut won = false;
        let n = self.cells.len();
        for i in 0..n {
            let cell = &self.cells[i];
            if cell.hi.x <= lo.x || cell.lo.x >= hi.x || cell.hi.y <= lo.y || cell.lo.y >= hi.y {
                continue;
            }
            lines.truncate(edges.len());
            if cell.owner.is_some() {
                // Nearer than the cell's owner: w_new − w_old ≥ 0.
                lines.push(depth.minus(&cell.depth));
            }
            let inside = cell.poly.clip_all(&lines);
            if inside.area() <= SLIVER_AREA {
                continue;
            }
            // A tie (coplanar facets) leaves the cell to its earlier owner.
            if cell.owner.is_some() && inside_is_tie(&inside, &depth, &cell.depth) {
                continue;
            }
            let (inside, rest) = cell.poly.split(&lines);
            let old = (cell.owner, cell.depth);
            for piece in rest {
                let (plo, phi) = piece.bounds();
                self.cells.push(Cell {
                    poly: piece,
                    lo: plo,
                    hi: phi,
                    owner: old.0,
                    depth: old.1,
                });
            }
            let (ilo, ihi) = inside.bounds();
            self.cells[i] = Cell {
                poly: inside,
                lo: ilo,
                hi: ihi,
                owner: Some(owner),
                depth,
            };
            won = true;
        }
        won
    }
}

/// Whether the new owner is nowhere strictly nearer than the old one on `piece`.
fn inside_is_tie(piece: &Convex, new: &Affine2, old: &Affine2) -> bool {
    let f = new.minus(old);
    piece.points.iter().all(|&p| f.at(p) <= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(w: f64) -> Affine2 {
        Affine2 {
            a: 0.0,
            b: 0.0,
            c: w,
        }
    }

    #[test]
    fn a_nearer_square_hides_a_farther_one_whatever_the_order() {
        let window = Convex::rect(0.0, 0.0, 4.0, 4.0);
        let near = Convex::rect(1.0, 1.0, 3.0, 3.0);
        let far = Convex::rect(0.0, 0.0, 2.0, 4.0);
        for order in [[0, 1], [1, 0]] {
            let mut cells = Cells::new(std::slice::from_ref(&window));
            for k in order {
                let (p, w) = if k == 0 { (&near, 2.0) } else { (&far, 1.0) };
                cells.insert(p, flat(w), k);
            }
            let area = |o: Option<u32>| -> f64 {
                cells
                    .cells
                    .iter()
                    .filter(|c| c.owner == o)
                    .map(|c| c.poly.area())
                    .sum()
            };
            assert!((area(Some(0)) - 4.0).abs() < 1e-12);
            // The far one: its 8 less the 2 the near square covers.
            assert!((area(Some(1)) - 6.0).abs() < 1e-12);
            assert!((area(None) - 6.0).abs() < 1e-12);
        }
    }

    #[test]
    fn crossing_planes_meet_along_a_line() {
        let window = Convex::rect(0.0, 0.0, 4.0, 4.0);
        let mut cells = Cells::new(std::slice::from_ref(&window));
        // w1 = x, w2 = 4 − x: the first is nearer right of x = 2.
        let w1 = Affine2 {
            a: 1.0,
            b: 0.0,
            c: 0.0,
        };
        let w2 = Affine2 {
            a: -1.0,
            b: 0.0,
            c: 4.0,
        };
        cells.insert(&window, w1, 0);
        cells.insert(&window, w2, 1);
        for c in &cells.cells {
            let x = c.poly.centroid().x;
            assert_eq!(c.owner, Some(if x > 2.0 { 0 } else { 1 }), "{x}");
        }
    }
}
