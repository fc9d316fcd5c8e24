//! Every accelerator against the brute-force oracle: 10⁵ random rays over several random
//! scenes must find the same nearest hit and give the same any-hit answer, for every
//! `AccelKind` and several build settings; built-in scenes render identically with each.
//!
//! The scenes are hostile on purpose: long thin and degenerate triangles, duplicated and
//! nested primitives, boxes that share faces, far-from-origin and tiny coordinates. The rays
//! too: from inside boxes, along axes (with zero direction components of both signs), lying
//! in the planes of box faces, grazing spheres and aimed at vertices and edges.

use crate::common;

use common::oracle::{
    random_cone, random_degenerates, random_ray, random_slivers, random_triangles, same_nearest,
    TestScene,
};
use common::{film_bits, icosphere, lattice_cube, rotate, trace_ray, Rng};
use prism::accel::{
    Accel, AccelKind, AccelSpec, BruteForce, Bvh, BvhBuilder, BvhOptions, Grid, GridOptions,
    KdTree, KdTreeOptions, NodeWidth, Octree, OctreeOptions, SceneIntersector,
};
use prism::geometry::{generate, AaBox, Geometry, Plane, Shape, Sphere};
use prism::math::{TraceRay, Vec3};
use prism::Stats;

/// Rays per scene; five scenes make the 10⁵ of the suite.
const RAYS: usize = 20_000;

/// Triangles of every shape, spheres (some nested, some overlapping), boxes, cones and
/// cylinders, and exact duplicates, inside `[-2, 2]³·scale + offset`.
fn mixed_scene(seed: u64, scale: f32, offset: Vec3) -> TestScene {
    let mut rng = Rng::new(seed);
    let mut s = TestScene::new();
    let p = |rng: &mut Rng| offset + scale * rng.point_in(Vec3::splat(-2.0), Vec3::splat(2.0));
    let mut tris = random_triangles(&mut rng, 250, p, |rng| scale * rng.range(0.01, 0.8));
    tris.extend(random_slivers(&mut rng, 60, scale, p));
    tris.extend(random_degenerates(&mut rng, 30, p));
    let duplicates: Vec<[Vec3; 3]> = tris.iter().step_by(17).copied().collect();
    tris.extend(duplicates);
    s.add_triangles(&tris);

    for _ in 0..120 {
        let c = p(&mut rng);
        let r = scale * rng.range(0.02, 0.6);
        let sphere = Sphere::new(c, r);
        s.geometry.add(Shape::Sphere(sphere), 0);
        s.features.push(c + r * rng.unit_vector());
        if rng.chance(0.15) {
            // A nested, inside-out or overlapping companion.
            let inner = Sphere {
                center: c + 0.1 * r * rng.unit_vector(),
                radius: r * rng.range(0.3, 1.2),
                inside_out: rng.chance(0.5),
            };
            s.geometry.add(Shape::Sphere(inner), 0);
        }
        if rng.chance(0.05) {
            s.geometry.add(Shape::Sphere(sphere), 0);
        }
    }
    for _ in 0..60 {
        let a = p(&mut rng);
        let b = a + scale
            * Vec3::new(
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
                rng.range(0.0, 1.0),
            );
        s.add_box(AaBox::new(a, b));
    }
    // Two boxes sharing a face exactly, and a flat box.
    let a = p(&mut rng);
    let (mid, far) = (
        a + scale * Vec3::splat(0.5),
        a + scale * Vec3::new(1.0, 0.5, 0.5),
    );
    s.add_box(AaBox::new(a, mid));
    s.add_box(AaBox::new(Vec3::new(mid.x, a.y, a.z), far));
    s.add_box(AaBox::new(a, Vec3::new(mid.x, a.y, mid.z)));
    for _ in 0..60 {
        let base = p(&mut rng);
        if let Some((c, rim)) = random_cone(&mut rng, base, scale) {
            s.geometry.add(Shape::from(c), 0);
            s.features.push(rim);
        }
    }
    s
}

