//! 3D convex hulls by quickhull (Barber, Dobkin, Huhdanpaa 1996), in f64.
//!
//! Robustness comes from a tolerance relative to the points' magnitude: a point counts as
//! outside a face only if it is farther than that, so duplicates and coplanar points never
//! create slivers or flip faces. A point coplanar with a face but beyond its edge is still
//! strictly outside the neighbouring face across that edge, so it is not lost. Callers that
//! need a conservative bound recompute each plane's offset over all points (`faces`).

use glam::DVec3;
use std::collections::HashMap;

/// A hull as triangles over indices into the input points, wound counter-clockwise seen
/// from outside.
#[derive(Clone, Debug)]
pub struct ConvexHull {
    /// The hull's faces.
    pub triangles: Vec<[usize; 3]>,
}

/// A plane `normal·x ≤ offset`, `normal` of unit length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfSpace {
    /// Outward unit normal.
    pub normal: DVec3,
    /// Distance of the plane from the origin along `normal`.
    pub offset: f64,
}

struct Face {
    v: [usize; 3],
    normal: DVec3,
    offset: f64,
    outside: Vec<usize>,
    alive: bool,
}

impl Face {
    fn new(points: &[DVec3], v: [usize; 3]) -> Face {
        let [a, b, c] = v.map(|i| points[i]);
        let normal = (b - a).cross(c - a).normalize_or_zero();
        Face {
            v,
            normal,
            offset: normal.dot(a),
            outside: Vec::new(),
            alive: true,
        }
    }

    fn distance(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }
}

/// The hull of `points`, or `None` when they span no volume (fewer than four points not
/// all in one plane, up to the tolerance).
pub fn convex_hull(points: &[DVec3]) -> Option<ConvexHull> {
    if points.len() < 4 || points.iter().any(|p| !p.is_finite()) {
        return None;
    }
    let magnitude = points
        .iter()
        .fold(0.0f64, |m, p| m.max(p.abs().max_element()));
    let tol = 1024.0 * f64::EPSILON * magnitude.max(f64::MIN_POSITIVE);
    let simplex = initial_simplex(points, tol)?;

    let mut faces: Vec<Face> = Vec::new();
    let mut edges: HashMap<(usize, usize), usize> = HashMap::new();
    let centroid = simplex.iter().map(|&i| points[i]).sum::<DVec3>() / 4.0;
    for skip in 0..4 {
        let mut v: Vec<usize> = (0..4).filter(|&k| k != skip).map(|k| simplex[k]).collect();
        let f = Face::new(points, [v[0], v[1], v[2]]);
        if f.distance(centroid) > 0.0 {
            v.swap(1, 2);
        }
        add_face(
            &mut faces,
            &mut edges,
            Face::new(points, [v[0], v[1], v[2]]),
        );
    }
    for (i, &p) in points.iter().enumerate() {
        if simplex.contains(&i) {
            continue;
        }
        if let Some(f) = faces.iter_mut().find(|f| f.distance(p) > tol) {
            f.outside.push(i);
        }
    }

    let mut pending: Vec<usize> = (0..faces.len()).collect();
    while let Some(fi) = pending.pop() {
        if !faces[fi].alive || faces[fi].outside.is_empty() {
            continue;
        }
        let eye = *faces[fi]
            .outside
            .iter()
            .max_by(|&&a, &&b| {
                let f = &faces[fi];
                f.distance(points[a]).total_cmp(&f.distance(points[b]))
            })
            .expect("non-empty");
        let eye_point = points[eye];

        // Faces the eye sees, grown from fi across edges so the set stays connected.
        let mut visible = vec![fi];
        let mut seen = std::collections::HashSet::from([fi]);
        let mut k = 0;
        while k < visible.len() {
            let v = faces[visible[k]].v;
            for e in 0..3 {
                let (a, b) = (v[e], v[(e + 1) % 3]);
                if let Some(&g) = edges.get(&(b, a)) {
                    if !seen.contains(&g) && faces[g].distance(eye_point) > tol {
                        seen.insert(g);
                        visible.push(g);
                    }
                }
            }
            k += 1;
        }
        // Horizon: edges of visible faces whose neighbour is not visible.
        let mut horizon = Vec::new();
        for &f in &visible {
            let v = faces[f].v;
            for e in 0..3 {
                let (a, b) = (v[e], v[(e + 1) % 3]);
                let neighbour = edges.get(&(b, a)).copied();
                if neighbour.is_none_or(|g| !seen.contains(&g)) {
                    horizon.push((a, b));
                }
            }
        }
        let mut orphans = Vec::new();
        for &f in &visible {
            faces[f].alive = false;
            let v = faces[f].v;
            for e in 0..3 {
                edges.remove(&(v[e], v[(e + 1) % 3]));
            }
            orphans.append(&mut faces[f].outside);
        }
        let first_new = faces.len();
        for (a, b) in horizon {
            add_face(&mut faces, &mut edges, Face::new(points, [a, b, eye]));
        }
        for i in orphans {
            if i == eye {
                continue;
            }
            let p = points[i];
            if let Some(f) = faces[first_new..].iter_mut().find(|f| f.distance(p) > tol) {
                f.outside.push(i);
            }
        }
        pending.extend(first_new..faces.len());
    }
    Some(ConvexHull {
        triangles: faces.iter().filter(|f| f.alive).map(|f| f.v).collect(),
    })
}

