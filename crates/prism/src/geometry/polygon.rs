//! Planar polygons to triangles by ear clipping, so concave faces (the SPD gears have
//! 144-vertex concave faces) render exactly, with the polygon's winding kept.

use crate::math::{Vec2, Vec3};

/// The polygon's normal by Newell's method: robust for concave polygons and for ones whose
/// first corners happen to be collinear. Its length is twice the polygon's area.
pub fn newell_normal(points: &[Vec3]) -> Vec3 {
    let mut n = Vec3::ZERO;
    for (i, a) in points.iter().enumerate() {
        let b = points[(i + 1) % points.len()];
        n += Vec3::new(
            (a.y - b.y) * (a.z + b.z),
            (a.z - b.z) * (a.x + b.x),
            (a.x - b.x) * (a.y + b.y),
        );
    }
    n
}

/// Triangles (as indices into `points`) covering the simple polygon `points`, each wound
/// like the polygon. Degenerate polygons (zero area) give no triangles; zero-area ears are
/// dropped. A self-intersecting polygon still gets a covering fan for what ear clipping
/// cannot cut.
pub fn triangulate(points: &[Vec3]) -> Vec<[u32; 3]> {
    let n = newell_normal(points);
    let len2 = n.length_squared();
    if points.len() < 3 || len2.is_nan() || len2 <= 0.0 {
        return Vec::new();
    }
    if points.len() == 3 {
        return vec![[0, 1, 2]];
    }
    // Project onto the plane of the two minor axes, oriented so the polygon is
    // counter-clockwise in 2D.
    let a = n.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    let (i1, i2) = ((axis + 1) % 3, (axis + 2) % 3);
    let flip = n[axis] < 0.0;
    let p2: Vec<Vec2> = points
        .iter()
        .map(|p| {
            if flip {
                Vec2::new(p[i2], p[i1])
            } else {
                Vec2::new(p[i1], p[i2])
            }
        })
        .collect();

    let mut remaining: Vec<u32> = (0..points.len() as u32).collect();
    // Drop repeated consecutive vertices: they make zero-length edges.
    remaining.dedup_by(|a, b| p2[*a as usize] == p2[*b as usize]);
    while remaining.len() > 1
        && p2[remaining[0] as usize] == p2[*remaining.last().unwrap() as usize]
    {
        remaining.pop();
    }

    let cross = |a: Vec2, b: Vec2, c: Vec2| (b - a).perp_dot(c - a);
    let mut out = Vec::with_capacity(points.len() - 2);
    while remaining.len() > 3 {
        let m = remaining.len();
        let mut clipped = false;
        for k in 0..m {
            let (ip, ic, inx) = (
                remaining[(k + m - 1) % m],
                remaining[k],
                remaining[(k + 1) % m],
            );
            let (pa, pb, pc) = (p2[ip as usize], p2[ic as usize], p2[inx as usize]);
            let turn = cross(pa, pb, pc);
            if turn < 0.0 {
                continue; // reflex corner
            }
            if turn == 0.0 {
                // Collinear corner: removing it changes nothing but the vertex count.
                remaining.remove(k);
                clipped = true;
                break;
            }
            let blocked = remaining.iter().any(|&j| {
                if j == ip || j == ic || j == inx {
                    return false;
                }
                let q = p2[j as usize];
                if q == pa || q == pb || q == pc {
                    return false;
                }
                cross(pa, pb, q) >= 0.0 && cross(pb, pc, q) >= 0.0 && cross(pc, pa, q) >= 0.0
            });
            if !blocked {
                out.push([ip, ic, inx]);
                remaining.remove(k);
                clipped = true;
                break;
            }
        }
        if !clipped {
            // Not a simple polygon: cover the rest with a fan rather than loop forever.
            for k in 1..remaining.len() - 1 {
                out.push([remaining[0], remaining[k], remaining[k + 1]]);
            }
            return out;
        }
    }
    if remaining.len() == 3
        && cross(
            p2[remaining[0] as usize],
            p2[remaining[1] as usize],
            p2[remaining[2] as usize],
        ) != 0.0
    {
        out.push([remaining[0], remaining[1], remaining[2]]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(points: &[Vec3], tris: &[[u32; 3]]) -> f32 {
        tris.iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| points[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum()
    }

    #[test]
    fn concave_polygon_area_is_preserved() {
        // An L shape (area 3) and a comb with deep notches, counter-clockwise in xy.
        let l: Vec<Vec3> = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .iter()
            .map(|&(x, y)| Vec3::new(x, y, 0.0))
            .collect();
        let t = triangulate(&l);
        assert_eq!(t.len(), 4);
        assert!((area(&l, &t) - 3.0).abs() < 1e-5);
        for tri in &t {
            let [a, b, c] = tri.map(|i| l[i as usize]);
            assert!((b - a).cross(c - a).z > 0.0, "winding kept");
        }
        let mut comb = vec![Vec3::new(0.0, 0.0, 1.0)];
        for i in 0..8 {
            let x = i as f32;
            comb.extend([
                Vec3::new(x + 0.25, 0.0, 1.0),
                Vec3::new(x + 0.25, 3.0, 1.0),
                Vec3::new(x + 0.75, 3.0, 1.0),
                Vec3::new(x + 0.75, 0.0, 1.0),
            ]);
        }
        comb.extend([
            Vec3::new(8.0, 0.0, 1.0),
            Vec3::new(8.0, -1.0, 1.0),
            Vec3::new(0.0, -1.0, 1.0),
        ]);
        let t = triangulate(&comb);
        let expected = newell_normal(&comb).length() * 0.5;
        assert!((area(&comb, &t) - expected).abs() < 1e-3 * expected);
        assert_eq!(t.len(), comb.len() - 2);
    }

    #[test]
    fn clockwise_and_degenerate() {
        let cw: Vec<Vec3> = [(0., 0.), (0., 1.), (1., 1.), (1., 0.)]
            .iter()
            .map(|&(x, y)| Vec3::new(x, 0.0, y))
            .collect();
        let t = triangulate(&cw);
        assert_eq!(t.len(), 2);
        let n = newell_normal(&cw);
        for tri in &t {
            let [a, b, c] = tri.map(|i| cw[i as usize]);
            assert!((b - a).cross(c - a).dot(n) > 0.0);
        }
        let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::X * 3.0];
        assert!(triangulate(&line).is_empty());
    }
}