/// Boxes stacked on an integer lattice (sharing faces) and axis-aligned quads at integer
/// coordinates: the home of rays lying exactly in slab planes.
fn lattice_scene() -> TestScene {
    let mut rng = Rng::new(77);
    let mut s = TestScene::new();
    for x in 0..6 {
        for y in 0..3 {
            for z in 0..6 {
                if rng.chance(0.35) {
                    let a = Vec3::new(x as f32, y as f32, z as f32);
                    s.add_box(AaBox::new(a, a + Vec3::ONE));
                }
            }
        }
    }
    for _ in 0..80 {
        let a = Vec3::new(
            rng.below(7) as f32,
            rng.below(4) as f32,
            rng.below(7) as f32,
        );
        let (u, v) = match rng.below(3) {
            0 => (Vec3::X, Vec3::Y),
            1 => (Vec3::Y, Vec3::Z),
            _ => (Vec3::Z, Vec3::X),
        };
        let q = generate::quad(a, a + u, a + u + v, a + v, 1.0, 1.0);
        s.features.extend([a, a + u, a + 0.5 * (u + v)]);
        s.geometry.add_mesh(q, 0);
    }
    for _ in 0..40 {
        let c = Vec3::new(
            rng.below(7) as f32,
            rng.below(4) as f32,
            rng.below(7) as f32,
        );
        s.geometry.add(Shape::Sphere(Sphere::new(c, 0.5)), 0);
        s.features.push(c + Vec3::new(0.5, 0.0, 0.0));
    }
    s
}

/// Closed meshes, overlapping each other, and a dense knot.
fn mesh_scene() -> TestScene {
    let mut s = TestScene::new();
    s.add_mesh(icosphere(Vec3::ZERO, 1.0, 3));
    s.add_mesh(icosphere(Vec3::new(0.7, 0.2, -0.1), 0.6, 2));
    let axis = Vec3::new(1.0, -2.0, 0.5);
    s.add_mesh(lattice_cube(4, |p| {
        rotate(p * 0.8, axis, 0.4) + Vec3::new(-1.0, 0.5, 0.3)
    }));
    s.add_mesh(lattice_cube(3, |p| p * Vec3::new(2.0, 0.1, 2.0) - Vec3::Y));
    s.add_mesh(generate::torus_knot(3000));
    s
}

fn bvh_settings() -> Vec<(String, BvhOptions)> {
    let mut settings = vec![
        ("default".to_string(), BvhOptions::default()),
        (
            "one primitive per leaf".to_string(),
            BvhOptions {
                max_leaf_size: 1,
                ..BvhOptions::default()
            },
        ),
        (
            "two bins, big leaves".to_string(),
            BvhOptions {
                bins: 2,
                max_leaf_size: 32,
                traversal_cost: 4.0,
                ..BvhOptions::default()
            },
        ),
    ];
    // Every builder with and without reinsertion, with subtrees of more than 16 primitives
    // built in parallel so the stitching of subtrees is exercised too; and LBVH, whose
    // trees reinsertion changes most, also with one primitive per leaf.
    for builder in BvhBuilder::ALL {
        for reinsert in [false, true] {
            let options = BvhOptions {
                builder,
                reinsert,
                parallel_threshold: 16,
                ..BvhOptions::default()
            };
            let name = format!(
                "{}{}",
                builder.name(),
                if reinsert { " + reinsert" } else { "" }
            );
            settings.push((name, options));
        }
    }
    // The 4-wide SSE layout too (the default is 8-wide where the CPU has AVX2).
    settings.push((
        "binned, 4-wide".to_string(),
        BvhOptions {
            width: NodeWidth::Four,
            ..BvhOptions::default()
        },
    ));
    let fine_lbvh = BvhOptions {
        builder: BvhBuilder::Lbvh,
        reinsert: true,
        max_leaf_size: 1,
        ..BvhOptions::default()
    };
    settings.push((
        "lbvh + reinsert, one primitive per leaf".to_string(),
        fine_lbvh,
    ));
    // Pre-split triangles: duplicate references with tight boxes, generously and with
    // one reference per leaf.
    for (presplit, max_leaf_size) in [(1.0, 8), (4.0, 1)] {
        settings.push((
            format!("pre-split {presplit}, leaves of {max_leaf_size}"),
            BvhOptions {
                presplit,
                max_leaf_size,
                ..BvhOptions::default()
            },
        ));
    }
    settings
}

