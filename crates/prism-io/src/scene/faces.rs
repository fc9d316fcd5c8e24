//! Polygons of mesh files (OBJ, PLY) to triangles, and whether a mesh's triangles cover
//! any area (glTF's too). Convex faces fan out from their first
//! corner, exactly as the TOML format's inline meshes do, so one mesh renders the same from
//! any of the three; other faces are ear-clipped by `geometry::polygon`, which keeps
//! concave faces exact.

use prism::geometry::polygon;
use prism::math::{Vec2, Vec3};

/// Ear clipping costs up to cubic time in the corner count; non-convex faces larger than
/// this are refused rather than left to run for minutes. Convex faces of any size fan out
/// in linear time.
pub(super) const MAX_NONCONVEX_CORNERS: usize = 1024;

/// Why a face could not be triangulated.
#[derive(Debug, PartialEq)]
pub(super) enum FaceError {
    /// A face needs three corners.
    TooFewCorners(usize),
    /// A non-convex face with more than `MAX_NONCONVEX_CORNERS` corners.
    TooLargeToClip(usize),
}

impl std::fmt::Display for FaceError {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            FaceError::TooFewCorners(n) => {
                write!(f, "a face has {n} corners; expected at least 3")
            }
            FaceError::TooLargeToClip(n) => write!(
                f,
                "a non-convex face has {n} corners; prism triangulates non-convex faces of up \
                 to {MAX_NONCONVEX_CORNERS} corners (convex faces may have any number)"
            ),
        }
    }
}

/// Whether any of `triangles` (indexing `positions`, all in range) has an area. Exactly
/// zero, not small: a face of any size at any scale keeps its area. A mesh without one
/// shows nothing, so the loaders leave it out with a warning rather than in silence.
pub(super) fn any_with_area(positions: &[Vec3], triangles: &[[u32; 3]]) -> bool {
    triangles.iter().any(|t| {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        (b - a).cross(c - a) != Vec3::ZERO
    })
}

/// Appends the triangles of the face whose corners index `positions` (all in range) to
/// `out`, wound like the face. Triangles pass through unchanged; a polygon of zero area
/// gives no triangles. `scratch` is reused between calls to avoid an allocation per face.
pub(super) fn triangulate(
    positions: &[Vec3],
    corners: &[u32],
    out: &mut Vec<[u32; 3]>,
    scratch: &mut Vec<Vec3>,
) -> Result<(), FaceError> {
    let n = corners.len();
    if n < 3 {
        return Err(FaceError::TooFewCorners(n));
    }
    if n == 3 {
        out.push([corners[0], corners[1], corners[2]]);
        return Ok(());
    }
    scratch.clear();
    scratch.extend(corners.iter().map(|&i| positions[i as usize]));
    let normal = polygon::newell_normal(scratch);
    // Zero area (or NaN, which the loaders rule out before): nothing to cover.
    if normal.length_squared().partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Ok(());
    }
    if is_convex(scratch, normal) {
        out.extend((1..n - 1).map(|k| [corners[0], corners[k], corners[k + 1]]));
        return Ok(());
    }
    if n > MAX_NONCONVEX_CORNERS {
        return Err(FaceError::TooLargeToClip(n));
    }
    out.extend(
        polygon::triangulate(scratch)
            .into_iter()
            .map(|t| t.map(|i| corners[i as usize])),
    );
    Ok(())
}

