//! `prism._prism.Scene`: a loaded or built-in scene, its render settings from the file, and
//! the accelerator last built for it, kept so that rendering the same scene again (the next
//! tile on a Dask worker, the next frame of a camera move) does not build it again.

use crate::errors::{bad_argument, scene_error};
use crate::render::Rendered;
use crate::settings::Settings;
use prism::accel::{AccelSpec, SceneIntersector};
use prism::render::Tile;
use prism::scene::PreparedScene;
use prism::Scene;
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyDict, PyTuple};
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Duration;

/// An accelerator built for the scene, with what it was built as.
pub(crate) struct Built {
    spec: AccelSpec,
    intersector: SceneIntersector,
    build_time: Duration,
}

/// A scene ready to render from Python.
#[pyclass(name = "Scene", module = "prism._prism")]
pub(crate) struct PyScene {
    pub(crate) scene: Scene,
    /// Where it came from: the file's path, or builtin:NAME.
    name: String,
    /// The last accelerator built; None until a render, and after a change to the geometry
    /// or the materials (which say whether shadows look through surfaces).
    pub(crate) built: Mutex<Option<Built>>,
}

impl PyScene {
    fn new(scene: Scene, name: String) -> Self {
        PyScene {
            scene,
            name,
            built: Mutex::new(None),
        }
    }

    /// Forgets the accelerator, after a change it depends on.
    pub(crate) fn invalidate(&self) {
        *self.built.lock().unwrap_or_else(|e| e.into_inner()) = None;
    }

    /// The cached accelerator for `spec`, or a new one.
    fn take_built(&self, spec: &AccelSpec) -> Built {
        let cached = self.built.lock().unwrap_or_else(|e| e.into_inner()).take();
        match cached {
            Some(b) if &b.spec == spec => b,
            _ => {
                let p = self.scene.prepare(spec);
                Built {
                    spec: spec.clone(),
                    intersector: p.intersector,
                    build_time: p.build_time,
                }
            }
        }
    }
}

/// `region` as Python gives it, (x0, y0, x1, y1), or the whole image.
fn region_of(region: Option<(u32, u32, u32, u32)>, options: &prism::RenderOptions) -> Tile {
    match region {
        Some((x0, y0, x1, y1)) => Tile { x0, y0, x1, y1 },
        None => Tile::full(options.width, options.height),
    }
}

