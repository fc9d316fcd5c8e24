//! The x86 lane types, written once: `x86_lanes!` makes a lane type over one register of
//! a width's intrinsic family, its arithmetic, and the `FloatLanes` operations that are one
//! intrinsic in every family (load, store, min, max, square root, the six comparisons by
//! predicate), instantiated below for AVX2 (`F32x8`) and AVX-512F (`F32x16`). A width's
//! own file (`avx2.rs`, `avx512.rs`) writes what its family does its own way: the
//! comparison and its mask, select, the mask's bits and the sign-bit operations
//! (`compare`, `blend`, `mask_bits`, `abs_bits`, `neg_bits`, `copysign_bits`, inherent
//! methods the trait's operations call).

// std::arch intrinsics can only be called in unsafe blocks. Each block the macros expand
// to is sound because a value of these types exists only inside a kernel compiled for its
// width's features and entered after `is_x86_feature_detected!` said the CPU has them (the
// module documentation of `lanes`).
#![allow(unsafe_code)]

use super::avx2::Mask8;
use std::arch::x86_64::*;

/// `impl $trait for $type` by the intrinsic `$intrinsic` on the two registers.
macro_rules! lane_op {
    ($trait:ident, $method:ident, $type:ident, $intrinsic:ident) => {
        impl std::ops::$trait for $type {
            type Output = $type;
            #[inline(always)]
            fn $method(self, other: $type) -> $type {
                // SAFETY: see the module's opening comment.
                $type(unsafe { $intrinsic(self.0, other.0) })
            }
        }
    };
}

/// A lane type `$name` of `$lanes` f32 lanes in a `$register`, its comparisons answered
/// as `$mask`, with the named intrinsics of its family.
macro_rules! x86_lanes {
    ($(
        $(#[$meta:meta])*
        $name:ident($register:ty), $lanes:literal lanes, mask $mask:ty:
            $set1:ident $loadu:ident $storeu:ident $add:ident $sub:ident $mul:ident $div:ident
            $min:ident $max:ident $sqrt:ident;
    )+) => {$(
        $(#[$meta])*
        #[derive(Clone, Copy, Debug)]
        pub(crate) struct $name(pub(super) $register);

        lane_op!(Add, add, $name, $add);
        lane_op!(Sub, sub, $name, $sub);
        lane_op!(Mul, mul, $name, $mul);
        lane_op!(Div, div, $name, $div);

        impl $crate::math::lanes::FloatLanes for $name {
            const LANES: usize = $lanes;
            type Mask = $mask;
            type Array = [f32; $lanes];

            #[inline(always)]
            fn splat(x: f32) -> $name {
                // SAFETY: see the module's opening comment.
                $name(unsafe { $set1(x) })
            }
            #[inline(always)]
            fn load<const K: usize>(row: &[f32; K], at: usize) -> $name {
                assert!(at + $lanes <= K, "{} lanes from {at} of {K}", $lanes);
                // SAFETY: the lanes from `at` lie in `row` (asserted); unaligned load.
                $name(unsafe { $loadu(row.as_ptr().add(at)) })
            }
            #[inline(always)]
            fn to_array(self) -> [f32; $lanes] {
                let mut out = [0.0f32; $lanes];
                // SAFETY: `out` holds every lane; unaligned store.
                unsafe { $storeu(out.as_mut_ptr(), self.0) };
                out
            }
            $crate::math::lanes::lane_fns!($name => $name:
                // SAFETY: see the module's opening comment.
                min(a, b) $name(unsafe { $min(a.0, b.0) });
                // SAFETY: see the module's opening comment.
                max(a, b) $name(unsafe { $max(a.0, b.0) });
                copysign(a, b) a.copysign_bits(b);
                abs(a) a.abs_bits();
                neg(a) a.neg_bits();
                // SAFETY: see the module's opening comment.
                sqrt(a) $name(unsafe { $sqrt(a.0) });
            );
            $crate::math::lanes::lane_fns!($name => $mask:
                eq(a, b) a.compare::<_CMP_EQ_OQ>(b);
                lt(a, b) a.compare::<_CMP_LT_OQ>(b);
                le(a, b) a.compare::<_CMP_LE_OQ>(b);
                gt(a, b) a.compare::<_CMP_GT_OQ>(b);
                ge(a, b) a.compare::<_CMP_GE_OQ>(b);
                not_lt(a, b) a.compare::<_CMP_NLT_UQ>(b);
            );
            #[inline(always)]
            fn select(mask: $mask, if_true: $name, if_false: $name) -> $name {
                $name::blend(mask, if_true, if_false)
            }
            #[inline(always)]
            fn bits(mask: $mask) -> u32 {
                $name::mask_bits(mask)
            }
        }
    )+};
}

pub(super) use lane_op;

// Each width's intrinsics, in the macro's order: set1, loadu, storeu, add, sub, mul, div,
// min, max, sqrt.
x86_lanes! {
    /// Eight f32 lanes in a 256-bit register (AVX2).
    F32x8(__m256), 8 lanes, mask Mask8: _mm256_set1_ps _mm256_loadu_ps _mm256_storeu_ps
        _mm256_add_ps _mm256_sub_ps _mm256_mul_ps _mm256_div_ps _mm256_min_ps _mm256_max_ps
        _mm256_sqrt_ps;
    /// Sixteen f32 lanes in a 512-bit register (AVX-512F).
    F32x16(__m512), 16 lanes, mask __mmask16: _mm512_set1_ps _mm512_loadu_ps _mm512_storeu_ps
        _mm512_add_ps _mm512_sub_ps _mm512_mul_ps _mm512_div_ps _mm512_min_ps _mm512_max_ps
        _mm512_sqrt_ps;
}
