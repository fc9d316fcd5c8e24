//! From fragments to pixels: a visible fragment (a convex cell) is cut along the pixel
//! grid, and each fragment ∩ pixel piece is handed on with its area. The box filter's pixel
//! value is then the area-weighted sum over the pieces, exactly.

use super::convex::{Affine2, Convex};

/// Calls `f(x, y, piece)` for each pixel (x, y) of the `width` × `height` film that `cell`
/// covers with positive area.
pub(crate) fn pixel_pieces(
    cell: &Convex,
    width: u32,
    height: u32,
    mut f: impl FnMut(u32, u32, Convex),
) {
    let (lo, hi) = cell.bounds();
    let y0 = lo.y.floor().max(0.0) as u32;
    let y1 = (hi.y.ceil().max(0.0) as u32).min(height);
    let x0 = lo.x.floor().max(0.0) as u32;
    let x1 = (hi.x.ceil().max(0.0) as u32).min(width);
    for y in y0..y1 {
        let row = band(cell, Axis::Y, y, y0, y1);
        if row.is_empty() {
            continue;
        }
        let (rlo, rhi) = row.bounds();
        let rx0 = (rlo.x.floor().max(x0 as f64) as u32).min(x1);
        let rx1 = (rhi.x.ceil().max(0.0) as u32).min(x1);
        for x in rx0..rx1 {
            let piece = band(&row, Axis::X, x, rx0, rx1);
            if piece.area() > 0.0 {
                f(x, y, piece);
            }
        }
    }
}

#[derive(Clone, Copy)]
enum Axis {
    X,
    Y,
}

/// `cell` cut to the band `k ≤ coordinate ≤ k + 1` of `axis`, where `first..end` are the
/// bands the cell spans: its outer sides need no cut (the cell lies inside them).
fn band(cell: &Convex, axis: Axis, k: u32, first: u32, end: u32) -> Convex {
    let (below, above) = match axis {
        Axis::X => ((1.0, 0.0), (-1.0, 0.0)),
        Axis::Y => ((0.0, 1.0), (0.0, -1.0)),
    };
    let mut out = cell.clone();
    if k > first {
        out = out.clip(&Affine2 {
            a: below.0,
            b: below.1,
            c: -(k as f64),
        });
    }
    if k + 1 < end {
        out = out.clip(&Affine2 {
            a: above.0,
            b: above.1,
            c: (k + 1) as f64,
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn pieces_of_a_triangle_sum_to_its_area() {
        let tri = Convex::from_points(vec![
            DVec2::new(0.3, 0.2),
            DVec2::new(7.9, 1.4),
            DVec2::new(2.2, 5.5),
        ])
        .unwrap();
        let mut total = 0.0;
        let mut count = 0;
        pixel_pieces(&tri, 16, 16, |x, y, p| {
            let (lo, hi) = p.bounds();
            assert!(lo.x >= x as f64 - 1e-12 && hi.x <= x as f64 + 1.0 + 1e-12);
            assert!(lo.y >= y as f64 - 1e-12 && hi.y <= y as f64 + 1.0 + 1e-12);
            total += p.area();
            count += 1;
        });
        assert!((total - tri.area()).abs() < 1e-12, "{total} {}", tri.area());
        assert!(count > 10);
    }
}
