//! Normal maps: a texture whose texels are directions in the surface's tangent frame
//! (glTF's `normalTexture`, MTL's `norm`), turning the shading normal per texel so that flat
//! triangles show the detail of the surface they stand for. Where the mesh has per-vertex
//! tangents (glTF's `TANGENT`, or ones the glTF loader generates with MikkTSpace for a
//! primitive with a normal texture, normals and uvs but no `TANGENT`), the frame is theirs:
//! z the shading normal, x the tangent interpolated across the triangle, made orthogonal to z
//! and normalised, y = w · (z × x) with w the tangent's handedness. Without tangents the
//! frame is the one the uvs give the triangle: x along ∂p/∂u, y along ∂p/∂v (the image's up,
//! as OpenGL-style maps and glTF's expect), z along the interpolated normal; it is each
//! triangle's own, as MikkTSpace's is before it averages across vertices, so seams between
//! triangles with different uv directions can show where a map was baked against averaged
//! tangents.
//!
//! Bump maps (MTL's `bump` and `map_Bump`) hold heights instead: the surface is taken as
//! displaced along its normal by the height times a scale, and the shading normal becomes
//! the displaced surface's, n − ∇h (Blinn 1978), with ∇h the height's gradient on the
//! tangent plane found from differences of the texture one texel apart in u and in v.

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
        let Some(t) = (dpdu - ns * ns.dot(dpdu)).try_normalize() else {
            return ns;
        };
        // The bitangent follows ∂p/∂v's side, so mirrored uvs keep the map's y.
        let b = if ns.cross(t).dot(dpdv) < 0.0 {
            -ns.cross(t)
        } else {
            ns.cross(t)
        };
        self.perturb_in_frame(ns, t, b, uv)
    }

    /// `ns` turned by the map's direction at `uv` in the frame of unit tangent `t` and
    /// bitangent `b` (both orthogonal to `ns`); `ns` itself where the result degenerates.
    pub fn perturb_in_frame(&self, ns: Vec3, t: Vec3, b: Vec3, uv: Vec2) -> Vec3 {
        let c = self.texture.eval(uv);
        let m = Vec3::new(
            (2.0 * c.x - 1.0) * self.scale,
            (2.0 * c.y - 1.0) * self.scale,
            2.0 * c.z - 1.0,
        );
        (t * m.x + b * m.y + ns * m.z).try_normalize().unwrap_or(ns)
    }
}

/// A height texture and the scale that turns its values into lengths along the normal.
#[derive(Clone, Debug, PartialEq)]
pub struct BumpMap {
    /// The heights, linear, in the red channel.
    pub texture: ImageTexture,
    /// MTL's `-bm`: a texel's value times this is its height in the scene's units.
    pub scale: f32,
}

impl BumpMap {
    /// `ns` turned as the displaced surface's normal at `uv`, with ∂p/∂u and ∂p/∂v of
    /// the undisplaced one; `ns` itself where the frame degenerates.
    pub fn perturb(&self, ns: Vec3, dpdu: Vec3, dpdv: Vec3, uv: Vec2) -> Vec3 {
        // One texel apart, as the image repeats in uv: central differences, exact for
        // heights that vary linearly between texel centres.
        let (w, h) = self.texture.size();
        let step = Vec2::ONE / (Vec2::new(w as f32, h as f32) * self.texture.scale);
        let height = |d: Vec2| self.texture.eval(uv + d).x;
        let dhdu =
            (height(Vec2::new(step.x, 0.0)) - height(Vec2::new(-step.x, 0.0))) / (2.0 * step.x);
        let dhdv =
            (height(Vec2::new(0.0, step.y)) - height(Vec2::new(0.0, -step.y))) / (2.0 * step.y);
        // The gradients of u and v on the tangent plane: the dual basis of ∂p/∂u and
        // ∂p/∂v projected onto it.
        let a = dpdu - ns * ns.dot(dpdu);
        let b = dpdv - ns * ns.dot(dpdv);
        let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
        let det = aa * bb - ab * ab;
        if !(det > 0.0 && det.is_finite()) {
            return ns;
        }
        let grad_u = (a * bb - b * ab) / det;
        let grad_v = (b * aa - a * ab) / det;
        let gradient = self.scale * (dhdu * grad_u + dhdv * grad_v);
        (ns - gradient).try_normalize().unwrap_or(ns)
    }
}

/// Turns `sp`'s shading normal by `material`'s normal map or bump map, where it has one
/// and the hit primitive `prim` is a triangle with tangents or uvs (a bump map, which needs
/// uvs, after a normal map, where it has both); the normal stays in the geometric normal's hemisphere (a map
/// cannot turn a surface's shading past its silhouette).
#[inline]
pub fn apply(material: &Material, geometry: &Geometry, prim: u32, sp: &mut SurfacePoint) {
    if material.normal_map.is_none() && material.bump_map.is_none() {
        return;
    }
    let Shape::Triangle { mesh, index } = geometry.primitives[prim as usize].shape else {
        return;
    };
    let mesh = &geometry.meshes[mesh as usize];
    let derivatives = mesh.uv_derivatives(index);
    let mut n = sp.ns;
    let mut turned = false;
    if let Some(map) = &material.normal_map {
        if let Some((t, b)) = mesh.tangent_frame(index, sp.p, n) {
            n = map.perturb_in_frame(n, t, b, sp.uv);
            turned = true;
        } else if let Some((dpdu, dpdv)) = derivatives {
            n = map.perturb(n, dpdu, dpdv, sp.uv);
            turned = true;
        }
    }
    if let (Some(map), Some((dpdu, dpdv))) = (&material.bump_map, derivatives) {
        n = map.perturb(n, dpdu, dpdv, sp.uv);
        turned = true;
    }
    if !turned {
        return;
    }
    // Keep it on the front side of the geometric normal, as interpolated normals are kept.
    let d = n.dot(sp.ng);
    sp.ns = if d > 0.0 {
        n
    } else {
        (n - sp.ng * (d - 1e-3)).try_normalize().unwrap_or(sp.ns)
    };
}
