//! `[[objects]]` entries to shapes in the scene's `Geometry`.

use super::diagnostics::Problem;
use super::mesh::mesh;
use super::schema::{ConeDef, ObjectDef};
use prism::geometry::{AaBox, Cone, Geometry, Plane, Shape, Sphere};
use std::ops::Range;

/// Adds the object whose table starts at `span`, with material index `material`.
pub(super) fn add_object(
    geometry: &mut Geometry,
    def: ObjectDef,
    span: Range<usize>,
    material: u32,
) -> Result<(), Problem> {
    let shape = match def {
        ObjectDef::Sphere(s) => Shape::Sphere(Sphere {
            center: s.center.0,
            radius: s.radius.0,
            inside_out: s.inside_out,
        }),
        ObjectDef::Plane(p) => Shape::Plane(Box::new(
            Plane::new(p.point.0, p.normal.0)
                .ok_or_else(|| Problem::at(span, "expected a plane normal of non-zero length"))?,
        )),
        ObjectDef::Cylinder(c) => {
            if c.base.0 == c.top.0 {
                return Err(Problem::at(
                    span,
                    "the cylinder's base and top coincide; expected two distinct points",
                ));
            }
            Shape::Cone(Box::new(
                Cone::cylinder(c.base.0, c.top.0, c.radius.0, c.capped).ok_or_else(|| {
                    Problem::at(span, "expected a cylinder axis of finite length")
                })?,
            ))
        }
        ObjectDef::Cone(c) => Shape::Cone(Box::new(cone(&c, span)?)),
        ObjectDef::Box(b) => {
            if b.min.0.cmpgt(b.max.0).any() {
                return Err(Problem::at(
                    span,
                    format!(
                        "expected min ≤ max on every axis, got min = {} and max = {}",
                        b.min.0, b.max.0
                    ),
                ));
            }
            Shape::Box(Box::new(AaBox::new(b.min.0, b.max.0)))
        }
        ObjectDef::Mesh(m) => {
            geometry.add_mesh(mesh(m, span)?, material);
            return Ok(());
        }
    };
    geometry.add(shape, material);
    Ok(())
}

fn cone(c: &ConeDef, span: Range<usize>) -> Result<Cone, Problem> {
    let apex_radius = c.apex_radius.map_or(0.0, |r| r.0);
    if c.base.0 == c.apex.0 {
        return Err(Problem::at(
            span,
            "the cone's base and apex coincide; expected two distinct points",
        ));
    }
    if c.base_radius.0 == 0.0 && apex_radius == 0.0 {
        return Err(Problem::at(
            span,
            "a cone with both radii 0 is a line: expected base_radius or apex_radius > 0",
        ));
    }
    Cone::new(c.base.0, c.base_radius.0, c.apex.0, apex_radius, c.capped)
        .ok_or_else(|| Problem::at(span, "expected a cone axis of finite length"))
}
