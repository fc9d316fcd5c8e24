//! Eight lanes with AVX2: `FloatLanes` over `__m256`, comparisons into vector masks that
//! `bits` turns into a `movemask`.

// std::arch intrinsics can only be called in unsafe blocks. Each block below is sound
// because a value of these types exists only inside a kernel compiled for AVX2 and entered
// after `is_x86_feature_detected!("avx2")` (the module documentation of `lanes`).
#![allow(unsafe_code)]

use super::FloatLanes;
use std::arch::x86_64::*;
use std::ops::{Add, BitAnd, BitOr, Div, Mul, Sub};

/// Eight f32 lanes in a 256-bit register.
#[derive(Clone, Copy, Debug)]
pub(crate) struct F32x8(__m256);

/// Eight lanes of a comparison: all ones where true.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Mask8(__m256);

macro_rules! binary {
    ($trait:ident, $method:ident, $type:ident, $intrinsic:ident) => {
        impl $trait for $type {
            type Output = $type;
            #[inline(always)]
            fn $method(self, other: $type) -> $type {
                // SAFETY: see the module's opening comment.
                $type(unsafe { $intrinsic(self.0, other.0) })
            }
        }
    };
}

binary!(Add, add, F32x8, _mm256_add_ps);
binary!(Sub, sub, F32x8, _mm256_sub_ps);
binary!(Mul, mul, F32x8, _mm256_mul_ps);
binary!(Div, div, F32x8, _mm256_div_ps);
binary!(BitAnd, bitand, Mask8, _mm256_and_ps);
binary!(BitOr, bitor, Mask8, _mm256_or_ps);

impl F32x8 {
    #[inline(always)]
    fn compare<const PREDICATE: i32>(self, other: F32x8) -> Mask8 {
        // SAFETY: see the module's opening comment.
        Mask8(unsafe { _mm256_cmp_ps::<PREDICATE>(self.0, other.0) })
    }

    /// The sign bit in every lane.
    #[inline(always)]
    fn sign() -> __m256 {
        // SAFETY: see the module's opening comment.
        unsafe { _mm256_set1_ps(-0.0) }
    }
}

impl FloatLanes for F32x8 {
    const LANES: usize = 8;
    type Mask = Mask8;
    type Array = [f32; 8];

    #[inline(always)]
    fn splat(x: f32) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_set1_ps(x) })
    }
    #[inline(always)]
    fn load<const K: usize>(row: &[f32; K], at: usize) -> F32x8 {
        assert!(at + 8 <= K, "eight lanes from {at} of {K}");
        // SAFETY: lanes `at .. at + 8` lie in `row` (asserted); unaligned load.
        F32x8(unsafe { _mm256_loadu_ps(row.as_ptr().add(at)) })
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 8] {
        let mut out = [0.0f32; 8];
        // SAFETY: `out` holds eight f32s; unaligned store.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) };
        out
    }
    #[inline(always)]
    fn min(self, other: F32x8) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_min_ps(self.0, other.0) })
    }
    #[inline(always)]
    fn max(self, other: F32x8) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_max_ps(self.0, other.0) })
    }
    #[inline(always)]
    fn abs(self) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_andnot_ps(F32x8::sign(), self.0) })
    }
    #[inline(always)]
    fn neg(self) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_xor_ps(self.0, F32x8::sign()) })
    }
    #[inline(always)]
    fn copysign(self, sign: F32x8) -> F32x8 {
        let s = F32x8::sign();
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_or_ps(_mm256_andnot_ps(s, self.0), _mm256_and_ps(s, sign.0)) })
    }
    #[inline(always)]
    fn sqrt(self) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn eq(self, other: F32x8) -> Mask8 {
        self.compare::<_CMP_EQ_OQ>(other)
    }
    #[inline(always)]
    fn lt(self, other: F32x8) -> Mask8 {
        self.compare::<_CMP_LT_OQ>(other)
    }
    #[inline(always)]
    fn le(self, other: F32x8) -> Mask8 {
        self.compare::<_CMP_LE_OQ>(other)
    }
    #[inline(always)]
    fn gt(self, other: F32x8) -> Mask8 {
        self.compare::<_CMP_GT_OQ>(other)
    }
    #[inline(always)]
    fn ge(self, other: F32x8) -> Mask8 {
        self.compare::<_CMP_GE_OQ>(other)
    }
    #[inline(always)]
    fn not_lt(self, other: F32x8) -> Mask8 {
        self.compare::<_CMP_NLT_UQ>(other)
    }
    #[inline(always)]
    fn select(mask: Mask8, if_true: F32x8, if_false: F32x8) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_blendv_ps(if_false.0, if_true.0, mask.0) })
    }
    #[inline(always)]
    fn bits(mask: Mask8) -> u32 {
        // SAFETY: see the module's opening comment.
        unsafe { _mm256_movemask_ps(mask.0) as u32 }
    }
}

impl F32x8 {
    /// Two four-lane values side by side: `low` in lanes 0..4, `high` in lanes 4..8.
    #[inline(always)]
    pub(crate) fn from_halves(low: glam::Vec4, high: glam::Vec4) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_set_m128(__m128::from(high), __m128::from(low)) })
    }
}
