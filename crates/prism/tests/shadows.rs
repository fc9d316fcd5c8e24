//! Shadow methods against the oracle: a light buffer must answer every shadow ray exactly
//! as the scene's accelerator does (the same any-hit answer, the same nearest hit for the
//! walk through transparent surfaces), for lights inside the scene, on a surface and far
//! away, and directional lights, for shading points on surfaces and in free space, for
//! directions on cell borders and cube edges, at 1, 10⁻³ and 10³ scale, over 8- and 4-wide BVHs and one of a single
//! leaf; and every method renders the same image.

use crate::common;

use common::oracle::{random_ray, random_triangles, TestScene};
use common::{icosphere, Rng};
use prism::accel::{AccelSpec, Hit, QueryMode, SceneIntersector};
use prism::geometry::{AaBox, Geometry, Plane, Shape, Sphere};
use prism::integrator::{BufferParams, LightBuffer, ShadowSpec};
use prism::math::robust::offset_ray_origin;
use prism::math::{Aabb, Ray, Vec3};
use prism::render::render;
use prism::scene::builtin;
use prism::Stats;
use std::sync::atomic::AtomicBool;

/// Shading points per light.
const POINTS: usize = 4_000;

/// Triangles, spheres, boxes, an icosphere and a floor plane in [-2, 2]³·scale + offset.
fn scene(seed: u64, scale: f32, offset: Vec3) -> TestScene {
    let mut rng = Rng::new(seed);
    let mut s = TestScene::new();
    let p = |rng: &mut Rng| offset + scale * rng.point_in(Vec3::splat(-2.0), Vec3::splat(2.0));
    let tris = random_triangles(&mut rng, 150, p, |rng| scale * rng.range(0.01, 0.8));
    s.add_triangles(&tris);
    for _ in 0..40 {
        let c = p(&mut rng);
        let r = scale * rng.range(0.02, 0.4);
        s.geometry.add(Shape::Sphere(Sphere::new(c, r)), 0);
        s.features.push(c + r * rng.unit_vector());
    }
    for _ in 0..10 {
        let a = p(&mut rng);
        let b = a + scale * rng.point_in(Vec3::splat(0.05), Vec3::splat(0.8));
        s.add_box(AaBox::new(a.min(b), a.max(b)));
    }
    s.add_mesh(icosphere(offset, 0.7 * scale, 2));
    s.geometry.add(
        Shape::Plane(Box::new(
            Plane::new(offset - Vec3::Y * 2.5 * scale, Vec3::Y).unwrap(),
        )),
        0,
    );
    s
}

/// A shading point: a hit of a random ray (with its surface's normal), or a point in free
/// space (with a random normal).
fn shading_point(
    rng: &mut Rng,
    s: &TestScene,
    intersector: &SceneIntersector,
    b: &Aabb,
) -> (Vec3, Vec3, Vec3) {
    if rng.chance(0.75) {
        for _ in 0..8 {
            let ray = random_ray(rng, s, b);
            let mut stats = Stats::default();
            if let Some(hit) = intersector.intersect(&s.geometry, &ray, f32::INFINITY, &mut stats) {
                let sp = s.geometry.surface(hit.prim, &ray, &hit.shape_hit());
                return (sp.p, sp.p_error, sp.ng);
            }
        }
    }
    let p = rng.point_in(b.min, b.max);
    (p, Vec3::ZERO, rng.unit_vector())
}

/// Points seen from `light` along cube edges and cell borders of a `res` buffer.
fn border_points(rng: &mut Rng, light: Vec3, reach: f32, res: u32) -> Vec<Vec3> {
    let mut out = Vec::new();
    for _ in 0..200 {
        let t = rng.range(-1.0, 1.0);
        let border = 2.0 * rng.below(res as usize + 1) as f32 / res as f32 - 1.0;
        let mut d = match rng.below(3) {
            0 => Vec3::new(1.0, 1.0, t),     // a cube edge
            1 => Vec3::new(1.0, border, t),  // a cell border on the +x face
            _ => Vec3::new(border, t, -1.0), // one on the −z face
        };
        if rng.chance(0.5) {
            d = -d;
        }
        out.push(light + d.normalize() * reach * rng.range(0.01, 1.0));
    }
    out
}