fn check_against_brute_force(name: &str, s: &TestScene, seed: u64) {
    let g = &s.geometry;
    let prims: Vec<u32> = (0..g.primitives.len() as u32).collect();
    let brute = BruteForce::new(prims.clone());
    let mut accels: Vec<(String, Box<dyn Accel>)> = Vec::new();
    for (n, o) in bvh_settings() {
        let bvh = Bvh::build(g, prims.clone(), &o);
        // Pre-splitting lists a primitive more than once; none may be missing.
        assert_eq!(bvh.info().primitives, prims.len(), "{name}/{n}: prims lost");
        accels.push((format!("bvh {n}"), Box::new(bvh)));
    }
    // Every other method with its default settings, and the spatial subdivisions also with
    // extreme ones: cells far bigger and far smaller than the primitives.
    for kind in AccelKind::ALL {
        if !matches!(kind, AccelKind::BruteForce | AccelKind::Bvh) {
            accels.push((kind.name().to_string(), kind.build(g, prims.clone())));
        }
    }
    for lambda in [0.3, 12.0] {
        let options = GridOptions {
            lambda,
            ..GridOptions::default()
        };
        let grid = Grid::build(g, prims.clone(), &options);
        accels.push((format!("grid λ = {lambda}"), Box::new(grid)));
    }
    let shallow_kd = KdTreeOptions {
        max_depth: 4,
        empty_bonus: 0.0,
        ..KdTreeOptions::default()
    };
    let deep_kd = KdTreeOptions {
        intersection_cost: 20.0,
        empty_bonus: 0.9,
        ..KdTreeOptions::default()
    };
    for (n, o) in [("shallow", shallow_kd), ("deep", deep_kd)] {
        let kd = KdTree::build(g, prims.clone(), &o);
        accels.push((format!("kdtree {n}"), Box::new(kd)));
    }
    let fine_octree = OctreeOptions {
        max_leaf_size: 1,
        max_depth: 9,
    };
    let octree = Octree::build(g, prims.clone(), &fine_octree);
    accels.push(("octree, one per leaf".into(), Box::new(octree)));
    for (n, a) in &accels {
        assert_eq!(a.info().primitives, prims.len(), "{name}/{n}: prims lost");
    }
    let bounds = g.world_bounds();
    let diag = bounds.extent().length();
    let mut rng = Rng::new(seed);
    let mut stats = Stats::default();
    let (mut hits, mut ties, mut occluded) = (0, 0, 0);
    for i in 0..RAYS {
        let ray = random_ray(&mut rng, s, &bounds);
        let tr = TraceRay::new(ray);
        let t_max = if rng.chance(0.7) {
            f32::INFINITY
        } else {
            rng.range(0.0, diag)
        };
        let expected = brute.intersect(g, &tr, t_max, &mut stats);
        hits += expected.is_some() as usize;
        // Any-hit bounds that straddle the nearest hit: exactly at it, or a hair either
        // side. The hair must exceed the rounding of a primitive's own t, which is relative
        // to the primitive's extent and coordinates (pbrt's δt), not to t: a ray starting
        // next to a triangle can report t with a large relative error. Bounds inside that
        // band are ties, and the BVH may legitimately cull there.
        let hair = 1e-5 * diag;
        let t_occ = match (expected, rng.below(4)) {
            (Some(h), 0) => h.t,
            (Some(h), 1) => h.t + hair,
            (Some(h), 2) => h.t - hair,
            _ => t_max,
        };
        let blocked = brute.occluded(g, &tr, t_occ, &mut stats);
        occluded += blocked as usize;
        for (setting, accel) in &accels {
            let got = accel.intersect(g, &tr, t_max, &mut stats);
            let ctx = || format!("{name}/{setting}, ray {i}: {ray:?}, t_max {t_max}");
            assert!(
                same_nearest(g, &tr, expected, got),
                "{}: brute force {expected:?}, accelerator {got:?}",
                ctx()
            );
            if let (Some(e), Some(b)) = (expected, got) {
                ties += (e.prim != b.prim) as usize;
            }
            assert_eq!(
                accel.occluded(g, &tr, t_occ, &mut stats),
                blocked,
                "{}: occluded within {t_occ} (brute-force nearest {expected:?})",
                ctx()
            );
        }
    }
    eprintln!(
        "{name}: {RAYS} rays, {} prims, {hits} hits, {occluded} occluded, {ties} ties",
        g.primitives.len()
    );
    // The ray mix must actually exercise both answers.
    assert!(hits > RAYS / 4 && hits < RAYS, "{name}: {hits} hits");
    assert!(
        occluded > RAYS / 10 && occluded < RAYS,
        "{name}: {occluded} occluded"
    );
}

