//! Local illumination at one point of a fragment, exactly as the Whitted integrator
//! computes it (I = Ia·ka·C + Le + Σ visible lights (kd·(N·L)·C + highlight)), with shadow
//! rays from that point through `Shadows` (so through transparent surfaces, filtered by
//! them). It is returned split as radiance = k1·C + k2, affine in the texture colour C, so
//! that the caller can integrate C exactly over a piece (the checker's squares) while the
//! lighting is taken at the piece's centroid.

use super::facets::Facet;
use crate::integrator::shadow::Shadows;
use crate::math::{Color, Ray, Vec3};
use crate::scene::Scene;
use crate::shading::Material;
use crate::stats::Stats;
use glam::DVec3;

/// Radiance at a point as k1·C + k2, and C there.
pub(crate) struct Local {
    /// The coefficient of the texture colour.
    pub(crate) k1: Color,
    /// The rest.
    pub(crate) k2: Color,
    /// The texture colour at the point.
    pub(crate) color: Color,
}

fn f(v: DVec3) -> Vec3 {
    Vec3::new(v.x as f32, v.y as f32, v.z as f32)
}

/// Shades `facet` at the real point `point`, seen from the real `apex` (the eye, or the
/// eye as the beam's interfaces map it), at tree depth `depth`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn local(
    scene: &Scene,
    shadows: &Shadows,
    facet: &Facet,
    material: &Material,
    point: DVec3,
    apex: DVec3,
    depth: u32,
    stats: &mut Stats,
) -> Local {
    let dir = (point - apex).normalize();
    let ray = Ray::new(f(apex), f(dir));
    let hit = facet.shape_hit(point, apex, dir);
    let sp = scene.geometry.surface(facet.prim, &ray, &hit);
    let (entering, ng, ns) = sp.facing(ray.dir);
    let to_eye = -ray.dir;
    // The texel's coefficients for the local terms; the beams' mirror and refraction
    // weights are the material's own (a beam's child has one weight).
    let k = material.coefficients_at(sp.uv);
    let mut k1 = k.ambient * scene.ambient;
    let mut k2 = Color::ZERO;
    if entering && k.is_emissive() {
        k2 += k.emission;
    }
    for (index, light) in scene.lights.iter().enumerate() {
        let Some(ls) = light.sample(sp.p) else {
            continue;
        };
        // SPD rule 10, as the ray tracer: no shadow ray to a light behind the surface.
        if ng.dot(ls.to_light) <= 0.0 {
            continue;
        }
        let visibility = shadows.visibility(index, depth, &sp, ng, &ls, stats);
        if visibility.max_element() <= 0.0 {
            continue;
        }
        k1 += visibility * ls.color * k.diffuse * ns.dot(ls.to_light).max(0.0);
        k2 += visibility * ls.color * k.highlight_term(ns, ls.to_light, to_eye);
    }
    Local {
        k1,
        k2,
        color: material.color_at(sp.uv, sp.p),
    }
}
