//! The regular n×n grid of subpixel centres (n = 1 is the single centre ray). Aligned
//! samples alias: a pattern finer than the grid reappears as a coarse false pattern.

use crate::math::Vec2;

/// Appends the n×n subpixel centres, row by row from the top-left.
pub(super) fn grid(n: u32, out: &mut Vec<Vec2>) {
    // Computed exactly as the renderer always has, so images stay bit-identical.
    let inv_n = 1.0 / n as f32;
    for j in 0..n {
        for i in 0..n {
            out.push(Vec2::new(
                (i as f32 + 0.5) * inv_n,
                (j as f32 + 0.5) * inv_n,
            ));
        }
    }
}
