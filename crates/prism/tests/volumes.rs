//! Node bounding volumes against the brute-force oracle and their own promises: every
//! volume kind finds the same nearest hit and any-hit answer as `BruteForce` on 10⁵
//! hostile rays over scales 10⁻³, 1 and 10³; fitted volumes contain random points of their
//! primitives; ray tests never miss a volume whose contents the ray hits; 26-DOPs are never
//! looser than 14-DOPs, which are never looser than boxes.

use crate::common;

use common::oracle::{
    random_cone, random_degenerates, random_ray, random_slivers, random_triangles, same_nearest,
    TestScene,
};
use common::{icosphere, rotate, Rng};
use prism::accel::volumes::{self, Dop14, Dop26, NodeVolume, Volume, VolumeBvh, CULL_SLACK};
use prism::accel::{Accel, BruteForce, Bvh, BvhOptions};
use prism::geometry::{AaBox, Geometry, Shape, Sphere, TriangleMesh};
use prism::math::{Aabb, Ray, TraceRay, Vec3};
use prism::Stats;

/// Rays per scene and volume kind; 5 scenes make 10⁵ per kind.
const RAYS: usize = 20_000;

/// Random scene of every bounded shape kind in `[-2, 2]³·scale + offset`: ordinary, long
/// thin and degenerate triangles, duplicates, nested spheres, boxes, cones along axes and
/// slanted, and a slanted closed mesh.
fn hostile_scene(seed: u64, scale: f32, offset: Vec3) -> TestScene {
    let mut rng = Rng::new(seed);
    let mut g = Geometry::default();
    let mut features = Vec::new();
    let mut boxes = Vec::new();
    let p = |rng: &mut Rng| offset + scale * rng.point_in(Vec3::splat(-2.0), Vec3::splat(2.0));
    let mut tris = random_triangles(&mut rng, 150, p, |rng| scale * rng.range(0.01, 0.8));
    tris.extend(random_slivers(&mut rng, 80, scale, p));
    tris.extend(random_degenerates(&mut rng, 20, p));
    let dup: Vec<_> = tris.iter().step_by(13).copied().collect();
    tris.extend(dup);
    for t in &tris {
        features.extend([t[0], 0.5 * (t[1] + t[2])]);
    }
    let positions = tris.iter().flatten().copied().collect();
    let indices = (0..tris.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    g.add_mesh(
        TriangleMesh::new(positions, indices, None, None).unwrap(),
        0,
    );
    for _ in 0..80 {
        let c = p(&mut rng);
        let r = scale * rng.range(0.02, 0.6);
        g.add(Shape::Sphere(Sphere::new(c, r)), 0);
        features.push(c + r * rng.unit_vector());
        if rng.chance(0.2) {
            let inner = Sphere {
                center: c + 0.1 * r * rng.unit_vector(),
                radius: r * rng.range(0.3, 1.2),
                inside_out: rng.chance(0.5),
            };
            g.add(Shape::Sphere(inner), 0);
        }
    }
    for _ in 0..40 {
        let a = p(&mut rng);
        let b = a + scale * rng.point_in(Vec3::ZERO, Vec3::ONE);
        let bx = AaBox::new(a, b);
        g.add(Shape::from(bx), 0);
        boxes.push(bx);
        features.extend([bx.min, bx.max]);
    }
    for _ in 0..40 {
        let base = p(&mut rng);
        if let Some((c, rim)) = random_cone(&mut rng, base, scale) {
            g.add(Shape::from(c), 0);
            features.push(rim);
        }
    }
    let axis = Vec3::new(1.0, -2.0, 0.5);
    let mut ico = icosphere(Vec3::ZERO, 1.0, 3);
    ico.transform(
        |v| offset + scale * rotate(v * Vec3::new(2.0, 0.3, 0.6), axis, 0.7),
        |n| n,
    );
    features.extend(ico.positions().iter().step_by(5));
    g.add_mesh(ico, 0);
    TestScene {
        geometry: g,
        features,
        boxes,
    }
}

fn check_scene(name: &str, seed: u64, scale: f32, offset: Vec3, options: &BvhOptions) {
    let s = hostile_scene(seed, scale, offset);
    let g = &s.geometry;
    let prims: Vec<u32> = (0..g.primitives.len() as u32).collect();
    let brute = BruteForce::new(prims.clone());
    let accels: Vec<(NodeVolume, Box<dyn Accel>)> = NodeVolume::ALL
        .iter()
        .map(|&v| (v, volumes::build(g, prims.clone(), options, v)))
        .collect();
    let bounds = g.world_bounds();
    let mut rng = Rng::new(seed * 31 + 7);
    let mut stats = Stats::default();
    let (mut hits, mut occluded) = (0, 0);
    for _ in 0..RAYS {
        let ray = TraceRay::new(random_ray(&mut rng, &s, &bounds));
        let expected = brute.intersect(g, &ray, f32::INFINITY, &mut stats);
        let t = expected.map_or(bounds.extent().length() * 4.0, |h| {
            h.t * rng.range(0.5, 1.5)
        });
        let expected_any = brute.occluded(g, &ray, t, &mut stats);
        hits += expected.is_some() as usize;
        occluded += expected_any as usize;
        for (v, accel) in &accels {
            let got = accel.intersect(g, &ray, f32::INFINITY, &mut stats);
            assert!(
                same_nearest(g, &ray, expected, got),
                "{name}/{v}: {:?}: {expected:?} vs {got:?}",
                ray.ray
            );
            assert_eq!(
                accel.occluded(g, &ray, t, &mut stats),
                expected_any,
                "{name}/{v}: {:?} occluded within {t}",
                ray.ray
            );
        }
    }
    assert!(hits > RAYS / 4 && hits < RAYS, "{name}: {hits} hits");
    assert!(occluded > RAYS / 10, "{name}: {occluded} occluded");
}

/// The default BVH options but for leaves of at most `max_leaf_size` primitives.
fn leaves_of_at_most(max_leaf_size: usize) -> BvhOptions {
    BvhOptions {
        max_leaf_size,
        ..BvhOptions::default()
    }
}

#[test]
fn every_volume_matches_brute_force_at_unit_scale() {
    check_scene("unit", 1, 1.0, Vec3::ZERO, &BvhOptions::default());
}

#[test]
fn every_volume_matches_brute_force_with_one_primitive_leaves() {
    check_scene(
        "leaf1",
        2,
        1.0,
        Vec3::new(0.3, -0.2, 0.1),
        &leaves_of_at_most(1),
    );
}

#[test]
fn every_volume_matches_brute_force_on_a_tiny_scene() {
    check_scene("tiny", 3, 1e-3, Vec3::splat(1e-3), &BvhOptions::default());
}

#[test]
fn every_volume_matches_brute_force_on_a_huge_offset_scene() {
    check_scene(
        "huge",
        4,
        1e3,
        Vec3::new(4e3, -2e3, 1e3),
        &leaves_of_at_most(2),
    );
}

#[test]
fn every_volume_matches_brute_force_on_a_far_tiny_scene() {
    check_scene(
        "far",
        5,
        1e-3,
        Vec3::new(3.0, -1.0, 2.0),
        &BvhOptions::default(),
    );
}

/// A random point on the surface of primitive `prim`.
fn point_on(g: &Geometry, prim: u32, rng: &mut Rng) -> Vec3 {
    match &g.primitives[prim as usize].shape {
        Shape::Triangle { mesh, index } => {
            let [a, b, c] = g.meshes[*mesh as usize].vertices(*index);
            let (mut u, mut v) = (rng.f32(), rng.f32());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            a + u * (b - a) + v * (c - a)
        }
        Shape::Sphere(s) => s.center + s.radius.abs() * rng.unit_vector(),
        Shape::Box(b) => {
            let mut p = rng.point_in(b.min, b.max);
            let axis = rng.below(3);
            p[axis] = if rng.chance(0.5) {
                b.min[axis]
            } else {
                b.max[axis]
            };
            p
        }
        Shape::Cone(c) => {
            let axis = (c.apex - c.base).normalize();
            let (u, w) = (
                axis.any_orthonormal_vector(),
                axis.cross(axis.any_orthonormal_vector()),
            );
            let s = rng.f32();
            let r = c.base_radius + s * (c.apex_radius - c.base_radius);
            let phi = std::f32::consts::TAU * rng.f32();
            c.base.lerp(c.apex, s) + r * (phi.cos() * u + phi.sin() * w)
        }
        Shape::Plane(_) => unreachable!("test scenes hold no planes"),
    }
}

/// Containment and never-miss for one volume kind on one scene: random points of every
/// primitive lie in every volume above it, and a ray that hits a primitive at `t` hits the
/// volume of every node above it no later than `t`.
fn check_volume_promises<V: Volume>(s: &TestScene, name: &str, seed: u64) {
    let g = &s.geometry;
    let prims: Vec<u32> = (0..g.primitives.len() as u32).collect();
    let bvh = Bvh::build(g, prims, &leaves_of_at_most(2));
    let tree = VolumeBvh::<V>::from_bvh(g, &bvh, name);
    let volumes: Vec<V> = tree.volumes().copied().collect();
    let mut rng = Rng::new(seed);
    for (i, v) in volumes.iter().enumerate() {
        for &prim in tree.node_prims(i) {
            for _ in 0..4 {
                let p = point_on(g, prim, &mut rng);
                assert!(
                    v.contains(p),
                    "{name}: node {i} misses {p:?} of prim {prim}"
                );
            }
        }
    }
    let bounds = g.world_bounds();
    for _ in 0..3000 {
        let ray = TraceRay::new(random_ray(&mut rng, s, &bounds));
        let prepared = V::prepare(&ray);
        for (i, v) in volumes.iter().enumerate() {
            let nearest = tree
                .node_prims(i)
                .iter()
                .filter_map(|&p| g.intersect(p, &ray, f32::INFINITY))
                .map(|h| h.t)
                .fold(f32::INFINITY, f32::min);
            if nearest < f32::INFINITY {
                // A primitive's reported distance may be off (thin triangles), so the test
                // leaves the slack that traversal leaves when it culls.
                let reach = nearest * CULL_SLACK;
                let entry = v.hit(&prepared, &ray, reach);
                assert!(
                    entry.is_some_and(|t| t <= reach),
                    "{name}: node {i} entry {entry:?} but contents hit at {nearest}: {:?} {v:?}",
                    ray.ray
                );
            }
        }
    }
}

fn check_all_volume_promises(s: &TestScene, seed: u64) {
    use prism::accel::volumes::{BoundingSphere, Obb};
    check_volume_promises::<Aabb>(s, "aabb", seed);
    check_volume_promises::<BoundingSphere>(s, "sphere", seed);
    check_volume_promises::<Obb>(s, "obb", seed);
    check_volume_promises::<Dop14>(s, "dop14", seed);
    check_volume_promises::<Dop26>(s, "dop26", seed);
}

/// At unit scale; the long tier adds 1e-3 and 1e3.
#[test]
fn volumes_contain_their_primitives_and_rays_never_miss_them() {
    check_all_volume_promises(&hostile_scene(21, 1.0, Vec3::ZERO), 1);
}

/// A scene whose primitives all lie in one slanted plane: OBB axes degenerate (one zero
/// eigenvalue), k-DOP slabs collapse to zero width along the normal-ish directions.
fn coplanar_scene() -> TestScene {
    let mut rng = Rng::new(9);
    let (u, v) = (
        Vec3::new(1.0, 2.0, 0.5).normalize(),
        Vec3::new(-2.0, 1.0, 0.0).normalize(),
    );
    let origin = Vec3::new(0.3, -0.1, 0.7);
    let mut tris = Vec::new();
    for _ in 0..200 {
        let q = |rng: &mut Rng| origin + rng.range(-2.0, 2.0) * u + rng.range(-2.0, 2.0) * v;
        let a = q(&mut rng);
        tris.push([
            a,
            q(&mut rng),
            if rng.chance(0.1) { a } else { q(&mut rng) },
        ]);
    }
    let mut features: Vec<Vec3> = tris.iter().map(|t| t[0]).collect();
    features.extend(tris.iter().map(|t| (t[0] + t[1] + t[2]) / 3.0));
    let positions = tris.iter().flatten().copied().collect();
    let indices = (0..tris.len() as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let mut geometry = Geometry::default();
    geometry.add_mesh(
        TriangleMesh::new(positions, indices, None, None).unwrap(),
        0,
    );
    let b = AaBox::new(origin - 0.1 * Vec3::ONE, origin + 0.1 * Vec3::ONE);
    TestScene {
        geometry,
        features,
        boxes: vec![b],
    }
}

#[test]
fn degenerate_inputs_coplanar_duplicate_and_single() {
    let flat = coplanar_scene();
    check_all_volume_promises(&flat, 4);
    // One primitive, and many copies of one primitive.
    for copies in [1, 300] {
        let mut g = Geometry::default();
        for _ in 0..copies {
            g.add(Shape::Sphere(Sphere::new(Vec3::new(1.0, 2.0, 3.0), 0.5)), 0);
        }
        let prims: Vec<u32> = (0..copies).collect();
        for v in NodeVolume::ALL {
            let accel = volumes::build(&g, prims.clone(), &BvhOptions::default(), v);
            let mut stats = Stats::default();
            let ray = TraceRay::new(Ray::new(Vec3::new(1.0, 2.0, -3.0), Vec3::Z));
            let h = accel.intersect(&g, &ray, f32::INFINITY, &mut stats);
            assert_eq!(h.map(|h| h.t), Some(5.5), "{v} with {copies} copies");
            assert!(accel.occluded(&g, &ray, 5.6, &mut stats));
            assert!(!accel.occluded(&g, &ray, 5.5, &mut stats));
            let empty = volumes::build(&g, Vec::new(), &BvhOptions::default(), v);
            assert!(empty
                .intersect(&g, &ray, f32::INFINITY, &mut stats)
                .is_none());
        }
    }
}

#[test]
fn dop26_is_never_looser_than_dop14_which_is_never_looser_than_the_box() {
    let s = hostile_scene(31, 1.0, Vec3::new(1.0, -2.0, 0.5));
    let g = &s.geometry;
    let prims: Vec<u32> = (0..g.primitives.len() as u32).collect();
    let bvh = Bvh::build(g, prims, &BvhOptions::default());
    let boxes = VolumeBvh::<Aabb>::from_bvh(g, &bvh, "aabb");
    let d14 = VolumeBvh::<Dop14>::from_bvh(g, &bvh, "dop14");
    let d26 = VolumeBvh::<Dop26>::from_bvh(g, &bvh, "dop26");
    let mut strictly_tighter = 0;
    for ((b, a), c) in boxes.volumes().zip(d14.volumes()).zip(d26.volumes()) {
        // 26 = 14 ∩ six more slabs: the shared slabs are the same.
        for i in 0..7 {
            assert_eq!(a.slab(i), c.slab(i));
        }
        // Along each 14-DOP direction, the slab lies within the box's extent (up to the
        // relative padding every volume carries).
        let scale = b.min.abs().max(b.max.abs()).max_element();
        for i in 0..7 {
            let n = volumes::kdop::DIRECTIONS[i];
            let box_hi: f32 = (0..3).map(|k| (n[k] * b.min[k]).max(n[k] * b.max[k])).sum();
            let box_lo: f32 = (0..3).map(|k| (n[k] * b.min[k]).min(n[k] * b.max[k])).sum();
            let (lo, hi) = a.slab(i);
            let pad = 1e-5 * scale * 3.0;
            assert!(
                lo >= box_lo - pad && hi <= box_hi + pad,
                "{i}: {lo} {hi} vs box {box_lo} {box_hi}"
            );
            strictly_tighter += (i >= 3 && (lo > box_lo + pad || hi < box_hi - pad)) as usize;
        }
    }
    assert!(
        strictly_tighter > 0,
        "the diagonal slabs never cut a corner"
    );
}

mod hulls {
    use super::Rng;
    use glam::DVec3;
    use prism::accel::volumes::hull::{convex_hull, ConvexHull};

    /// Every point on the inner side of every hull triangle's plane (up to rounding).
    fn assert_contains_all(hull: &ConvexHull, points: &[DVec3]) {
        let scale = points
            .iter()
            .fold(0.0f64, |m, p| m.max(p.abs().max_element()));
        for t in &hull.triangles {
            let [a, b, c] = t.map(|i| points[i]);
            let n = (b - a).cross(c - a).normalize();
            for p in points {
                assert!(n.dot(*p - a) <= 1e-9 * scale, "{p:?} outside {t:?}");
            }
        }
        for f in hull.faces(points) {
            for p in points {
                assert!(f.normal.dot(*p) <= f.offset);
            }
        }
    }

    fn cube_corners(scale: f64, offset: DVec3) -> Vec<DVec3> {
        (0..8)
            .map(|i| {
                offset + scale * DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, (i >> 2) as f64)
            })
            .collect()
    }

    #[test]
    fn a_cube_has_six_faces_of_two_triangles() {
        for (scale, offset) in [
            (1.0, DVec3::ZERO),
            (1e-3, DVec3::splat(5.0)),
            (1e3, DVec3::ZERO),
        ] {
            let p = cube_corners(scale, offset);
            let h = convex_hull(&p).unwrap();
            assert_eq!(h.triangles.len(), 12, "scale {scale}");
            assert_eq!(h.faces(&p).len(), 6, "scale {scale}");
            assert_contains_all(&h, &p);
        }
    }

    #[test]
    fn duplicates_and_points_on_faces_and_edges_change_nothing() {
        let mut rng = Rng::new(3);
        let mut p = cube_corners(2.0, DVec3::new(-1.0, 0.5, 3.0));
        let corners = p.clone();
        for _ in 0..4 {
            p.extend(corners.iter().copied());
        }
        for _ in 0..200 {
            // On a face (one coordinate at a bound), on an edge (two), or inside.
            let mut q = DVec3::new(
                rng.range(-1.0, 1.0) as f64,
                rng.range(0.5, 2.5) as f64,
                rng.range(3.0, 5.0) as f64,
            );
            for k in 0..rng.below(3) {
                let axis = (k + rng.below(3)) % 3;
                q[axis] = if rng.chance(0.5) {
                    corners[0][axis]
                } else {
                    corners[7][axis]
                };
            }
            p.push(q);
        }
        let h = convex_hull(&p).unwrap();
        assert_eq!(h.faces(&p).len(), 6);
        assert_contains_all(&h, &p);
        // Hull vertices are corners or lie on the cube's surface (a face point may be kept
        // as a vertex inside a face); either way the faces are the cube's six.
        for i in h.triangles.iter().flatten() {
            let q = p[*i];
            let on_surface = (0..3).any(|k| q[k] == corners[0][k] || q[k] == corners[7][k]);
            assert!(on_surface, "hull vertex {q:?} is inside the cube");
        }
    }

    #[test]
    fn random_points_in_a_ball_are_all_inside_their_hull() {
        let mut rng = Rng::new(5);
        for (n, scale) in [(50, 1.0), (2000, 1e-3), (2000, 1e3)] {
            let p: Vec<DVec3> = (0..n)
                .map(|_| {
                    let u = rng.unit_vector() * rng.f32().cbrt();
                    u.as_dvec3() * scale + DVec3::splat(scale * 0.3)
                })
                .collect();
            let h = convex_hull(&p).unwrap();
            assert_contains_all(&h, &p);
            // Euler: a triangulated sphere has 2V − 4 faces.
            let mut used: Vec<usize> = h.triangles.iter().flatten().copied().collect();
            used.sort();
            used.dedup();
            assert_eq!(h.triangles.len(), 2 * used.len() - 4);
        }
    }

    #[test]
    fn flat_point_sets_have_no_hull() {
        let mut rng = Rng::new(6);
        let (u, v) = (DVec3::new(1.0, 2.0, 0.5), DVec3::new(-2.0, 1.0, 0.0));
        let p: Vec<DVec3> = (0..100)
            .map(|_| rng.f32() as f64 * u + rng.f32() as f64 * v)
            .collect();
        assert!(convex_hull(&p).is_none());
        assert!(convex_hull(&p[..3]).is_none());
    }
}

/// Minutes of CPU time between them, so the README's test command leaves them out:
/// `cargo test --release -- --ignored long_tier` runs them (.ci/run does).
mod long_tier {
    use super::*;

    #[test]
    #[ignore = "long tier: every volume's promises at 1e-3 and 1e3"]
    fn volumes_contain_their_primitives_and_rays_never_miss_them_at_every_scale() {
        check_all_volume_promises(&hostile_scene(22, 1e-3, Vec3::splat(2e-3)), 2);
        check_all_volume_promises(&hostile_scene(23, 1e3, Vec3::new(-3e3, 5e3, 1e3)), 3);
    }
}
