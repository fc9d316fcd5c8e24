//! Beams and the beam tree. A beam is a cone from the eye through its window (convex cells
//! of the film) into a *virtual* scene: the real scene under an affine map, the product of
//! one map per interface the beam passed. A mirror's map is the reflection in its plane
//! (Heckbert & Hanrahan's mirrored apex, seen the other way round: instead of moving the
//! apex behind the mirror, the world is mirrored in front of the fixed eye, so every beam
//! projects onto the same film). Refraction through a plane has no such exact map, since
//! refracted rays from one point do not meet in one point; as Heckbert & Hanrahan do, it is
//! approximated by a linear map: a scale of depth below the interface by
//! s = η·cosθi/cosθt, computed for the fragment's central ray, which refracts that ray
//! exactly and the others approximately (s → η, the apparent depth of paraxial optics, near
//! normal incidence; the error grows with the spread of angles across the fragment).

use super::convex::{Affine2, Convex};
use super::view::View;
use crate::math::Color;
use crate::shading::Material;
use glam::{DAffine3, DMat3, DVec2, DVec3};

/// One interface a beam passed on its way from the eye, for its weight at a film point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Link {
    /// The interface's unit normal in the virtual space of the beam that met it.
    pub(crate) normal: DVec3,
    /// Its material.
    pub(crate) material: u32,
    /// Reflection (else transmission).
    pub(crate) reflect: bool,
    /// η_incident/η_transmitted of the crossing.
    pub(crate) eta: f32,
}

/// The plane a secondary beam left through: only what lies beyond it belongs to the beam.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Interface {
    /// Its unit normal and offset (n·X = k) in virtual space (the same in the parent's and
    /// the child's: reflection and the depth scale keep the plane fixed).
    pub(crate) normal: DVec3,
    /// Offset.
    pub(crate) k: f64,
    /// Its inverse depth on the film.
    pub(crate) w: Affine2,
    /// The facet it is, which the beam leaves out.
    pub(crate) facet: u32,
}

/// A beam of the tree.
#[derive(Clone, Debug)]
pub(crate) struct Beam {
    /// Real scene → this beam's virtual scene.
    pub(crate) to_virtual: DAffine3,
    /// Its cross-section on the film.
    pub(crate) window: Vec<Convex>,
    /// The interface it left through (None for the view's beam).
    pub(crate) interface: Option<Interface>,
    /// The interfaces from the eye to it.
    pub(crate) chain: Vec<Link>,
    /// Depth in the tree: the view's beam is 1, as the eye ray is.
    pub(crate) depth: u32,
}

impl Beam {
    /// The beam of a film rectangle.
    pub(crate) fn view(window: Convex) -> Beam {
        Beam {
            to_virtual: DAffine3::IDENTITY,
            window: vec![window],
            interface: None,
            chain: Vec::new(),
            depth: 1,
        }
    }

    /// What this beam's radiance is worth at film point `p`: the product of the reflection
    /// and transmission weights of its chain, each at the incidence angle of the ray
    /// through `p` (per point, so Fresnel weights vary across a fragment as they should).
    pub(crate) fn weight(&self, view: &View, materials: &[Material], p: DVec2) -> Color {
        let mut w = Color::ONE;
        if self.chain.is_empty() {
            return w;
        }
        let dir = view.dir(p).normalize();
        for link in &self.chain {
            let cos = dir.dot(link.normal).abs().min(1.0) as f32;
            let s = materials[link.material as usize].specular_weights(cos, link.eta);
            w *= if link.reflect {
                Color::splat(s.reflect)
            } else {
                s.transmit
            };
        }
        w
    }

    /// The real-space half-spaces (n·X + c ≥ 0) that bound this beam: its four sides and
    /// the far side of its interface, for culling.
    pub(crate) fn real_planes(&self, view: &View, lo: DVec2, hi: DVec2) -> Vec<(DVec3, f64)> {
        let mut planes: Vec<(DVec3, f64)> = view.frustum(lo, hi).to_vec();
        if let Some(i) = &self.interface {
            planes.push(beyond(view, i.normal, i.k));
        }
        let a = self.to_virtual.matrix3;
        let b = self.to_virtual.translation;
        planes
            .into_iter()
            .map(|(n, c)| (a.transpose() * n, n.dot(b) + c))
            .collect()
    }

    /// The child beam through `window`, a fragment on the plane n·X = k (virtual space, unit
    /// n) of facet `facet`, reflected in it.
    pub(crate) fn reflected(&self, window: Vec<Convex>, plane: Interface, link: Link) -> Beam {
        let n = plane.normal;
        // X ↦ X − 2(n·X − k)n.
        let m = DMat3::IDENTITY - 2.0 * outer(n, n);
        let map = DAffine3::from_mat3_translation(m, 2.0 * plane.k * n);
        self.child(map, window, plane, link)
    }

    /// The child beam through `window` refracted at the plane: depth beyond it scaled by
    /// `s` (Heckbert & Hanrahan's linear approximation, see the module's notes).
    pub(crate) fn refracted(
        &self,
        window: Vec<Convex>,
        plane: Interface,
        link: Link,
        s: f64,
    ) -> Beam {
        let n = plane.normal;
        // X ↦ X + (s − 1)(n·X − k)n.
        let m = DMat3::IDENTITY + (s - 1.0) * outer(n, n);
        let map = DAffine3::from_mat3_translation(m, -(s - 1.0) * plane.k * n);
        self.child(map, window, plane, link)
    }

    fn child(&self, map: DAffine3, window: Vec<Convex>, plane: Interface, link: Link) -> Beam {
        let mut chain = self.chain.clone();
        chain.push(link);
        Beam {
            to_virtual: map * self.to_virtual,
            window,
            interface: Some(plane),
            chain,
            depth: self.depth + 1,
        }
    }
}

/// n ⊗ n.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// The half-space of points beyond the plane n·X = k as the eye sees it.
fn beyond(view: &View, n: DVec3, k: f64) -> (DVec3, f64) {
    let side = if n.dot(view.eye) - k >= 0.0 {
        1.0
    } else {
        -1.0
    };
    // −side·(n·X − k) ≥ 0.
    (-side * n, side * k)
}

/// s = η·cosθi/cosθt for a crossing with cosine `cos_i` and η = `eta`; None under total
/// internal reflection.
pub(crate) fn depth_scale(cos_i: f64, eta: f64) -> Option<f64> {
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    Some(eta * cos_i / (1.0 - sin2_t).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_depth_scale_refracts_the_central_ray_exactly() {
        // A ray at 40° into glass (η = 1/1.5) through the plane z = 0 at the origin.
        let eta = 1.0 / 1.5f64;
        let (sin_i, cos_i) = 40f64.to_radians().sin_cos();
        let s = depth_scale(cos_i, eta).unwrap();
        let sin_t = eta * sin_i;
        let cos_t = (1.0 - sin_t * sin_t).sqrt();
        // A point 2 units along the refracted ray below the plane.
        let real = DVec3::new(2.0 * sin_t, 0.0, -2.0 * cos_t);
        let scaled = DVec3::new(real.x, real.y, real.z * s);
        // ...lies on the unrefracted continuation of the incident ray.
        let incident = DVec3::new(sin_i, 0.0, -cos_i);
        assert!(scaled.normalize().dot(incident) > 1.0 - 1e-12);
        assert!((depth_scale(1.0, eta).unwrap() - eta).abs() < 1e-15);
        assert!(depth_scale(0.3, 1.5).is_none());
    }
}
