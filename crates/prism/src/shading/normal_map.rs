//! Normal maps: a texture whose texels are directions in the surface's tangent frame
//! (glTF's `normalTexture`, MTL's `norm`), turning the shading normal per texel so that flat
//! triangles show the detail of the surface they stand for. The frame is the one the uvs
//! give the triangle: x along ∂p/∂u, y along ∂p/∂v (the image's up, as OpenGL-style maps
//! and glTF's expect), z along the interpolated normal. Without tangents in the file this
//! frame is each triangle's own, as MikkTSpace's is before it averages across vertices:
//! seams between triangles with different uv directions can show where a map was baked
//! against averaged tangents.

use super::{ImageTexture, Material};
use crate::geometry::{Geometry, Shape, SurfacePoint};
use crate::math::{Vec2, Vec3};

/// A normal map and how strongly it turns the normal.
#[derive(Clone, Debug, PartialEq)]
pub struct NormalMap {
    /// The directions, as linear values in [0, 1] (each channel v stands for 2v − 1).
    pub texture: ImageTexture,
    /// glTF's `scale`: multiplies the x and y of each direction.
    pub scale: f32,
}

impl NormalMap {
    /// `ns` turned by the map's direction at `uv` in the frame of ∂p/∂u and ∂p/∂v; `ns`
    /// itself where the frame or the result degenerates.
    pub fn perturb(&self, ns: Vec3, dpdu: Vec3, dpdv: Vec3, uv: Vec2) -> Vec3 {
        let c = self.texture.eval(uv);
        let m = Vec3::new(
            (2.0 * c.x - 1.0) * self.scale,
            (2.0 * c.y - 1.0) * self.scale,
            2.0 * c.z - 1.0,
        );
        let Some(t) = (dpdu - ns * ns.dot(dpdu)).try_normalize() else {
            return ns;
        };
        // The bitangent follows ∂p/∂v's side, so mirrored uvs keep the map's y.
        let b = if ns.cross(t).dot(dpdv) < 0.0 {
            -ns.cross(t)
        } else {
            ns.cross(t)
        };
        (t * m.x + b * m.y + ns * m.z).try_normalize().unwrap_or(ns)
    }
}

/// Turns `sp`'s shading normal by `material`'s normal map, where it has one and the hit
/// primitive `prim` is a triangle with uvs; the normal stays in the geometric normal's
/// hemisphere (a map cannot turn a surface's shading past its silhouette).
#[inline]
pub fn apply(material: &Material, geometry: &Geometry, prim: u32, sp: &mut SurfacePoint) {
    let Some(map) = &material.normal_map else {
        return;
    };
    let Shape::Triangle { mesh, index } = geometry.primitives[prim as usize].shape else {
        return;
    };
    let Some((dpdu, dpdv)) = geometry.meshes[mesh as usize].uv_derivatives(index) else {
        return;
    };
    let n = map.perturb(sp.ns, dpdu, dpdv, sp.uv);
    // Keep it on the front side of the geometric normal, as interpolated normals are kept.
    let d = n.dot(sp.ng);
    sp.ns = if d > 0.0 {
        n
    } else {
        (n - sp.ng * (d - 1e-3)).try_normalize().unwrap_or(sp.ns)
    };
}
