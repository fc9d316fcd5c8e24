//! The path tracer held to what must be true of it: closed forms (the white furnace), its
//! estimators agreeing with each other, materials that never make light, reciprocity,
//! determinism whatever the threads and tiles, progressive = one shot, and scale
//! invariance. Statistical assertions compare with a few standard errors measured from the
//! render itself, so they fail on a bias, not on noise.

use prism::camera::{Camera, Projection};
use prism::geometry::{generate, Shape, Sphere};
use prism::integrator::Strategy;
use prism::math::{Color, Vec3};
use prism::options::{IntegratorKind, RenderOptions};
use prism::render::{render, Film, Progressive};
use prism::sampling::SamplerKind;
use prism::scene::builtin;
use prism::shading::{Bsdf, FresnelMode, Highlight, Material, Texture};
use prism::Scene;
use std::sync::atomic::AtomicBool;

fn path_options(width: u32, height: u32, max_depth: u32) -> RenderOptions {
    RenderOptions {
        width,
        height,
        max_depth,
        integrator: IntegratorKind::Path,
        threads: 2,
        ..RenderOptions::default()
    }
}

fn progressive(scene: &Scene, options: &RenderOptions, spp: u32) -> Film {
    let prepared = scene.prepare_for(options);
    let mut p = Progressive::new(options.width, options.height).unwrap();
    p.advance(&prepared, options, spp, &AtomicBool::new(false))
        .unwrap();
    p.film()
}

/// Mean over pixels and channels, and its standard error, for a film whose pixels all
/// have the same expectation.
fn mean_and_error(film: &Film) -> (f64, f64) {
    let values: Vec<f64> = film
        .pixels
        .iter()
        .map(|c| (c.x + c.y + c.z) as f64 / 3.0)
        .collect();
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// A camera at the centre of a hollow sphere of albedo `albedo` whose inside emits `le`.
fn furnace(albedo: f32, le: f32, radius: f32) -> Scene {
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::ZERO,
            look_at: Vec3::new(0.3, 0.2, 1.0) * radius,
            up: Vec3::Y,
            fov_degrees: 90.0,
            projection: Projection::Perspective,
        },
        ambient: Color::ZERO,
        ..Scene::default()
    };
    let wall = scene.add_material(Material {
        name: "furnace".into(),
        color: Texture::Solid(Color::splat(albedo)),
        ambient: 0.0,
        diffuse: 1.0,
        emission: Color::splat(le),
        ..Material::default()
    });
    scene.geometry.add(
        Shape::Sphere(Sphere {
            center: Vec3::ZERO,
            radius,
            inside_out: true,
        }),
        wall,
    );
    scene
}

#[test]
fn the_white_furnace_converges_to_the_truncated_geometric_series() {
    let (a, le) = (0.8f32, 0.5f32);
    for (depth, strategy, radius) in [
        (12, Strategy::Mis, 1.0),
        (3, Strategy::Mis, 1e-3),
        (40, Strategy::Mis, 1e3),
        (12, Strategy::LightOnly, 1.0),
        (12, Strategy::BsdfOnly, 1.0),
    ] {
        let scene = furnace(a, le, radius);
        let options = RenderOptions {
            path_strategy: strategy,
            ..path_options(32, 32, depth)
        };
        let film = progressive(&scene, &options, 64);
        let (mean, error) = mean_and_error(&film);
        // Vertex k (the camera's hit is 1) adds Le·a^(k−1), up to k = max_depth.
        let expected = le as f64 * (1.0 - (a as f64).powi(depth as i32)) / (1.0 - a as f64);
        assert!(
            (mean - expected).abs() < 4.0 * error + 1e-4 * expected,
            "depth {depth}, {strategy:?}, radius {radius}: mean {mean} ± {error}, expected {expected}"
        );
        assert!(error < 0.02 * expected, "too noisy to test: ± {error}");
    }
}

#[test]
fn the_furnace_test_fails_when_the_albedo_is_wrong() {
    // The same check against the wrong albedo must fail: the test can see a 2 % bias.
    let scene = furnace(0.8, 0.5, 1.0);
    let film = progressive(&scene, &path_options(32, 32, 12), 64);
    let (mean, error) = mean_and_error(&film);
    let wrong = 0.5 * (1.0 - 0.78f64.powi(12)) / (1.0 - 0.78);
    assert!((mean - wrong).abs() > 4.0 * error, "{mean} ± {error}");
}