/// Whether `ray` (towards the light, `distance` long) is blocked, once the buffer has
/// answered it as the accelerator does in both query modes (the buffer's counts go to
/// `stats`).
fn agrees(
    buffer: &LightBuffer,
    g: &Geometry,
    intersector: &SceneIntersector,
    ray: &Ray,
    distance: f32,
    stats: &mut Stats,
    what: &str,
) -> bool {
    let any = buffer.query(g, intersector, ray, distance, QueryMode::Any, stats);
    let blocked = intersector.occluded(g, ray, distance, &mut Stats::default());
    assert_eq!(any.is_some(), blocked, "{what}");
    let nearest = buffer.query(g, intersector, ray, distance, QueryMode::Nearest, stats);
    let expected = intersector.intersect(g, ray, distance, &mut Stats::default());
    assert_eq!(nearest, expected, "{what}");
    blocked
}

/// The buffer's packet answers for `rays` (each with its distance and the accelerator's
/// answers: whether it is blocked, its nearest hit), in packets of 64 in the given order and
/// of 7 (a packet's rays spread over many cells, and a last packet of fewer), against the
/// accelerator's: any-hit and nearest-hit packets.
fn check_packets(
    buffer: &LightBuffer,
    g: &Geometry,
    intersector: &SceneIntersector,
    rays: &[(Ray, f32, bool, Option<Hit>)],
    what: &str,
) {
    for size in [64, 7] {
        for (k, chunk) in rays.chunks(size).enumerate() {
            let packet: Vec<Ray> = chunk.iter().map(|r| r.0).collect();
            let t_max: Vec<f32> = chunk.iter().map(|r| r.1).collect();
            let mut any = vec![None; chunk.len()];
            let mut nearest = vec![None; chunk.len()];
            let mut stats = Stats::default();
            buffer.any_hit_packet(g, intersector, &packet, &t_max, &mut any, &mut stats);
            buffer.nearest_packet(g, intersector, &packet, &t_max, &mut nearest, &mut stats);
            for (i, r) in chunk.iter().enumerate() {
                let at = format!("{what}: packet {k} of {size}, ray {i} ({:?})", r.0);
                assert_eq!(any[i].is_some(), r.2, "{at}: any-hit packet {:?}", any[i]);
                assert_eq!(nearest[i], r.3, "{at}: nearest-hit packet");
            }
            assert_eq!(stats.light_buffer_queries, 2 * chunk.len() as u64);
        }
    }
}

/// A buffer of `res` cells a side, within a generous budget.
fn params(res: u32) -> BufferParams {
    BufferParams {
        res,
        budget_bytes: 1 << 30,
    }
}

