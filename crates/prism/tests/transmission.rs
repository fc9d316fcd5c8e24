//! Coloured transmission: a transparent surface's `transmit` is a colour filter. A red pane
//! casts a red shadow, and light through k panes keeps t^k of each channel; both checked
//! against the closed-form values.

use prism::camera::{Camera, Projection};
use prism::geometry::{Plane, Shape, TriangleMesh};
use prism::light::Light;
use prism::math::{Color, Vec3};
use prism::render::render;
use prism::shading::{Material, Texture};
use prism::Scene;
use std::sync::atomic::AtomicBool;

/// A filter with three different channels, so that a mixed-up channel shows.
const RED_GLASS: Color = Color::new(0.9, 0.3, 0.1);

/// Glass that only filters: no surface shading, no reflection, index 1 (rays go straight).
fn filter(kt: Color) -> Material {
    Material {
        name: "filter".into(),
        ambient: 0.0,
        diffuse: 0.0,
        specular: 0.0,
        reflect: 0.0,
        transmit: kt,
        ior: 1.0,
        ..Material::default()
    }
}

/// A square pane of half-size `half`, level at height `y`, facing up.
fn pane(y: f32, half: f32) -> TriangleMesh {
    let p = |x: f32, z: f32| Vec3::new(x, y, z);
    TriangleMesh::new(
        vec![
            p(-half, -half),
            p(-half, half),
            p(half, half),
            p(half, -half),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
        None,
        None,
    )
    .expect("a valid quad")
}

/// The centre pixel of a 1×1 render.
fn centre_pixel(scene: &Scene, max_depth: u32) -> Color {
    let mut options = scene.options.clone();
    options.width = 1;
    options.height = 1;
    options.max_depth = max_depth;
    let prepared = scene.prepare(&options.accel);
    let result = render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap();
    result.film.pixels[0]
}

fn assert_close(actual: Color, expected: Color, what: &str) {
    for c in 0..3 {
        let err = (actual[c] - expected[c]).abs();
        assert!(
            err <= 1e-6 * expected[c].abs().max(1e-3),
            "{what}: channel {c} is {}, expected {} (whole pixel {actual}, expected {expected})",
            actual[c],
            expected[c]
        );
    }
}

#[test]
fn a_red_pane_casts_a_red_shadow() {
    // A white Lambert floor lit straight from above with irradiance 1, and a red pane
    // above it. The camera sits below the pane's height and looks at the floor under it,
    // so its ray meets the floor only; the shadow ray meets the pane.
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::new(0.0, 0.5, 6.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            fov_degrees: 10.0,
            projection: Projection::Perspective,
        },
        ambient: Color::ZERO,
        background: Color::ZERO,
        lights: vec![Light::Directional {
            direction: -Vec3::Y,
            color: Color::ONE,
        }],
        ..Scene::default()
    };
    let floor = scene.add_material(Material {
        name: "floor".into(),
        color: Texture::Solid(Color::ONE),
        ambient: 0.0,
        diffuse: 1.0,
        ..Material::default()
    });
    let glass = scene.add_material(filter(RED_GLASS));
    scene.geometry.add(
        Shape::Plane(Box::new(Plane::new(Vec3::ZERO, Vec3::Y).unwrap())),
        floor,
    );
    scene.geometry.add_mesh(pane(1.0, 2.0), glass);

    // kd·C·(n·l)·E·kt = 1·1·1·1·kt.
    assert_close(
        centre_pixel(&scene, 5),
        RED_GLASS,
        "floor in the pane's shadow",
    );

    // Two panes: the shadow ray crosses both, kt² per channel.
    let second = scene.add_material(filter(RED_GLASS));
    scene.geometry.add_mesh(pane(1.5, 2.0), second);
    assert_close(
        centre_pixel(&scene, 5),
        RED_GLASS * RED_GLASS,
        "floor under two panes",
    );
}

#[test]
fn light_through_k_panes_keeps_t_to_the_k_per_channel() {
    // The camera looks straight down through k panes at a white background.
    for k in 1..=4u32 {
        let mut scene = Scene {
            camera: Camera {
                eye: Vec3::new(0.0, 10.0, 0.0),
                look_at: Vec3::ZERO,
                up: Vec3::Z,
                fov_degrees: 10.0,
                projection: Projection::Perspective,
            },
            ambient: Color::ZERO,
            background: Color::ONE,
            ..Scene::default()
        };
        let glass = scene.add_material(filter(RED_GLASS));
        for i in 0..k {
            scene.geometry.add_mesh(pane(i as f32, 1.0), glass);
        }
        // Each pane adds one generation of rays: the eye ray and k refracted rays.
        let expected = RED_GLASS.powf(k as f32);
        let pixel = centre_pixel(&scene, k + 1);
        assert_close(pixel, expected, &format!("through {k} panes"));
        // With one generation fewer the background is never reached.
        assert_eq!(centre_pixel(&scene, k), Color::ZERO, "{k} panes, depth {k}");
    }
}

#[test]
fn grey_transmission_is_a_grey_filter() {
    // A number in the scene file is a grey: the same picture as its colour [t, t, t].
    let grey = |transmit: &str| {
        let text = format!(
            "[camera]\neye = [0, 10, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\nfov = 10\n\
             [world]\nbackground = 1\nambient = 0\n\
             [materials.glass]\ndiffuse = 0\nambient = 0\ntransmit = {transmit}\nior = 1\n\
             [[objects]]\ntype = \"box\"\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\n\
             material = \"glass\"\n"
        );
        let scene =
            prism_io::scene::parse_toml(&text, std::path::Path::new("grey.toml")).expect("valid");
        centre_pixel(&scene, 5)
    };
    let number = grey("0.5");
    assert_eq!(number, grey("[0.5, 0.5, 0.5]"));
    // Two faces of the box: 0.5².
    assert_close(number, Color::splat(0.25), "grey box");
}

#[test]
fn shadow_rays_go_only_where_the_light_adds_something() {
    // The Whitted scene's glass has no diffuse term and a highlight of exponent 200, which
    // is exactly zero away from the mirror direction: its shadow rays there could change
    // nothing, so they are not cast. SPD's rules cast them (and count them); with every
    // branch traced (min_weight 0) the two rule sets trace the same camera, reflected and
    // refracted rays, so the images must be equal bit for bit, with fewer shadow rays.
    let scene = prism::scene::builtin::find("whitted").unwrap();
    let prepared = scene.prepare(&scene.options.accel);
    for packets in [true, false] {
        let run = |spd_rules: bool| {
            let options = prism::RenderOptions {
                width: 64,
                height: 36,
                threads: 1,
                min_weight: 0.0,
                spd_rules,
                packets,
                ..scene.options.clone()
            };
            render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap()
        };
        let (skipping, casting) = (run(false), run(true));
        assert_eq!(
            skipping.film.pixels, casting.film.pixels,
            "packets {packets}"
        );
        let (s, c) = (&skipping.stats, &casting.stats);
        assert_eq!(
            (s.primary_rays, s.reflected_rays, s.refracted_rays),
            (c.primary_rays, c.reflected_rays, c.refracted_rays)
        );
        assert!(
            s.shadow_rays < c.shadow_rays * 9 / 10,
            "packets {packets}: {} shadow rays against {}",
            s.shadow_rays,
            c.shadow_rays
        );
        assert!(s.shadow_rays > 0);
    }
}