/// An area light (a quad facing down) over a floor that is partly diffuse, partly glossy.
fn lit_floor(shininess: f32) -> Scene {
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::new(0.0, 2.0, -4.0),
            look_at: Vec3::new(0.0, 0.0, 0.0),
            up: Vec3::Y,
            fov_degrees: 50.0,
            projection: Projection::Perspective,
        },
        ambient: Color::ZERO,
        ..Scene::default()
    };
    let floor = scene.add_material(Material {
        name: "floor".into(),
        color: Texture::Solid(Color::new(0.7, 0.5, 0.3)),
        ambient: 0.0,
        diffuse: 0.5,
        specular: 0.4,
        shininess,
        ..Material::default()
    });
    let light = scene.add_material(Material {
        name: "light".into(),
        color: Texture::Solid(Color::ZERO),
        emission: Color::new(4.0, 3.0, 2.0),
        ..Material::default()
    });
    let v = Vec3::new;
    scene.geometry.add_mesh(
        generate::quad(
            v(-3., 0., -3.),
            v(-3., 0., 3.),
            v(3., 0., 3.),
            v(3., 0., -3.),
            1.,
            1.,
        ),
        floor,
    );
    // Facing down: counter-clockwise seen from below.
    scene.geometry.add_mesh(
        generate::quad(
            v(-0.5, 1.5, -0.5),
            v(0.5, 1.5, -0.5),
            v(0.5, 1.5, 0.5),
            v(-0.5, 1.5, 0.5),
            1.,
            1.,
        ),
        light,
    );
    scene
}

/// z-score of the mean per-pixel difference of two independent renders of one picture.
fn difference_z(a: &Film, b: &Film) -> f64 {
    let d: Vec<f64> = (a.pixels.iter().zip(&b.pixels))
        .map(|(x, y)| ((x.x + x.y + x.z) - (y.x + y.y + y.z)) as f64 / 3.0)
        .collect();
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    mean / (var / n).sqrt()
}

#[test]
fn mis_light_only_and_bsdf_only_agree_within_noise() {
    for shininess in [1.0, 30.0] {
        let scene = lit_floor(shininess);
        let film = |strategy, seed| {
            let options = RenderOptions {
                path_strategy: strategy,
                seed,
                ..path_options(48, 32, 4)
            };
            progressive(&scene, &options, 64)
        };
        let mis = film(Strategy::Mis, 1);
        let light = film(Strategy::LightOnly, 2);
        let bsdf = film(Strategy::BsdfOnly, 3);
        let (m, _) = mean_and_error(&mis);
        assert!(m > 0.01, "the floor is lit: {m}");
        for (name, other) in [("light-only", &light), ("bsdf-only", &bsdf)] {
            let z = difference_z(&mis, other);
            assert!(
                z.abs() < 4.5,
                "shininess {shininess}: MIS vs {name}: z = {z}"
            );
        }
        // The check can fail: a light 10 % too bright is seen.
        let brighter = Film {
            pixels: light.pixels.iter().map(|c| *c * 1.1).collect(),
            ..light.clone()
        };
        assert!(difference_z(&mis, &brighter).abs() > 4.5);
    }
}

/// Unit directions spread over the upper hemisphere of +z.
fn hemisphere_directions(n: u32) -> Vec<Vec3> {
    let mut out = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let u1 = (i as f32 + 0.5) / n as f32;
            let u2 = (j as f32 + 0.5) / n as f32;
            out.push(prism::math::warp::cosine_hemisphere(u1, u2).normalize());
        }
    }
    out
}

fn materials_under_test() -> Vec<(&'static str, Material)> {
    let base = Material {
        color: Texture::Solid(Color::ONE),
        ambient: 0.0,
        diffuse: 0.0,
        ..Material::default()
    };
    vec![
        (
            "lambert",
            Material {
                diffuse: 1.0,
                ..base.clone()
            },
        ),
        (
            "phong 1",
            Material {
                specular: 1.0,
                shininess: 1.0,
                ..base.clone()
            },
        ),
        (
            "phong 50",
            Material {
                specular: 1.0,
                shininess: 50.0,
                ..base.clone()
            },
        ),
        (
            "blinn-phong 400",
            Material {
                specular: 1.0,
                shininess: 400.0,
                highlight: Highlight::BlinnPhong,
                ..base.clone()
            },
        ),
        (
            "mirror",
            Material {
                reflect: 1.0,
                ..base.clone()
            },
        ),
        (
            "glass",
            Material {
                transmit: Color::ONE,
                ior: 1.5,
                fresnel: FresnelMode::Exact,
                ..base.clone()
            },
        ),
        (
            "whitted overbright",
            Material {
                diffuse: 0.9,
                specular: 0.8,
                shininess: 20.0,
                reflect: 0.9,
                transmit: Color::ONE,
                fresnel: FresnelMode::Schlick,
                ..base.clone()
            },
        ),
    ]
}

