//! Sine and cosine written once over `FloatLanes`, so that a kernel in lanes and the scalar
//! code (`f32`, one lane) draw the same directions bit for bit: the wavefront's diffuse
//! bounces in lanes (`integrator/diffuse_lanes.rs`) and the one-path tracer's
//! `warp::cosine_hemisphere` both call `sincos`.
//!
//! Cephes' `sinf`/`cosf` (Moshier): the argument reduced by the nearest multiple of π/2
//! in three parts (Cody and Waite), the first two short enough that their products with
//! the multiple are exact, then minimax polynomials on [−π/4, π/4], the quadrant picking
//! which of the two and its sign. Only additions, multiplications, comparisons and selects,
//! none fused, so every width gives the same bits; the rounding to the nearest multiple is
//! the 1.5·2²³ trick (an addition and a subtraction).

use super::FloatLanes;

/// 1.5·2²³: added and subtracted, rounds a number of magnitude below 2²² to the nearest
/// integer (ties to even).
const ROUNDER: f32 = 12_582_912.0;
/// π/2 in three parts (Cephes' π/4 ones doubled): the first has 8 significant bits, so its
/// product with a multiple of π/2 below 2¹⁶ is exact.
const PIO2_1: f32 = 1.570_312_5;
const PIO2_2: f32 = 4.837_513e-4;
const PIO2_3: f32 = 7.549_79e-8;

/// `t` rounded to the nearest integer, for |t| < 2²².
#[inline(always)]
fn round_small<L: FloatLanes>(t: L) -> L {
    (t + L::splat(ROUNDER)) - L::splat(ROUNDER)
}

/// (sin x, cos x), lane by lane, within two ulps (or 2⁻²⁴ near zero) for |x| up to 8192,
/// Cephes' bound; larger arguments lose accuracy, NaN and infinities give NaN.
#[inline(always)]
pub(crate) fn sincos<L: FloatLanes>(x: L) -> (L, L) {
    let k = round_small(x * L::splat(std::f32::consts::FRAC_2_PI));
    let r = ((x - k * L::splat(PIO2_1)) - k * L::splat(PIO2_2)) - k * L::splat(PIO2_3);
    // k mod 4, as −2 ..= 2 (−1 is quadrant 3, ±2 quadrant 2).
    let q = k - round_small(k * L::splat(0.25)) * L::splat(4.0);
    let z = r * r;
    let sin = ((L::splat(-1.951_529_6e-4) * z + L::splat(8.332_161e-3)) * z
        - L::splat(1.666_665_5e-1))
        * z
        * r
        + r;
    let cos = ((L::splat(2.443_315_7e-5) * z - L::splat(1.388_731_6e-3)) * z
        + L::splat(4.166_664_6e-2))
        * z
        * z
        - L::splat(0.5) * z
        + L::splat(1.0);
    // Quadrants 1 and 3 swap the two; sin is negative in 2 and 3, cos in 1 and 2.
    let swap = q.abs().eq(L::splat(1.0));
    let (s, c) = (L::select(swap, cos, sin), L::select(swap, sin, cos));
    let sin_negative = q.lt(L::splat(-0.5)) | q.gt(L::splat(1.5));
    let cos_negative = q.gt(L::splat(0.5)) | q.lt(L::splat(-1.5));
    (
        L::select(sin_negative, s.neg(), s),
        L::select(cos_negative, c.neg(), c),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    /// Arguments over several turns both ways, the quadrants' edges and the path tracer's
    /// 2π·u for u in (0, 1).
    fn arguments() -> Vec<f32> {
        let mut xs: Vec<f32> = (-40_000..=40_000).map(|i| i as f32 * 1e-3).collect();
        for k in -8..=8 {
            let edge = k as f32 * std::f32::consts::FRAC_PI_4;
            xs.extend([edge, edge.next_up(), edge.next_down()]);
        }
        xs.extend((0..100_000).map(|i| 2.0 * std::f32::consts::PI * ((i as f32 + 0.5) * 1e-5)));
        xs.extend([0.0, -0.0, 1e-30, 5000.0, -8192.0, 8192.0]);
        xs
    }

    #[test]
    fn sincos_is_within_two_ulps_of_the_true_values() {
        for x in arguments() {
            let (s, c) = sincos(x);
            let (ts, tc) = (f64::from(x).sin(), f64::from(x).cos());
            // Two ulps of the value, or of 2⁻²⁴ near zero (the absolute error there).
            let ulp = |v: f64| (v.abs().max(0.5) * f64::from(f32::EPSILON)).max(1e-9);
            assert!(
                (f64::from(s) - ts).abs() <= 2.0 * ulp(ts),
                "sin {x}: {s} against {ts}"
            );
            assert!(
                (f64::from(c) - tc).abs() <= 2.0 * ulp(tc),
                "cos {x}: {c} against {tc}"
            );
        }
    }

    /// Every width gives the scalar bits.
    fn lanes_agree<L: FloatLanes>() {
        let xs = arguments();
        let mut row = [0.0f32; 16];
        for chunk in xs.chunks(L::LANES) {
            row[..chunk.len()].copy_from_slice(chunk);
            let (s, c) = sincos(L::load(&row, 0));
            let (s, c) = (s.to_array(), c.to_array());
            for (k, &x) in chunk.iter().enumerate() {
                let (ws, wc) = sincos(x);
                assert_eq!(s[k].to_bits(), ws.to_bits(), "sin {x}, {} lanes", L::LANES);
                assert_eq!(c[k].to_bits(), wc.to_bits(), "cos {x}, {} lanes", L::LANES);
            }
        }
    }

    #[test]
    fn four_lanes_give_the_scalar_bits() {
        lanes_agree::<Vec4>();
    }

    #[cfg(target_arch = "x86_64")]
    #[test]
    #[cfg_attr(not(prism_host_avx2), ignore = "this CPU lacks AVX2")]
    fn eight_lanes_give_the_scalar_bits() {
        if is_x86_feature_detected!("avx2") {
            lanes_agree::<super::super::F32x8>();
        }
    }
}
