//! Shadow methods against the oracle: a light buffer must answer every shadow ray exactly
//! as the scene's accelerator does (the same any-hit answer, the same nearest hit for the
//! walk through transparent surfaces), for lights inside the scene, on a surface and far
//! away, for shading points on surfaces and in free space, for directions on cell borders
//! and cube edges, at 1, 10⁻³ and 10³ scale; and every method renders the same image.

mod common;

use common::oracle::{random_ray, TestScene};
use common::{icosphere, Rng};
use prism::accel::{AccelSpec, QueryMode, SceneIntersector};
use prism::geometry::{AaBox, Plane, Shape, Sphere};
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
    let mut tris = Vec::new();
    for _ in 0..150 {
        let a = p(&mut rng);
        let size = scale * rng.range(0.01, 0.8);
        tris.push([
            a,
            a + size * rng.unit_vector(),
            a + size * rng.unit_vector(),
        ]);
    }
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
    // Walks as long as they come (every answer the lists' own), and the automatic limit
    // beyond which the accelerator answers.
    let buffers = [
        LightBuffer::build(g, light, res, 1 << 30).expect("within the budget"),
        LightBuffer::build_with(
            g,
            light,
            &BufferParams {
                res,
                budget_bytes: 1 << 30,
                max_walk: LightBuffer::auto_max_walk(g.primitives.len()),
                opaque: &|_| true,
                bounds: None,
            },
        )
        .unwrap(),
    ];
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
    }
    (blocked, total)
}

fn check_scene(scale: f32, offset: Vec3, seed: u64) {
    let s = scene(seed, scale, offset);
    let intersector = SceneIntersector::build(&s.geometry, &AccelSpec::default());
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

#[test]
fn the_light_buffer_answers_as_the_accelerator() {
    check_scene(1.0, Vec3::ZERO, 1);
    check_scene(1.0, Vec3::new(3.0, -1.0, 2.0), 2);
}

#[test]
fn the_light_buffer_answers_as_the_accelerator_at_every_scale() {
    check_scene(1e-3, Vec3::new(2e-3, 0.0, -1e-3), 3);
    check_scene(1e3, Vec3::new(-5e3, 2e3, 0.0), 4);
}

#[test]
fn a_budget_too_small_refuses_the_buffer() {
    let s = scene(5, 1.0, Vec3::ZERO);
    let err = LightBuffer::build(&s.geometry, Vec3::ZERO, 64, 64);
    assert!(err.is_err(), "64 bytes cannot hold the lists");
}

/// Every shadow method renders every built-in scene bit for bit as the accelerator does.
#[test]
fn every_shadow_method_renders_the_same_image() {
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
            "both:walk=1",
            "light-buffer:res=5,walk=1000",
        ] {
            options.shadows = method.parse::<ShadowSpec>().unwrap();
            let result = render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap();
            let film = result.film.pixels;
            match &reference {
                None => reference = Some(film),
                Some(r) => assert!(
                    r.iter()
                        .zip(&film)
                        .all(|(a, b)| a.to_array().map(f32::to_bits)
                            == b.to_array().map(f32::to_bits)),
                    "{name}: {method} renders another image than any-hit"
                ),
            }
            if !["any-hit", "cache", "auto"].contains(&method) {
                assert!(
                    result.stats.light_buffer_queries > 0 || scene.lights.is_empty(),
                    "{name}: {method} built no buffer"
                );
            }
        }
    }
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