#[test]
fn no_material_reflects_more_light_than_it_receives() {
    let n = Vec3::Z;
    for (name, m) in materials_under_test() {
        for wo in hemisphere_directions(6) {
            for entering in [true, false] {
                let bsdf = Bsdf::new(&m.coefficients(), Color::ONE, wo, n, n, entering);
                // The mean sampled weight f·cos/pdf over a stratified grid of numbers is
                // the albedo for wo.
                let k = 48u32;
                let mut sum = Color::ZERO;
                for a in 0..k {
                    for b in 0..k {
                        for c in 0..4 {
                            let u = |i: u32, m: u32| (i as f32 + 0.5) / m as f32;
                            if let Some(s) = bsdf.sample(u(c, 4), u(a, k), u(b, k)) {
                                assert!(s.weight.is_finite() && s.weight.min_element() >= 0.0);
                                sum += s.weight;
                                if !s.delta {
                                    // The weight is f·cos/pdf of the returned direction.
                                    let w = bsdf.eval(s.wi) * bsdf.cos(s.wi) / bsdf.pdf(s.wi);
                                    assert!(
                                        (w - s.weight).abs().max_element()
                                            < 1e-3 * (1.0 + w.max_element()),
                                        "{name}"
                                    );
                                }
                            }
                        }
                    }
                }
                let albedo = sum / (k * k * 4) as f32;
                assert!(
                    albedo.max_element() <= 1.0 + 2e-3,
                    "{name}, wo {wo}, entering {entering}: albedo {albedo}"
                );
                if name == "lambert" {
                    assert!((albedo - Color::ONE).abs().max_element() < 1e-3, "{albedo}");
                }
                if name == "glass" || name == "mirror" {
                    // A lossless interface: reflection and transmission sum to one.
                    assert!(
                        (albedo - Color::ONE).abs().max_element() < 1e-4,
                        "{name} {albedo}"
                    );
                }
            }
        }
    }
}

#[test]
fn the_phong_lobe_integrates_to_its_albedo_and_no_more() {
    // Independent of the sampler: f·cos integrated over the hemisphere by the midpoint
    // rule, for a lobe at normal incidence (where normalised Phong reaches ks) and off it.
    let m = Material {
        color: Texture::Solid(Color::ONE),
        ambient: 0.0,
        diffuse: 0.0,
        specular: 1.0,
        shininess: 20.0,
        ..Material::default()
    };
    for (wo, at_most, at_least) in [
        (Vec3::Z, 1.0 + 1e-3, 1.0 - 1e-2),
        (Vec3::new(0.6, 0.0, 0.8), 1.0, 0.5),
    ] {
        let bsdf = Bsdf::new(&m.coefficients(), Color::ONE, wo, Vec3::Z, Vec3::Z, true);
        let (nt, np) = (2000, 400);
        let mut sum = 0.0f64;
        for i in 0..nt {
            let theta = (i as f64 + 0.5) / nt as f64 * std::f64::consts::FRAC_PI_2;
            for j in 0..np {
                let phi = (j as f64 + 0.5) / np as f64 * 2.0 * std::f64::consts::PI;
                let wi = Vec3::new(
                    (theta.sin() * phi.cos()) as f32,
                    (theta.sin() * phi.sin()) as f32,
                    theta.cos() as f32,
                );
                let d_omega = theta.sin()
                    * (std::f64::consts::FRAC_PI_2 / nt as f64)
                    * (2.0 * std::f64::consts::PI / np as f64);
                sum += bsdf.eval(wi).x as f64 * theta.cos() * d_omega;
            }
        }
        assert!(sum <= at_most && sum >= at_least, "wo {wo}: albedo {sum}");
    }
}

