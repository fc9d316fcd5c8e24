//! Optics against closed forms: mirror reflection, Snell's law both ways, the critical
//! angle, the exact Fresnel equations (checked against their independent angle form),
//! Schlick's error bound, and the energy bookkeeping of `Material::specular_weights`.

use crate::common;

use common::{assert_rel, assert_vec_close};
use prism::math::{Color, Vec3};
use prism::shading::fresnel::{exact, schlick};
use prism::shading::optics::{reflect, refract};
use prism::shading::{FresnelMode, Material, SpecularWeights};
use std::f64::consts::PI;

const IOR: f64 = 1.5;

/// A unit direction travelling down onto the surface y = 0 (normal +y) at angle `theta`
/// from the normal, in the xy plane.
fn incident(theta: f64) -> Vec3 {
    Vec3::new(theta.sin() as f32, -theta.cos() as f32, 0.0)
}

/// Fresnel reflectance from the angle form of the equations (Hecht):
/// R_s = sin²(θi − θt)/sin²(θi + θt), R_p = tan²(θi − θt)/tan²(θi + θt); unpolarised is
/// their mean. Independent of the amplitude form prism implements.
fn fresnel_angle_form(theta_i: f64, n1: f64, n2: f64) -> f64 {
    let sin_t = n1 / n2 * theta_i.sin();
    if sin_t >= 1.0 {
        return 1.0;
    }
    if theta_i == 0.0 {
        return ((n1 - n2) / (n1 + n2)).powi(2);
    }
    let theta_t = sin_t.asin();
    let rs = ((theta_i - theta_t).sin() / (theta_i + theta_t).sin()).powi(2);
    let rp = ((theta_i - theta_t).tan() / (theta_i + theta_t).tan()).powi(2);
    0.5 * (rs + rp)
}

#[test]
fn reflection_mirrors_about_the_normal() {
    let wi = Vec3::new(1.0, -1.0, 0.0).normalize();
    assert_vec_close(
        reflect(wi, Vec3::Y),
        Vec3::new(1.0, 1.0, 0.0).normalize(),
        1e-7,
        "45°",
    );
    assert_eq!(reflect(-Vec3::Z, Vec3::Z), Vec3::Z, "normal incidence");
    // Angle in = angle out, in the plane of incidence, for an arbitrary normal.
    let n = Vec3::new(0.3, 0.8, -0.5).normalize();
    let wi = Vec3::new(-0.2, -0.9, 0.4).normalize();
    let wo = reflect(wi, n);
    assert_rel(wo.length(), 1.0, 1e-6, 1.0, "unit length");
    assert_rel(wo.dot(n), -wi.dot(n) as f64, 1e-6, 1.0, "equal angles");
    assert_rel(wi.cross(n).dot(wo), 0.0, 1e-6, 1.0, "coplanar");
}

#[test]
fn snell_entering_and_leaving() {
    for deg in (0..90).step_by(5) {
        let theta = (deg as f64).to_radians();
        // Entering glass: sinθt = sinθi / 1.5 (the x component of the refracted ray).
        let t = refract(incident(theta), Vec3::Y, (1.0 / IOR) as f32).unwrap();
        assert_rel(t.x, theta.sin() / IOR, 1e-6, 1.0, "entering: sinθt");
        assert!(t.y < 0.0, "continues downwards");
        assert_rel(t.length(), 1.0, 1e-6, 1.0, "unit length");
        assert_eq!(t.z, 0.0, "stays in the plane of incidence");
        // Leaving glass below the critical angle: sinθt = 1.5 sinθi.
        if IOR * theta.sin() < 0.999 {
            let t = refract(incident(theta), Vec3::Y, IOR as f32).unwrap();
            assert_rel(t.x, IOR * theta.sin(), 2e-6, 1.0, "leaving: sinθt");
            assert!(t.y < 0.0);
        }
    }
    // Refraction is reversible: going back through the surface recovers the direction.
    let wi = incident(0.6);
    let t = refract(wi, Vec3::Y, (1.0 / IOR) as f32).unwrap();
    let back = refract(-t, -Vec3::Y, IOR as f32).unwrap();
    assert_vec_close(back, -wi, 1e-6, "reversibility");
}

#[test]
fn total_internal_reflection_starts_at_the_critical_angle() {
    let critical = (1.0 / IOR).asin();
    // One micro-radian either side is ~1e3 times the f32 error of η²sin²θ here.
    let below = refract(incident(critical - 1e-6), Vec3::Y, IOR as f32);
    let above = refract(incident(critical + 1e-6), Vec3::Y, IOR as f32);
    let t = below.expect("just below the critical angle: refracts");
    assert!(t.x > 0.999, "grazing exit, got {t:?}");
    assert!(above.is_none(), "just above the critical angle: TIR");
    assert!(refract(incident(1.2), Vec3::Y, IOR as f32).is_none());
    // Entering the denser medium never reflects totally.
    assert!(refract(incident(PI / 2.0 - 1e-4), Vec3::Y, (1.0 / IOR) as f32).is_some());
}