#[test]
fn bvh_matches_brute_force_on_a_mixed_scene() {
    check_against_brute_force("mixed", &mixed_scene(11, 1.0, Vec3::ZERO), 101);
}

#[test]
fn bvh_matches_brute_force_on_a_tiny_scene() {
    check_against_brute_force("tiny", &mixed_scene(12, 1e-3, Vec3::splat(1e-3)), 102);
}

#[test]
fn bvh_matches_brute_force_on_a_huge_offset_scene() {
    let offset = Vec3::new(4e3, -2e3, 1e3);
    check_against_brute_force("huge", &mixed_scene(13, 1e3, offset), 103);
}

#[test]
fn bvh_matches_brute_force_on_a_lattice_scene() {
    check_against_brute_force("lattice", &lattice_scene(), 104);
}

#[test]
fn bvh_matches_brute_force_on_closed_meshes() {
    check_against_brute_force("meshes", &mesh_scene(), 105);
}

#[test]
fn scene_intersector_agrees_across_accelerators_with_planes() {
    // Planes live outside the accelerator; the combined answer must not depend on it.
    let mut s = mixed_scene(14, 1.0, Vec3::ZERO);
    s.geometry.add(
        Shape::from(Plane::new(Vec3::new(0.0, -1.5, 0.0), Vec3::Y).unwrap()),
        0,
    );
    s.geometry.add(
        Shape::from(Plane::new(Vec3::new(0.3, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.2)).unwrap()),
        0,
    );
    let brute = SceneIntersector::build(&s.geometry, &AccelKind::BruteForce.into());
    let others: Vec<_> = AccelKind::ALL[1..]
        .iter()
        .map(|&k| (k, SceneIntersector::build(&s.geometry, &k.into())))
        .collect();
    let bounds = s.geometry.world_bounds();
    let mut rng = Rng::new(106);
    let mut stats = Stats::default();
    let mut plane_hits = 0;
    for _ in 0..5000 {
        let ray = random_ray(&mut rng, &s, &bounds);
        let a = brute.intersect(&s.geometry, &ray, f32::INFINITY, &mut stats);
        for (kind, other) in &others {
            let b = other.intersect(&s.geometry, &ray, f32::INFINITY, &mut stats);
            assert!(
                same_nearest(&s.geometry, &TraceRay::new(ray), a, b),
                "{}: {ray:?}: {a:?} vs {b:?}",
                kind.name()
            );
        }
        if let Some(h) = a {
            plane_hits += matches!(
                s.geometry.primitives[h.prim as usize].shape,
                Shape::Plane(_)
            ) as usize;
            let t = h.t * rng.range(0.5, 1.5);
            let expected = brute.occluded(&s.geometry, &ray, t, &mut stats);
            for (kind, other) in &others {
                assert_eq!(
                    other.occluded(&s.geometry, &ray, t, &mut stats),
                    expected,
                    "{}: {ray:?} occluded within {t}",
                    kind.name()
                );
            }
        }
    }
    assert!(plane_hits > 100, "planes hit only {plane_hits} times");
}

