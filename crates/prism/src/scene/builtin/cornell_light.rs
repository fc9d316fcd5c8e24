//! The Cornell box as measured (Cornell University Program of Computer Graphics, "Cornell
//! Box Data", www.graphics.cornell.edu/online/box/data.html): the room, the two blocks and
//! the ceiling light in millimetres, the camera 800 mm in front of the opening with a
//! 35 mm lens on a 25 mm square film. Lit only by its area light: a scene for the path
//! tracer.
//!
//! The published reflectances and emission are spectra; the RGB values here are the usual
//! approximations (those of the scenes shipped with pbrt-v3 and Mitsuba): white 0.73, red
//! (0.63, 0.065, 0.05), green (0.14, 0.45, 0.09), light radiance (17, 12, 4) and the light's
//! own reflectance 0.78. The light quad sits at y = 548.7, 0.1 mm below the ceiling it is
//! cut into in the data, so the two never coincide.
//!
//! The glass variant replaces the blocks by two spheres standing where they stood: a
//! mirror behind, where the tall block was, and glass (η = 1.5, exact Fresnel) in front.

use crate::camera::Camera;
use crate::geometry::{generate, Shape, Sphere};
use crate::math::{Color, Vec3};
use crate::options::IntegratorKind;
use crate::scene::Scene;
use crate::shading::Material;

/// Which blocks stand in the box.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Variant {
    /// The two white diffuse blocks of the measured box.
    Diffuse,
    /// A mirror sphere and a glass sphere.
    Glass,
}

type Quad = [[f32; 3]; 4];

const FLOOR: Quad = [
    [552.8, 0.0, 0.0],
    [0.0, 0.0, 0.0],
    [0.0, 0.0, 559.2],
    [549.6, 0.0, 559.2],
];
const CEILING: Quad = [
    [556.0, 548.8, 0.0],
    [556.0, 548.8, 559.2],
    [0.0, 548.8, 559.2],
    [0.0, 548.8, 0.0],
];
const BACK: Quad = [
    [549.6, 0.0, 559.2],
    [0.0, 0.0, 559.2],
    [0.0, 548.8, 559.2],
    [556.0, 548.8, 559.2],
];
const RIGHT_GREEN: Quad = [
    [0.0, 0.0, 559.2],
    [0.0, 0.0, 0.0],
    [0.0, 548.8, 0.0],
    [0.0, 548.8, 559.2],
];
const LEFT_RED: Quad = [
    [552.8, 0.0, 0.0],
    [549.6, 0.0, 559.2],
    [556.0, 548.8, 559.2],
    [556.0, 548.8, 0.0],
];
const LIGHT: Quad = [
    [343.0, 548.7, 227.0],
    [343.0, 548.7, 332.0],
    [213.0, 548.7, 332.0],
    [213.0, 548.7, 227.0],
];
const SHORT_BLOCK: [Quad; 5] = [
    [
        [130.0, 165.0, 65.0],
        [82.0, 165.0, 225.0],
        [240.0, 165.0, 272.0],
        [290.0, 165.0, 114.0],
    ],
    [
        [290.0, 0.0, 114.0],
        [290.0, 165.0, 114.0],
        [240.0, 165.0, 272.0],
        [240.0, 0.0, 272.0],
    ],
    [
        [130.0, 0.0, 65.0],
        [130.0, 165.0, 65.0],
        [290.0, 165.0, 114.0],
        [290.0, 0.0, 114.0],
    ],
    [
        [82.0, 0.0, 225.0],
        [82.0, 165.0, 225.0],
        [130.0, 165.0, 65.0],
        [130.0, 0.0, 65.0],
    ],
    [
        [240.0, 0.0, 272.0],
        [240.0, 165.0, 272.0],
        [82.0, 165.0, 225.0],
        [82.0, 0.0, 225.0],
    ],
];
const TALL_BLOCK: [Quad; 5] = [
    [
        [423.0, 330.0, 247.0],
        [265.0, 330.0, 296.0],
        [314.0, 330.0, 456.0],
        [472.0, 330.0, 406.0],
    ],
    [
        [423.0, 0.0, 247.0],
        [423.0, 330.0, 247.0],
        [472.0, 330.0, 406.0],
        [472.0, 0.0, 406.0],
    ],
    [
        [472.0, 0.0, 406.0],
        [472.0, 330.0, 406.0],
        [314.0, 330.0, 456.0],
        [314.0, 0.0, 456.0],
    ],
    [
        [314.0, 0.0, 456.0],
        [314.0, 330.0, 456.0],
        [265.0, 330.0, 296.0],
        [265.0, 0.0, 296.0],
    ],
    [
        [265.0, 0.0, 296.0],
        [265.0, 330.0, 296.0],
        [423.0, 330.0, 247.0],
        [423.0, 0.0, 247.0],
    ],
];