#[test]
fn the_smooth_lobes_are_reciprocal() {
    let n = Vec3::Z;
    for (name, m) in materials_under_test() {
        let dirs = hemisphere_directions(5);
        for &a in &dirs {
            for &b in &dirs {
                let fab = Bsdf::new(&m.coefficients(), Color::ONE, a, n, n, true).eval(b);
                let fba = Bsdf::new(&m.coefficients(), Color::ONE, b, n, n, true).eval(a);
                assert!(
                    (fab - fba).abs().max_element() <= 1e-4 * (1.0 + fab.max_element()),
                    "{name}: f({a}, {b}) = {fab} but f({b}, {a}) = {fba}"
                );
            }
        }
    }
}

fn small_cornell(name: &str) -> (Scene, RenderOptions) {
    let scene = builtin::find(name).unwrap();
    let options = RenderOptions {
        width: 48,
        height: 48,
        samples: 2,
        ..scene.options.clone()
    };
    (scene, options)
}

#[test]
fn a_path_traced_image_is_the_same_for_any_thread_count_and_tile_size() {
    for name in ["cornell-light", "cornell-light-glass"] {
        let (scene, options) = small_cornell(name);
        let prepared = scene.prepare_for(&options);
        let film = |threads, tile_size| {
            let o = RenderOptions {
                threads,
                tile_size,
                ..options.clone()
            };
            render(&prepared, &o, &|_| {}, &AtomicBool::new(false))
                .unwrap()
                .film
        };
        let reference = film(1, 16);
        assert!(reference.pixels.iter().any(|c| c.max_element() > 0.1));
        assert_eq!(reference, film(2, 16), "{name}: 2 threads");
        assert_eq!(reference, film(2, 5), "{name}: tiles of 5");
        assert_eq!(reference, film(3, 48), "{name}: one tile");
        // A different seed is a different image.
        let other = RenderOptions {
            seed: 7,
            ..options.clone()
        };
        let seeded = render(&prepared, &other, &|_| {}, &AtomicBool::new(false)).unwrap();
        assert_ne!(reference, seeded.film);
    }
}

/// The path integrator's rays start on surfaces inside the scene, so a BVH left at
/// `rays=auto` is built for rays from inside when it renders (and for rays from outside
/// when Whitted does); the tree is the only thing that changes, never a pixel.
#[test]
fn the_path_tracer_builds_its_bvh_for_rays_from_inside_and_the_image_does_not_change() {
    let (scene, options) = small_cornell("cornell-light");
    assert_eq!(options.integrator, IntegratorKind::Path);
    let describe = |o: &RenderOptions| scene.prepare_for(o).intersector.accel.describe();
    assert!(describe(&options).contains("for rays from inside"));
    let whitted = RenderOptions {
        integrator: IntegratorKind::Whitted,
        ..options.clone()
    };
    assert!(!describe(&whitted).contains("for rays from inside"));
    // Told otherwise, the path tracer builds what it is told.
    let outside = RenderOptions {
        accel: "bvh:rays=outside".parse().unwrap(),
        ..options.clone()
    };
    assert!(!describe(&outside).contains("for rays from inside"));

    let film_and_tests = |o: &RenderOptions| {
        let r = render(&scene.prepare_for(o), o, &|_| {}, &AtomicBool::new(false)).unwrap();
        (r.film, r.stats.primitive_tests)
    };
    let (inside_film, inside_tests) = film_and_tests(&options);
    let (outside_film, outside_tests) = film_and_tests(&outside);
    assert_eq!(inside_film, outside_film);
    // The room's walls no longer share leaves that every path vertex enters.
    assert!(
        inside_tests * 2 < outside_tests,
        "triangle tests: {inside_tests} from inside, {outside_tests} from outside"
    );
}