#[test]
fn fresnel_at_normal_incidence() {
    for n in [1.33f64, 1.5, 2.417] {
        let r0 = ((n - 1.0) / (n + 1.0)).powi(2);
        assert_rel(exact(1.0, (1.0 / n) as f32), r0, 1e-6, 0.0, "entering");
        assert_rel(exact(1.0, n as f32), r0, 1e-6, 0.0, "leaving");
        assert_rel(schlick(1.0, (1.0 / n) as f32), r0, 1e-6, 0.0, "Schlick R0");
    }
    assert_rel(exact(1.0, (1.0 / IOR) as f32), 0.04, 1e-6, 0.0, "glass: 4%");
}

#[test]
fn fresnel_matches_the_angle_form() {
    for i in 0..=1000 {
        let theta = i as f64 / 1000.0 * (PI / 2.0 - 1e-3);
        let cos = theta.cos() as f32;
        let entering = fresnel_angle_form(theta, 1.0, IOR);
        assert_rel(
            exact(cos, (1.0 / IOR) as f32),
            entering,
            1e-5,
            1e-2,
            "entering",
        );
        let leaving = fresnel_angle_form(theta, IOR, 1.0);
        // Near the critical angle R is steep in θ; compare away from a small band.
        let critical = (1.0 / IOR).asin();
        if (theta - critical).abs() > 1e-3 {
            assert_rel(exact(cos, IOR as f32), leaving, 1e-4, 1e-2, "leaving");
        }
    }
}

#[test]
fn fresnel_is_symmetric_under_reversal() {
    // Entering at θi and leaving at the matching θt reflect the same fraction.
    for deg in 0..90 {
        let theta_i = (deg as f64).to_radians();
        let theta_t = (theta_i.sin() / IOR).asin();
        let r_in = exact(theta_i.cos() as f32, (1.0 / IOR) as f32);
        let r_out = exact(theta_t.cos() as f32, IOR as f32);
        assert_rel(r_out, r_in as f64, 1e-4, 1e-3, &format!("θi = {deg}°"));
    }
}

#[test]
fn fresnel_is_one_beyond_the_critical_angle() {
    let critical = (1.0 / IOR).asin();
    for k in 1..=100 {
        let theta = critical + 1e-5 + (PI / 2.0 - critical - 1e-5) * k as f64 / 100.0;
        let cos = theta.cos() as f32;
        assert_eq!(exact(cos, IOR as f32), 1.0, "exact at {theta}");
        assert_eq!(schlick(cos, IOR as f32), 1.0, "Schlick at {theta}");
    }
    // And R rises to 1 continuously as θ approaches it from below.
    let near = exact((critical - 1e-4).cos() as f32, IOR as f32);
    assert!(near > 0.9, "R just below the critical angle is {near}");
}

#[test]
fn brewster_angle_kills_parallel_reflectance() {
    // At tanθB = n2/n1, r_par = 0, so the unpolarised R is r_perp²/2 exactly.
    for (n1, n2) in [(1.0, IOR), (IOR, 1.0), (1.0, 2.417)] {
        let theta_b = (n2 / n1).atan();
        let theta_t = (n1 / n2 * theta_b.sin()).asin();
        let (ci, ct) = (theta_b.cos(), theta_t.cos());
        let r_perp = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct);
        let r = exact(ci as f32, (n1 / n2) as f32);
        assert_rel(r, 0.5 * r_perp * r_perp, 1e-4, 0.0, "R at Brewster");
        // Off Brewster the parallel part is back, so R is strictly larger than r_perp²/2.
        let off = theta_b + 0.2;
        if (n1 / n2 * off.sin()) < 1.0 {
            let t = (n1 / n2 * off.sin()).asin();
            let rp = (n1 * off.cos() - n2 * t.cos()) / (n1 * off.cos() + n2 * t.cos());
            assert!(exact(off.cos() as f32, (n1 / n2) as f32) as f64 > 0.5 * rp * rp + 1e-4);
        }
    }
}

/// Largest |Schlick − exact| for glass (η = 1.5), measured over 10⁵ angles each way.
const SCHLICK_MEASURED: f32 = 0.0357;
const SCHLICK_BOUND: f32 = 0.037;

#[test]
fn schlick_stays_close_to_exact() {
    let mut worst = 0.0f32;
    for eta in [(1.0 / IOR) as f32, IOR as f32] {
        for i in 0..=100_000 {
            let cos = i as f32 / 100_000.0;
            let d = (schlick(cos, eta) - exact(cos, eta)).abs();
            worst = worst.max(d);
        }
    }
    eprintln!("max |Schlick − exact| for η = 1.5: {worst:.5}");
    assert!(
        worst < SCHLICK_BOUND,
        "Schlick differs from exact by {worst} (measured {SCHLICK_MEASURED} when written)"
    );
    assert!(
        worst > 0.03,
        "suspiciously close ({worst}): is Schlick still an approximation?"
    );
}

fn glass(fresnel: FresnelMode, kr: f32, kt: f32) -> Material {
    Material {
        reflect: kr,
        transmit: Color::splat(kt),
        ior: IOR as f32,
        fresnel,
        ..Material::default()
    }
}

