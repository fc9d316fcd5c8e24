//! Changing a scene from Python before a render: the camera (for a camera move or an
//! animation's frames) and the materials' coefficients (for a parameter sweep). Each change
//! is checked as the loaders check a file's values, so a bad number is a `ValueError` here
//! rather than a strange picture later.

use crate::errors::bad_argument;
use prism::math::{Color, Vec3};
use prism::shading::{Material, Texture};
use prism::Scene;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A point or direction from a 3-sequence of finite numbers.
fn vec3(name: &str, v: [f32; 3]) -> PyResult<Vec3> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(Vec3::from_array(v))
    } else {
        Err(bad_argument(format!(
            "{name} must be three finite numbers, got {v:?}"
        )))
    }
}

/// A colour from a 3-sequence of finite numbers, none negative.
fn color(name: &str, v: [f32; 3]) -> PyResult<Color> {
    if v.iter().all(|x| x.is_finite() && *x >= 0.0) {
        Ok(Color::from_array(v))
    } else {
        Err(bad_argument(format!(
            "{name} must be three finite numbers of at least 0, got {v:?}"
        )))
    }
}

/// The camera as a dict: eye, look_at, up (lists of three) and fov (degrees).
pub(crate) fn camera<'py>(py: Python<'py>, scene: &Scene) -> PyResult<Bound<'py, PyDict>> {
    let c = &scene.camera;
    let d = PyDict::new(py);
    d.set_item("eye", c.eye.to_array())?;
    d.set_item("look_at", c.look_at.to_array())?;
    d.set_item("up", c.up.to_array())?;
    d.set_item("fov", c.fov_degrees)?;
    Ok(d)
}

/// Moves the camera; what is not given stays. Refuses a camera that cannot make rays.
pub(crate) fn set_camera(
    scene: &mut Scene,
    eye: Option<[f32; 3]>,
    look_at: Option<[f32; 3]>,
    up: Option<[f32; 3]>,
    fov: Option<f32>,
) -> PyResult<()> {
    let mut c = scene.camera;
    if let Some(v) = eye {
        c.eye = vec3("eye", v)?;
    }
    if let Some(v) = look_at {
        c.look_at = vec3("look_at", v)?;
    }
    if let Some(v) = up {
        c.up = vec3("up", v)?;
    }
    if let Some(v) = fov {
        c.fov_degrees = v;
    }
    c.validate()
        .map_err(|e| bad_argument(format!("camera: {e}")))?;
    scene.camera = c;
    Ok(())
}

/// The materials as dicts of their coefficients (the colour only where it is solid).
pub(crate) fn materials<'py>(py: Python<'py>, scene: &Scene) -> PyResult<Vec<Bound<'py, PyDict>>> {
    scene
        .materials
        .iter()
        .map(|m| {
            let d = PyDict::new(py);
            d.set_item("name", &m.name)?;
            if let Texture::Solid(c) = &m.color {
                d.set_item("color", c.to_array())?;
            }
            d.set_item("ambient", m.ambient)?;
            d.set_item("diffuse", m.diffuse)?;
            d.set_item("specular", m.specular)?;
            d.set_item("shininess", m.shininess)?;
            d.set_item("reflect", m.reflect)?;
            d.set_item("transmit", m.transmit.to_array())?;
            d.set_item("ior", m.ior)?;
            d.set_item("emission", m.emission.to_array())?;
            Ok(d)
        })
        .collect()
}

/// The changes `set_material` takes, each None when not given.
pub(crate) struct MaterialChange {
    pub(crate) color: Option<[f32; 3]>,
    pub(crate) ambient: Option<f32>,
    pub(crate) diffuse: Option<f32>,
    pub(crate) specular: Option<f32>,
    pub(crate) shininess: Option<f32>,
    pub(crate) reflect: Option<f32>,
    pub(crate) transmit: Option<[f32; 3]>,
    pub(crate) ior: Option<f32>,
    pub(crate) emission: Option<[f32; 3]>,
}

/// What a coefficient accepts.
#[derive(Clone, Copy)]
enum Bounds {
    /// 0 to 1.
    Unit,
    /// 0 or more, no upper bound.
    NonNegative,
    /// More than 0, no upper bound.
    Positive,
}

impl Bounds {
    fn contains(self, v: f32) -> bool {
        v.is_finite()
            && match self {
                Bounds::Unit => (0.0..=1.0).contains(&v),
                Bounds::NonNegative => v >= 0.0,
                Bounds::Positive => v > 0.0,
            }
    }

    /// The range in words; a missing upper bound is said, not printed as `f32::MAX`.
    fn text(self) -> &'static str {
        match self {
            Bounds::Unit => "between 0 and 1",
            Bounds::NonNegative => "a finite number of at least 0 (no upper bound)",
            Bounds::Positive => "a finite number greater than 0 (no upper bound)",
        }
    }
}

/// A coefficient within `bounds`, or a `ValueError` saying the range.
fn within(name: &str, v: f32, bounds: Bounds) -> PyResult<f32> {
    if bounds.contains(v) {
        Ok(v)
    } else {
        Err(bad_argument(format!(
            "{name} must be {}, got {v}",
            bounds.text()
        )))
    }
}

/// Changes the material named `name` (every material of that name).
pub(crate) fn set_material(scene: &mut Scene, name: &str, change: &MaterialChange) -> PyResult<()> {
    let found: Vec<usize> = (scene.materials.iter().enumerate())
        .filter(|(_, m)| m.name == name)
        .map(|(i, _)| i)
        .collect();
    if found.is_empty() {
        let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
        return Err(bad_argument(format!(
            "no material named '{name}'; the scene has: {}",
            names.join(", ")
        )));
    }
    let mut changed: Material = scene.materials[found[0]].clone();
    let m = &mut changed;
    if let Some(v) = change.color {
        m.color = Texture::Solid(color("color", v)?);
    }
    if let Some(v) = change.ambient {
        m.ambient = within("ambient", v, Bounds::NonNegative)?;
    }
    if let Some(v) = change.diffuse {
        m.diffuse = within("diffuse", v, Bounds::NonNegative)?;
    }
    if let Some(v) = change.specular {
        m.specular = within("specular", v, Bounds::NonNegative)?;
    }
    if let Some(v) = change.shininess {
        m.shininess = within("shininess", v, Bounds::NonNegative)?;
    }
    if let Some(v) = change.reflect {
        m.reflect = within("reflect", v, Bounds::Unit)?;
    }
    if let Some(v) = change.transmit {
        m.transmit = color("transmit", v)?;
    }
    if let Some(v) = change.ior {
        m.ior = within("ior", v, Bounds::Positive)?;
    }
    if let Some(v) = change.emission {
        m.emission = color("emission", v)?;
    }
    for i in found {
        // Each keeps its own colour texture unless a colour was given.
        let mut next = changed.clone();
        if change.color.is_none() {
            next.color = scene.materials[i].color.clone();
        }
        scene.materials[i] = next;
    }
    Ok(())
}