#[test]
fn progressive_frames_continue_each_other_bit_for_bit() {
    for integrator in [IntegratorKind::Path, IntegratorKind::Whitted] {
        let (scene, options) = small_cornell("cornell-light-glass");
        let options = RenderOptions {
            integrator,
            ..options
        };
        let prepared = scene.prepare_for(&options);
        let cancel = AtomicBool::new(false);
        let mut frames = Progressive::new(48, 48).unwrap();
        for _ in 0..3 {
            frames.advance(&prepared, &options, 2, &cancel).unwrap();
        }
        assert_eq!(frames.samples(), 6);
        let mut once = Progressive::new(48, 48).unwrap();
        let one = RenderOptions {
            threads: 1,
            ..options.clone()
        };
        once.advance(&prepared, &one, 6, &cancel).unwrap();
        assert_eq!(frames.film(), once.film(), "{integrator}");

        // A reset starts the sequence again.
        frames.reset();
        assert_eq!(frames.samples(), 0);
        frames.advance(&prepared, &options, 6, &cancel).unwrap();
        assert_eq!(frames.film(), once.film(), "{integrator} after reset");

        // A cancelled advance adds nothing.
        frames
            .advance(&prepared, &options, 4, &AtomicBool::new(true))
            .unwrap();
        assert_eq!(frames.samples(), 6);
        assert_eq!(frames.film(), once.film());
    }
}

#[test]
fn progressive_packets_give_every_sample_its_single_ray_value() {
    // Packets of 8 × 8 camera rays (a band of 8 rows, blocks clipped at the 45th column
    // and the 21st row) against one ray at a time: the same sums bit for bit, the same
    // rays per pixel; the centre sampler puts every sample on the same point. Whitted's
    // ray trees, and the path tracer's paths breadth first (the Cornell boxes' area
    // light, the Whitted scene's point lights, glass and mirrors).
    let cases = [
        ("whitted", IntegratorKind::Whitted),
        ("whitted", IntegratorKind::Path),
        ("cornell-light", IntegratorKind::Path),
        ("cornell-light-glass", IntegratorKind::Path),
    ];
    let cancel = AtomicBool::new(false);
    for (name, integrator) in cases {
        let scene = builtin::find(name).unwrap();
        for sampler in [SamplerKind::Jittered, SamplerKind::Centre] {
            let options = |packets: bool, threads: usize| RenderOptions {
                width: 45,
                height: 21,
                threads,
                packets,
                sampler,
                integrator,
                ..scene.options.clone()
            };
            let prepared = scene.prepare_for(&options(true, 2));
            let run = |packets: bool, threads: usize| {
                let mut p = Progressive::new(45, 21).unwrap();
                let stats = p
                    .advance(&prepared, &options(packets, threads), 3, &cancel)
                    .unwrap();
                (p, stats)
            };
            let ((packets, packet_stats), (single, single_stats)) = (run(true, 2), run(false, 1));
            let case = format!("{name}, {integrator}, {sampler}");
            // The packets did walk together (their node visits count once a packet).
            assert!(
                packet_stats.node_visits < single_stats.node_visits,
                "{case}"
            );
            assert_eq!(packets.film(), single.film(), "{case}");
            let rays = |p: &Progressive| -> Vec<(u64, u64)> {
                p.pixels().iter().map(|t| (t.camera_rays, t.rays)).collect()
            };
            assert_eq!(rays(&packets), rays(&single), "{case}");
            assert!(packets.pixels().iter().all(|t| t.camera_rays == 3));
            if sampler == SamplerKind::Centre && integrator == IntegratorKind::Whitted {
                // Three samples at the centre: three times one ray's radiance.
                let options = RenderOptions {
                    width: 45,
                    height: 21,
                    sampler: SamplerKind::Grid,
                    samples: 1,
                    ..scene.options.clone()
                };
                let once = render(&prepared, &options, &|_| {}, &cancel).unwrap().film;
                for (a, b) in packets.film().pixels.iter().zip(&once.pixels) {
                    assert!((*a - *b).abs().max_element() <= 1e-6 * b.max_element().max(1.0));
                }
            }
        }
    }
}