/// Every shadow ray towards `light` gets the same answers from the buffer and from the
/// accelerator.
fn check_light(
    s: &TestScene,
    intersector: &SceneIntersector,
    light: Vec3,
    res: u32,
    seed: u64,
) -> (usize, usize) {
    let g = &s.geometry;
    let buffers =
        [LightBuffer::build(intersector, light, &params(res)).expect("within the budget")];
    assert!(!buffers[0].info().orthographic);
    let bounds = (0..g.primitives.len() as u32)
        .filter_map(|i| g.bounds(i))
        .fold(Aabb::EMPTY, |a, b| a.union(&b));
    let mut rng = Rng::new(seed);
    let mut points: Vec<(Vec3, Vec3, Vec3)> = (0..POINTS)
        .map(|_| shading_point(&mut rng, s, intersector, &bounds))
        .collect();
    let reach = bounds.extent().length();
    // Points behind vertices, edge midpoints and box corners as the light sees them: their
    // shadow rays pass exactly over a primitive's outline, at the edge of its footprint.
    for _ in 0..POINTS / 2 {
        let f = s.features[rng.below(s.features.len())];
        let p = light + (f - light) * rng.range(1.001, 3.0);
        points.push((p, Vec3::ZERO, rng.unit_vector()));
    }
    points.extend(
        border_points(&mut rng, light, reach, res)
            .into_iter()
            .map(|p| (p, Vec3::ZERO, Vec3::Y)),
    );
    let mut blocked = 0;
    let total = points.len();
    let mut answered = Vec::new();
    for (p, p_error, n) in points {
        let d = light - p;
        let distance = d.length();
        if distance.is_nan() || distance <= 0.0 {
            continue;
        }
        let dir = d / distance;
        let ng = if n.dot(dir) < 0.0 { -n } else { n };
        let ray = Ray::new(offset_ray_origin(p, p_error, ng, dir), dir);
        let mut stats = Stats::default();
        let occluded = intersector.occluded(g, &ray, distance, &mut stats);
        let expected = intersector.intersect(g, &ray, distance, &mut stats);
        for buffer in &buffers {
            let any = buffer.query(g, intersector, &ray, distance, QueryMode::Any, &mut stats);
            assert_eq!(
                any.is_some(),
                occluded,
                "light {light}, point {p}: the buffer says {any:?}, the accelerator {occluded}"
            );
            let nearest = buffer.query(
                g,
                intersector,
                &ray,
                distance,
                QueryMode::Nearest,
                &mut stats,
            );
            assert_eq!(
                nearest, expected,
                "light {light}, point {p}: nearest hits differ"
            );
        }
        blocked += occluded as usize;
        answered.push((ray, distance, occluded, expected));
    }
    let what = format!("light {light}, res {res}");
    check_packets(&buffers[0], g, intersector, &answered, &what);
    // As a render gathers them: rays of neighbouring points, in the order of their cells.
    answered.sort_by(|a, b| {
        let key = |r: &Ray| (r.dir.x.to_bits(), r.dir.y.to_bits());
        key(&a.0).cmp(&key(&b.0))
    });
    check_packets(&buffers[0], g, intersector, &answered, &what);
    (blocked, total)
}

/// The buffer against the accelerator over the BVH `accel` names (its cells hold that
/// tree's subtrees, in its layout).
fn check_scene(scale: f32, offset: Vec3, seed: u64) {
    for accel in ["bvh", "bvh:width=4", "bvh:leaf=1"] {
        check_scene_with(scale, offset, seed, accel);
    }
}

fn check_scene_with(scale: f32, offset: Vec3, seed: u64, accel: &str) {
    let s = scene(seed, scale, offset);
    let spec: AccelSpec = accel.parse().unwrap();
    let intersector = SceneIntersector::build(&s.geometry, &spec);
    let mut rng = Rng::new(seed ^ 0x5eed);
    let lights = [
        // Inside the scene's bounds.
        offset + scale * rng.point_in(Vec3::splat(-1.5), Vec3::splat(1.5)),
        // On a surface: a triangle vertex, a box corner, a sphere's surface.
        s.features[rng.below(s.features.len())],
        s.features[rng.below(s.features.len())],
        // Far away.
        offset + scale * 1e3 * Vec3::new(0.3, 1.0, 0.2),
        // Above, as a lamp over a table.
        offset + scale * Vec3::new(0.1, 4.0, -0.3),
    ];
    let (mut blocked, mut total) = (0, 0);
    for (i, &light) in lights.iter().enumerate() {
        for res in [
            8,
            64,
            LightBuffer::auto_resolution(s.geometry.primitives.len()),
        ] {
            let seed = seed + i as u64 * 31 + res as u64;
            let (b, t) = check_light(&s, &intersector, light, res, seed);
            blocked += b;
            total += t;
        }
    }
    // Both answers occur often, or the test would prove little.
    assert!(
        blocked > total / 10 && blocked < total - total / 10,
        "{blocked} of {total} shadow rays blocked"
    );
}

/// The 8-wide BVH at unit scale; the long tier adds the other layouts, an offset scene
/// and the extreme scales.
#[test]
fn the_light_buffer_answers_as_the_accelerator() {
    check_scene_with(1.0, Vec3::ZERO, 1, "bvh");
}

