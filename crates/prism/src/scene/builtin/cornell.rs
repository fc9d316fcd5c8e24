//! A Cornell box lit by one point light below the ceiling, with a mirror sphere and a glass
//! sphere: every Whitted effect in a closed room.

use crate::camera::{Camera, Projection};
use crate::geometry::{generate, Shape, Sphere};
use crate::light::Light;
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::{FresnelMode, Material, Texture};

pub(super) fn cornell() -> Scene {
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::new(0.5, 0.5, -1.35),
            look_at: Vec3::new(0.5, 0.5, 0.5),
            up: Vec3::Y,
            fov_degrees: 38.0,
            projection: Projection::Perspective,
        },
        background: Color::ZERO,
        ambient: Color::splat(0.15),
        ..Scene::default()
    };
    scene.options.width = 512;
    scene.options.height = 512;

    let wall = |scene: &mut Scene, name: &str, color: Color| {
        scene.add_material(Material {
            name: name.into(),
            color: Texture::Solid(color),
            ambient: 1.0,
            diffuse: 0.85,
            ..Material::default()
        })
    };
    let white = wall(&mut scene, "white", Color::splat(0.75));
    let red = wall(&mut scene, "red", Color::new(0.75, 0.1, 0.1));
    let green = wall(&mut scene, "green", Color::new(0.12, 0.6, 0.12));
    let mirror = scene.add_material(Material {
        name: "mirror".into(),
        color: Texture::Solid(Color::splat(0.9)),
        ambient: 0.0,
        diffuse: 0.0,
        specular: 0.8,
        shininess: 300.0,
        reflect: 0.9,
        ..Material::default()
    });
    let glass = scene.add_material(Material {
        name: "glass".into(),
        color: Texture::Solid(Color::ONE),
        ambient: 0.0,
        diffuse: 0.0,
        specular: 0.8,
        shininess: 300.0,
        transmit: Color::ONE,
        ior: 1.5,
        fresnel: FresnelMode::Exact,
        ..Material::default()
    });

    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    // Walls face into the box. Looking along +z with +y up, +x is on the image's left.
    let walls = [
        (
            v(0., 0., 0.),
            v(0., 0., 1.),
            v(1., 0., 1.),
            v(1., 0., 0.),
            white,
        ), // floor
        (
            v(0., 1., 0.),
            v(1., 1., 0.),
            v(1., 1., 1.),
            v(0., 1., 1.),
            white,
        ), // ceiling
        (
            v(0., 0., 1.),
            v(0., 1., 1.),
            v(1., 1., 1.),
            v(1., 0., 1.),
            white,
        ), // back
        (
            v(1., 0., 0.),
            v(1., 0., 1.),
            v(1., 1., 1.),
            v(1., 1., 0.),
            red,
        ), // left
        (
            v(0., 0., 0.),
            v(0., 1., 0.),
            v(0., 1., 1.),
            v(0., 0., 1.),
            green,
        ), // right
    ];
    for (a, b, c, d, m) in walls {
        scene
            .geometry
            .add_mesh(generate::quad(a, b, c, d, 1.0, 1.0), m);
    }
    scene
        .geometry
        .add(Shape::Sphere(Sphere::new(v(0.68, 0.2, 0.62), 0.2)), mirror);
    scene
        .geometry
        .add(Shape::Sphere(Sphere::new(v(0.3, 0.18, 0.32), 0.18)), glass);
    scene.lights = vec![Light::Point {
        position: v(0.5, 0.93, 0.45),
        color: Color::splat(0.85),
    }];
    scene
}
