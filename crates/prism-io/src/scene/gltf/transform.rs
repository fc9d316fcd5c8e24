//! Node transforms: a node's `matrix` or its translation, rotation and scale (T·R·S),
//! composed from the root down in f64 so deep hierarchies do not accumulate f32 rounding,
//! and what a world transform does to points, normals and winding.

use glam::{DAffine3, DMat3, DMat4, DQuat, DVec3};
use gltf::json::scene::Node;
use prism::math::Vec3;

/// A node's transform relative to its parent. Only the affine part of a `matrix` is used
/// (glTF requires node matrices to be affine).
pub(super) fn local(node: &Node) -> Result<DAffine3, String> {
    let finite = |values: &[f32], what: &str| {
        if values.iter().all(|v| v.is_finite()) {
            Ok(())
        } else {
            Err(format!("its {what} has a non-finite value"))
        }
    };
    if let Some(m) = &node.matrix {
        finite(m, "matrix")?;
        let cols = m.map(f64::from);
        return Ok(DAffine3::from_mat4(DMat4::from_cols_array(&cols)));
    }
    let t = node.translation.unwrap_or([0.0; 3]);
    let s = node.scale.unwrap_or([1.0; 3]);
    let r = node.rotation.as_ref().map_or([0.0, 0.0, 0.0, 1.0], |q| q.0);
    finite(&t, "translation")?;
    finite(&s, "scale")?;
    finite(&r, "rotation")?;
    let [x, y, z, w] = r.map(f64::from);
    let q = DQuat::from_xyzw(x, y, z, w);
    // Exporters write unit quaternions to a few digits; renormalise rather than reject.
    if q.length_squared() == 0.0 {
        return Err("its rotation quaternion is zero".into());
    }
    Ok(DAffine3::from_scale_rotation_translation(
        DVec3::from(s.map(f64::from)),
        q.normalize(),
        DVec3::from(t.map(f64::from)),
    ))
}

/// A world transform applied to mesh data.
pub(super) struct Placement {
    affine: DAffine3,
    /// The inverse transpose of the linear part; `None` when it is singular.
    normal: Option<DMat3>,
}

impl Placement {
    pub(super) fn new(affine: DAffine3) -> Self {
        let det = affine.matrix3.determinant();
        let normal = (det != 0.0 && det.is_finite()).then(|| affine.matrix3.inverse().transpose());
        Placement { affine, normal }
    }

    pub(super) fn point(&self, p: Vec3) -> Vec3 {
        self.affine.transform_point3(p.as_dvec3()).as_vec3()
    }

    /// The transformed normal's direction, or `None` if the transform flattens space.
    /// Computed in f64 and normalised there, so scales of 1e-3 or 1e3 lose nothing.
    pub(super) fn normal(&self, n: Vec3) -> Option<Vec3> {
        let m = self.normal?;
        (m * n.as_dvec3()).try_normalize().map(|v| v.as_vec3())
    }

    /// The transformed direction of a vector in the surface (a tangent), through the
    /// linear part, normalised in f64; `None` if it collapses.
    pub(super) fn direction(&self, d: Vec3) -> Option<Vec3> {
        (self.affine.matrix3 * d.as_dvec3())
            .try_normalize()
            .map(|v| v.as_vec3())
    }

    pub(super) fn flattens(&self) -> bool {
        self.normal.is_none()
    }

    /// A transform with negative determinant mirrors: counter-clockwise faces turn
    /// clockwise, so their winding must be reversed to keep the outside outside.
    pub(super) fn mirrors(&self) -> bool {
        self.affine.matrix3.determinant() < 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normals_stay_perpendicular_under_non_uniform_scale() {
        let p = Placement::new(DAffine3::from_scale(DVec3::new(2.0, 1.0, 1.0)));
        // The plane x + y = 0 has normal (1, 1, 0); scaled by 2 in x it becomes x/2 + y = 0.
        let n = p.normal(Vec3::new(1.0, 1.0, 0.0)).unwrap();
        let expected = Vec3::new(0.5, 1.0, 0.0).normalize();
        assert!((n - expected).length() < 1e-6, "{n}");
        assert!(!p.mirrors());
        let mirror = Placement::new(DAffine3::from_scale(DVec3::new(-1.0, 1.0, 1.0)));
        assert!(mirror.mirrors());
        assert_eq!(mirror.normal(Vec3::X), Some(-Vec3::X));
        let flat = Placement::new(DAffine3::from_scale(DVec3::new(0.0, 1.0, 1.0)));
        assert!(flat.flattens());
    }
}
