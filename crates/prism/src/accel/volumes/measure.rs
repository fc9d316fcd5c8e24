//! How tight a volume is, as a number comparable across kinds: the chance that a random
//! line meeting a node's box also meets its volume. By Cauchy's formula this is the
//! ratio of the two surface areas for convex bodies, and it measures the test a ray
//! actually runs (padding included), so it is estimated with random lines, not formulas.

use super::volume::Volume;
use crate::geometry::Geometry;
use crate::math::hash::uniform;
use crate::math::{Aabb, Ray, TraceRay, Vec3};

/// Lines hitting the volume and lines hitting the box, over `lines` isotropic random lines
/// through a ball around `bounds` that contains the volume too.
pub(super) fn crossings<V: Volume>(volume: &V, bounds: &Aabb, lines: u32, seed: u64) -> (u64, u64) {
    crossings_with(
        |ray| volume.hit(&V::prepare(ray), ray, f32::INFINITY).is_some(),
        bounds,
        lines,
        seed,
    )
}

/// `crossings` for any ray test.
pub(super) fn crossings_with(
    hits: impl Fn(&TraceRay) -> bool,
    bounds: &Aabb,
    lines: u32,
    seed: u64,
) -> (u64, u64) {
    let center = bounds.center();
    // Every volume kind lies within three half-diagonals of the box's centre (a sphere
    // around the contents' mean is the widest).
    let reach = 3.0 * 0.5 * bounds.extent().length();
    if reach.is_nan() || reach <= 0.0 {
        return (0, 0);
    }
    let (mut on_volume, mut on_box) = (0, 0);
    for k in 0..lines {
        let u = |dim: u32| uniform(k, 0, 0, dim, seed);
        let z = 1.0 - 2.0 * u(0);
        let phi = std::f32::consts::TAU * u(1);
        let s = (1.0 - z * z).max(0.0).sqrt();
        let dir = Vec3::new(s * phi.cos(), s * phi.sin(), z);
        // Uniform in the disc of radius `reach` perpendicular to the direction.
        let (a, b) = (
            dir.any_orthonormal_vector(),
            dir.cross(dir.any_orthonormal_vector()),
        );
        let rho = reach * u(2).sqrt();
        let psi = std::f32::consts::TAU * u(3);
        let through = center + rho * (psi.cos() * a + psi.sin() * b);
        let ray = TraceRay::new(Ray::new(through - 2.0 * reach * dir, dir));
        on_volume += hits(&ray) as u64;
        on_box += bounds
            .hit(ray.ray.origin, ray.inv_dir, f32::INFINITY)
            .is_some() as u64;
    }
    (on_volume, on_box)
}

/// The box of a set of primitives.
pub(super) fn prims_bounds(geometry: &Geometry, prims: &[u32]) -> Aabb {
    prims
        .iter()
        .filter_map(|&p| geometry.bounds(p))
        .fold(Aabb::EMPTY, |a, b| a.union(&b))
}
