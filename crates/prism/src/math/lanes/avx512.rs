//! Sixteen lanes with AVX-512F: `FloatLanes` over `__m512`, comparisons straight into
//! mask registers. The sign-bit operations go through the integer view, since their float
//! forms need AVX-512DQ.

// std::arch intrinsics can only be called in unsafe blocks. Each block below is sound
// because a value of this type exists only inside a kernel compiled for AVX-512F and
// entered after `is_x86_feature_detected!("avx512f")` (the module documentation of `lanes`).
#![allow(unsafe_code)]

use super::FloatLanes;
use std::arch::x86_64::*;
use std::ops::{Add, Div, Mul, Sub};

/// Sixteen f32 lanes in a 512-bit register.
#[derive(Clone, Copy, Debug)]
pub(crate) struct F32x16(__m512);

macro_rules! binary {
    ($trait:ident, $method:ident, $intrinsic:ident) => {
        impl $trait for F32x16 {
            type Output = F32x16;
            #[inline(always)]
            fn $method(self, other: F32x16) -> F32x16 {
                // SAFETY: see the module's opening comment.
                F32x16(unsafe { $intrinsic(self.0, other.0) })
            }
        }
    };
}

binary!(Add, add, _mm512_add_ps);
binary!(Sub, sub, _mm512_sub_ps);
binary!(Mul, mul, _mm512_mul_ps);
binary!(Div, div, _mm512_div_ps);

impl F32x16 {
    #[inline(always)]
    fn compare<const PREDICATE: i32>(self, other: F32x16) -> __mmask16 {
        // SAFETY: see the module's opening comment.
        unsafe { _mm512_cmp_ps_mask::<PREDICATE>(self.0, other.0) }
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
}

impl FloatLanes for F32x16 {
    const LANES: usize = 16;
    type Mask = __mmask16;
    type Array = [f32; 16];

    #[inline(always)]
    fn splat(x: f32) -> F32x16 {
        // SAFETY: see the module's opening comment.
        F32x16(unsafe { _mm512_set1_ps(x) })
    }
    #[inline(always)]
    fn load<const K: usize>(row: &[f32; K], at: usize) -> F32x16 {
        assert!(at + 16 <= K, "sixteen lanes from {at} of {K}");
        // SAFETY: lanes `at .. at + 16` lie in `row` (asserted); unaligned load.
        F32x16(unsafe { _mm512_loadu_ps(row.as_ptr().add(at)) })
    }
    #[inline(always)]
    fn to_array(self) -> [f32; 16] {
        let mut out = [0.0f32; 16];
        // SAFETY: `out` holds sixteen f32s; unaligned store.
        unsafe { _mm512_storeu_ps(out.as_mut_ptr(), self.0) };
        out
    }
    #[inline(always)]
    fn min(self, other: F32x16) -> F32x16 {
        // SAFETY: see the module's opening comment.
        F32x16(unsafe { _mm512_min_ps(self.0, other.0) })
    }
    #[inline(always)]
    fn max(self, other: F32x16) -> F32x16 {
        // SAFETY: see the module's opening comment.
        F32x16(unsafe { _mm512_max_ps(self.0, other.0) })
    }
    #[inline(always)]
    fn abs(self) -> F32x16 {
        // SAFETY: see the module's opening comment.
        F32x16(unsafe { _mm512_abs_ps(self.0) })
    }
    #[inline(always)]
    fn neg(self) -> F32x16 {
        // SAFETY: see the module's opening comment.
        self.bitwise(|x| unsafe { _mm512_xor_si512(x, F32x16::sign()) })
    }
    #[inline(always)]
    fn copysign(self, sign: F32x16) -> F32x16 {
        let s = F32x16::sign();
        // SAFETY: see the module's opening comment.
        self.bitwise(|x| unsafe {
            _mm512_or_si512(
                _mm512_andnot_si512(s, x),
                _mm512_and_si512(s, _mm512_castps_si512(sign.0)),
            )
        })
    }
    #[inline(always)]
    fn sqrt(self) -> F32x16 {
        // SAFETY: see the module's opening comment.
        F32x16(unsafe { _mm512_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn eq(self, other: F32x16) -> __mmask16 {
        self.compare::<_CMP_EQ_OQ>(other)
    }
    #[inline(always)]
    fn lt(self, other: F32x16) -> __mmask16 {
        self.compare::<_CMP_LT_OQ>(other)
    }
    #[inline(always)]
    fn le(self, other: F32x16) -> __mmask16 {
        self.compare::<_CMP_LE_OQ>(other)
    }
    #[inline(always)]
    fn gt(self, other: F32x16) -> __mmask16 {
        self.compare::<_CMP_GT_OQ>(other)
    }
    #[inline(always)]
    fn ge(self, other: F32x16) -> __mmask16 {
        self.compare::<_CMP_GE_OQ>(other)
    }
    #[inline(always)]
    fn not_lt(self, other: F32x16) -> __mmask16 {
        self.compare::<_CMP_NLT_UQ>(other)
    }
    #[inline(always)]
    fn select(mask: __mmask16, if_true: F32x16, if_false: F32x16) -> F32x16 {
        // SAFETY: see the module's opening comment.
        F32x16(unsafe { _mm512_mask_blend_ps(mask, if_false.0, if_true.0) })
    }
    #[inline(always)]
    fn bits(mask: __mmask16) -> u32 {
        u32::from(mask)
    }
}
