//! Rays, and the per-ray constants that traversal and triangle tests precompute once.

use glam::Vec3;

/// A ray `origin + t * dir`. `dir` is unit length everywhere in prism, so `t` is a distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
}

impl Ray {
    /// A ray from `origin` along `dir` (which the caller keeps unit length).
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        Ray { origin, dir }
    }

    /// The point at distance `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}

/// A ray prepared for traversal: reciprocal direction for slab tests and the shear
/// constants of the watertight triangle test (Woop, Benthin, Wald 2013), computed once per
/// ray instead of once per node or triangle.
#[derive(Clone, Copy, Debug)]
pub struct TraceRay {
    /// The ray itself.
    pub ray: Ray,
    /// `1 / dir` per axis (±infinity for a zero component), for the slab test.
    pub inv_dir: Vec3,
    /// Axis permutation: `kz` is the dominant axis of `dir`; `kx`, `ky` keep winding.
    pub kx: usize,
    /// The axis that plays y after the permutation.
    pub ky: usize,
    /// The dominant axis of `dir`, which plays z.
    pub kz: usize,
    /// Shear that maps `dir` onto +z: `(dir[kx]/dir[kz], dir[ky]/dir[kz], 1/dir[kz])`.
    pub shear: Vec3,
}

impl TraceRay {
    /// Precomputes the traversal constants of `ray`.
    pub fn new(ray: Ray) -> Self {
        let d = ray.dir;
        let a = d.abs();
        let kz = if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let inv_dir = d.recip();
        // 1 / d[kz] is the inverse direction's own component: one division fewer.
        let shear = Vec3::new(d[kx] / d[kz], d[ky] / d[kz], inv_dir[kz]);
        TraceRay {
            ray,
            inv_dir,
            kx,
            ky,
            kz,
            shear,
        }
    }
}
