//! What eight lanes do their own way with AVX2 (`F32x8`, made in `x86.rs`): comparisons
//! into vector masks that `bits` turns into a `movemask`, select by blend, the sign-bit
//! operations on the float view.

// std::arch intrinsics can only be called in unsafe blocks. Each block below is sound
// because a value of these types exists only inside a kernel compiled for AVX2 and entered
// after `is_x86_feature_detected!("avx2")` (the module documentation of `lanes`).
#![allow(unsafe_code)]

use super::x86::{lane_op, F32x8};
use std::arch::x86_64::*;

/// Eight lanes of a comparison: all ones where true.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Mask8(__m256);

lane_op!(BitAnd, bitand, Mask8, _mm256_and_ps);
lane_op!(BitOr, bitor, Mask8, _mm256_or_ps);

impl F32x8 {
    #[inline(always)]
    pub(super) fn compare<const PREDICATE: i32>(self, other: F32x8) -> Mask8 {
        // SAFETY: see the module's opening comment.
        Mask8(unsafe { _mm256_cmp_ps::<PREDICATE>(self.0, other.0) })
    }

    #[inline(always)]
    pub(super) fn blend(mask: Mask8, if_true: F32x8, if_false: F32x8) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_blendv_ps(if_false.0, if_true.0, mask.0) })
    }

    #[inline(always)]
    pub(super) fn mask_bits(mask: Mask8) -> u32 {
        // SAFETY: see the module's opening comment.
        unsafe { _mm256_movemask_ps(mask.0) as u32 }
    }

    /// The sign bit in every lane.
    #[inline(always)]
    fn sign() -> __m256 {
        // SAFETY: see the module's opening comment.
        unsafe { _mm256_set1_ps(-0.0) }
    }

    #[inline(always)]
    pub(super) fn abs_bits(self) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_andnot_ps(F32x8::sign(), self.0) })
    }

    #[inline(always)]
    pub(super) fn neg_bits(self) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_xor_ps(self.0, F32x8::sign()) })
    }

    #[inline(always)]
    pub(super) fn copysign_bits(self, sign: F32x8) -> F32x8 {
        let s = F32x8::sign();
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_or_ps(_mm256_andnot_ps(s, self.0), _mm256_and_ps(s, sign.0)) })
    }

    /// Two four-lane values side by side: `low` in lanes 0..4, `high` in lanes 4..8.
    #[inline(always)]
    pub(crate) fn from_halves(low: glam::Vec4, high: glam::Vec4) -> F32x8 {
        // SAFETY: see the module's opening comment.
        F32x8(unsafe { _mm256_set_m128(__m128::from(high), __m128::from(low)) })
    }
}