#[pymethods]
impl PyScene {
    /// Where the scene came from: its file, or builtin:NAME.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// The warnings the loader gave (a missing MTL file, a feature read but not rendered).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.scene.warnings.clone()
    }

    /// The image size the scene asks for, (width, height).
    #[getter]
    fn size(&self) -> (u32, u32) {
        (self.scene.options.width, self.scene.options.height)
    }

    /// Primitives, lights and materials, by count.
    fn info(&self) -> (usize, usize, usize) {
        (
            self.scene.geometry.primitives.len(),
            self.scene.lights.len(),
            self.scene.materials.len(),
        )
    }

    /// Renders, or only `region` = (x0, y0, x1, y1) of the image, with the settings given;
    /// returns (pixels as bytearray of f32 RGB, width, height, statistics as JSON).
    #[pyo3(signature = (*, width=None, height=None, spp=None, sampler=None, filter=None,
        accel=None, integrator=None, shadows=None, seed=None, threads=None, tile=None,
        depth=None, packets=None, region=None, settings=None))]
    #[allow(clippy::too_many_arguments)]
    fn render<'py>(
        &self,
        py: Python<'py>,
        width: Option<u32>,
        height: Option<u32>,
        spp: Option<u32>,
        sampler: Option<String>,
        filter: Option<String>,
        accel: Option<String>,
        integrator: Option<String>,
        shadows: Option<String>,
        seed: Option<u64>,
        threads: Option<usize>,
        tile: Option<u32>,
        depth: Option<u32>,
        packets: Option<bool>,
        region: Option<(u32, u32, u32, u32)>,
        settings: Option<Vec<(String, String)>>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let settings = Settings {
            width,
            height,
            spp,
            sampler,
            filter,
            accel,
            integrator,
            shadows,
            seed,
            threads,
            tile,
            depth,
            packets,
            others: settings.unwrap_or_default(),
        };
        let options = settings.apply(&self.scene.options)?;
        self.scene
            .validate()
            .map_err(|e| scene_error(format!("{}: the scene is not valid: {e}", self.name)))?;
        let region = region_of(region, &options);
        let built = py.allow_threads(|| self.take_built(&options.accel_to_build()));
        let prepared = PreparedScene {
            scene: &self.scene,
            intersector: built.intersector,
            build_time: built.build_time,
            has_transmissive: self.scene.materials.iter().any(|m| m.is_transmissive()),
        };
        let result = crate::render::render(py, &prepared, &options, region);
        // The accelerator goes back to the cache whether or not the render succeeded.
        *self.built.lock().unwrap_or_else(|e| e.into_inner()) = Some(Built {
            spec: built.spec,
            intersector: prepared.intersector,
            build_time: prepared.build_time,
        });
        let Rendered {
            pixels,
            width,
            height,
            stats,
        } = result?;
        PyTuple::new(
            py,
            [
                PyByteArray::new(py, &pixels).into_any(),
                width.into_pyobject(py)?.into_any(),
                height.into_pyobject(py)?.into_any(),
                stats.to_string().into_pyobject(py)?.into_any(),
            ],
        )
    }

    /// The camera: eye, look_at, up and fov (degrees).
    #[getter]
    fn camera<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::overrides::camera(py, &self.scene)
    }

    /// Moves the camera; what is not given stays. The accelerator is kept.
    #[pyo3(signature = (*, eye=None, look_at=None, up=None, fov=None))]
    fn set_camera(
        &mut self,
        eye: Option<[f32; 3]>,
        look_at: Option<[f32; 3]>,
        up: Option<[f32; 3]>,
        fov: Option<f32>,
    ) -> PyResult<()> {
        crate::overrides::set_camera(&mut self.scene, eye, look_at, up, fov)
    }

    /// The materials' names and coefficients.
    #[getter]
    fn materials<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        crate::overrides::materials(py, &self.scene)
    }

    /// Changes the coefficients of the material `name`; what is not given stays.
    #[pyo3(signature = (name, *, color=None, ambient=None, diffuse=None, specular=None,
        shininess=None, reflect=None, transmit=None, ior=None, emission=None))]
    #[allow(clippy::too_many_arguments)]
    fn set_material(
        &mut self,
        name: &str,
        color: Option<[f32; 3]>,
        ambient: Option<f32>,
        diffuse: Option<f32>,
        specular: Option<f32>,
        shininess: Option<f32>,
        reflect: Option<f32>,
        transmit: Option<[f32; 3]>,
        ior: Option<f32>,
        emission: Option<[f32; 3]>,
    ) -> PyResult<()> {
        let change = crate::overrides::MaterialChange {
            color,
            ambient,
            diffuse,
            specular,
            shininess,
            reflect,
            transmit,
            ior,
            emission,
        };
        crate::overrides::set_material(&mut self.scene, name, &change)?;
        // Emission and transparency decide which primitives are lights and what shadow
        // rays see through; the accelerator itself does not change, but start clean.
        self.invalidate();
        Ok(())
    }

    fn __repr__(&self) -> String {
        let (primitives, lights, materials) = self.info();
        format!(
            "<prism.Scene {} ({primitives} primitives, {lights} lights, {materials} materials)>",
            self.name
        )
    }
}

/// Loads a scene file (TOML, NFF, glTF/GLB, OBJ, PLY) by its extension.
#[pyfunction]
pub(crate) fn load(py: Python<'_>, path: PathBuf) -> PyResult<PyScene> {
    let scene = py
        .allow_threads(|| prism_io::scene::load(&path))
        .map_err(scene_error)?;
    Ok(PyScene::new(scene, path.display().to_string()))
}

/// Loads a scene file and lists every file the load read (the scene file first, then
/// meshes, libraries, buffers and textures), as paths joined onto the file's folder: what a
/// machine without this file system needs to load it (`prism.distributed`). Returns the
/// list and the image size the scene asks for.
#[pyfunction]
pub(crate) fn scene_files(py: Python<'_>, path: PathBuf) -> PyResult<(Vec<PathBuf>, (u32, u32))> {
    let (scene, files) = py.allow_threads(|| prism_io::scene::load_listing_files(&path));
    let scene = scene.map_err(scene_error)?;
    Ok((files, (scene.options.width, scene.options.height)))
}

/// A built-in scene by name (`builtins()` lists them; also sphereflake:N).
#[pyfunction]
pub(crate) fn builtin(name: &str) -> PyResult<PyScene> {
    match prism::scene::builtin::find(name) {
        Some(scene) => Ok(PyScene::new(scene, format!("builtin:{name}"))),
        None => Err(bad_argument(format!(
            "no built-in scene named '{name}'; available: {} (or sphereflake:N)",
            prism::scene::builtin::names().join(", ")
        ))),
    }
}

/// The built-in scenes' names and descriptions.
#[pyfunction]
pub(crate) fn builtins() -> Vec<(&'static str, &'static str)> {
    (prism::scene::builtin::BUILTINS.iter())
        .map(|b| (b.name, b.description))
        .collect()
}
