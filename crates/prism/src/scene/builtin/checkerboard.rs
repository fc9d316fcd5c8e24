//! An endless black-and-white checkered plane running to the horizon, lit by ambient light
//! alone so every pixel is exactly the area average of the pattern it covers: the classic
//! aliasing test, with an exact reference that sampling can be measured against.

use super::staging::stage;
use crate::camera::Camera;
use crate::geometry::{Plane, Shape};
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::{Checker, CheckerSpace, Material, Texture};

pub(super) fn checkerboard() -> Scene {
    let camera = Camera::perspective(
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, 0.75, 4.0),
        Vec3::Y,
        50.0,
    );
    let mut scene = stage(camera, (640, 360), Color::new(0.55, 0.7, 0.9), 1.0);
    let board = scene.add_material(Material {
        name: "checker".into(),
        color: Texture::Checker(Checker {
            a: Color::ONE,
            b: Color::ZERO,
            size: 1.0,
            space: CheckerSpace::Uv,
        }),
        ambient: 1.0,
        diffuse: 0.0,
        ..Material::default()
    });
    let plane = Plane::new(Vec3::ZERO, Vec3::Y).expect("the normal is not zero");
    scene.geometry.add(Shape::Plane(Box::new(plane)), board);
    scene
}
