//! MikkTSpace tangents (the `mikktspace` crate, the reference port) for primitives whose
//! material has a normal texture but whose file gives no TANGENT: the frame normal maps are
//! usually baked against, averaged across the triangles that share a vertex.
//!
//! MikkTSpace gives one tangent per triangle corner. Corners of one vertex agree unless the
//! vertex lies on a seam (a change of handedness, or of uv direction too sharp to average);
//! there the vertex is copied, one copy per tangent, so that each keeps its own.

use prism::math::{Vec2, Vec3, Vec4};
use std::collections::HashMap;

/// The tangents of a primitive's corners, as MikkTSpace reports them.
struct Corners<'a> {
    positions: &'a [Vec3],
    normals: &'a [Vec3],
    uvs: &'a [Vec2],
    triangles: &'a [[u32; 3]],
    tangents: Vec<[[f32; 4]; 3]>,
}

impl Corners<'_> {
    fn vertex(&self, face: usize, corner: usize) -> usize {
        self.triangles[face][corner] as usize
    }
}

impl mikktspace::Geometry for Corners<'_> {
    fn num_faces(&self) -> usize {
        self.triangles.len()
    }

    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }

    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.positions[self.vertex(face, vert)].to_array()
    }

    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.normals[self.vertex(face, vert)].to_array()
    }

    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.uvs[self.vertex(face, vert)].to_array()
    }

    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        self.tangents[face][vert] = tangent;
    }
}

/// One tangent per vertex (xyz, handedness w) for `triangles`, from positions, unit
/// normals and uvs (prism's, v up the image, as MikkTSpace's bakers use); vertices whose
/// corners get different tangents are copied (appended to `positions`, `normals` and `uvs`,
/// and `triangles` renumbered). None where the input is not finite or MikkTSpace fails;
/// the normal map then keeps each triangle's uv frame.
pub(super) fn generate(
    positions: &mut Vec<Vec3>,
    normals: &mut Vec<Vec3>,
    uvs: &mut Vec<Vec2>,
    triangles: &mut [[u32; 3]],
) -> Option<Vec<Vec4>> {
    let finite = positions.iter().all(|p| p.is_finite())
        && normals.iter().all(|n| n.is_finite())
        && uvs.iter().all(|t| t.is_finite());
    if !finite || triangles.is_empty() {
        return None;
    }
    let unit: Vec<Vec3> = normals
        .iter()
        .map(|n| n.try_normalize().unwrap_or(Vec3::Z))
        .collect();
    let mut corners = Corners {
        positions,
        normals: &unit,
        uvs,
        triangles,
        tangents: vec![[[1.0, 0.0, 0.0, 1.0]; 3]; triangles.len()],
    };
    if !mikktspace::generate_tangents(&mut corners) {
        return None;
    }
    let corner_tangents = corners.tangents;
    let mut tangents: Vec<Option<Vec4>> = vec![None; positions.len()];
    let mut copies: HashMap<(u32, [u32; 4]), u32> = HashMap::new();
    for (tri, per_corner) in triangles.iter_mut().zip(corner_tangents) {
        for (v, t) in tri.iter_mut().zip(per_corner) {
            let t = Vec4::from_array(t);
            let i = *v as usize;
            match tangents[i] {
                None => tangents[i] = Some(t),
                Some(have) if have == t => {}
                Some(_) => {
                    let key = (*v, t.to_array().map(f32::to_bits));
                    *v = *copies.entry(key).or_insert_with(|| {
                        positions.push(positions[i]);
                        normals.push(normals[i]);
                        uvs.push(uvs[i]);
                        tangents.push(Some(t));
                        (positions.len() - 1) as u32
                    });
                }
            }
        }
    }
    // Vertices no triangle uses keep a placeholder; no hit reads them.
    Some(
        tangents
            .into_iter()
            .map(|t| t.unwrap_or(Vec4::new(1.0, 0.0, 0.0, 1.0)))
            .collect(),
    )
}
