//! A primitive as the top-down builders move it: its box and its build position in 32
//! bytes. Partitioning moves the references themselves, so every later pass over a node
//! reads its primitives in order from one array. Indices into separate box and centroid
//! arrays, as before, cost two cache misses a primitive per pass once a node's
//! primitives were scattered by the partitions above it (a million-triangle build spent
//! most of its time there).

use crate::math::{Aabb, Vec3};
use glam::{Vec3A, Vec4};

#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub(super) struct PrimRef {
    /// The box's minimum in xyz; the build position's bits in w.
    lo: Vec4,
    /// The box's maximum in xyz; w is 0.
    hi: Vec4,
}

impl PrimRef {
    pub(super) fn new(index: u32, bounds: &Aabb) -> PrimRef {
        PrimRef {
            lo: bounds.min.extend(f32::from_bits(index)),
            hi: bounds.max.extend(0.0),
        }
    }

    /// The primitive's build position (into `BuildPrims::bounds`).
    #[inline(always)]
    pub(super) fn index(&self) -> u32 {
        self.lo.w.to_bits()
    }

    /// The box's minimum in a SIMD register. The lane holding the index is replaced,
    /// so arithmetic never meets its bits (small integers are denormal floats).
    #[inline(always)]
    pub(super) fn min(&self) -> Vec3A {
        Vec3A::from(self.lo.truncate())
    }

    #[inline(always)]
    pub(super) fn max(&self) -> Vec3A {
        Vec3A::from_vec4(self.hi)
    }

    /// The box's maximum with 0 in the fourth lane.
    #[inline(always)]
    pub(super) fn max4(&self) -> Vec4 {
        self.hi
    }

    /// The box's centre, bit for bit `Aabb::center` of its box.
    #[inline(always)]
    pub(super) fn centroid(&self) -> Vec3A {
        0.5 * (self.min() + self.max())
    }
}

/// A box in SIMD registers, for the builders' inner loops (`Aabb` keeps plain `Vec3`s).
#[derive(Clone, Copy, Debug)]
pub(super) struct SimdBox {
    pub min: Vec3A,
    pub max: Vec3A,
}

impl SimdBox {
    pub(super) const EMPTY: SimdBox = SimdBox {
        min: Vec3A::splat(f32::INFINITY),
        max: Vec3A::splat(f32::NEG_INFINITY),
    };

    #[inline(always)]
    pub(super) fn grow(&mut self, min: Vec3A, max: Vec3A) {
        self.min = self.min.min(min);
        self.max = self.max.max(max);
    }

    #[inline(always)]
    pub(super) fn grow_point(&mut self, p: Vec3A) {
        self.grow(p, p);
    }

    #[inline(always)]
    pub(super) fn union(&self, o: &SimdBox) -> SimdBox {
        SimdBox {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// `Aabb::surface_area` of a box that is not empty, bit for bit (the same operations
    /// in the same order), so that SAH costs and the trees they choose stay the same.
    #[inline(always)]
    pub(super) fn surface_area(&self) -> f32 {
        let e = self.max - self.min;
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// The volume of a box that is not empty.
    #[inline(always)]
    pub(super) fn volume(&self) -> f32 {
        let e = self.max - self.min;
        e.x * e.y * e.z
    }

    pub(super) fn to_aabb(self) -> Aabb {
        if self.min.cmpgt(self.max).any() {
            return Aabb::EMPTY;
        }
        Aabb {
            min: Vec3::from(self.min),
            max: Vec3::from(self.max),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reference_keeps_its_index_and_box() {
        let b = Aabb::new(Vec3::new(-1.5, 0.0, 2.0), Vec3::new(3.0, 0.25, 2.0));
        for index in [0, 1, 7, 0x7f80_0001, u32::MAX] {
            let r = PrimRef::new(index, &b);
            assert_eq!(r.index(), index);
            assert_eq!(Vec3::from(r.centroid()), b.center());
            assert_eq!(Vec3::from(r.min()), b.min);
            assert_eq!(Vec3::from(r.max()), b.max);
        }
    }

    #[test]
    fn simd_boxes_grow_as_aabbs_do() {
        let a = Aabb::new(Vec3::new(-1.0, 2.0, 0.5), Vec3::new(0.0, 3.0, 4.0));
        let p = Vec3::new(5.0, -2.0, 1.0);
        let mut s = SimdBox::EMPTY;
        assert_eq!(s.to_aabb(), Aabb::EMPTY);
        s.grow(a.min.into(), a.max.into());
        s.grow_point(p.into());
        assert_eq!(s.to_aabb(), a.union_point(p));
        assert_eq!(s.union(&SimdBox::EMPTY).to_aabb(), s.to_aabb());
        assert_eq!(s.surface_area(), a.union_point(p).surface_area());
    }
}