/// Whether the planar polygon turns one way only and winds around once. Projected onto the
/// plane of the two axes the normal points least along, oriented counter-clockwise; a
/// polygon whose corners all turn left but whose edges sweep their x (or y) sign more than
/// twice winds more than once (a pentagram) and is not convex.
fn is_convex(points: &[Vec3], normal: Vec3) -> bool {
    let a = normal.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    let (i1, i2) = ((axis + 1) % 3, (axis + 2) % 3);
    let flip = normal[axis] < 0.0;
    let project = |p: Vec3| {
        if flip {
            Vec2::new(p[i2], p[i1])
        } else {
            Vec2::new(p[i1], p[i2])
        }
    };
    let n = points.len();
    let mut sign_changes = [0usize; 2];
    let mut last_sign = [0.0f32; 2];
    let mut first_sign = [0.0f32; 2];
    for i in 0..n {
        let p0 = project(points[i]);
        let p1 = project(points[(i + 1) % n]);
        let p2 = project(points[(i + 2) % n]);
        let edge = p1 - p0;
        if edge.perp_dot(p2 - p1) < 0.0 {
            return false;
        }
        for axis in 0..2 {
            let s = if edge[axis] > 0.0 {
                1.0
            } else if edge[axis] < 0.0 {
                -1.0
            } else {
                continue;
            };
            if last_sign[axis] == 0.0 {
                first_sign[axis] = s;
            } else if s != last_sign[axis] {
                sign_changes[axis] += 1;
            }
            last_sign[axis] = s;
        }
    }
    // Close the loop: the last edge's sign against the first one's.
    for axis in 0..2 {
        if last_sign[axis] != 0.0 && last_sign[axis] != first_sign[axis] {
            sign_changes[axis] += 1;
        }
    }
    sign_changes.iter().all(|&c| c <= 2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn xy(points: &[(f32, f32)]) -> Vec<Vec3> {
        points.iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect()
    }

    fn run(points: &[Vec3]) -> Vec<[u32; 3]> {
        let corners: Vec<u32> = (0..points.len() as u32).collect();
        let mut out = Vec::new();
        triangulate(points, &corners, &mut out, &mut Vec::new()).unwrap();
        out
    }

    #[test]
    fn convex_faces_fan_from_the_first_corner() {
        let square = xy(&[(0., 0.), (1., 0.), (1., 1.), (0., 1.)]);
        assert_eq!(run(&square), vec![[0, 1, 2], [0, 2, 3]]);
        // Clockwise in xy is counter-clockwise seen from -z: still convex, still a fan.
        let cw: Vec<Vec3> = square.iter().rev().copied().collect();
        assert_eq!(run(&cw), vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn concave_and_self_winding_faces_are_clipped() {
        let l = xy(&[(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]);
        let tris = run(&l);
        assert_eq!(tris.len(), 4);
        assert!(!is_convex(&l, polygon::newell_normal(&l)));
        // A pentagram's corners all turn the same way, yet it winds around twice.
        let star: Vec<Vec3> = (0..5)
            .map(|i| {
                let a = (i as f32) * 4.0 * std::f32::consts::PI / 5.0;
                Vec3::new(a.cos(), a.sin(), 0.0)
            })
            .collect();
        assert!(!is_convex(&star, polygon::newell_normal(&star)));
    }

    #[test]
    fn small_and_degenerate_faces() {
        let mut out = Vec::new();
        let p = xy(&[(0., 0.), (1., 0.)]);
        assert_eq!(
            triangulate(&p, &[0, 1], &mut out, &mut Vec::new()),
            Err(FaceError::TooFewCorners(2))
        );
        let line = xy(&[(0., 0.), (1., 0.), (2., 0.), (3., 0.)]);
        assert!(run(&line).is_empty());
    }

    /// A comb: a zigzag bottom edge (every other corner reflex) under a flat top.
    fn comb(corners: usize) -> Vec<Vec3> {
        let bottom = corners - 2;
        let mut points: Vec<Vec3> = (0..bottom)
            .map(|i| Vec3::new(i as f32, if i % 2 == 0 { 0.0 } else { 0.5 }, 0.0))
            .collect();
        points.push(Vec3::new(bottom as f32, 2.0, 0.0));
        points.push(Vec3::new(0.0, 2.0, 0.0));
        points
    }

    #[test]
    fn huge_nonconvex_faces_are_refused() {
        let fits = comb(MAX_NONCONVEX_CORNERS);
        let area: f32 = run(&fits)
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| fits[i as usize]);
                0.5 * (b - a).cross(c - a).length()
            })
            .sum();
        let expected = 0.5 * polygon::newell_normal(&fits).length();
        assert!(
            (area - expected).abs() <= 1e-4 * expected,
            "{area} vs {expected}"
        );
        let big = comb(MAX_NONCONVEX_CORNERS + 1);
        let corners: Vec<u32> = (0..big.len() as u32).collect();
        let result = triangulate(&big, &corners, &mut Vec::new(), &mut Vec::new());
        assert_eq!(result, Err(FaceError::TooLargeToClip(big.len())));
    }
}