/// A directional light's buffer against the accelerator: shadow rays along `to_light`
/// from shading points, from points behind the primitives' outlines (vertices, box
/// corners, sphere points) as the light sees them, and from points so far away that the
/// buffer must hand them to the BVH. Returns (blocked, rays, rays the buffer answered).
fn check_directional(
    s: &TestScene,
    intersector: &SceneIntersector,
    to_light: Vec3,
    res: u32,
    seed: u64,
) -> (usize, usize, u64) {
    let g = &s.geometry;
    let buffer = LightBuffer::build_directional(intersector, to_light, &params(res))
        .expect("within the budget");
    let info = buffer.info();
    assert!(info.orthographic && info.resolution == res && info.cells == 1 + (res * res) as usize);
    let bounds = (0..g.primitives.len() as u32)
        .filter_map(|i| g.bounds(i))
        .fold(Aabb::EMPTY, |a, b| a.union(&b));
    let reach = bounds.extent().length();
    let mut rng = Rng::new(seed);
    let mut points: Vec<(Vec3, Vec3, Vec3)> = (0..POINTS)
        .map(|_| shading_point(&mut rng, s, intersector, &bounds))
        .collect();
    for _ in 0..POINTS / 2 {
        let f = s.features[rng.below(s.features.len())];
        // The ray from p along to_light passes exactly over f.
        let p = f - to_light * reach * rng.range(1e-3, 2.0);
        points.push((p, Vec3::ZERO, rng.unit_vector()));
    }
    for _ in 0..50 {
        let f = s.features[rng.below(s.features.len())];
        points.push((f - to_light * reach * 1e4, Vec3::ZERO, Vec3::Y));
    }
    let (mut blocked, mut stats) = (0, Stats::default());
    let mut answered = Vec::new();
    for &(p, p_error, n) in &points {
        let ng = if n.dot(to_light) < 0.0 { -n } else { n };
        let ray = Ray::new(offset_ray_origin(p, p_error, ng, to_light), to_light);
        let what = format!("direction {to_light}, point {p}, res {res}");
        let b = agrees(
            &buffer,
            g,
            intersector,
            &ray,
            f32::INFINITY,
            &mut stats,
            &what,
        );
        blocked += b as usize;
        let nearest = intersector.intersect(g, &ray, f32::INFINITY, &mut Stats::default());
        answered.push((ray, f32::INFINITY, b, nearest));
    }
    let what = format!("direction {to_light}, res {res}");
    check_packets(&buffer, g, intersector, &answered, &what);
    // Each ray asked twice (any and nearest).
    let answered = (stats.light_buffer_queries - stats.light_buffer_fallbacks) / 2;
    (blocked, points.len(), answered)
}

fn check_directional_scene(scale: f32, offset: Vec3, seed: u64) {
    check_directional_with(scale, offset, seed, &["bvh", "bvh:width=4", "bvh:leaf=1"]);
}

fn check_directional_with(scale: f32, offset: Vec3, seed: u64, accels: &[&str]) {
    let mut rng = Rng::new(seed ^ 0xd1);
    let mut directions = vec![
        Vec3::Y,
        -Vec3::Y,
        Vec3::X,
        -Vec3::Z,
        Vec3::ONE.normalize(),
        Vec3::new(1e-7, 1.0, -1e-7).normalize(),
        Vec3::new(0.0, 0.6, 0.8),
    ];
    directions.extend((0..3).map(|_| rng.unit_vector()));
    for accel in accels {
        let s = scene(seed, scale, offset);
        let intersector = SceneIntersector::build(&s.geometry, &accel.parse().unwrap());
        let (mut blocked, mut total, mut answered) = (0, 0, 0);
        for (i, &d) in directions.iter().enumerate() {
            for res in [1, 8, 64] {
                let (b, t, a) = check_directional(&s, &intersector, d, res, seed + i as u64);
                blocked += b;
                total += t;
                answered += a;
            }
        }
        // Both answers occur often, and the buffer (not the BVH it falls back to) gave
        // nearly all of them, or the test would prove little.
        assert!(
            blocked > total / 10 && blocked < total - total / 10,
            "{accel}: {blocked} of {total} shadow rays blocked"
        );
        assert!(
            answered as usize > total * 9 / 10,
            "{accel}: the buffer answered {answered} of {total}"
        );
    }
}

