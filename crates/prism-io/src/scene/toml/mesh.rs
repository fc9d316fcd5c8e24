//! Inline meshes: faces fanned into triangles, optional normals and uvs, and the mesh
//! transform (scale, then rotate about x, y, z, then translate), which mesh files included
//! by `include` use too.

use super::diagnostics::Problem;
use super::schema::{MeshDef, TransformDef};
use glam::Mat3;
use prism::geometry::TriangleMesh;
use prism::math::Vec3;
use std::ops::Range;

/// The affine map of a `transform` table, and what it does to normals.
pub(super) struct Transform {
    rotation: Mat3,
    scale: Vec3,
    translate: Vec3,
}

impl Transform {
    pub(super) fn new(def: &TransformDef) -> Self {
        let r = def.rotate.map_or(Vec3::ZERO, |r| r.0);
        Transform {
            rotation: Mat3::from_rotation_z(r.z.to_radians())
                * Mat3::from_rotation_y(r.y.to_radians())
                * Mat3::from_rotation_x(r.x.to_radians()),
            scale: def.scale.map_or(Vec3::ONE, |s| s.0),
            translate: def.translate.map_or(Vec3::ZERO, |t| t.0),
        }
    }

    fn point(&self, p: Vec3) -> Vec3 {
        self.rotation * (self.scale * p) + self.translate
    }

    /// The inverse transpose of M = R·S is R·S⁻¹ (R orthonormal, S diagonal). Dividing by
    /// the scale relative to its smallest factor (≥ 1 in size) gives the same direction
    /// without overflow, and no determinant is ever formed.
    fn normal(&self, n: Vec3) -> Vec3 {
        let relative = self.scale / self.scale.abs().min_element();
        let m = self.rotation * (n / relative);
        (m / m.abs().max_element()).try_normalize().unwrap_or(n)
    }

    /// A mirroring transform turns counter-clockwise faces clockwise.
    fn mirrors(&self) -> bool {
        self.scale.x * self.scale.y * self.scale.z < 0.0
    }

    /// Moves a mesh that is already built, keeping its outside outside. Fails when a
    /// position overflows.
    pub(super) fn apply(&self, mesh: &mut TriangleMesh) -> Result<(), String> {
        mesh.transform(|p| self.point(p), |n| self.normal(n));
        if self.mirrors() {
            mesh.reverse_winding();
        }
        match mesh.positions().iter().position(|p| !p.is_finite()) {
            Some(i) => Err(format!(
                "the transform moves vertex {i} beyond the range of 32-bit floats; expected \
                 finite positions after the transform"
            )),
            None => Ok(()),
        }
    }
}

/// Builds the mesh of an `objects` entry whose table starts at `span`.
pub(super) fn mesh(def: MeshDef, span: Range<usize>) -> Result<TriangleMesh, Problem> {
    let (Some(positions), Some(indices)) = (def.positions, def.indices) else {
        return Err(Problem::at(
            span,
            "a mesh needs `positions` and `indices` (a mesh written out) or `file` (an OBJ or \
             PLY file)",
        ));
    };
    let count = positions.len();
    if indices.is_empty() {
        return Err(Problem::at(
            span,
            "a mesh needs at least one face: expected indices = [[i, j, k], …]",
        ));
    }
    let transform = def.transform.as_ref().map(Transform::new);
    let mirrored = transform.as_ref().is_some_and(Transform::mirrors);

    let mut triangles = Vec::new();
    for (face_index, face) in indices.iter().enumerate() {
        let vertices = face.get_ref();
        if vertices.len() < 3 {
            return Err(Problem::at(
                face.span(),
                format!(
                    "face {face_index} has {} vertices; expected at least 3",
                    vertices.len()
                ),
            ));
        }
        if let Some(&bad) = vertices.iter().find(|&&i| i as usize >= count) {
            return Err(Problem::at(
                face.span(),
                format!(
                    "face {face_index} refers to vertex {bad}, but the mesh has {count} \
                     positions: expected indices from 0 to {}",
                    count.saturating_sub(1)
                ),
            ));
        }
        // A fan around the first vertex: exact for convex polygons.
        for k in 1..vertices.len() - 1 {
            let (a, b, c) = (vertices[0], vertices[k], vertices[k + 1]);
            triangles.push(if mirrored { [a, c, b] } else { [a, b, c] });
        }
    }

    let check_count = |what: &str, n: usize, span: Range<usize>| {
        if n == count {
            Ok(())
        } else {
            Err(Problem::at(
                span,
                format!("expected one {what} per position ({count}), got {n}"),
            ))
        }
    };
    let mut normals: Option<Vec<Vec3>> = match def.normals {
        Some(n) => {
            check_count("normal", n.get_ref().len(), n.span())?;
            Some(n.into_inner().into_iter().map(|d| d.0).collect())
        }
        None => None,
    };
    let uvs = match def.uvs {
        Some(uv) => {
            check_count("uv", uv.get_ref().len(), uv.span())?;
            Some(uv.into_inner().into_iter().map(|t| t.0).collect())
        }
        None => None,
    };

    let mut positions: Vec<Vec3> = positions.into_iter().map(|p| p.0).collect();
    if let Some(t) = &transform {
        positions.iter_mut().for_each(|p| *p = t.point(*p));
        if let Some(ns) = &mut normals {
            ns.iter_mut().for_each(|n| *n = t.normal(*n));
        }
    }
    // The checks above leave only one failure: a transform that overflows a position.
    TriangleMesh::new(positions, triangles, normals, uvs).map_err(|e| {
        Problem::at(
            span,
            format!("invalid mesh: {e}; expected finite positions after the transform"),
        )
    })
}
