//! Analytic ray–shape tests: every expected distance, barycentric and normal here is worked
//! out by hand (or in f64), and each shape is checked outside, inside, behind, at grazing
//! angles and against `t_max`. Tolerances are relative and stated at each assertion.

use crate::common;

use common::{assert_rel, assert_vec_close, icosphere, lattice_cube, rotate, trace_ray, Rng};
use prism::geometry::{
    intersect_triangle, AaBox, Cone, Geometry, Plane, Shape, ShapeHit, Sphere, TriangleMesh,
};
use prism::math::robust::{next_up, offset_ray_origin};
use prism::math::{Aabb, Ray, Vec3};

/// Relative tolerance for distances computed by a handful of f32 operations.
const REL: f64 = 4e-7;

fn sphere_hit(s: &Sphere, o: Vec3, d: Vec3, t_max: f32) -> Option<ShapeHit> {
    s.intersect(&Ray::new(o, d), t_max)
}

// ---------------------------------------------------------------------------------------
// Spheres

#[test]
fn sphere_hit_from_outside_on_axis_is_exact() {
    let s = Sphere::new(Vec3::ZERO, 2.0);
    let h = sphere_hit(&s, Vec3::new(0.0, 0.0, -5.0), Vec3::Z, f32::INFINITY).unwrap();
    assert_eq!(h.t, 3.0, "5 − 2 is exact in f32");
    let sp = s.surface(&Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z), &h);
    assert_vec_close(sp.p, Vec3::new(0.0, 0.0, -2.0), 0.0, "hit point");
    assert_vec_close(sp.ng, -Vec3::Z, 0.0, "outward normal");
}

#[test]
fn sphere_hit_at_known_points_in_any_direction() {
    // Build rays backwards from a chosen surface point, so the answer is known exactly.
    let mut rng = Rng::new(1);
    for _ in 0..2000 {
        let center = rng.point_in(Vec3::splat(-10.0), Vec3::splat(10.0));
        let radius = rng.range(0.1, 5.0);
        let s = Sphere::new(center, radius);
        let n = rng.unit_vector();
        let p = center + radius * n;
        // A direction into the sphere at that point (d·n < −0.2, away from grazing).
        let d = loop {
            let d = rng.unit_vector();
            if d.dot(n) < -0.2 {
                break d;
            }
        };
        let t = rng.range(0.5, 20.0);
        let o = p - t * d;
        let h = sphere_hit(&s, o, d, f32::INFINITY).expect("aimed at the sphere");
        // The ray origin itself carries rounding of |o| ≈ |p| + t: bound by that scale.
        let scale = (t + p.abs().max_element() + radius) as f64;
        assert_rel(h.t, t as f64, 1e-6 * scale / t as f64, 0.0, "distance");
        let sp = s.surface(&Ray::new(o, d), &h);
        assert_vec_close(sp.ng, n, 2e-4 * scale as f32 / radius, "normal");
        assert_rel(
            (sp.p - center).length(),
            radius as f64,
            1e-6,
            1.0,
            "re-projected point",
        );
    }
}

#[test]
fn sphere_hit_from_inside_returns_far_wall() {
    let s = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 4.0);
    let o = Vec3::new(1.0, 2.0, 4.0); // one unit above the centre along z
    let up = sphere_hit(&s, o, Vec3::Z, f32::INFINITY).unwrap();
    let down = sphere_hit(&s, o, -Vec3::Z, f32::INFINITY).unwrap();
    assert_eq!(up.t, 3.0);
    assert_eq!(down.t, 5.0);
    let sp = s.surface(&Ray::new(o, Vec3::Z), &up);
    assert_vec_close(sp.ng, Vec3::Z, 1e-7, "outward normal seen from inside");
}

#[test]
fn sphere_behind_and_t_max() {
    let s = Sphere::new(Vec3::ZERO, 2.0);
    let o = Vec3::new(0.0, 0.0, -5.0);
    assert!(
        sphere_hit(&s, o, -Vec3::Z, f32::INFINITY).is_none(),
        "behind"
    );
    assert!(
        sphere_hit(&s, o, Vec3::X, f32::INFINITY).is_none(),
        "beside"
    );
    // t = 3 exactly: the bound is exclusive.
    assert!(
        sphere_hit(&s, o, Vec3::Z, 3.0).is_none(),
        "t_max = t excludes"
    );
    assert!(sphere_hit(&s, o, Vec3::Z, 2.999).is_none(), "t_max < t");
    assert_eq!(sphere_hit(&s, o, Vec3::Z, 3.0001).unwrap().t, 3.0);
}

#[test]
fn sphere_near_tangent_rays() {
    let r = 2.0f32;
    let s = Sphere::new(Vec3::ZERO, r);
    for offset in [1e-3f32, 1e-4, 1e-5] {
        let inside = Vec3::new(r * (1.0 - offset), 0.0, -10.0);
        let outside = Vec3::new(r * (1.0 + offset), 0.0, -10.0);
        let h = sphere_hit(&s, inside, Vec3::Z, f32::INFINITY)
            .unwrap_or_else(|| panic!("a ray {offset} inside the silhouette must hit"));
        let x = r as f64 * (1.0 - offset as f64);
        let expected = 10.0 - (r as f64 * r as f64 - x * x).sqrt();
        // Near the silhouette t is ill-conditioned in the offset: allow for x's rounding.
        assert_rel(h.t, expected, 1e-5, 1.0, "near-tangent distance");
        assert!(
            sphere_hit(&s, outside, Vec3::Z, f32::INFINITY).is_none(),
            "a ray {offset} outside the silhouette must miss"
        );
    }
}