/// The 8-wide BVH at unit scale; the long tier adds the rest, as for point lights.
#[test]
fn the_directional_light_buffer_answers_as_the_accelerator() {
    check_directional_with(1.0, Vec3::ZERO, 21, &["bvh"]);
}

#[test]
fn a_budget_too_small_refuses_the_buffer() {
    let s = scene(5, 1.0, Vec3::ZERO);
    let intersector = SceneIntersector::build(&s.geometry, &AccelSpec::default());
    let small = BufferParams {
        res: 64,
        budget_bytes: 64,
    };
    let err = LightBuffer::build(&intersector, Vec3::ZERO, &small);
    assert!(err.is_err(), "64 bytes cannot hold the cells");
}

/// Another accelerator has no subtrees for cells to hold: no buffer, and `Shadows` says why.
#[test]
fn a_buffer_needs_a_bvh() {
    let s = scene(6, 1.0, Vec3::ZERO);
    let intersector = SceneIntersector::build(&s.geometry, &"grid".parse().unwrap());
    assert!(LightBuffer::build(&intersector, Vec3::ZERO, &params(8)).is_err());
}

/// A tree whose root is a leaf (a few primitives) has no wide node: its cells hold the
/// root leaf itself, and answer as the accelerator does, at every scale.
#[test]
fn a_tree_of_one_leaf_answers_as_the_accelerator() {
    for scale in [1e-3f32, 1.0, 1e3] {
        let mut s = TestScene::new();
        s.add_box(AaBox::new(
            Vec3::new(-1.0, -1.0, 2.0) * scale,
            Vec3::new(1.0, 1.0, 3.0) * scale,
        ));
        let g = &s.geometry;
        let intersector = SceneIntersector::build(g, &AccelSpec::default());
        let buffer = LightBuffer::build(&intersector, Vec3::ZERO, &params(4)).unwrap();
        let mut rng = Rng::new(11);
        let mut blocked = 0;
        for _ in 0..2000 {
            let p = rng.point_in(Vec3::splat(-4.0), Vec3::splat(4.0)) * scale;
            let d = -p;
            let distance = d.length();
            let ray = Ray::new(p, d / distance);
            let mut stats = Stats::default();
            let what = format!("scale {scale}, point {p}");
            blocked += agrees(&buffer, g, &intersector, &ray, distance, &mut stats, &what) as usize;
        }
        assert!(blocked > 50, "scale {scale}: {blocked} blocked");
    }
}

/// The cache in packets: the blocker remembered for a light and depth answers the next
/// packet's rays it blocks; afterwards the last ray's blocker is remembered, or nothing
/// where the last ray is unblocked; depths keep their own; a tile starts empty.
#[test]
fn the_cache_answers_packets_with_the_last_rays_blocker() {
    let mut scene = prism::scene::Scene::default();
    let material = scene.add_material(prism::shading::Material::default());
    // Two spheres above a row of points, under a light high above.
    for x in [-2.0, 2.0] {
        let sphere = Sphere::new(Vec3::new(x, 5.0, 0.0), 1.0);
        scene.geometry.add(Shape::Sphere(sphere), material);
    }
    let light = Vec3::new(0.0, 1e3, 0.0);
    scene.lights = vec![prism::light::Light::Point {
        position: light,
        color: prism::math::Color::ONE,
    }];
    let prepared = scene.prepare(&AccelSpec::default());
    let shadows = prism::integrator::Shadows::new(&prepared, "cache".parse().unwrap());
    // Eight rays from points under the sphere at `x` (or in the open, far off), the last
    // one from `last_x`.
    let packet = |x: f32, last_x: f32| -> (Vec<Ray>, Vec<f32>) {
        (0..8)
            .map(|k| {
                let x = if k == 7 { last_x } else { x };
                let p = Vec3::new(x + 0.01 * k as f32, 0.0, 0.0);
                let d = light - p;
                (Ray::new(p, d / d.length()), d.length())
            })
            .unzip()
    };
    let run = |x: f32, last_x: f32, depth: u32| -> (Vec<bool>, u64) {
        let (rays, t_max) = packet(x, last_x);
        let mut blocked = vec![false; rays.len()];
        let mut stats = Stats::default();
        shadows.blocked_packet(0, depth, &rays, &t_max, &mut blocked, &mut stats);
        (blocked, stats.shadow_cache_hits)
    };
    prism::integrator::begin_piece();
    // Nothing remembered yet: every ray walks.
    assert_eq!(run(-2.0, -2.0, 1), (vec![true; 8], 0));
    // The left sphere is remembered: it answers the next packet alone.
    assert_eq!(run(-2.0, -2.0, 1), (vec![true; 8], 8));
    // Under the right sphere, the left one answers nothing; the right one is remembered.
    assert_eq!(run(2.0, 2.0, 1), (vec![true; 8], 0));
    assert_eq!(run(2.0, 2.0, 1), (vec![true; 8], 8));
    // Another depth remembers on its own.
    assert_eq!(run(2.0, 2.0, 2), (vec![true; 8], 0));
    // A packet whose last ray is in the open: the cache answers its seven blocked rays,
    // and forgets the blocker.
    let mut open = vec![true; 8];
    open[7] = false;
    assert_eq!(run(2.0, 40.0, 1), (open, 7));
    assert_eq!(run(2.0, 2.0, 1), (vec![true; 8], 0));
    // A new tile starts with nothing remembered.
    prism::integrator::begin_piece();
    assert_eq!(run(2.0, 2.0, 1), (vec![true; 8], 0));
}

