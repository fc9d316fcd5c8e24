//! What sixteen lanes do their own way with AVX-512F (`F32x16`, made in `x86.rs`):
//! comparisons straight into mask registers, select by masked blend, and the sign-bit
//! operations through the integer view, since their float forms need AVX-512DQ.

// std::arch intrinsics can only be called in unsafe blocks. Each block below is sound
// because a value of this type exists only inside a kernel compiled for AVX-512F and
// entered after `is_x86_feature_detected!("avx512f")` (the module documentation of
// `lanes`).
#![allow(unsafe_code)]

use super::x86::F32x16;
use std::arch::x86_64::*;

impl F32x16 {
    #[inline(always)]
    pub(super) fn compare<const PREDICATE: i32>(self, other: F32x16) -> __mmask16 {
        // SAFETY: see the module's opening comment.
        unsafe { _mm512_cmp_ps_mask::<PREDICATE>(self.0, other.0) }
    }

    #[inline(always)]
    pub(super) fn blend(mask: __mmask16, if_true: F32x16, if_false: F32x16) -> F32x16 {
        // SAFETY: see the module's opening comment.
        F32x16(unsafe { _mm512_mask_blend_ps(mask, if_false.0, if_true.0) })
    }

    #[inline(always)]
    pub(super) fn mask_bits(mask: __mmask16) -> u32 {
        u32::from(mask)
    }

    /// The lanes' bits as integers, and back.
    #[inline(always)]
    fn bitwise(self, f: impl Fn(__m512i) -> __m512i) -> F32x16 {
        // SAFETY: see the module's opening comment.
        F32x16(unsafe { _mm512_castsi512_ps(f(_mm512_castps_si512(self.0))) })
    }

    /// The sign bit in every lane, as integers.
    #[inline(always)]
    fn sign() -> __m512i {
        // SAFETY: see the module's opening comment.
        unsafe { _mm512_set1_epi32(i32::MIN) }
    }

    #[inline(always)]
    pub(super) fn abs_bits(self) -> F32x16 {
        // SAFETY: see the module's opening comment.
        F32x16(unsafe { _mm512_abs_ps(self.0) })
    }

    #[inline(always)]
    pub(super) fn neg_bits(self) -> F32x16 {
        // SAFETY: see the module's opening comment.
        self.bitwise(|x| unsafe { _mm512_xor_si512(x, F32x16::sign()) })
    }

    #[inline(always)]
    pub(super) fn copysign_bits(self, sign: F32x16) -> F32x16 {
        let s = F32x16::sign();
        // SAFETY: see the module's opening comment.
        self.bitwise(|x| unsafe {
            _mm512_or_si512(
                _mm512_andnot_si512(s, x),
                _mm512_and_si512(s, _mm512_castps_si512(sign.0)),
            )
        })
    }
}