/// The weights of a grey material, whose transmission is one number.
#[derive(Debug)]
struct Grey {
    reflect: f32,
    transmit: f32,
    total_internal_reflection: bool,
}

impl Grey {
    fn of(w: SpecularWeights) -> Grey {
        Grey {
            reflect: w.reflect,
            transmit: w.transmit.x,
            total_internal_reflection: w.total_internal_reflection,
        }
    }
}

#[test]
fn specular_weights_conserve_energy() {
    for mode in [FresnelMode::Off, FresnelMode::Exact, FresnelMode::Schlick] {
        for (kr, kt) in [(0.0, 1.0), (0.05, 0.95), (0.3, 0.5), (0.8, 0.0)] {
            let m = glass(mode, kr, kt);
            for eta in [(1.0 / IOR) as f32, IOR as f32] {
                for i in 0..=1000 {
                    let cos = i as f32 / 1000.0;
                    let full = m.specular_weights(cos, eta);
                    let what = format!("{mode:?} kr={kr} kt={kt} η={eta} cos={cos}");
                    assert_eq!(full.transmit, Color::splat(full.transmit.x), "{what}: grey");
                    let w = Grey::of(full);
                    assert!(w.reflect >= 0.0 && w.transmit >= 0.0, "{what}: {w:?}");
                    assert!(w.reflect + w.transmit <= kr + kt + 1e-6, "{what}: {w:?}");
                    if w.total_internal_reflection {
                        assert_eq!(w.transmit, 0.0, "{what}: TIR transmits nothing");
                        assert_rel(w.reflect, (kr + kt) as f64, 1e-6, 1.0, &what);
                    }
                    if mode == FresnelMode::Off && !w.total_internal_reflection {
                        assert_eq!((w.reflect, w.transmit), (kr, kt), "{what}");
                    }
                    if mode == FresnelMode::Exact && !w.total_internal_reflection {
                        let r = exact(cos, eta);
                        assert_rel(w.reflect, ((kr + kt) * r) as f64, 1e-6, 1e-6, &what);
                        assert_rel(w.transmit, (kt * (1.0 - r)) as f64, 1e-6, 1e-6, &what);
                    }
                }
            }
        }
    }
}

#[test]
fn coloured_transmission_tints_the_refracted_ray_only() {
    // Red glass: the interface reflects white light weighted by its clearest channel; the
    // refracted ray keeps kt·(1 − R) per channel.
    let kt = Color::new(0.9, 0.3, 0.1);
    for mode in [FresnelMode::Off, FresnelMode::Exact] {
        let m = Material {
            reflect: 0.05,
            transmit: kt,
            ior: IOR as f32,
            fresnel: mode,
            ..Material::default()
        };
        for eta in [(1.0 / IOR) as f32, IOR as f32] {
            for i in 0..=100 {
                let cos = i as f32 / 100.0;
                let w = m.specular_weights(cos, eta);
                let what = format!("{mode:?} η={eta} cos={cos}");
                if w.total_internal_reflection {
                    assert_eq!(w.transmit, Color::ZERO, "{what}");
                    assert_rel(w.reflect, 0.05 + 0.9, 1e-6, 1.0, &what);
                    continue;
                }
                let r = match mode {
                    FresnelMode::Off => 0.0,
                    _ => exact(cos, eta),
                };
                for c in 0..3 {
                    assert_rel(w.transmit[c], (kt[c] * (1.0 - r)) as f64, 1e-6, 1e-6, &what);
                }
                let reflect = match mode {
                    FresnelMode::Off => 0.05,
                    _ => (0.05 + 0.9) * r,
                };
                assert_rel(w.reflect, reflect as f64, 1e-6, 1e-6, &what);
            }
        }
    }
}

#[test]
fn specular_weights_tir_agrees_with_refract() {
    // The weights and the refracted direction must agree on where TIR begins, or a
    // transmitted weight would be spent on a ray that cannot be traced.
    let critical = (1.0 / IOR).asin();
    for mode in [FresnelMode::Off, FresnelMode::Exact, FresnelMode::Schlick] {
        let m = glass(mode, 0.1, 0.9);
        for k in -50..=50 {
            let theta = critical + k as f64 * 1e-6;
            let wi = incident(theta);
            let cos = -wi.dot(Vec3::Y);
            let w = m.specular_weights(cos, IOR as f32);
            let t = refract(wi, Vec3::Y, IOR as f32);
            let w = Grey::of(w);
            assert_eq!(
                w.total_internal_reflection,
                t.is_none(),
                "{mode:?} at θ = critical {:+}µrad",
                k
            );
            if k > 5 {
                assert!(w.total_internal_reflection, "{mode:?}: {k} µrad above");
                assert_eq!(w.transmit, 0.0);
                assert_rel(w.reflect, 1.0, 1e-6, 1.0, "all weight to reflection");
            }
            if k < -5 {
                assert!(!w.total_internal_reflection, "{mode:?}: {k} µrad below");
            }
        }
    }
}