#[test]
fn empty_and_single_primitive_accelerators() {
    for kind in AccelKind::ALL {
        let mut g = Geometry::default();
        let ray = trace_ray(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        let mut stats = Stats::default();
        let empty = kind.build(&g, Vec::new());
        assert!(empty
            .intersect(&g, &ray, f32::INFINITY, &mut stats)
            .is_none());
        assert!(!empty.occluded(&g, &ray, f32::INFINITY, &mut stats));
        g.add(Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0)), 0);
        let one = kind.build(&g, vec![0]);
        let h = one.intersect(&g, &ray, f32::INFINITY, &mut stats).unwrap();
        assert_eq!((h.prim, h.t), (0, 4.0), "{}", kind.name());
        assert!(one.occluded(&g, &ray, 4.5, &mut stats));
        assert!(!one.occluded(&g, &ray, 4.0, &mut stats));
    }
}

#[test]
fn bvh_handles_many_coincident_primitives() {
    // 500 copies of one sphere: no split can separate their centroids, leaves must still
    // stay bounded and every query still answer.
    let mut g = Geometry::default();
    for _ in 0..500 {
        g.add(Shape::Sphere(Sphere::new(Vec3::splat(1.0), 0.5)), 0);
    }
    let bvh = Bvh::build(&g, (0..500).collect(), &BvhOptions::default());
    assert_eq!(bvh.primitive_count(), 500);
    let mut stats = Stats::default();
    let ray = trace_ray(Vec3::new(1.0, 1.0, -3.0), Vec3::Z);
    assert_eq!(
        bvh.intersect(&g, &ray, f32::INFINITY, &mut stats)
            .map(|h| h.t),
        Some(3.5)
    );
}

#[test]
fn every_accelerator_handles_many_coincident_primitives() {
    // No subdivision can separate 500 copies of one sphere; builds must stop anyway.
    let mut g = Geometry::default();
    for _ in 0..500 {
        g.add(Shape::Sphere(Sphere::new(Vec3::splat(1.0), 0.5)), 0);
    }
    let ray = trace_ray(Vec3::new(1.0, 1.0, -3.0), Vec3::Z);
    for kind in AccelKind::ALL {
        let accel = kind.build(&g, (0..500).collect());
        let mut stats = Stats::default();
        let t = accel.intersect(&g, &ray, f32::INFINITY, &mut stats);
        assert_eq!(t.map(|h| h.t), Some(3.5), "{}", kind.name());
        // Mailboxing: each copy is tested at most once.
        assert!(stats.primitive_tests <= 500, "{}", kind.name());
    }
}

#[test]
fn built_in_scenes_render_identically_with_every_accelerator() {
    use prism::render::render;
    use prism::scene::builtin;
    use std::sync::atomic::AtomicBool;
    for name in ["whitted", "cornell", "sphereflake:2"] {
        let scene = builtin::find(name).unwrap();
        let options = prism::RenderOptions {
            width: 64,
            height: 48,
            samples: 1,
            ..scene.options.clone()
        };
        let image = |spec: AccelSpec| {
            let prepared = scene.prepare(&spec);
            let r = render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap();
            film_bits(&r.film)
        };
        let reference = image(AccelKind::BruteForce.into());
        let mut specs: Vec<AccelSpec> = AccelKind::ALL[1..].iter().map(|&k| k.into()).collect();
        for builder in BvhBuilder::ALL {
            for reinsert in [false, true] {
                specs.push(AccelSpec::Bvh(BvhOptions {
                    builder,
                    reinsert,
                    ..BvhOptions::default()
                }));
            }
        }
        specs.push("bvh:split=2".parse().unwrap());
        specs.push("bvh:width=4".parse().unwrap());
        specs.push("bvh:rays=inside".parse().unwrap());
        specs.push("bvh:rays=inside,trav=3".parse().unwrap());
        for volume in ["sphere", "obb", "dop14", "dop26", "hull"] {
            specs.push(format!("bvh:volume={volume}").parse().unwrap());
        }
        for spec in specs {
            assert!(
                image(spec.clone()) == reference,
                "{name}: image with {spec} differs from brute force"
            );
        }
    }
}
