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

/// A scene as plain data: everything a render needs, nothing derived (see `prepare`).
#[derive(Clone, Debug)]
pub struct Scene {
    /// Where the picture is taken from.
    pub camera: Camera,
    /// Radiance of rays that hit nothing.
    pub background: Color,
    /// Ia, the ambient light every surface receives (scaled by its ka).
    pub ambient: Color,
    /// Every light source.
    pub lights: Vec<Light>,
    /// Materials, referred to by index from the primitives.
    pub materials: Vec<Material>,
    /// Every shape.
    pub geometry: Geometry,
    /// Settings the scene asks for (size, depth…); the CLI may override them.
    pub options: RenderOptions,
    /// What the loader read but could not use, or had to guess (a missing MTL file, a
    /// feature prism does not render), one sentence each naming the file. The scene still
    /// renders; the CLI prints these, and `--strict` makes them errors.
    pub warnings: Vec<String>,
}

/// Why a scene cannot be rendered as it is.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SceneError {
    /// The camera defines no view.
    #[error(transparent)]
    Camera(#[from] crate::camera::CameraError),
    /// A primitive names a material that does not exist.
    #[error("primitive {prim} uses material {material}, but only {count} materials exist")]
    MissingMaterial {
        /// The primitive's index.
        prim: usize,
        /// The material index it names.
        material: u32,
        /// How many materials the scene has.
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

    /// Checks what loaders cannot rule out by construction: a usable camera and material indices in
    /// range.
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

    /// Builds the acceleration structure `options` ask for, for their integrator
    /// (`RenderOptions::accel_to_build`); the scene itself is not changed.
    pub fn prepare_for(&self, options: &RenderOptions) -> PreparedScene<'_> {
        self.prepare(&options.accel_to_build())
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
    /// The scene.
    pub scene: &'a Scene,
    /// The accelerator over its bounded primitives, with the unbounded ones beside it.
    pub intersector: SceneIntersector,
    /// How long building the accelerator took.
    pub build_time: Duration,
    /// Whether shadow rays must look through transparent surfaces.
    pub has_transmissive: bool,
}
