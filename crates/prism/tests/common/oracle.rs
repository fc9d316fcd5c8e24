//! The brute-force oracle's test material, shared by the accelerator suites: scenes that
//! remember their boxes and surface features, hostile random rays aimed at them, and the
//! rule for when two nearest hits agree.

use super::Rng;
use prism::accel::Hit;
use prism::geometry::{AaBox, Cone, Geometry, Shape, TriangleMesh};
use prism::math::{Aabb, Ray, TraceRay, Vec3};

pub(crate) struct TestScene {
    pub geometry: Geometry,
    /// Solid boxes, to start rays inside.
    pub boxes: Vec<AaBox>,
    /// Points on surfaces (vertices, edge midpoints, box corners) to aim at or start from.
    pub features: Vec<Vec3>,
}

impl TestScene {
    pub(crate) fn new() -> Self {
        TestScene {
            geometry: Geometry::default(),
            boxes: Vec::new(),
            features: Vec::new(),
        }
    }

    pub(crate) fn add_box(&mut self, b: AaBox) {
        self.geometry.add(Shape::from(b), 0);
        self.boxes.push(b);
        self.features.extend([b.min, b.max, 0.5 * (b.min + b.max)]);
    }

    pub(crate) fn add_triangles(&mut self, tris: &[[Vec3; 3]]) {
        let positions: Vec<Vec3> = tris.iter().flatten().copied().collect();
        for t in tris {
            self.features
                .extend([t[0], 0.5 * (t[0] + t[1]), 0.5 * (t[1] + t[2])]);
        }
        let indices = (0..tris.len() as u32)
            .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect();
        let mesh = TriangleMesh::new(positions, indices, None, None).unwrap();
        self.geometry.add_mesh(mesh, 0);
    }

    pub(crate) fn add_mesh(&mut self, mesh: TriangleMesh) {
        self.features.extend(mesh.positions().iter().step_by(3));
        self.geometry.add_mesh(mesh, 0);
    }
}

/// `count` triangles, each a corner `corner(rng)` and two edges in random directions of
/// one length `size(rng)`: from slivers to large ones, as the sizes run.
pub(crate) fn random_triangles(
    rng: &mut Rng,
    count: usize,
    corner: impl Fn(&mut Rng) -> Vec3,
    size: impl Fn(&mut Rng) -> f32,
) -> Vec<[Vec3; 3]> {
    (0..count)
        .map(|_| {
            let a = corner(rng);
            let size = size(rng);
            [
                a,
                a + size * rng.unit_vector(),
                a + size * rng.unit_vector(),
            ]
        })
        .collect()
}

/// `count` long, thin triangles: a long edge (3·`scale`) from a corner `corner(rng)` and a
/// third vertex very close to it.
pub(crate) fn random_slivers(
    rng: &mut Rng,
    count: usize,
    scale: f32,
    corner: impl Fn(&mut Rng) -> Vec3,
) -> Vec<[Vec3; 3]> {
    (0..count)
        .map(|_| {
            let a = corner(rng);
            let b = a + scale * 3.0 * rng.unit_vector();
            let c = a.lerp(b, rng.f32()) + scale * 1e-3 * rng.unit_vector();
            [a, b, c]
        })
        .collect()
}

/// `count` degenerate triangles on two points `point(rng)`: collinear or with a repeated
/// vertex, as a coin falls.
pub(crate) fn random_degenerates(
    rng: &mut Rng,
    count: usize,
    point: impl Fn(&mut Rng) -> Vec3,
) -> Vec<[Vec3; 3]> {
    (0..count)
        .map(|_| {
            let (a, b) = (point(rng), point(rng));
            if rng.chance(0.5) {
                [a, b, a.lerp(b, 0.25)]
            } else {
                [a, b, b]
            }
        })
        .collect()
}