fn add_quad(scene: &mut Scene, q: &Quad, material: u32) {
    let [a, b, c, d] = q.map(Vec3::from_array);
    scene
        .geometry
        .add_mesh(generate::quad(a, b, c, d, 1.0, 1.0), material);
}

fn matte(name: &str, color: Color) -> Material {
    Material::matte(name, color, 0.0, 1.0)
}

pub(super) fn cornell_light(variant: Variant) -> Scene {
    // 35 mm lens, 25 mm film: 2·atan(12.5/35) across.
    let fov = 2.0 * (12.5f32 / 35.0).atan().to_degrees();
    let mut scene = Scene {
        camera: Camera::perspective(
            Vec3::new(278.0, 273.0, -800.0),
            Vec3::new(278.0, 273.0, 0.0),
            Vec3::Y,
            fov,
        ),
        background: Color::ZERO,
        ambient: Color::ZERO,
        ..Scene::default()
    };
    let o = &mut scene.options;
    o.width = 512;
    o.height = 512;
    o.integrator = IntegratorKind::Path;
    o.max_depth = 6;
    o.samples = 8;

    let white = scene.add_material(matte("white", Color::splat(0.73)));
    let red = scene.add_material(matte("red", Color::new(0.63, 0.065, 0.05)));
    let green = scene.add_material(matte("green", Color::new(0.14, 0.45, 0.09)));
    let light = scene.add_material(Material {
        emission: Color::new(17.0, 12.0, 4.0),
        ..matte("light", Color::splat(0.78))
    });
    for q in [&FLOOR, &CEILING, &BACK] {
        add_quad(&mut scene, q, white);
    }
    add_quad(&mut scene, &RIGHT_GREEN, green);
    add_quad(&mut scene, &LEFT_RED, red);
    add_quad(&mut scene, &LIGHT, light);
    match variant {
        Variant::Diffuse => {
            for q in SHORT_BLOCK.iter().chain(&TALL_BLOCK) {
                add_quad(&mut scene, q, white);
            }
        }
        Variant::Glass => {
            let mirror =
                scene.add_material(Material::matte("mirror", Color::ONE, 0.0, 0.0).reflecting(1.0));
            let glass = scene.add_material(
                Material::matte("glass", Color::ONE, 0.0, 0.0).glass(Color::ONE, 1.5),
            );
            scene.geometry.add(
                Shape::Sphere(Sphere::new(Vec3::new(368.0, 100.0, 351.0), 100.0)),
                mirror,
            );
            scene.geometry.add(
                Shape::Sphere(Sphere::new(Vec3::new(186.0, 90.0, 169.0), 90.0)),
                glass,
            );
        }
    }
    scene
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_face_of_the_room_and_the_blocks_faces_the_inside_of_the_room_or_out_of_its_block() {
        let normal = |q: &Quad| {
            let [a, b, c, _] = q.map(Vec3::from_array);
            (b - a).cross(c - a).normalize()
        };
        let centroid = |q: &Quad| q.iter().map(|&p| Vec3::from_array(p)).sum::<Vec3>() / 4.0;
        let room = Vec3::new(278.0, 274.4, 279.6);
        for q in [&FLOOR, &CEILING, &BACK, &RIGHT_GREEN, &LEFT_RED, &LIGHT] {
            assert!(normal(q).dot(room - centroid(q)) > 0.0, "{q:?}");
        }
        for block in [&SHORT_BLOCK, &TALL_BLOCK] {
            let inside = block.iter().map(centroid).sum::<Vec3>() / 5.0;
            for q in block.iter() {
                assert!(normal(q).dot(centroid(q) - inside) > 0.0, "{q:?}");
            }
        }
    }
}
