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
    #[inline]
    pub fn new(ray: Ray) -> Self {
        let d = ray.dir.to_array();
        let inv_dir = d.map(|v| 1.0 / v);
        let (axes, shear) = watertight_axes(d, inv_dir);
        TraceRay::with_constants(ray, inv_dir, axes, shear)
    }

    /// The ray with constants computed elsewhere (a packet's SIMD lanes): `inv_dir` as
    /// `new` computes it, `axes` and `shear` as `watertight_axes` gives them.
    #[inline(always)]
    pub(crate) fn with_constants(
        ray: Ray,
        inv_dir: [f32; 3],
        axes: u32,
        shear: [f32; 3],
    ) -> TraceRay {
        let [kx, ky, kz] = permutation(axes);
        TraceRay {
            ray,
            inv_dir: Vec3::from_array(inv_dir),
            kx,
            ky,
            kz,
            shear: Vec3::from_array(shear),
        }
    }
}

/// The axes (kx, ky, kz) of a permutation as `watertight_axes` codes it.
#[inline(always)]
pub(crate) fn permutation(axes: u32) -> [usize; 3] {
    let axes = axes as usize;
    [axes & 3, axes >> 2 & 3, axes >> 4]
}

/// The watertight test's constants for direction `d` (`inv` = `1 / d` per axis): the axis
/// permutation as `kx | ky << 2 | kz << 4` (`kz` the dominant axis, `kx` and `ky` the
/// next ones cyclically, swapped when `d` runs toward negative `kz` so that the winding is
/// kept) and the shear `(d[kx] / d[kz], d[ky] / d[kz], 1 / d[kz])`. Choices as selects, not
/// branches or run-time indices into a `Vec3` (each a `match`), so that a packet's loop
/// over its rays vectorises (`accel/bvh/packet.rs`) and a single ray and a packet's lane
/// get the same constants bit for bit.
#[inline(always)]
pub(crate) fn watertight_axes(d: [f32; 3], inv: [f32; 3]) -> (u32, [f32; 3]) {
    const fn code(kx: u32, ky: u32, kz: u32) -> u32 {
        kx | ky << 2 | kz << 4
    }
    let a = d.map(f32::abs);
    let (x_dominant, y_dominant) = (a[0] >= a[1] && a[0] >= a[2], a[1] >= a[2]);
    // (d[kx], d[ky], d[kz]), 1 / d[kz], and the permutation before and after the swap.
    let (dx, dy, dz, inv_z, axes, swapped) = if x_dominant {
        (d[1], d[2], d[0], inv[0], code(1, 2, 0), code(2, 1, 0))
    } else if y_dominant {
        (d[2], d[0], d[1], inv[1], code(2, 0, 1), code(0, 2, 1))
    } else {
        (d[0], d[1], d[2], inv[2], code(0, 1, 2), code(1, 0, 2))
    };
    let negative = dz < 0.0;
    let (dx, dy) = if negative { (dy, dx) } else { (dx, dy) };
    // 1 / d[kz] is the inverse direction's own component: one division fewer.
    let axes = if negative { swapped } else { axes };
    (axes, [dx / dz, dy / dz, inv_z])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::hash::uniform;

    /// The constants as the watertight test's paper states them, with branches and
    /// indices: what `watertight_axes` must give bit for bit.
    fn reference(d: Vec3) -> ([usize; 3], Vec3) {
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
        let shear = Vec3::new(d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
        ([kx, ky, kz], shear)
    }

    #[test]
    fn constants_follow_the_dominant_axis_and_keep_the_winding() {
        let u = |k: u32| uniform(k, 0, 0, 0, 5) * 2.0 - 1.0;
        let mut dirs: Vec<Vec3> = (0..500)
            .map(|k| Vec3::new(u(3 * k), u(3 * k + 1), u(3 * k + 2)))
            .collect();
        // Ties between the largest components, zeros and signs on every axis, a NaN.
        for x in [-1.0f32, -0.5, 0.0, 0.5, 1.0] {
            for y in [-1.0f32, -0.5, 0.0, 0.5, 1.0] {
                for z in [-1.0f32, -0.5, 0.0, 0.5, 1.0] {
                    dirs.push(Vec3::new(x, y, z));
                }
            }
        }
        dirs.push(Vec3::new(0.3, f32::NAN, -0.2));
        for d in dirs {
            let t = TraceRay::new(Ray::new(Vec3::ZERO, d));
            let (k, shear) = reference(d);
            assert_eq!([t.kx, t.ky, t.kz], k, "{d:?}");
            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
            assert_eq!(bits(t.shear), bits(shear), "{d:?}");
            assert_eq!(bits(t.inv_dir), bits(d.recip()), "{d:?}");
        }
    }
}