#[test]
fn small_distant_sphere_keeps_its_precision() {
    // b² − c would lose the whole answer here (|f|² ≈ 2.5e5, r² = 1e-4 < one ulp of it).
    let c = Vec3::new(300.0, 400.0, 0.0);
    let r = 0.01f32;
    let s = Sphere::new(c, r);
    let side = Vec3::Z;
    for (k, frac) in [0.0f32, 0.5, 0.9, 0.99].into_iter().enumerate() {
        let d = (c + frac * r * side).normalize();
        let h = sphere_hit(&s, Vec3::ZERO, d, f32::INFINITY)
            .unwrap_or_else(|| panic!("impact parameter {frac}·r must hit"));
        let p = h.t * d;
        assert_rel(
            (p - c).length(),
            r as f64,
            0.05,
            0.0,
            &format!("hit point lies on the small sphere (case {k})"),
        );
    }
    for frac in [1.02f32, 1.1, 2.0] {
        let d = (c + frac * r * side).normalize();
        assert!(
            sphere_hit(&s, Vec3::ZERO, d, f32::INFINITY).is_none(),
            "impact parameter {frac}·r must miss"
        );
    }
}

#[test]
fn inside_out_sphere_normals_point_inwards() {
    let c = Vec3::new(0.5, -1.0, 2.0);
    let s = Sphere {
        center: c,
        radius: 1.5,
        inside_out: true,
    };
    let mut rng = Rng::new(2);
    for _ in 0..100 {
        let d = rng.unit_vector();
        // From the centre: every hit is on the wall, and the normal faces the centre.
        let ray = Ray::new(c, d);
        let h = s.intersect(&ray, f32::INFINITY).unwrap();
        assert_rel(h.t, 1.5, REL, 1.0, "radius");
        let sp = s.surface(&ray, &h);
        assert_vec_close(sp.ng, -d, 1e-6, "inward geometric normal");
        assert_vec_close(sp.ns, -d, 1e-6, "inward shading normal");
    }
}

// ---------------------------------------------------------------------------------------
// Triangles

#[test]
fn triangle_known_barycentrics_and_distance() {
    let (v0, v1, v2) = (Vec3::ZERO, Vec3::X, Vec3::Y);
    let h = intersect_triangle(
        &trace_ray(Vec3::new(0.25, 0.5, 1.0), -Vec3::Z),
        v0,
        v1,
        v2,
        f32::INFINITY,
    )
    .unwrap();
    assert_rel(h.t, 1.0, REL, 1.0, "t");
    assert_rel(h.b1, 0.25, REL, 1.0, "b1 (weight of v1)");
    assert_rel(h.b2, 0.5, REL, 1.0, "b2 (weight of v2)");
    // Both windings hit: no back-face culling.
    let back = intersect_triangle(
        &trace_ray(Vec3::new(0.25, 0.5, -1.0), Vec3::Z),
        v0,
        v1,
        v2,
        f32::INFINITY,
    )
    .unwrap();
    assert_rel(back.t, 1.0, REL, 1.0, "t from behind");
}

#[test]
fn triangle_random_barycentrics_round_trip() {
    let mut rng = Rng::new(3);
    let mut checked = 0;
    while checked < 5000 {
        let v = [0; 3].map(|_| rng.point_in(Vec3::splat(-4.0), Vec3::splat(4.0)));
        let normal = (v[1] - v[0]).cross(v[2] - v[0]);
        let area2 = normal.length();
        let longest = [v[1] - v[0], v[2] - v[1], v[0] - v[2]]
            .iter()
            .map(|e| e.length())
            .fold(0.0, f32::max);
        // Well-shaped triangles only: slivers make barycentrics ill-conditioned.
        if area2 < 0.2 * longest * longest {
            continue;
        }
        let (b1, b2) = (rng.range(0.05, 0.9), rng.range(0.05, 0.9));
        if b1 + b2 > 0.95 {
            continue;
        }
        let p = (1.0 - b1 - b2) * v[0] + b1 * v[1] + b2 * v[2];
        let d = loop {
            let d = rng.unit_vector();
            if d.dot(normal / area2).abs() > 0.3 {
                break d;
            }
        };
        let t = rng.range(0.5, 10.0);
        let o = p - t * d;
        let h = intersect_triangle(&trace_ray(o, d), v[0], v[1], v[2], f32::INFINITY)
            .expect("aimed inside the triangle");
        // Rounding of o and of the sheared vertices: relative to the coordinate scale.
        let scale = (t + 8.0) as f64;
        assert_rel(h.t, t as f64, 2e-6 * scale / t as f64, 0.0, "t");
        assert_rel(h.b1, b1 as f64, 1e-4, 1.0, "b1");
        assert_rel(h.b2, b2 as f64, 1e-4, 1.0, "b2");
        checked += 1;
    }
}