/// Every shadow method renders every built-in scene bit for bit as the accelerator does.
#[test]
fn every_shadow_method_renders_the_same_image() {
    // Cache hits in renders whose shadow rays went in packets, over all scenes.
    let mut packet_cache_hits = 0;
    for name in [
        "whitted",
        "cornell",
        "sphereflake:2",
        "checkerboard",
        "pearls",
    ] {
        let scene = builtin::find(name).unwrap();
        let mut options = scene.options.clone();
        options.width = 96;
        options.height = 72;
        let prepared = scene.prepare(&options.accel);
        let mut reference = None;
        for method in [
            "any-hit",
            "cache",
            "light-buffer",
            "both",
            "auto",
            "light-buffer:res=7",
            "both:res=1",
            "light-buffer:res=300",
        ] {
            // Shadow rays in packets (camera rays in packets) and one at a time.
            for packets in [true, false] {
                options.shadows = method.parse::<ShadowSpec>().unwrap();
                options.packets = packets;
                let result = render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap();
                let film = result.film.pixels;
                match &reference {
                    None => reference = Some(film),
                    Some(r) => assert!(
                        r.iter()
                            .zip(&film)
                            .all(|(a, b)| a.to_array().map(f32::to_bits)
                                == b.to_array().map(f32::to_bits)),
                        "{name}: {method} (packets {packets}) renders another image than any-hit"
                    ),
                }
                if !["any-hit", "cache", "auto"].contains(&method) {
                    assert!(
                        result.stats.light_buffer_queries > 0 || scene.lights.is_empty(),
                        "{name}: {method} built no buffer"
                    );
                }
                if packets && method == "cache" {
                    packet_cache_hits += result.stats.shadow_cache_hits;
                }
            }
        }
    }
    assert!(
        packet_cache_hits > 0,
        "the cache answered no ray of a packet"
    );
}

/// The SPD scenes (Haines' own test scenes) render bit for bit alike with every method.
#[test]
fn spd_scenes_render_the_same_with_every_shadow_method() {
    let Some(dir) = common::shared_data("scenes/spd") else {
        return;
    };
    for name in [
        "balls", "gears", "mount", "rings", "teapot", "tetra", "tree",
    ] {
        let mut scene = prism_io::scene::load(&dir.join(format!("{name}.nff"))).unwrap();
        let mut options = scene.options.clone();
        prism::preset::apply_spd(&mut scene, &mut options);
        options.width = 65;
        options.height = 65;
        let prepared = scene.prepare(&options.accel);
        let mut reference = None;
        for method in ["any-hit", "both", "auto", "light-buffer:res=48"] {
            options.shadows = method.parse::<ShadowSpec>().unwrap();
            let film = render(&prepared, &options, &|_| {}, &AtomicBool::new(false))
                .unwrap()
                .film
                .pixels;
            match &reference {
                None => reference = Some(film),
                Some(r) => assert!(r == &film, "{name}: {method} differs from any-hit"),
            }
        }
    }
}