/// A cone or cylinder standing on `base`, of a height and radii up to `scale`, its axis
/// along a coordinate axis a third of the time, a cylinder half the time, capped half the
/// time; with a point on its base rim for rays to aim at. None where the draw is
/// degenerate.
pub(crate) fn random_cone(rng: &mut Rng, base: Vec3, scale: f32) -> Option<(Cone, Vec3)> {
    let axis = if rng.chance(0.3) {
        rng.axis_direction()
    } else {
        rng.unit_vector()
    };
    let h = scale * rng.range(0.1, 1.0);
    let rb = scale * rng.range(0.0, 0.4);
    let ra = if rng.chance(0.5) {
        rb
    } else {
        scale * rng.range(0.0, 0.4)
    };
    let cone = Cone::new(base, rb, base + h * axis, ra, rng.chance(0.5))?;
    Some((cone, base + rb * axis.any_orthonormal_vector()))
}

/// A ray of one of several kinds, chosen at random.
pub(crate) fn random_ray(rng: &mut Rng, s: &TestScene, bounds: &Aabb) -> Ray {
    let lo = bounds.min - 0.2 * bounds.extent();
    let hi = bounds.max + 0.2 * bounds.extent();
    let feature = |rng: &mut Rng| s.features[rng.below(s.features.len())];
    loop {
        let (o, d) = match rng.below(10) {
            // Random origin and direction.
            0..=2 => (rng.point_in(lo, hi), rng.unit_vector()),
            // Aimed at a vertex, edge midpoint or surface point.
            3 | 4 => {
                let o = rng.point_in(lo, hi);
                (o, feature(rng) - o)
            }
            // Axis-parallel, half of them lying in a slab plane of some feature.
            5 => {
                let mut o = rng.point_in(lo, hi);
                let d = rng.axis_direction();
                if rng.chance(0.5) {
                    let f = feature(rng);
                    for k in 0..3 {
                        if d[k] == 0.0 && rng.chance(0.7) {
                            o[k] = f[k];
                        }
                    }
                }
                (o, d)
            }
            // From inside a box.
            6 if !s.boxes.is_empty() => {
                let b = s.boxes[rng.below(s.boxes.len())];
                let o = rng.point_in(b.min, b.max);
                let d = if rng.chance(0.3) {
                    rng.axis_direction()
                } else {
                    rng.unit_vector()
                };
                (o, d)
            }
            // In the plane of a box face, along it (diagonally or along an axis).
            7 if !s.boxes.is_empty() => {
                let b = s.boxes[rng.below(s.boxes.len())];
                let axis = rng.below(3);
                let mut o = rng.point_in(lo, hi);
                o[axis] = if rng.chance(0.5) {
                    b.min[axis]
                } else {
                    b.max[axis]
                };
                let mut d = rng.unit_vector();
                d[axis] = 0.0;
                (o, d)
            }
            // Starting exactly on a surface feature (an un-offset secondary ray).
            8 => (feature(rng), rng.unit_vector()),
            // Grazing: through a point displaced sideways from a feature by a hair.
            _ => {
                let o = rng.point_in(lo, hi);
                let f = feature(rng);
                let side = (f - o).any_orthonormal_vector();
                let hair = (bounds.extent().max_element() * 1e-6) * rng.range(-1.0, 1.0);
                (o, f + hair * side - o)
            }
        };
        if let Some(d) = d.try_normalize() {
            return Ray::new(o, d);
        }
    }
}

/// Nearest hits agree if the distances are bit-equal, or if the two primitives tie: each,
/// tested alone, reports the same distance to within a few ulps.
pub(crate) fn same_nearest(
    geometry: &Geometry,
    ray: &TraceRay,
    a: Option<Hit>,
    b: Option<Hit>,
) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) if a.t.to_bits() == b.t.to_bits() => true,
        (Some(a), Some(b)) => {
            let ta = geometry.intersect(a.prim, ray, f32::INFINITY).map(|h| h.t);
            let tb = geometry.intersect(b.prim, ray, f32::INFINITY).map(|h| h.t);
            matches!((ta, tb), (Some(x), Some(y)) if (x - y).abs() <= 4e-7 * x.max(y))
        }
        _ => false,
    }
}
