//! The workload of a benchmark: one camera ray through the centre of each pixel, one
//! shadow ray from each primary hit point to each light in front of the surface, and one
//! incoherent ray from each primary hit point in a cosine-distributed direction about the
//! surface (a diffuse bounce, as embree-bench's incoherent rays). The hit points come from
//! a reference accelerator, so every method is timed on exactly the same rays.

use prism::camera::CameraError;
use prism::math::robust::offset_ray_origin;
use prism::math::{hash, warp, Frame, Ray};
use prism::scene::PreparedScene;
use prism::stats::Stats;
use serde::Serialize;

/// The seed of the incoherent rays' directions (any fixed number: the rays only need to
/// be the same for every method and run).
const BOUNCE_SEED: u64 = 0x1ac0;

/// A ray to a light and the distance to it (infinite for directional lights).
#[derive(Clone, Copy, Debug)]
pub struct ShadowRay {
    /// The ray, from a hit point towards the light.
    pub ray: Ray,
    /// Distance to the light (infinite for directional lights).
    pub t_max: f32,
    /// The light it goes to (an index into the scene's lights).
    pub light: u32,
    /// The pixel whose camera ray's hit it leaves from (row-major).
    pub pixel: u32,
}

/// The fixed rays of one scene.
#[derive(Clone, Debug, Default)]
pub struct RaySet {
    /// Image width the camera rays were made for.
    pub width: u32,
    /// Image height the camera rays were made for.
    pub height: u32,
    /// One camera ray per pixel, row-major.
    pub primary: Vec<Ray>,
    /// The shadow rays of the camera rays' hits.
    pub shadow: Vec<ShadowRay>,
    /// One diffuse bounce from each camera ray's hit (nearest hit, unbounded).
    pub incoherent: Vec<Ray>,
    /// Primary rays that hit something.
    pub primary_hits: usize,
    /// The reference's answers, which every method must reproduce.
    pub primary_digest: super::HitDigest,
    /// The reference's answers for the shadow rays.
    pub shadow_digest: super::HitDigest,
    /// The reference's answers for the incoherent rays.
    pub incoherent_digest: super::HitDigest,
}

/// Counts for reports.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct RaySetSize {
    /// Camera rays.
    pub primary: usize,
    /// Shadow rays.
    pub shadow: usize,
    /// Incoherent rays.
    pub incoherent: usize,
}

impl RaySet {
    /// Camera rays of a `width` × `height` image of the scene and the shadow rays of their
    /// hits, found with `reference` (any accelerator: all give the same hits).
    pub fn generate(
        reference: &PreparedScene,
        width: u32,
        height: u32,
    ) -> Result<Self, CameraError> {
        let scene = reference.scene;
        let camera = scene.camera.setup(width, height)?;
        let mut set = RaySet {
            width,
            height,
            ..RaySet::default()
        };
        let mut stats = Stats::default();
        for y in 0..height {
            for x in 0..width {
                let ray = camera.ray(x as f32 + 0.5, y as f32 + 0.5);
                set.primary.push(ray);
                let Some(hit) = reference.intersector.intersect(
                    &scene.geometry,
                    &ray,
                    f32::INFINITY,
                    &mut stats,
                ) else {
                    continue;
                };
                set.primary_hits += 1;
                let sp = scene.geometry.surface(hit.prim, &ray, &hit.shape_hit());
                // Shade from the side the ray arrived on, as the integrator does.
                let ng = if ray.dir.dot(sp.ng) < 0.0 {
                    sp.ng
                } else {
                    -sp.ng
                };
                let bounce = Frame::from_z(ng).to_world(warp::cosine_hemisphere(
                    hash::uniform(x, y, 0, 0, BOUNCE_SEED),
                    hash::uniform(x, y, 0, 1, BOUNCE_SEED),
                ));
                let bounce = bounce.normalize();
                let origin = offset_ray_origin(sp.p, sp.p_error, ng, bounce);
                set.incoherent.push(Ray::new(origin, bounce));
                for (index, light) in scene.lights.iter().enumerate() {
                    let Some(ls) = light.sample(sp.p) else {
                        continue;
                    };
                    if ng.dot(ls.to_light) <= 0.0 {
                        continue;
                    }
                    let origin = offset_ray_origin(sp.p, sp.p_error, ng, ls.to_light);
                    set.shadow.push(ShadowRay {
                        ray: Ray::new(origin, ls.to_light),
                        t_max: ls.distance,
                        light: index as u32,
                        pixel: y * width + x,
                    });
                }
            }
        }
        let geometry = &scene.geometry;
        set.primary_digest = super::digest::primary(&reference.intersector, geometry, &set.primary);
        set.shadow_digest = super::digest::shadow(&reference.intersector, geometry, &set.shadow);
        set.incoherent_digest =
            super::digest::primary(&reference.intersector, geometry, &set.incoherent);
        Ok(set)
    }

    /// Rays of every kind in all: one pass of the bench over the set.
    pub fn len(&self) -> usize {
        self.primary.len() + self.shadow.len() + self.incoherent.len()
    }

    /// Whether the set holds no rays.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// How many rays of each kind the set holds.
    pub fn size(&self) -> RaySetSize {
        RaySetSize {
            primary: self.primary.len(),
            shadow: self.shadow.len(),
            incoherent: self.incoherent.len(),
        }
    }
}