/// A box whose outline, seen from the light, lies exactly on a cell border, met by shadow
/// rays whose lines pass the light a little off (as offset origins make them): the part of
/// the box a ray meets is seen from the light across the border from the ray's own
/// direction, in the next cell, and the ray must still find the box (the footprints'
/// slack). Two boxes at the +z face's corners make its window the whole face, so its cell
/// borders lie at −1 + 2i/res; leaves of one primitive, so the box's leaf has its outline;
/// at 1, 10⁻³ and 10³ scale. With no slack, the buffer misses the box (tried).
#[test]
fn outlines_on_cell_borders_are_in_both_cells() {
    for scale in [1.0f32, 1e-3, 1e3] {
        let mut s = TestScene::new();
        // From the origin, the edge x = 0.5, z = 2 is seen at u = x/z = 0.25: a border of a
        // res-8 face (cells 0.25 wide).
        s.add_box(AaBox::new(
            Vec3::new(0.5, -0.5, 1.0) * scale,
            Vec3::new(1.0, 0.5, 2.0) * scale,
        ));
        for c in [Vec3::new(10.0, 10.0, 10.0), Vec3::new(-10.0, -10.0, 10.0)] {
            s.add_box(AaBox::new((c - 1.0) * scale, (c + 1.0) * scale));
        }
        let g = &s.geometry;
        let intersector = SceneIntersector::build(g, &"bvh:leaf=1".parse().unwrap());
        let light = Vec3::ZERO;
        let buffer = LightBuffer::build(&intersector, light, &params(8)).unwrap();
        let (mut blocked, mut total) = (0, 0);
        let mut stats = Stats::default();
        for delta in [2e-5f32, 1e-4, 2e-4] {
            for y in [-0.3f32, 0.0, 0.2] {
                for beyond in [0.5f32, 1.0, 4.0] {
                    // A point h in the box just inside its edge, seen at u = 0.25 + δ/4, and
                    // a ray through h towards e, δ beside the light: its direction is seen
                    // at u ≈ 0.25 − δ/4, in the cell before the border.
                    let h = Vec3::new(2.0 * (0.25 + delta / 4.0), y, 2.0) * 0.9995;
                    let e = Vec3::new(delta, 0.0, 0.0);
                    let p = (h + (h - e) * beyond) * scale;
                    let d = e * scale - p;
                    let distance = d.length();
                    let ray = Ray::new(p, d / distance);
                    let a =
                        buffer.query(g, &intersector, &ray, distance, QueryMode::Any, &mut stats);
                    let b = intersector.occluded(g, &ray, distance, &mut Stats::default());
                    assert_eq!(a.is_some(), b, "scale {scale}, point {p}");
                    blocked += b as usize;
                    total += 1;
                }
            }
        }
        assert!(
            blocked * 10 > total * 9,
            "scale {scale}: {blocked} of {total} rays blocked"
        );
        assert_eq!(stats.light_buffer_fallbacks, 0, "the buffer answered");
    }
}