#[test]
fn triangle_misses_behind_outside_and_beyond_t_max() {
    let (v0, v1, v2) = (Vec3::ZERO, Vec3::X, Vec3::Y);
    let hit = |o: Vec3, d: Vec3, t_max: f32| {
        intersect_triangle(&trace_ray(o, d), v0, v1, v2, t_max).map(|h| h.t)
    };
    let o = Vec3::new(0.25, 0.25, 2.0);
    assert!(hit(o, Vec3::Z, f32::INFINITY).is_none(), "behind");
    assert!(hit(Vec3::new(-0.01, 0.25, 2.0), -Vec3::Z, f32::INFINITY).is_none());
    assert!(hit(Vec3::new(0.51, 0.5, 2.0), -Vec3::Z, f32::INFINITY).is_none());
    assert!(hit(o, -Vec3::Z, 2.0).is_none(), "t_max = t excludes");
    assert_eq!(hit(o, -Vec3::Z, 2.0001), Some(2.0));
    // A ray in the triangle's plane sees no area.
    assert!(hit(Vec3::new(-1.0, 0.25, 0.0), Vec3::X, f32::INFINITY).is_none());
}

#[test]
fn offset_origins_never_rehit_the_surface_they_leave() {
    // The robust offset (math/robust.rs) must put a secondary ray's origin on the intended
    // side of the surface, at any scale: leaving outwards there is nothing to hit on a
    // convex shape; leaving inwards the next hit is the far wall, not the point itself.
    let mut rng = Rng::new(4);
    for scale in [1e-3f32, 1.0, 1e3] {
        for _ in 0..300 {
            let c = scale * rng.point_in(Vec3::splat(-5.0), Vec3::splat(5.0));
            let r = scale * rng.range(0.1, 2.0);
            let mut g = Geometry::default();
            g.add(Shape::Sphere(Sphere::new(c, r)), 0);
            g.add(
                Shape::from(AaBox::new(
                    c - Vec3::splat(r),
                    c + r * Vec3::new(1.0, 0.5, 2.0),
                )),
                0,
            );
            let axis = rng.unit_vector();
            g.add(
                Shape::from(Cone::new(c, r, c + r * axis, 0.3 * r, true).unwrap()),
                0,
            );
            g.add_mesh(icosphere(c, r, 1), 0);
            for prim in 0..g.primitives.len() as u32 {
                // Aim at the shape from outside to get a surface point.
                let o = c + 6.0 * r * rng.unit_vector();
                let target = c + 0.2 * r * rng.unit_vector();
                let ray = Ray::new(o, (target - o).normalize());
                let Some(h) = g.intersect(prim, &prism::math::TraceRay::new(ray), f32::INFINITY)
                else {
                    continue;
                };
                let sp = g.surface(prim, &ray, &h);
                for _ in 0..8 {
                    let d = rng.unit_vector();
                    let cos = d.dot(sp.ng);
                    if cos.abs() < 0.05 {
                        continue;
                    }
                    let origin = offset_ray_origin(sp.p, sp.p_error, sp.ng, d);
                    let again = g.intersect(prim, &trace_ray(origin, d), f32::INFINITY);
                    // Inwards only on the smooth sphere: near a box or cone rim a short
                    // hit on the neighbouring face is legitimate.
                    if cos > 0.0 {
                        assert!(
                            again.is_none(),
                            "prim {prim} at scale {scale}: outgoing ray re-hit at t = {:e}",
                            again.unwrap().t
                        );
                    } else if let (0, Some(again)) = (prim, again) {
                        assert!(
                            again.t > 1e-3 * r,
                            "prim {prim} at scale {scale}: ingoing ray re-hit at t = {:e}",
                            again.t
                        );
                    }
                }
            }
        }
    }
}

/// Nearest hit over all triangles of `mesh` by brute force.
fn mesh_hit(mesh: &TriangleMesh, o: Vec3, d: Vec3) -> Option<f32> {
    let ray = trace_ray(o, d);
    (0..mesh.triangle_count() as u32)
        .filter_map(|i| {
            let [a, b, c] = mesh.vertices(i);
            intersect_triangle(&ray, a, b, c, f32::INFINITY).map(|h| h.t)
        })
        .min_by(f32::total_cmp)
}

/// Every vertex and every edge midpoint of the mesh: the places a leaky test lets rays by.
fn vertices_and_edge_midpoints(mesh: &TriangleMesh) -> Vec<Vec3> {
    let mut out = Vec::new();
    for i in 0..mesh.triangle_count() as u32 {
        let [a, b, c] = mesh.vertices(i);
        out.extend([a, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)]);
    }
    out
}

fn closed_meshes() -> Vec<(&'static str, TriangleMesh, Vec3, f32)> {
    let axis = Vec3::new(1.0, 2.0, 3.0);
    let off = Vec3::new(1000.0, -500.0, 250.0);
    vec![
        ("icosphere", icosphere(Vec3::ZERO, 1.0, 3), Vec3::ZERO, 1.0),
        (
            "icosphere far from the origin",
            icosphere(off, 2.0, 2),
            off,
            2.0,
        ),
        (
            "axis-aligned lattice cube",
            lattice_cube(4, |p| p),
            Vec3::ZERO,
            1.0,
        ),
        (
            "rotated lattice cube",
            lattice_cube(5, |p| rotate(p, axis, 0.7)),
            Vec3::ZERO,
            1.0,
        ),
        (
            "tiny rotated cube",
            lattice_cube(3, |p| rotate(p * 1e-3, axis, 1.3) + Vec3::splat(1e-3)),
            Vec3::splat(1e-3),
            1e-3,
        ),
    ]
}