/// `render` with the path tracer: paths traced breadth first in packets give every pixel
/// exactly the value and the rays one path at a time gives, on several samplers (the
/// corner pattern's packets run along rows, the others' are blocks of pixels).
#[test]
fn path_traced_packets_render_the_single_path_image() {
    for name in ["cornell-light", "cornell-light-glass", "whitted"] {
        let scene = builtin::find(name).unwrap();
        for sampler in [
            SamplerKind::Jittered,
            SamplerKind::Corners,
            SamplerKind::Random,
        ] {
            let options = |packets: bool| RenderOptions {
                width: 37,
                height: 29,
                samples: 2,
                threads: 2,
                packets,
                sampler,
                integrator: IntegratorKind::Path,
                ..scene.options.clone()
            };
            let prepared = scene.prepare_for(&options(true));
            let cancel = AtomicBool::new(false);
            let packets = render(&prepared, &options(true), &|_| {}, &cancel).unwrap();
            let single = render(&prepared, &options(false), &|_| {}, &cancel).unwrap();
            let case = format!("{name}, {sampler}");
            assert!(
                packets.film.pixels.iter().any(|c| c.max_element() > 0.05),
                "{case}"
            );
            assert_eq!(packets.film, single.film, "{case}");
            let s = (&packets.stats, &single.stats);
            assert_eq!(s.0.total_rays(), s.1.total_rays(), "{case}");
            assert_eq!(s.0.shadow_rays, s.1.shadow_rays, "{case}");
            assert_eq!(s.0.primary_hits, s.1.primary_hits, "{case}");
            // The packets did walk together: a packet's node visits count once for all
            // its rays.
            assert!(
                s.0.node_visits < s.1.node_visits,
                "{case}: {} {}",
                s.0.node_visits,
                s.1.node_visits
            );
        }
    }
}

#[test]
fn progressive_whitted_refines_towards_the_supersampled_image() {
    // Whitted's samples are jittered positions: the progressive mean of many converges to
    // the image a dense grid gives, and the error shrinks as samples accumulate.
    let scene = builtin::find("whitted").unwrap();
    let options = RenderOptions {
        width: 40,
        height: 30,
        threads: 2,
        ..scene.options.clone()
    };
    let prepared = scene.prepare_for(&options);
    let grid = RenderOptions {
        samples: 16,
        ..options.clone()
    };
    let reference = render(&prepared, &grid, &|_| {}, &AtomicBool::new(false))
        .unwrap()
        .film;
    let error = |film: &Film| {
        (film.pixels.iter().zip(&reference.pixels))
            .map(|(a, b)| (*a - *b).abs().element_sum() as f64)
            .sum::<f64>()
    };
    let mut p = Progressive::new(40, 30).unwrap();
    let cancel = AtomicBool::new(false);
    p.advance(&prepared, &options, 1, &cancel).unwrap();
    let first = error(&p.film());
    p.advance(&prepared, &options, 63, &cancel).unwrap();
    let later = error(&p.film());
    assert!(later < 0.5 * first, "{first} then {later}");
}

#[test]
fn the_cornell_box_renders_the_same_at_a_thousandth_and_a_thousand_times_its_size() {
    for name in ["cornell-light", "cornell-light-glass"] {
        let scene = builtin::find(name).unwrap();
        let options = RenderOptions {
            width: 64,
            height: 64,
            threads: 2,
            ..scene.options.clone()
        };
        let reference = progressive(&scene, &options, 16);
        let (mean, _) = mean_and_error(&reference);
        for factor in [1e-3f32, 1e3] {
            let scaled = scene.scaled(factor).unwrap();
            let film = progressive(&scaled, &options, 16);
            let (m, _) = mean_and_error(&film);
            assert!(
                (m - mean).abs() < 0.01 * mean,
                "{name} × {factor}: mean {m} against {mean}"
            );
            // Same random numbers, so nearly every path is the same path: most pixels
            // agree closely, whatever rounding changed in a few.
            let close = (film.pixels.iter().zip(&reference.pixels))
                .filter(|(a, b)| (**a - **b).abs().max_element() <= 0.02 * (1.0 + b.max_element()))
                .count();
            let share = close as f64 / film.pixels.len() as f64;
            assert!(
                share > 0.9,
                "{name} × {factor}: only {share} of pixels agree"
            );
        }
    }
}