fn add_face(faces: &mut Vec<Face>, edges: &mut HashMap<(usize, usize), usize>, face: Face) {
    let id = faces.len();
    for e in 0..3 {
        edges.insert((face.v[e], face.v[(e + 1) % 3]), id);
    }
    faces.push(face);
}

/// Four points spanning a tetrahedron of more than `tol` in every dimension.
fn initial_simplex(points: &[DVec3], tol: f64) -> Option<[usize; 4]> {
    let lo = points.iter().fold(DVec3::INFINITY, |m, p| m.min(*p));
    let hi = points.iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(*p));
    let axis = (hi - lo).max_position();
    let argmax = |key: &dyn Fn(DVec3) -> f64| {
        (0..points.len()).max_by(|&a, &b| key(points[a]).total_cmp(&key(points[b])))
    };
    // Lexicographic extremes are true vertices of the hull, not points inside a face.
    let (b_axis, c_axis) = ((axis + 1) % 3, (axis + 2) % 3);
    let lexicographic = |a: &usize, b: &usize| {
        let (p, q) = (points[*a], points[*b]);
        p[axis]
            .total_cmp(&q[axis])
            .then(p[b_axis].total_cmp(&q[b_axis]))
            .then(p[c_axis].total_cmp(&q[c_axis]))
    };
    let i0 = (0..points.len()).min_by(lexicographic)?;
    let i1 = (0..points.len()).max_by(lexicographic)?;
    let (a, b) = (points[i0], points[i1]);
    if a.distance(b) <= tol {
        return None;
    }
    let line = (b - a).normalize();
    let off_line = |p: DVec3| (p - a).reject_from_normalized(line).length();
    let i2 = argmax(&off_line)?;
    if off_line(points[i2]) <= tol {
        return None;
    }
    let normal = line.cross(points[i2] - a).normalize();
    let off_plane = |p: DVec3| normal.dot(p - a).abs();
    let i3 = argmax(&off_plane)?;
    if off_plane(points[i3]) <= tol {
        return None;
    }
    Some([i0, i1, i2, i3])
}

impl ConvexHull {
    /// The hull's distinct face planes (coplanar triangles merged), each offset moved out
    /// to the largest `normal·p` over all `points`, so every point is inside every plane
    /// whatever rounding the construction suffered.
    pub fn faces(&self, points: &[DVec3]) -> Vec<HalfSpace> {
        let mut planes: Vec<HalfSpace> = Vec::new();
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| points[i]);
            let Some(normal) = (b - a).cross(c - a).try_normalize() else {
                continue;
            };
            // Coplanar with a plane already kept: the same normal to within rounding.
            if planes.iter().any(|p| p.normal.dot(normal) >= 1.0 - 1e-12) {
                continue;
            }
            planes.push(HalfSpace {
                normal,
                offset: normal.dot(a),
            });
        }
        for p in &mut planes {
            p.offset = points
                .iter()
                .map(|x| p.normal.dot(*x))
                .fold(f64::MIN, f64::max);
        }
        planes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tetrahedron_is_its_own_hull() {
        let p = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let h = convex_hull(&p).unwrap();
        assert_eq!(h.triangles.len(), 4);
        assert_eq!(h.faces(&p).len(), 4);
    }

    #[test]
    fn collinear_and_coincident_points_have_no_hull() {
        let line: Vec<DVec3> = (0..10).map(|i| DVec3::splat(i as f64)).collect();
        assert!(convex_hull(&line).is_none());
        assert!(convex_hull(&[DVec3::ONE; 6]).is_none());
    }
}
