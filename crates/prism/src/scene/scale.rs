//! Uniform scaling of a whole scene about the origin. Nothing in prism may depend on the
//! units a scene is modelled in, and this is how the tests hold it to that: the same scene
//! at 1e-3 and 1e3 must render the same picture.

use super::Scene;
use crate::camera::Projection;
use crate::geometry::{AaBox, Cone, Plane, Shape, Sphere};
use crate::light::Light;
use crate::shading::{CheckerSpace, Texture};

impl Scene {
    /// The scene scaled by `factor` about the origin: shapes, the camera and point lights
    /// move and grow; directions, angles, colours and light intensities (which have no
    /// falloff) stay, so the image is the same up to rounding. Solid (world-space) checkers
    /// scale along. Textures in uv space keep their uv, except that a plane's uv are world
    /// distances, so uv checkers on planes do not follow the scale.
    ///
    /// `None` unless `factor` is positive and finite, or if a shape degenerates in f32
    /// (a cone's height or radius under- or overflowing).
    pub fn scaled(&self, factor: f32) -> Option<Scene> {
        if !(factor > 0.0 && factor.is_finite()) {
            return None;
        }
        let mut scene = self.clone();
        scene.camera.eye *= factor;
        scene.camera.look_at *= factor;
        if let Projection::Orthographic { size } = &mut scene.camera.projection {
            *size *= factor;
        }
        for light in &mut scene.lights {
            if let Light::Point { position, .. } | Light::Spot { position, .. } = light {
                *position *= factor;
            }
        }
        for material in &mut scene.materials {
            if let Texture::Checker(c) = &mut material.color {
                if c.space == CheckerSpace::Solid {
                    c.size *= factor;
                }
            }
        }
        for mesh in &mut scene.geometry.meshes {
            mesh.transform(|p| p * factor, |n| n);
        }
        for prim in &mut scene.geometry.primitives {
            let scaled = match &prim.shape {
                Shape::Sphere(s) => Shape::Sphere(Sphere {
                    center: s.center * factor,
                    radius: s.radius * factor,
                    inside_out: s.inside_out,
                }),
                // Moved with their mesh above.
                Shape::Triangle { .. } => continue,
                Shape::Plane(p) => {
                    Shape::Plane(Box::new(Plane::new(p.point * factor, p.normal())?))
                }
                Shape::Cone(c) => Shape::Cone(Box::new(Cone::new(
                    c.base * factor,
                    c.base_radius * factor,
                    c.apex * factor,
                    c.apex_radius * factor,
                    c.capped,
                )?)),
                Shape::Box(b) => Shape::Box(Box::new(AaBox::new(b.min * factor, b.max * factor))),
            };
            prim.shape = scaled;
        }
        Some(scene)
    }
}