/// Mitsuba 3's path tracer on the same Cornell boxes (64², 16384 paths per pixel, max depth
/// 6: `bench/mitsuba-cornell.py --write-reference`), against prism's progressive render
/// of 256 paths per pixel. Both place samples uniformly in the pixel with a box filter, so
/// every pixel has the same expectation in both.
#[test]
fn the_cornell_boxes_agree_with_mitsuba() {
    let data = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    for (name, max_flip) in [("cornell-light", 0.04), ("cornell-light-glass", 0.08)] {
        let reference =
            prism_io::output::read_image(&data.join(format!("{name}-mitsuba.exr"))).unwrap();
        let scene = builtin::find(name).unwrap();
        let options = RenderOptions {
            width: reference.width,
            height: reference.height,
            threads: 2,
            ..scene.options.clone()
        };
        let film = progressive(&scene, &options, 256);
        // The light itself (radiance 17) and its outline, where the cameras' rounding
        // differs, would dominate: the comparison keeps the pixels both see below 1.
        let lit: Vec<bool> = (film.pixels.iter().zip(&reference.pixels))
            .map(|(a, b)| a.max_element() < 1.0 && b.max_element() < 1.0)
            .collect();
        let masked = |f: &Film| Film {
            pixels: (f.pixels.iter().zip(&lit))
                .filter(|(_, &keep)| keep)
                .map(|(c, _)| *c)
                .collect(),
            ..f.clone()
        };
        let (ours, theirs) = (masked(&film), masked(&reference));
        let z = difference_z(&ours, &theirs);
        assert!(
            z.abs() < 4.0,
            "{name}: prism − Mitsuba = {z} standard errors"
        );
        let brighter = Film {
            pixels: ours.pixels.iter().map(|c| *c * 1.03).collect(),
            ..ours.clone()
        };
        assert!(
            difference_z(&brighter, &theirs).abs() > 4.0,
            "{name}: the test cannot see 3 %"
        );
        let flip = prism_lab::metrics::compare(&reference, &film, None, 67.0)
            .unwrap()
            .flip;
        assert!(flip < max_flip, "{name}: mean FLIP {flip}");
        eprintln!("{name}: z = {z:.2}, FLIP {flip:.4}");
    }
}

#[test]
fn point_spot_and_directional_lights_give_the_path_tracer_whitteds_direct_light() {
    // A Whitted light's colour is the irradiance it gives a surface facing it; the path
    // tracer takes it as π × that, so on a Lambertian surface direct light (max depth 2)
    // is Whitted's kd·C·cos θ·colour exactly, shadows included.
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::new(0.0, 3.0, -5.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            fov_degrees: 60.0,
            projection: Projection::Perspective,
        },
        ambient: Color::ZERO,
        ..Scene::default()
    };
    let matte = scene.add_material(Material {
        name: "matte".into(),
        color: Texture::Solid(Color::new(0.6, 0.5, 0.4)),
        ambient: 0.0,
        diffuse: 0.9,
        ..Material::default()
    });
    let v = Vec3::new;
    scene.geometry.add_mesh(
        generate::quad(
            v(-4., 0., -4.),
            v(-4., 0., 4.),
            v(4., 0., 4.),
            v(4., 0., -4.),
            1.,
            1.,
        ),
        matte,
    );
    scene
        .geometry
        .add(Shape::Sphere(Sphere::new(v(0.5, 0.7, 0.0), 0.7)), matte);
    scene.lights = vec![
        prism::light::Light::Point {
            position: v(-2.0, 4.0, -1.0),
            color: Color::new(0.5, 0.4, 0.3),
        },
        prism::light::Light::Directional {
            direction: v(1.0, -2.0, 0.5).normalize(),
            color: Color::splat(0.3),
        },
        prism::light::Light::Spot {
            position: v(2.0, 3.0, -2.0),
            direction: v(-0.5, -1.0, 0.5).normalize(),
            color: Color::splat(0.6),
            cos_inner: 0.95,
            cos_outer: 0.8,
        },
    ];
    // Every light tested: by default a light that could change a pixel by less than
    // 1/255 casts no shadow ray, its visibility estimated from the other lights'
    // (adaptive shadow testing), where the path tracer tests it.
    let whitted = RenderOptions {
        width: 48,
        height: 32,
        max_depth: 2,
        threads: 2,
        min_weight: 0.0,
        ..RenderOptions::default()
    };
    let path = RenderOptions {
        integrator: IntegratorKind::Path,
        ..whitted.clone()
    };
    let prepared = scene.prepare(&whitted.accel);
    let cancel = AtomicBool::new(false);
    let a = render(&prepared, &whitted, &|_| {}, &cancel).unwrap().film;
    let b = render(&prepared, &path, &|_| {}, &cancel).unwrap().film;
    let lit = a.pixels.iter().filter(|c| c.max_element() > 0.05).count();
    assert!(lit > a.pixels.len() / 2, "the scene is lit: {lit} pixels");
    for (i, (x, y)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        assert!(
            (*x - *y).abs().max_element() <= 1e-4 * (1.0 + x.max_element()),
            "pixel {i}: Whitted {x}, path {y}"
        );
    }
}
