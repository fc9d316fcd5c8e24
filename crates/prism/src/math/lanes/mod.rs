//! Lanes of f32 for SIMD kernels written once: `FloatLanes`, the handful of operations the
//! kernels make (splat, load, arithmetic, min and max, comparisons into a mask, select,
//! the mask's bits), implemented for one lane (`f32`), four (glam's `Vec4`: SSE on x86-64,
//! portable elsewhere), eight (`F32x8`, AVX2) and sixteen (`F32x16`, AVX-512F), the last two
//! made by one macro (`x86.rs`) with what each does its own way beside it. A kernel is
//! one generic function over `L: FloatLanes`; each width is a monomorphisation of it, as
//! Embree's kernels are templates over its `vfloat<N>`.
//!
//! Every implementation maps an operation to the one instruction (or glam call) the
//! hand-written kernels used, and none fuses a multiply and an add, so a kernel gives the
//! same bits in every width: lane for lane, the scalar code's operations in its order.
//! Where widths could differ, the operation says how: `min` and `max` return their second
//! operand when either is NaN on x86 (`minps`/`maxps`, and glam's `Vec4` there), while the
//! `f32` lane takes the number (`f32::min`), as the scalar code it serves always has.
//!
//! How a kernel is compiled for a width: the x86 implementations are `#[inline(always)]`
//! methods over `std::arch` intrinsics, with no target feature of their own, so they take
//! the features of the function they are inlined into. A kernel is likewise an
//! `#[inline(always)]` generic function, and each width's entry point is a
//! `#[target_feature(enable = …)]` function that calls it with its lane type, entered only
//! after `is_x86_feature_detected!` said yes (see `accel/bvh/simd8.rs`). A value of `F32x8`
//! or `F32x16` only ever exists inside such an entry point; nothing else makes one.

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;
mod trig;
#[cfg(target_arch = "x86_64")]
mod x86;

pub(crate) use trig::sincos;

#[cfg(target_arch = "x86_64")]
pub(crate) use x86::{F32x16, F32x8};

use glam::{BVec4A, Vec4};
use std::ops::{Add, BitAnd, BitOr, Div, Index, Mul, Sub};

/// `FloatLanes` methods that are one expression each, as a table: `name(a) expression;`
/// makes `fn name(self)` with `a` the lanes, `name(a, b) expression;` makes `fn
/// name(self, other)` with `a` the first operand and `b` the second; each returns `$out`.
/// The comparisons and the methods that are the lane type's own read as one line each.
macro_rules! lane_fns {
    ($lane:ty => $out:ty: $($method:ident($($arg:ident),+) $body:expr;)+) => {$(
        $crate::math::lanes::lane_fns!(@one $lane, $out, $method($($arg),+) $body);
    )+};
    (@one $lane:ty, $out:ty, $method:ident($a:ident) $body:expr) => {
        #[inline(always)]
        fn $method(self) -> $out {
            let $a = self;
            $body
        }
    };
    (@one $lane:ty, $out:ty, $method:ident($a:ident, $b:ident) $body:expr) => {
        #[inline(always)]
        fn $method(self, other: $lane) -> $out {
            let ($a, $b) = (self, other);
            $body
        }
    };
}
pub(crate) use lane_fns;