#[test]
fn closed_meshes_do_not_leak_for_rays_from_inside() {
    let mut rng = Rng::new(5);
    for (name, mesh, center, size) in closed_meshes() {
        let targets = vertices_and_edge_midpoints(&mesh);
        let max_dist = mesh
            .positions()
            .iter()
            .map(|p| (*p - center).length())
            .fold(0.0, f32::max);
        let mut origins = vec![center];
        for _ in 0..4 {
            origins.push(center + 0.5 * size * rng.point_in(-Vec3::ONE, Vec3::ONE));
        }
        let mut rays = 0;
        for &o in &origins {
            let mut dirs: Vec<Vec3> = targets
                .iter()
                .filter_map(|&t| (t - o).try_normalize())
                .collect();
            dirs.extend((0..2000).map(|_| rng.unit_vector()));
            dirs.extend((0..6).map(|i| {
                let mut d = Vec3::ZERO;
                d[i % 3] = if i < 3 { 1.0 } else { -1.0 };
                d
            }));
            for d in dirs {
                let t = mesh_hit(&mesh, o, d)
                    .unwrap_or_else(|| panic!("{name}: ray from {o:?} along {d:?} leaked"));
                assert!(
                    t > 0.0 && t <= 2.0 * max_dist,
                    "{name}: implausible t = {t} inside a mesh of radius {max_dist}"
                );
                rays += 1;
            }
        }
        assert!(rays > 10_000, "{name}: only {rays} rays");
    }
}

/// Vertices and edges (as their midpoints) of a mesh, each with the triangles meeting there.
fn features_with_faces(mesh: &TriangleMesh) -> Vec<(Vec3, Vec<usize>)> {
    use std::collections::BTreeMap;
    let mut vertices: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    let mut edges: BTreeMap<(u32, u32), Vec<usize>> = BTreeMap::new();
    for (t, idx) in mesh.indices().iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (idx[k], idx[(k + 1) % 3]);
            vertices.entry(a).or_default().push(t);
            edges.entry((a.min(b), a.max(b))).or_default().push(t);
        }
    }
    let p = |i: u32| mesh.positions()[i as usize];
    let mut out: Vec<(Vec3, Vec<usize>)> = vertices.into_iter().map(|(v, f)| (p(v), f)).collect();
    out.extend(
        edges
            .into_iter()
            .map(|((a, b), f)| (0.5 * (p(a) + p(b)), f)),
    );
    out
}

#[test]
fn closed_meshes_are_hit_through_edges_and_vertices_from_outside() {
    let mut rng = Rng::new(6);
    for (name, mesh, center, size) in closed_meshes() {
        let features = features_with_faces(&mesh);
        let mut rays = 0;
        for _ in 0..6 {
            let o = center + 4.0 * size * rng.unit_vector();
            for (target, faces) in &features {
                // Only features whose every triangle faces o: off the silhouette, where a
                // ray rounded past the feature still lands on a neighbouring triangle.
                let to_origin = (o - *target).normalize();
                let facing = faces.iter().all(|&f| {
                    let [a, b, c] = mesh.vertices(f as u32);
                    (b - a).cross(c - a).normalize().dot(to_origin) > 0.2
                });
                if !facing {
                    continue;
                }
                let d = (*target - o).normalize();
                assert!(
                    mesh_hit(&mesh, o, d).is_some(),
                    "{name}: ray from {o:?} towards {target:?} missed"
                );
                rays += 1;
            }
        }
        assert!(rays > 100, "{name}: only {rays} rays");
    }
}

