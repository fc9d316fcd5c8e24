//! The scene file as serde sees it: one struct per table, unknown keys rejected. Values
//! that later checks may need to point at are `Spanned`. docs/scene-format.md documents
//! every key; keep the two in step.
//!
//! Tagged tables (`type = "sphere"`) reach serde as externally tagged enums because
//! `tagged::retag` rewrites them first; serde's internally tagged enums would buffer the
//! table and lose the spans.

use super::values::{Direction, Finite, NonNegative, Point, Positive, Rgb, Scale2, Scale3, Uv};
use prism::options::RenderOptions;
use prism::shading::{FresnelMode, Highlight};
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Spanned;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneDef {
    pub render: Option<Spanned<RenderOptions>>,
    pub camera: Option<Spanned<CameraDef>>,
    #[serde(default)]
    pub world: WorldDef,
    #[serde(default)]
    pub materials: BTreeMap<String, Spanned<MaterialDef>>,
    #[serde(default)]
    pub lights: Vec<Spanned<LightDef>>,
    #[serde(default)]
    pub objects: Vec<Spanned<ObjectDef>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraDef {
    pub eye: Option<Spanned<Point>>,
    pub look_at: Option<Spanned<Point>>,
    pub up: Option<Spanned<Direction>>,
    pub fov: Option<Spanned<Finite>>,
    /// Makes the camera orthographic, its view this many units across the shorter side.
    pub orthographic: Option<Spanned<Finite>>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct WorldDef {
    pub background: Option<Rgb>,
    pub ambient: Option<Rgb>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialDef {
    pub color: Option<Rgb>,
    pub texture: Option<Spanned<TextureDef>>,
    pub ambient: Option<NonNegative>,
    pub diffuse: Option<NonNegative>,
    pub specular: Option<NonNegative>,
    pub shininess: Option<NonNegative>,
    pub highlight: Option<Highlight>,
    pub reflect: Option<NonNegative>,
    /// A colour filter, or one number for a grey.
    pub transmit: Option<Rgb>,
    pub ior: Option<Positive>,
    pub fresnel: Option<FresnelMode>,
    /// Radiance emitted from the front side: an area light.
    pub emission: Option<Rgb>,
}

pub(super) const TEXTURE_TYPES: &[&str] = &["solid", "checker", "image"];

#[derive(Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum TextureDef {
    Solid(SolidDef),
    Checker(CheckerDef),
    Image(ImageDef),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SolidDef {
    pub color: Rgb,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CheckerDef {
    pub a: Rgb,
    pub b: Rgb,
    pub size: Option<Positive>,
    #[serde(default)]
    pub space: CheckerSpaceDef,
}

#[derive(Clone, Copy, Debug, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum CheckerSpaceDef {
    #[default]
    Uv,
    Solid,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ImageDef {
    pub path: Spanned<String>,
    pub scale: Option<Scale2>,
}

pub(super) const LIGHT_TYPES: &[&str] = &["point", "directional", "spot"];

#[derive(Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum LightDef {
    Point(PointLightDef),
    Directional(DirectionalLightDef),
    Spot(SpotLightDef),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PointLightDef {
    pub position: Point,
    pub color: Option<Rgb>,
    pub intensity: Option<NonNegative>,
}

/// A spot light: a point light shining along `direction` into a cone whose strength fades
/// from `inner_angle` to `outer_angle` (degrees from the axis).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SpotLightDef {
    pub position: Point,
    pub direction: Direction,
    pub inner_angle: Option<Spanned<NonNegative>>,
    pub outer_angle: Option<Spanned<NonNegative>>,
    pub color: Option<Rgb>,
    pub intensity: Option<NonNegative>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct DirectionalLightDef {
    pub direction: Direction,
    pub color: Option<Rgb>,
    pub intensity: Option<NonNegative>,
}

pub(super) const OBJECT_TYPES: &[&str] = &["sphere", "plane", "cylinder", "cone", "box", "mesh"];

#[derive(Debug, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum ObjectDef {
    Sphere(SphereDef),
    Plane(PlaneDef),
    Cylinder(CylinderDef),
    Cone(ConeDef),
    Box(BoxDef),
    Mesh(MeshDef),
}

impl ObjectDef {
    /// The material reference every object may carry.
    pub(super) fn material(&self) -> Option<&Spanned<String>> {
        match self {
            ObjectDef::Sphere(o) => o.material.as_ref(),
            ObjectDef::Plane(o) => o.material.as_ref(),
            ObjectDef::Cylinder(o) => o.material.as_ref(),
            ObjectDef::Cone(o) => o.material.as_ref(),
            ObjectDef::Box(o) => o.material.as_ref(),
            ObjectDef::Mesh(o) => o.material.as_ref(),
        }
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct SphereDef {
    pub center: Point,
    pub radius: Positive,
    #[serde(default)]
    pub inside_out: bool,
    pub material: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct PlaneDef {
    pub point: Point,
    pub normal: Direction,
    pub material: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct CylinderDef {
    pub base: Point,
    pub top: Point,
    pub radius: Positive,
    #[serde(default)]
    pub capped: bool,
    pub material: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct ConeDef {
    pub base: Point,
    pub base_radius: NonNegative,
    pub apex: Point,
    pub apex_radius: Option<NonNegative>,
    #[serde(default)]
    pub capped: bool,
    pub material: Option<Spanned<String>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct BoxDef {
    pub min: Point,
    pub max: Point,
    pub material: Option<Spanned<String>>,
}

/// A mesh written out (`positions`, `indices`…) or read from a `file`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct MeshDef {
    /// An OBJ or PLY file, relative to the scene file; excludes the inline keys.
    pub file: Option<Spanned<String>>,
    pub positions: Option<Vec<Point>>,
    /// Faces: three or more vertex indices each, fanned into triangles.
    pub indices: Option<Vec<Spanned<Vec<u32>>>>,
    pub normals: Option<Spanned<Vec<Direction>>>,
    pub uvs: Option<Spanned<Vec<Uv>>>,
    pub transform: Option<TransformDef>,
    pub material: Option<Spanned<String>>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct TransformDef {
    pub translate: Option<Point>,
    /// Degrees about x, then y, then z.
    pub rotate: Option<Point>,
    pub scale: Option<Scale3>,
}