/// A ray whose line passes the light δ off meets, very near the light, a small box that
/// the light sees in another cell than the ray's direction: the buffer finds it in its
/// node of the leaves nearest the light, which such a query walks too, without asking the
/// whole BVH; at 1, 10⁻³ and 10³ scale. (Two boxes at the +z face's corners make its
/// window the whole face.)
#[test]
fn leaves_near_the_light_are_walked_when_a_ray_passes_it_off() {
    for scale in [1.0f32, 1e-3, 1e3] {
        let delta = 1e-3;
        let mut s = TestScene::new();
        // Seen from the light at u ≈ 0.14 to 0.27 (cells 9 and 10 of 16 over −1 to 1); the
        // rays' direction at u = 0 (cell 8).
        let c = Vec3::new(2.0 * delta, 0.0, 10.0 * delta);
        s.add_box(AaBox::new(
            (c - delta / 2.0) * scale,
            (c + delta / 2.0) * scale,
        ));
        for c in [Vec3::new(10.0, 10.0, 10.0), Vec3::new(-10.0, -10.0, 10.0)] {
            s.add_box(AaBox::new((c - 1.0) * scale, (c + 1.0) * scale));
        }
        let g = &s.geometry;
        let intersector = SceneIntersector::build(g, &"bvh:leaf=1".parse().unwrap());
        let buffer = LightBuffer::build(&intersector, Vec3::ZERO, &params(16)).unwrap();
        let mut stats = Stats::default();
        let mut blocked = 0;
        for y in [-0.4f32, 0.0, 0.3] {
            for x in [1.7f32, 2.0, 2.3] {
                let p = Vec3::new(x * delta, y * delta, 5.0) * scale;
                let ray = Ray::new(p, -Vec3::Z);
                let distance = p.z;
                let what = format!("scale {scale}, point {p}");
                blocked +=
                    agrees(&buffer, g, &intersector, &ray, distance, &mut stats, &what) as usize;
            }
        }
        assert_eq!(blocked, 9, "scale {scale}: every ray meets the small box");
        assert_eq!(stats.light_buffer_fallbacks, 0, "the buffer answered");
    }
}

/// The shadow rays' share of each pixel's work adds up to the render's shadow counts, and
/// never exceeds the pixel's whole work: what `--cost-rays shadow` paints.
#[test]
fn per_pixel_shadow_work_adds_up_to_the_statistics() {
    let scene = builtin::find("whitted").unwrap();
    let mut options = scene.options.clone();
    options.width = 40;
    options.height = 30;
    let prepared = scene.prepare(&options.accel);
    for method in ["any-hit", "both"] {
        options.shadows = method.parse::<ShadowSpec>().unwrap();
        let r = render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap();
        let rays = &r.rays;
        assert_eq!(
            rays.shadow_tests.iter().sum::<u64>(),
            r.stats.shadow_tests,
            "{method}"
        );
        assert_eq!(
            rays.shadow_node_visits.iter().sum::<u64>(),
            r.stats.shadow_node_visits,
            "{method}"
        );
        assert!(
            r.stats.shadow_tests > 0,
            "{method}: shadow rays tested something"
        );
        for i in 0..rays.shadow_tests.len() {
            assert!(rays.shadow_tests[i] <= rays.primitive_tests[i]);
            assert!(rays.shadow_node_visits[i] <= rays.node_visits[i]);
        }
    }
}

/// Minutes of CPU time between them, so the README's test command leaves them out:
/// `cargo test --release -- --ignored long_tier` runs them (.ci/run does).
mod long_tier {
    use super::*;

    #[test]
    #[ignore = "long tier: every BVH layout, two scenes"]
    fn the_light_buffer_answers_as_the_accelerator_over_every_layout() {
        check_scene(1.0, Vec3::ZERO, 1);
        check_scene(1.0, Vec3::new(3.0, -1.0, 2.0), 2);
    }

    #[test]
    #[ignore = "long tier: every BVH layout at 1e-3 and 1e3"]
    fn the_light_buffer_answers_as_the_accelerator_at_every_scale() {
        check_scene(1e-3, Vec3::new(2e-3, 0.0, -1e-3), 3);
        check_scene(1e3, Vec3::new(-5e3, 2e3, 0.0), 4);
    }

    #[test]
    #[ignore = "long tier: every BVH layout, two scenes"]
    fn the_directional_light_buffer_answers_as_the_accelerator_over_every_layout() {
        check_directional_scene(1.0, Vec3::ZERO, 21);
        check_directional_scene(1.0, Vec3::new(3.0, -1.0, 2.0), 22);
    }

    #[test]
    #[ignore = "long tier: every BVH layout at 1e-3 and 1e3"]
    fn the_directional_light_buffer_answers_as_the_accelerator_at_every_scale() {
        check_directional_scene(1e-3, Vec3::new(2e-3, 0.0, -1e-3), 23);
        check_directional_scene(1e3, Vec3::new(-5e3, 2e3, 0.0), 24);
    }
}