#[test]
fn flat_grid_has_no_cracks_at_shared_vertices() {
    // A triangulated 8×8 grid: rays straight down through every lattice point and edge
    // midpoint, and obliquely, must all hit.
    let n = 8u32;
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push(Vec3::new(
                i as f32 * 0.37 - 1.3,
                0.25,
                j as f32 * 0.29 - 1.1,
            ));
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut faces = Vec::new();
    for j in 0..n {
        for i in 0..n {
            faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mesh = TriangleMesh::new(positions.clone(), faces, None, None).unwrap();
    let interior: Vec<Vec3> = vertices_and_edge_midpoints(&mesh)
        .into_iter()
        .filter(|p| {
            let (lo, hi) = (positions[0], positions[positions.len() - 1]);
            p.x > lo.x && p.x < hi.x && p.z > lo.z && p.z < hi.z
        })
        .collect();
    let mut rng = Rng::new(7);
    for &p in &interior {
        for d in [-Vec3::Y, Vec3::Y] {
            assert!(
                mesh_hit(&mesh, p - d, d).is_some(),
                "crack at {p:?} along {d:?}"
            );
        }
        for _ in 0..8 {
            let d = rng.unit_vector();
            if d.y.abs() < 0.2 {
                continue;
            }
            assert!(mesh_hit(&mesh, p - 3.0 * d, d).is_some(), "crack at {p:?}");
        }
    }
}

#[test]
fn test_meshes_are_closed_and_face_outwards() {
    // Guards the helpers above: each edge used twice in opposite directions, and the
    // signed volume positive (counter-clockwise seen from outside).
    for (name, mesh, center, _) in closed_meshes() {
        let mut edges = std::collections::HashMap::new();
        let mut volume = 0.0f64;
        for i in 0..mesh.triangle_count() as u32 {
            let [a, b, c] = mesh.vertices(i).map(|p| (p - center).as_dvec3());
            volume += a.dot(b.cross(c)) / 6.0;
            let idx = mesh.indices()[i as usize];
            for k in 0..3 {
                *edges.entry((idx[k], idx[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1, "{name}: edge {a}->{b} used {count} times");
            assert!(edges.contains_key(&(b, a)), "{name}: edge {a}->{b} is open");
        }
        assert!(volume > 0.0, "{name}: faces point inwards");
    }
}

// ---------------------------------------------------------------------------------------
// Planes

#[test]
fn plane_hits_and_normal() {
    let p = Plane::new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 3.0, 0.0)).unwrap();
    assert_eq!(p.normal(), Vec3::Y);
    let o = Vec3::new(0.5, 3.0, -0.5);
    let down = Ray::new(o, -Vec3::Y);
    let h = p.intersect(&down, f32::INFINITY).unwrap();
    assert_eq!(h.t, 2.0);
    let sp = p.surface(&down, &h);
    assert_vec_close(sp.p, Vec3::new(0.5, 1.0, -0.5), 1e-6, "hit point");
    assert_eq!(
        sp.ng,
        Vec3::Y,
        "the plane's own normal, whichever side is hit"
    );
    let slanted = Ray::new(o, Vec3::new(1.0, -1.0, 0.0).normalize());
    assert_rel(
        p.intersect(&slanted, f32::INFINITY).unwrap().t,
        2.0 * std::f64::consts::SQRT_2,
        REL,
        1.0,
        "45°",
    );
    // From below, upwards.
    let up = Ray::new(Vec3::new(0.0, -1.5, 0.0), Vec3::Y);
    assert_eq!(p.intersect(&up, f32::INFINITY).unwrap().t, 2.5);
    assert!(
        p.intersect(&Ray::new(o, Vec3::Y), f32::INFINITY).is_none(),
        "away"
    );
    assert!(
        p.intersect(&Ray::new(o, Vec3::X), f32::INFINITY).is_none(),
        "parallel"
    );
    assert!(p.intersect(&down, 2.0).is_none(), "t_max = t excludes");
    assert!(Plane::new(Vec3::ZERO, Vec3::ZERO).is_none(), "zero normal");
}

// ---------------------------------------------------------------------------------------
// Boxes

fn test_box() -> AaBox {
    AaBox::new(Vec3::new(1.0, 2.0, 3.0), Vec3::new(-1.0, -2.0, -3.0))
}

fn box_hit(b: &AaBox, o: Vec3, d: Vec3) -> Option<(f32, Vec3)> {
    let ray = trace_ray(o, d);
    let h = b.intersect(&ray, f32::INFINITY)?;
    Some((h.t, b.surface(&ray.ray, &h).ng))
}

#[test]
fn box_faces_from_outside() {
    let b = test_box();
    assert_eq!(b.min, Vec3::new(-1.0, -2.0, -3.0), "corners are sorted");
    let cases = [
        (Vec3::new(0.2, 0.3, -10.0), Vec3::Z, 7.0, -Vec3::Z),
        (Vec3::new(0.2, 0.3, 10.0), -Vec3::Z, 7.0, Vec3::Z),
        (Vec3::new(-5.0, 0.3, 0.5), Vec3::X, 4.0, -Vec3::X),
        (Vec3::new(5.0, 0.3, 0.5), -Vec3::X, 4.0, Vec3::X),
        (Vec3::new(0.2, -6.0, 0.5), Vec3::Y, 4.0, -Vec3::Y),
        (Vec3::new(0.2, 6.0, 0.5), -Vec3::Y, 4.0, Vec3::Y),
    ];
    for (o, d, t, n) in cases {
        let (ht, hn) = box_hit(&b, o, d).unwrap_or_else(|| panic!("{o:?} {d:?} missed"));
        assert_eq!((ht, hn), (t, n), "from {o:?} along {d:?}");
    }
    // Oblique: enters the x = −1 face at (−1, 0, 0) from (−3, −2, 0).
    let (t, n) = box_hit(
        &b,
        Vec3::new(-3.0, -2.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0).normalize(),
    )
    .unwrap();
    assert_rel(t, 2.0 * std::f64::consts::SQRT_2, REL, 1.0, "oblique");
    assert_eq!(n, -Vec3::X);
    assert!(
        box_hit(&b, Vec3::new(0.0, 0.0, -10.0), -Vec3::Z).is_none(),
        "behind"
    );
    assert!(
        box_hit(&b, Vec3::new(1.5, 0.0, -10.0), Vec3::Z).is_none(),
        "beside"
    );
    let ray = trace_ray(Vec3::new(0.2, 0.3, -10.0), Vec3::Z);
    assert!(b.intersect(&ray, 7.0).is_none(), "t_max = t excludes");
}

#[test]
fn box_from_inside_hits_the_exit_face() {
    let b = test_box();
    let o = Vec3::new(0.25, -0.5, 1.0);
    for (d, t, n) in [
        (Vec3::X, 0.75, Vec3::X),
        (-Vec3::X, 1.25, -Vec3::X),
        (Vec3::Y, 2.5, Vec3::Y),
        (-Vec3::Y, 1.5, -Vec3::Y),
        (Vec3::Z, 2.0, Vec3::Z),
        (-Vec3::Z, 4.0, -Vec3::Z),
    ] {
        assert_eq!(box_hit(&b, o, d), Some((t, n)), "from inside along {d:?}");
    }
}

#[test]
fn box_axis_parallel_rays_in_a_face_plane_touch_it() {
    // The box is closed: a ray sliding along a face plane touches it where it enters the
    // other slabs, for either sign of the zero direction components.
    let b = test_box();
    for zero in [0.0f32, -0.0] {
        for x in [-1.0f32, 1.0] {
            let o = Vec3::new(x, 0.5, -10.0);
            let d = Vec3::new(zero, zero, 1.0);
            let (t, n) = box_hit(&b, o, d)
                .unwrap_or_else(|| panic!("ray in the plane x = {x} (zero = {zero}) missed"));
            assert_eq!(t, 7.0);
            assert_eq!(n, -Vec3::Z);
        }
    }
    // Just outside the plane: a miss.
    let o = Vec3::new(next_up(1.0), 0.5, -10.0);
    assert!(box_hit(&b, o, Vec3::Z).is_none());
}

// ---------------------------------------------------------------------------------------
// Cones and cylinders

fn cone_hit(c: &Cone, o: Vec3, d: Vec3) -> Option<(f32, Vec3)> {
    let ray = Ray::new(o, d);
    let h = c.intersect(&ray, f32::INFINITY)?;
    Some((h.t, c.surface(&ray, &h).ng))
}

#[test]
fn cylinder_side_and_caps() {
    let capped = Cone::cylinder(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), 1.0, true).unwrap();
    let open = Cone::cylinder(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), 1.0, false).unwrap();
    for c in [&capped, &open] {
        let (t, n) = cone_hit(c, Vec3::new(-5.0, 0.0, 1.0), Vec3::X).unwrap();
        assert_rel(t, 4.0, REL, 1.0, "side from outside");
        assert_vec_close(n, -Vec3::X, 1e-6, "side normal");
        let (t, n) = cone_hit(c, Vec3::new(0.0, 0.0, 1.0), Vec3::Y).unwrap();
        assert_rel(t, 1.0, REL, 1.0, "side from inside");
        assert_vec_close(n, Vec3::Y, 1e-6, "side normal (outward) from inside");
    }
    // Along and parallel to the axis: the caps, or nothing when open.
    for x in [0.0f32, 0.5, -0.99] {
        let o = Vec3::new(x, 0.0, -3.0);
        let (t, n) = cone_hit(&capped, o, Vec3::Z).unwrap();
        assert_rel(t, 3.0, REL, 1.0, "base cap");
        assert_vec_close(n, -Vec3::Z, 1e-6, "base cap normal");
        let (t, n) = cone_hit(&capped, Vec3::new(x, 0.0, 7.0), -Vec3::Z).unwrap();
        assert_rel(t, 5.0, REL, 1.0, "top cap");
        assert_vec_close(n, Vec3::Z, 1e-6, "top cap normal");
        assert!(
            cone_hit(&open, o, Vec3::Z).is_none(),
            "open: through both ends"
        );
        let (t, n) = cone_hit(&capped, Vec3::new(x, 0.0, 0.5), Vec3::Z).unwrap();
        assert_rel(t, 1.5, REL, 1.0, "top cap from inside");
        assert_vec_close(n, Vec3::Z, 1e-6, "top cap normal from inside");
        assert!(cone_hit(&open, Vec3::new(x, 0.0, 0.5), Vec3::Z).is_none());
    }
    // Into the open top, onto the inner wall at (1, 0, 1.5).
    let d = Vec3::new(1.0, 0.0, -1.0).normalize();
    let (t, n) = cone_hit(&open, Vec3::new(0.0, 0.0, 2.5), d).unwrap();
    assert_rel(t, std::f64::consts::SQRT_2, 1e-6, 1.0, "inner wall");
    assert_vec_close(n, Vec3::X, 1e-6, "inner wall normal faces the outside");
    let (t, n) = cone_hit(&capped, Vec3::new(0.0, 0.0, 2.5), d).unwrap();
    assert_rel(
        t,
        0.5 * std::f64::consts::SQRT_2,
        1e-6,
        1.0,
        "top cap, oblique",
    );
    assert_vec_close(n, Vec3::Z, 1e-6, "top cap normal");
    // Above and beside: misses.
    assert!(cone_hit(&capped, Vec3::new(-5.0, 0.0, 2.5), Vec3::X).is_none());
    assert!(cone_hit(&capped, Vec3::new(-5.0, 1.5, 1.0), Vec3::X).is_none());
}

#[test]
fn cylinder_in_a_general_position() {
    let mut rng = Rng::new(8);
    for _ in 0..500 {
        let base = rng.point_in(Vec3::splat(-5.0), Vec3::splat(5.0));
        let axis = rng.unit_vector();
        let h = rng.range(0.5, 3.0);
        let r = rng.range(0.2, 2.0);
        let c = Cone::cylinder(base, base + h * axis, r, true).unwrap();
        let perp = axis.any_orthonormal_vector();
        let perp = rotate(perp, axis, rng.range(0.0, std::f32::consts::TAU));
        let p = base + rng.range(0.05, 0.95) * h * axis + r * perp;
        let dist = rng.range(0.5, 5.0);
        let (t, n) = cone_hit(&c, p + dist * perp, -perp).expect("aimed at the side");
        assert_rel(t, dist as f64, 2e-5, 10.0, "distance to the side");
        assert_vec_close(n, perp, 1e-4, "side normal");
        let q = base + 0.3 * r * perp;
        let (t, n) = cone_hit(&c, q - dist * axis, axis).expect("aimed at the base cap");
        assert_rel(t, dist as f64, 2e-5, 10.0, "distance to the base cap");
        assert_vec_close(n, -axis, 1e-5, "base cap normal");
    }
}

#[test]
fn cone_side_apex_and_base() {
    // Base radius 1 at z = 0, apex (radius 0) at z = 1: x² + y² = (1 − z)².
    let capped = Cone::new(Vec3::ZERO, 1.0, Vec3::Z, 0.0, true).unwrap();
    let open = Cone::new(Vec3::ZERO, 1.0, Vec3::Z, 0.0, false).unwrap();
    for c in [&capped, &open] {
        let (t, n) = cone_hit(c, Vec3::new(-5.0, 0.0, 0.5), Vec3::X).unwrap();
        assert_rel(t, 4.5, REL, 1.0, "side");
        let expected = Vec3::new(-1.0, 0.0, 1.0).normalize();
        assert_vec_close(n, expected, 1e-6, "side normal is the gradient");
        let (t, _) = cone_hit(c, Vec3::new(0.0, 0.0, 3.0), -Vec3::Z).unwrap();
        assert_rel(t, 2.0, 1e-6, 1.0, "along the axis onto the apex");
    }
    let (t, n) = cone_hit(&capped, Vec3::new(0.2, 0.1, -2.0), Vec3::Z).unwrap();
    assert_rel(t, 2.0, REL, 1.0, "base cap");
    assert_vec_close(n, -Vec3::Z, 1e-6, "base cap normal");
    // Open: up through the base onto the inside of the side at z = 1 − 0.3.
    let (t, _) = cone_hit(&open, Vec3::new(0.3, 0.0, -2.0), Vec3::Z).unwrap();
    assert_rel(t, 2.7, 1e-6, 1.0, "inner side of an open cone");
    // A truncated cone (frustum) with both caps: radius 2 at z = 0, 1 at z = 2.
    let frustum = Cone::new(Vec3::ZERO, 2.0, Vec3::new(0.0, 0.0, 2.0), 1.0, true).unwrap();
    let (t, _) = cone_hit(&frustum, Vec3::new(0.0, -5.0, 1.0), Vec3::Y).unwrap();
    assert_rel(t, 3.5, REL, 1.0, "frustum side at radius 1.5");
    let (t, n) = cone_hit(&frustum, Vec3::new(0.9, 0.0, 5.0), -Vec3::Z).unwrap();
    assert_rel(t, 3.0, REL, 1.0, "frustum top cap");
    assert_vec_close(n, Vec3::Z, 1e-6, "frustum top cap normal");
    assert!(cone_hit(&frustum, Vec3::new(1.1, 0.0, 5.0), -Vec3::Z).is_some_and(|(t, _)| t > 3.0));
    assert!(
        Cone::new(Vec3::ZERO, 1.0, Vec3::ZERO, 1.0, true).is_none(),
        "no height"
    );
    assert!(
        Cone::new(Vec3::ZERO, -1.0, Vec3::Z, 1.0, true).is_none(),
        "negative radius"
    );
}

// ---------------------------------------------------------------------------------------
// Bounding boxes

#[test]
fn aabb_slab_test() {
    let b = Aabb::new(Vec3::new(-1.0, 0.5, -4.0), Vec3::new(2.0, 3.0, -1.0));
    let hit = |o: Vec3, d: Vec3, t_max: f32| b.hit(o, d.recip(), t_max);
    // Entry distance on a hit from outside; 0 from inside.
    assert_eq!(
        hit(Vec3::new(0.0, 1.0, -10.0), Vec3::Z, f32::INFINITY),
        Some(6.0)
    );
    assert_eq!(
        hit(Vec3::new(0.0, 1.0, -2.0), Vec3::Z, f32::INFINITY),
        Some(0.0)
    );
    let d = Vec3::new(1.0, 1.0, 1.0).normalize();
    let t = hit(Vec3::new(-2.0, -0.5, -5.0), d, f32::INFINITY).unwrap();
    assert_rel(t, 3f64.sqrt(), REL, 1.0, "diagonal entry");
    // Misses: behind, beside, beyond t_max.
    assert_eq!(
        hit(Vec3::new(0.0, 1.0, -10.0), -Vec3::Z, f32::INFINITY),
        None
    );
    assert_eq!(
        hit(Vec3::new(5.0, 1.0, -10.0), Vec3::Z, f32::INFINITY),
        None
    );
    assert_eq!(hit(Vec3::new(0.0, 1.0, -10.0), Vec3::Z, 5.9), None);
    assert_eq!(hit(Vec3::new(0.0, 1.0, -10.0), Vec3::Z, 6.0), Some(6.0));
}

#[test]
fn aabb_axis_parallel_rays() {
    let b = Aabb::new(Vec3::new(-1.0, 0.5, -4.0), Vec3::new(2.0, 3.0, -1.0));
    for zero in [0.0f32, -0.0] {
        let d = Vec3::new(zero, zero, 1.0);
        let inv = d.recip();
        // Inside both zero-direction slabs, outside, and exactly on each slab plane (where
        // the slab arithmetic meets 0·∞): the box is closed, so the planes count as inside.
        assert_eq!(
            b.hit(Vec3::new(0.0, 1.0, -10.0), inv, f32::INFINITY),
            Some(6.0)
        );
        assert_eq!(b.hit(Vec3::new(2.5, 1.0, -10.0), inv, f32::INFINITY), None);
        assert_eq!(b.hit(Vec3::new(0.0, 0.4, -10.0), inv, f32::INFINITY), None);
        for o in [
            Vec3::new(-1.0, 1.0, -10.0),
            Vec3::new(2.0, 1.0, -10.0),
            Vec3::new(0.0, 0.5, -10.0),
            Vec3::new(0.0, 3.0, -10.0),
            Vec3::new(2.0, 3.0, -10.0),
            Vec3::new(-1.0, 0.5, -10.0),
        ] {
            assert_eq!(
                b.hit(o, inv, f32::INFINITY),
                Some(6.0),
                "ray in a slab plane from {o:?} (zero = {zero})"
            );
            assert_eq!(
                b.hit(o + Vec3::new(0.0, 0.0, 8.0), inv, f32::INFINITY),
                Some(0.0)
            );
        }
    }
    // A flat box (a triangle's bounds in an axis plane), ray lying in it and crossing it.
    let flat = Aabb::new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 1.0, 1.0));
    let along = Vec3::new(1.0, 0.0, 0.0);
    assert_eq!(
        flat.hit(Vec3::new(-1.0, 1.0, 0.5), along.recip(), f32::INFINITY),
        Some(1.0)
    );
    assert_eq!(
        flat.hit(Vec3::new(0.5, 3.0, 0.5), (-Vec3::Y).recip(), f32::INFINITY),
        Some(2.0)
    );
}