/// A box whose outline, seen from the light, lies exactly on cell borders: shadow rays that
/// graze its edge there must still find it in their cell (the footprints' slack).
#[test]
fn outlines_on_cell_borders_are_in_both_cells() {
    let mut s = TestScene::new();
    // From the origin, the edge x = 0.5, z = 2 is seen at u = x/z = 0.25, and the edge
    // y = 0.5, z = 2 at v = 0.25: both borders of a res-8 face (cells 0.25 wide).
    s.add_box(AaBox::new(
        Vec3::new(0.5, -0.5, 1.0),
        Vec3::new(1.0, 0.5, 2.0),
    ));
    let g = &s.geometry;
    let intersector = SceneIntersector::build(g, &AccelSpec::default());
    let light = Vec3::ZERO;
    let buffer = LightBuffer::build(g, light, 8, 1 << 20).unwrap();
    let mut agree = 0;
    for k in [1.5f32, 2.0, 3.7, 10.0] {
        for y in [-0.5f32, -0.25, 0.0, 0.3, 0.5] {
            for step in -3i32..=3 {
                let x = f32::from_bits((0.5f32 * k).to_bits().wrapping_add_signed(step));
                let p = Vec3::new(x, y * k, 2.0 * k);
                let d = light - p;
                let distance = d.length();
                let ray = Ray::new(p, d / distance);
                let mut stats = Stats::default();
                let a = buffer.query(g, &intersector, &ray, distance, QueryMode::Any, &mut stats);
                let b = intersector.occluded(g, &ray, distance, &mut stats);
                assert_eq!(a.is_some(), b, "point {p}");
                agree += b as usize;
            }
        }
    }
    assert!(agree > 0, "some grazing rays touch the box");
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

/// A scene whose light-buffer windows span whole faces (a box around everything holds the
/// light, so its cell borders are at −1 + 2i/res) with one large opaque triangle over the
/// light at z = 2·scale.
fn covered_scene(scale: f32) -> TestScene {
    let mut s = TestScene::new();
    s.add_box(AaBox::new(
        Vec3::splat(-50.0 * scale),
        Vec3::splat(50.0 * scale),
    ));
    s.add_triangles(&[[
        Vec3::new(-3.0, -3.0, 2.0) * scale,
        Vec3::new(3.0, -3.0, 2.0) * scale,
        Vec3::new(-3.0, 3.0, 2.0) * scale,
    ]]);
    s
}

/// Cells wholly covered by an opaque triangle ask it first, for points behind it only; the
/// answers stay the accelerator's at every cell border, on the triangle's outline, in front
/// of it and behind it, at 1, 10⁻³ and 10³ scale.
#[test]
fn covered_cells_answer_as_the_accelerator_in_front_and_behind() {
    for scale in [1.0f32, 1e-3, 1e3] {
        let s = covered_scene(scale);
        let g = &s.geometry;
        let intersector = SceneIntersector::build(g, &AccelSpec::default());
        let light = Vec3::ZERO;
        let res = 8;
        let buffer = LightBuffer::build(g, light, res, 1 << 24).unwrap();
        assert!(
            buffer.info().covered_cells > 0,
            "scale {scale}: no cell covered"
        );
        let mut rng = Rng::new(7);
        let (mut in_front, mut behind) = (Stats::default(), Stats::default());
        let mut blocked = 0;
        for i in 0..4000 {
            // Face coordinates on cell borders, on the triangle's hypotenuse u + v = 0,
            // or anywhere.
            let border =
                |rng: &mut Rng| 2.0 * rng.below(res as usize + 1) as f32 / res as f32 - 1.0;
            let (u, v) = match i % 3 {
                0 => (border(&mut rng), border(&mut rng)),
                1 => {
                    let u = rng.range(-1.0, 1.0);
                    (u, -u)
                }
                _ => (rng.range(-1.0, 1.0), border(&mut rng)),
            };
            let k = [1.0, 1.9, 2.0, 2.1, 6.0, 20.0][rng.below(6)];
            let base = Vec3::new(u, v, 1.0) * (k * scale);
            let step = rng.below(7) as i32 - 3;
            let p = Vec3::new(
                f32::from_bits(base.x.to_bits().wrapping_add_signed(step)),
                base.y,
                base.z,
            );
            let d = light - p;
            let distance = d.length();
            let ray = Ray::new(p, d / distance);
            let stats = if k < 2.0 { &mut in_front } else { &mut behind };
            let a = buffer.query(g, &intersector, &ray, distance, QueryMode::Any, stats);
            let b = intersector.occluded(g, &ray, distance, &mut Stats::default());
            assert_eq!(a.is_some(), b, "scale {scale}, point {p}");
            let n = buffer.query(g, &intersector, &ray, distance, QueryMode::Nearest, stats);
            let m = intersector.intersect(g, &ray, distance, &mut Stats::default());
            assert_eq!(n, m, "scale {scale}, point {p}: nearest hits differ");
            blocked += b as usize;
        }
        assert!(blocked > 500, "scale {scale}: {blocked} blocked");
        assert!(
            behind.light_buffer_covered > 100,
            "scale {scale}: the covers answered {} rays",
            behind.light_buffer_covered
        );
        assert_eq!(
            in_front.light_buffer_covered, 0,
            "scale {scale}: asked in front"
        );
    }
}

/// Transparent surfaces never cover a cell: the buffer built with the triangle taken as
/// transparent has no covered cell, and through `Shadows` a glass scene renders as any-hit.
#[test]
fn transparent_occluders_never_cover_a_cell() {
    let s = covered_scene(1.0);
    let g = &s.geometry;
    let params = |opaque: &'static dyn Fn(u32) -> bool| BufferParams {
        res: 8,
        budget_bytes: 1 << 24,
        max_walk: usize::MAX,
        opaque,
        bounds: None,
    };
    let opaque = LightBuffer::build_with(g, Vec3::ZERO, &params(&|_| true)).unwrap();
    let glass = LightBuffer::build_with(g, Vec3::ZERO, &params(&|_| false)).unwrap();
    assert!(opaque.info().covered_cells > 0);
    assert_eq!(glass.info().covered_cells, 0);
}
