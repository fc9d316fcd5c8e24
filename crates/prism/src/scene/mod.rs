//! `Scene` is plain data: camera, lights, materials, shapes and the render options the
//! scene suggests. The built-ins (`builtin`) and the file loaders of prism-io produce it;
//! `prepare` builds what rendering needs.

pub mod builtin;
mod scale;

use crate::accel::{AccelSpec, SceneIntersector};
use crate::camera::{Camera, Projection};
use crate::geometry::Geometry;
use crate::light::Light;
use crate::math::{Color, Vec3};
use crate::options::RenderOptions;
use crate::shading::Material;
use std::time::{Duration, Instant};

#[derive(Clone, Debug)]
pub struct Scene {
    pub camera: Camera,
    /// Radiance of rays that hit nothing.
    pub background: Color,
    /// Ia, the ambient light every surface receives (scaled by its ka).
    pub ambient: Color,
    pub lights: Vec<Light>,
    pub materials: Vec<Material>,
    pub geometry: Geometry,
    /// Settings the scene asks for (size, depth…); the CLI may override them.
    pub options: RenderOptions,
    /// What the loader read but could not use, or had to guess (a missing MTL file, a
    /// feature prism does not render), one sentence each naming the file. The scene still
    /// renders; the CLI prints these, and `--strict` makes them errors.
    pub warnings: Vec<String>,
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SceneError {
    #[error(transparent)]
    Camera(#[from] crate::camera::CameraError),
    #[error("primitive {prim} uses material {material}, but only {count} materials exist")]
    MissingMaterial {
        prim: usize,
        material: u32,
        count: usize,
    },
}

impl Default for Scene {
    fn default() -> Self {
        Scene {
            camera: Camera {
                eye: Vec3::new(0.0, 0.0, 5.0),
                look_at: Vec3::ZERO,
                up: Vec3::Y,
                fov_degrees: 45.0,
                projection: Projection::Perspective,
            },
            background: Color::ZERO,
            ambient: Color::splat(0.1),
            lights: Vec::new(),
            materials: Vec::new(),
            geometry: Geometry::default(),
            options: RenderOptions::default(),
            warnings: Vec::new(),
        }
    }
}

impl Scene {
    /// Adds a material and returns its index for primitives to use.
    pub fn add_material(&mut self, material: Material) -> u32 {
        self.materials.push(material);
        self.materials.len() as u32 - 1
    }

    pub fn validate(&self) -> Result<(), SceneError> {
        self.camera.validate()?;
        let count = self.materials.len();
        if let Some((prim, p)) = self
            .geometry
            .primitives
            .iter()
            .enumerate()
            .find(|(_, p)| p.material as usize >= count)
        {
            return Err(SceneError::MissingMaterial {
                prim,
                material: p.material,
                count,
            });
        }
        Ok(())
    }

    /// Builds the acceleration structure; the scene itself is not changed.
    pub fn prepare(&self, accel: &AccelSpec) -> PreparedScene<'_> {
        let start = Instant::now();
        let intersector = SceneIntersector::build(&self.geometry, accel);
        PreparedScene {
            scene: self,
            intersector,
            build_time: start.elapsed(),
            has_transmissive: self.materials.iter().any(Material::is_transmissive),
        }
    }
}

/// A scene ready to trace: the data plus its acceleration structure.
pub struct PreparedScene<'a> {
    pub scene: &'a Scene,
    pub intersector: SceneIntersector,
    pub build_time: Duration,
    /// Whether shadow rays must look through transparent surfaces.
    pub has_transmissive: bool,
}