#[test]
fn aabb_empty_is_never_hit() {
    let mut rng = Rng::new(9);
    for _ in 0..100 {
        let o = rng.point_in(-Vec3::ONE, Vec3::ONE);
        let d = rng.unit_vector();
        assert_eq!(Aabb::EMPTY.hit(o, d.recip(), f32::INFINITY), None);
        assert_eq!(Aabb::EMPTY.hit(o, Vec3::X.recip(), f32::INFINITY), None);
    }
}

#[test]
fn aabb_is_conservative_for_the_shapes_it_bounds() {
    // Any ray that hits a shape also hits its bounds, no later than the shape.
    let mut rng = Rng::new(10);
    let mut geometry = Geometry::default();
    for _ in 0..200 {
        let c = rng.point_in(Vec3::splat(-3.0), Vec3::splat(3.0));
        let r = rng.range(0.05, 1.0);
        geometry.add(Shape::Sphere(Sphere::new(c, r)), 0);
        let d = rng.unit_vector();
        if let Some(cone) = Cone::new(c, r, c + d, rng.range(0.0, 1.0), rng.chance(0.5)) {
            geometry.add(Shape::from(cone), 0);
        }
        geometry.add(Shape::from(AaBox::new(c, c + rng.unit_vector())), 0);
    }
    geometry.add_mesh(icosphere(Vec3::ZERO, 2.0, 1), 0);
    let mut checked = 0;
    for _ in 0..20_000 {
        let o = rng.point_in(Vec3::splat(-5.0), Vec3::splat(5.0));
        let d = if rng.chance(0.2) {
            rng.axis_direction()
        } else {
            rng.unit_vector()
        };
        let ray = trace_ray(o, d);
        for prim in 0..geometry.primitives.len() as u32 {
            if let Some(h) = geometry.intersect(prim, &ray, f32::INFINITY) {
                let bounds = geometry.bounds(prim).unwrap();
                let entry = bounds.hit(o, ray.inv_dir, h.t);
                assert!(
                    entry.is_some_and(|e| e <= h.t),
                    "prim {prim} hit at {} but its bounds {bounds:?} report {entry:?}",
                    h.t
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 10_000, "only {checked} hits checked");
}

/// Every shape kind reports hits strictly nearer than `t_max`: asked again with its own
/// hit's distance as the limit, it finds nothing there. (Accelerators rely on this to break
/// exact ties toward the lower primitive id; a cylinder's f64 root rounding up to t_max in
/// f32 once let the SPD rings pick another primitive than brute force.)
#[test]
fn hits_are_strictly_nearer_than_t_max() {
    let mut rng = Rng::new(77);
    let mut g = Geometry::default();
    g.add(Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0)), 0);
    g.add(
        Shape::Cone(Box::new(
            Cone::new(
                Vec3::new(-1.0, 0.2, -0.3),
                0.5,
                Vec3::new(1.0, -0.1, 0.4),
                0.2,
                true,
            )
            .unwrap(),
        )),
        0,
    );
    g.add(
        Shape::Cone(Box::new(
            Cone::new(
                Vec3::new(0.0, -1.0, 0.0),
                0.3,
                Vec3::new(0.1, 1.0, 0.2),
                0.3,
                false,
            )
            .unwrap(),
        )),
        0,
    );
    g.add(
        Shape::from(AaBox::new(Vec3::splat(-0.7), Vec3::splat(0.6))),
        0,
    );
    g.add_mesh(icosphere(Vec3::new(0.2, 0.1, 0.0), 0.9, 1), 0);
    let mut checked = 0;
    for _ in 0..20_000 {
        let o = rng.point_in(Vec3::splat(-4.0), Vec3::splat(4.0));
        let d = (rng.point_in(Vec3::splat(-0.5), Vec3::splat(0.5)) - o).normalize();
        let ray = trace_ray(o, d);
        for prim in 0..g.primitives.len() as u32 {
            if let Some(h) = g.intersect(prim, &ray, f32::INFINITY) {
                checked += 1;
                let again = g.intersect(prim, &ray, h.t);
                assert!(
                    again.is_none_or(|a| a.t < h.t),
                    "prim {prim}: hit at {} reported again with t_max = {}",
                    again.unwrap().t,
                    h.t
                );
            }
        }
    }
    assert!(checked > 20_000, "too few hits to mean anything: {checked}");
}
