//! Orthonormal frames, for local coordinates of shapes and for camera bases.

use glam::Vec3;

/// An orthonormal basis: three unit axes at right angles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First axis.
    pub x: Vec3,
    /// Second axis.
    pub y: Vec3,
    /// Third axis; the normal for frames built from one.
    pub z: Vec3,
}

impl Frame {
    /// A frame whose z axis is `n` (unit length). Duff et al. 2017, branchless and
    /// continuous except on the -z pole, where it stays orthonormal.
    pub fn from_z(n: Vec3) -> Frame {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let x = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let y = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Frame { x, y, z: n }
    }

    /// World vector `v` in this frame's coordinates.
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }

    /// Vector `v`, given in this frame's coordinates, in world coordinates.
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        v.x * self.x + v.y * self.y + v.z * self.z
    }
}