/// `impl FloatLanes` for a lane type whose every operation is one expression, as a table:
/// `splat`, `load` and `to_array` with their arguments named; `own`, the operations that are
/// the lane type's method of the same name; the other operations on lanes and the
/// comparisons in `lane_fns!`'s form; then `select` and `bits`.
macro_rules! float_lanes {
    (
        $(#[$meta:meta])*
        $lane:ty, lanes $lanes:literal, mask $mask:ty:
        splat($x:ident) $splat:expr;
        load($row:ident, $at:ident) $load:expr;
        to_array($a:ident) $to_array:expr;
        own { $($own:ident($($own_arg:ident),+);)+ }
        lanes { $($op:tt)+ }
        masks { $($cmp:tt)+ }
        select($m:ident, $t:ident, $f:ident) $select:expr;
        bits($b:ident) $bits:expr;
    ) => {
        $(#[$meta])*
        impl FloatLanes for $lane {
            const LANES: usize = $lanes;
            type Mask = $mask;
            type Array = [f32; $lanes];

            #[inline(always)]
            fn splat($x: f32) -> $lane {
                $splat
            }
            #[inline(always)]
            fn load<const K: usize>($row: &[f32; K], $at: usize) -> $lane {
                $load
            }
            #[inline(always)]
            fn to_array(self) -> [f32; $lanes] {
                let $a = self;
                $to_array
            }
            lane_fns!($lane => $lane: $($own($($own_arg),+) <$lane>::$own($($own_arg),+);)+);
            lane_fns!($lane => $lane: $($op)+);
            lane_fns!($lane => $mask: $($cmp)+);
            #[inline(always)]
            fn select($m: $mask, $t: $lane, $f: $lane) -> $lane {
                $select
            }
            #[inline(always)]
            fn bits($b: $mask) -> u32 {
                $bits
            }
        }
    };
}

/// `LANES` f32 values operated on together, lane by lane.
pub(crate) trait FloatLanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self>
{
    /// Lanes per value (at most 32, so that a mask's bits fit a `u32`).
    const LANES: usize;
    /// A comparison's answer, lane by lane.
    type Mask: Copy + BitAnd<Output = Self::Mask> + BitOr<Output = Self::Mask>;
    /// The lanes stored to memory, for the scalar steps after a kernel.
    type Array: Copy + Index<usize, Output = f32>;

    /// `x` in every lane.
    fn splat(x: f32) -> Self;
    /// Lanes `at .. at + LANES` of `row`.
    fn load<const K: usize>(row: &[f32; K], at: usize) -> Self;
    /// The lanes in memory.
    fn to_array(self) -> Self::Array;
    /// The lesser of each pair; where either is NaN, see the module's documentation.
    fn min(self, other: Self) -> Self;
    /// The greater of each pair; where either is NaN, see the module's documentation.
    fn max(self, other: Self) -> Self;
    /// The magnitude (the sign bit cleared).
    fn abs(self) -> Self;
    /// The sign bit flipped.
    fn neg(self) -> Self;
    /// The magnitude of `self` with the sign bit of `sign`.
    fn copysign(self, sign: Self) -> Self;
    /// The square root.
    fn sqrt(self) -> Self;
    /// `self == other` (false where either is NaN).
    fn eq(self, other: Self) -> Self::Mask;
    /// `self < other` (false where either is NaN).
    fn lt(self, other: Self) -> Self::Mask;
    /// `self <= other` (false where either is NaN).
    fn le(self, other: Self) -> Self::Mask;
    /// `self > other` (false where either is NaN).
    fn gt(self, other: Self) -> Self::Mask;
    /// `self >= other` (false where either is NaN).
    fn ge(self, other: Self) -> Self::Mask;
    /// `!(self < other)`: true where either is NaN.
    fn not_lt(self, other: Self) -> Self::Mask;
    /// `if_true` in the lanes of `mask`, `if_false` in the others.
    fn select(mask: Self::Mask, if_true: Self, if_false: Self) -> Self;
    /// The mask as bits, bit k for lane k.
    fn bits(mask: Self::Mask) -> u32;

    /// Bits of every lane.
    #[inline(always)]
    fn all_lanes() -> u32 {
        u32::MAX >> (32 - Self::LANES)
    }

    /// `|a|`, `|b|`, `|c|`: the greatest, combined as `(|a| max |b|) max |c|`.
    #[inline(always)]
    fn abs_max([a, b, c]: [Self; 3]) -> Self {
        a.abs().max(b.abs()).max(c.abs())
    }
}

/// `[f(0), f(1), f(2)]`, for a kernel's per-axis values: written out, because
/// `<[T; 3]>::map` is not always inlined, and a kernel's operations outside the function it
/// is inlined into lose its target features (each becomes a call).
#[inline(always)]
pub(crate) fn axes<T>(f: impl Fn(usize) -> T) -> [T; 3] {
    [f(0), f(1), f(2)]
}

float_lanes! {
    /// One lane: the scalar code's own operations, so that a kernel serves it too.
    f32, lanes 1, mask bool:
    splat(x) x;
    load(row, at) row[at];
    to_array(a) [a];
    own { min(a, b); max(a, b); copysign(a, b); abs(a); sqrt(a); }
    lanes { neg(a) -a; }
    masks {
        eq(a, b) a == b;
        lt(a, b) a < b;
        le(a, b) a <= b;
        gt(a, b) a > b;
        ge(a, b) a >= b;
        not_lt(a, b) a.partial_cmp(&b) != Some(std::cmp::Ordering::Less);
    }
    select(mask, if_true, if_false) if mask { if_true } else { if_false };
    bits(mask) u32::from(mask);
}

float_lanes! {
    /// Four lanes through glam: SSE on x86-64 (each operation the `_mm_*` one of the same
    /// name), plain f32 elsewhere.
    Vec4, lanes 4, mask BVec4A:
    splat(x) Vec4::splat(x);
    load(row, at) Vec4::from_slice(&row[at..at + 4]);
    to_array(a) Vec4::to_array(&a);
    own { min(a, b); max(a, b); copysign(a, b); abs(a); }
    lanes {
        neg(a) -a;
        sqrt(a) Vec4::new(a.x.sqrt(), a.y.sqrt(), a.z.sqrt(), a.w.sqrt());
    }
    masks {
        eq(a, b) a.cmpeq(b);
        lt(a, b) a.cmplt(b);
        le(a, b) a.cmple(b);
        gt(a, b) a.cmpgt(b);
        ge(a, b) a.cmpge(b);
        not_lt(a, b) !a.cmplt(b);
    }
    select(mask, if_true, if_false) Vec4::select(mask, if_true, if_false);
    bits(mask) mask.bitmask();
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Numbers every operation meets: signed zeros, tiny and huge values, infinities, NaN.
    const SPECIAL: [f32; 12] = [
        0.0,
        -0.0,
        1.0,
        -2.5,
        1e-30,
        -3e30,
        f32::MIN_POSITIVE,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        7.0,
        -7.0,
    ];

    /// Each width's operations, lane by lane, against the scalar ones on every pair of
    /// `SPECIAL` values: the same bits, and `min`/`max` with NaN (and equal zeros) as the
    /// module says (the second operand on x86, the number for `f32`).
    fn agrees_with_scalar<L: FloatLanes>() {
        let n = L::LANES;
        let mut pairs = Vec::new();
        for &a in &SPECIAL {
            for &b in &SPECIAL {
                pairs.push((a, b));
            }
        }
        while pairs.len() % n != 0 {
            pairs.push((1.0, 2.0));
        }
        for chunk in pairs.chunks(n) {
            let mut xs = [0.0f32; 32];
            let mut ys = [0.0f32; 32];
            for (k, &(a, b)) in chunk.iter().enumerate() {
                xs[k] = a;
                ys[k] = b;
            }
            let (x, y) = (L::load(&xs, 0), L::load(&ys, 0));
            // `want` gives None where the platform decides (min and max of a NaN on
            // several lanes off x86-64).
            let agree = |got: L, want: &dyn Fn(f32, f32) -> Option<f32>, what: &str| {
                let got = got.to_array();
                for k in 0..n {
                    let Some(w) = want(xs[k], ys[k]) else {
                        continue;
                    };
                    let g = got[k];
                    assert!(
                        g.to_bits() == w.to_bits() || (g.is_nan() && w.is_nan()),
                        "{n} lanes, {what}({}, {}): {g} against {w}",
                        xs[k],
                        ys[k]
                    );
                }
            };
            let same = |got: L, want: &dyn Fn(f32, f32) -> f32, what: &str| {
                agree(got, &|a, b| Some(want(a, b)), what)
            };
            same(x + y, &|a, b| a + b, "add");
            same(x - y, &|a, b| a - b, "sub");
            same(x * y, &|a, b| a * b, "mul");
            same(x / y, &|a, b| a / b, "div");
            same(x.abs(), &|a, _| a.abs(), "abs");
            same(x.neg(), &|a, _| -a, "neg");
            same(x.copysign(y), &|a, b| a.copysign(b), "copysign");
            same(x.sqrt(), &|a, _| a.sqrt(), "sqrt");
            // Several lanes on x86-64 are `minps`/`maxps`: the first operand where it is
            // strictly less (greater), else the second (NaN and equal zeros included).
            // Elsewhere those cases are the platform's.
            let one_lane = n == 1;
            let min_max = move |a: f32, b: f32, first: bool, f: fn(f32, f32) -> f32| {
                if one_lane {
                    Some(f(a, b))
                } else if cfg!(target_arch = "x86_64") {
                    Some(if first { a } else { b })
                } else if a.is_nan() || b.is_nan() || a == b {
                    None
                } else {
                    Some(f(a, b))
                }
            };
            agree(x.min(y), &|a, b| min_max(a, b, a < b, f32::min), "min");
            agree(x.max(y), &|a, b| min_max(a, b, a > b, f32::max), "max");
            let mask_is = |got: L::Mask, want: fn(f32, f32) -> bool, what: &str| {
                let bits = L::bits(got);
                for k in 0..n {
                    let w = want(xs[k], ys[k]);
                    assert_eq!(
                        bits >> k & 1 == 1,
                        w,
                        "{n} lanes, {what}({}, {})",
                        xs[k],
                        ys[k]
                    );
                }
                assert_eq!(
                    bits & !L::all_lanes(),
                    0,
                    "{n} lanes, {what}: bits past the lanes"
                );
            };
            mask_is(x.eq(y), |a, b| a == b, "eq");
            mask_is(x.lt(y), |a, b| a < b, "lt");
            mask_is(x.le(y), |a, b| a <= b, "le");
            mask_is(x.gt(y), |a, b| a > b, "gt");
            mask_is(x.ge(y), |a, b| a >= b, "ge");
            mask_is(
                x.not_lt(y),
                |a, b| a >= b || a.is_nan() || b.is_nan(),
                "not_lt",
            );
            mask_is(x.lt(y) | x.eq(y), |a, b| a <= b, "or");
            mask_is(x.le(y) & x.ge(y), |a, b| a == b, "and");
            same(
                L::select(x.lt(y), x, y),
                &|a, b| if a < b { a } else { b },
                "select",
            );
            same(L::splat(xs[0]), &|_, _| xs[0], "splat");
        }
    }

    #[test]
    fn one_lane_is_the_scalar_code() {
        agrees_with_scalar::<f32>();
    }

    #[test]
    fn four_lanes_agree_with_the_scalar_code() {
        agrees_with_scalar::<Vec4>();
    }

    /// A width whose instructions the CPU may lack runs where it has them; where it has
    /// not, the build script marks the test ignored, with the reason.
    fn agrees_where_the_cpu_has_it<L: FloatLanes>(has_it: bool) {
        if has_it {
            agrees_with_scalar::<L>();
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    #[cfg_attr(not(prism_host_avx2), ignore = "this CPU lacks AVX2")]
    fn eight_lanes_agree_with_the_scalar_code() {
        agrees_where_the_cpu_has_it::<F32x8>(is_x86_feature_detected!("avx2"));
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    #[cfg_attr(not(prism_host_avx512), ignore = "this CPU lacks AVX-512F")]
    fn sixteen_lanes_agree_with_the_scalar_code() {
        agrees_where_the_cpu_has_it::<F32x16>(is_x86_feature_detected!("avx512f"));
    }
}
