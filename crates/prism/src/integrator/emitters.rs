//! Area lights: the primitives whose material emits, sampled by area for next-event
//! estimation. An emitter is chosen in proportion to its power (area × mean radiance, an
//! emissive texture's mean texel counted alike on every primitive of its material), then
//! a point uniformly over its area, so the density of a point is
//! P(emitter) / area, the same everywhere on one emitter, which is what MIS asks of a hit
//! that BSDF sampling found. A point's radiance is that of the texel there, where the
//! material has an emissive texture.
//!
//! Triangles (so quads and whole meshes) and spheres are sampled. Planes, boxes and cones
//! that emit still shine when a path hits them, but light samples never aim at them.

use crate::geometry::{Geometry, Primitive, Shape, ShapeHit, TriangleMesh, Uv};
use crate::math::robust::gamma;
use crate::math::warp::{uniform_sphere, uniform_triangle};
use crate::math::{Color, Ray, Vec2, Vec3};
use crate::scene::Scene;

/// Marks a primitive that light samples never choose.
const NOT_SAMPLED: u32 = u32::MAX;

#[derive(Clone, Copy, Debug)]
struct Emitter {
    prim: u32,
    area: f32,
    /// The density per unit area of its points (`probability / area`), made once.
    pdf_area: f32,
    /// What a point on it needs from the scene, where that is the same at every point.
    flat: Option<FlatTriangle>,
}

/// A triangle of a mesh without vertex normals, of a material without an emissive
/// texture: everything `Emitters::sample` reads from the scene to draw a point on it (the
/// corners, the face normal, the radiance), gathered once, so that a light sample does
/// not look up the primitive, its material, its mesh, its corner indices and corners (a
/// quarter of a Cornell box's shade stage went to `Emitters::sample`). The point is
/// `TriangleMesh::flat_point` of the same corners, the normal the mesh's kept face normal,
/// the radiance the material's: the same bits. 48 bytes more per emitting triangle.
#[derive(Clone, Copy, Debug)]
struct FlatTriangle {
    corners: [Vec3; 3],
    n: Vec3,
    radiance: Color,
}

/// The `FlatTriangle` of primitive `prim`, where it is one.
fn flat_triangle(scene: &Scene, prim: &Primitive) -> Option<FlatTriangle> {
    let Shape::Triangle { mesh, index } = prim.shape else {
        return None;
    };
    let material = &scene.materials[prim.material as usize];
    if material.emission_map.is_some() {
        return None;
    }
    let (corners, n) = scene.geometry.meshes[mesh as usize].flat_triangle(index)?;
    Some(FlatTriangle {
        corners,
        n,
        radiance: material.emission_at(Vec2::ZERO),
    })
}

/// The scene's sampled area lights and the choice between them.
#[derive(Clone, Debug, Default)]
pub struct Emitters {
    list: Vec<Emitter>,
    /// Cumulative probability of choosing emitters 0..=i; the last is 1.
    cdf: Vec<f32>,
    /// Per primitive, its index in `list` (or `NOT_SAMPLED`); empty without emitters.
    by_prim: Vec<u32>,
}

/// A point on an area light.
#[derive(Clone, Copy, Debug)]
pub struct EmitterSample {
    /// The point.
    pub p: Vec3,
    /// Per-axis bound on the error of `p`.
    pub p_error: Vec3,
    /// The light's geometric normal there: it emits towards this side.
    pub n: Vec3,
    /// Radiance it emits.
    pub radiance: Color,
    /// Density of the point per unit area, the choice of the emitter included.
    pub pdf_area: f32,
}

impl Emitters {
    /// The emitting primitives of `scene` that light samples can aim at.
    pub fn new(scene: &Scene) -> Emitters {
        let geometry = &scene.geometry;
        let mut list = Vec::new();
        let mut power = Vec::new();
        // Once per material: an emissive texture's mean reads every texel.
        let mean: Vec<Color> = scene.materials.iter().map(|m| m.mean_emission()).collect();
        for (prim, p) in geometry.primitives.iter().enumerate() {
            let radiance = mean[p.material as usize];
            if radiance.max_element() <= 0.0 {
                continue;
            }
            let Some(area) = area(geometry, &p.shape) else {
                continue;
            };
            if !(area > 0.0 && area.is_finite()) {
                continue;
            }
            list.push(Emitter {
                prim: prim as u32,
                area,
                pdf_area: 0.0,
                flat: flat_triangle(scene, p),
            });
            // f64: a million small triangles' areas sum without losing the last ones.
            power.push(area as f64 * (radiance.x + radiance.y + radiance.z) as f64);
        }
        if list.is_empty() {
            return Emitters::default();
        }
        let total: f64 = power.iter().sum();
        let mut running = 0.0f64;
        let mut cdf: Vec<f32> = power
            .iter()
            .map(|w| {
                running += w;
                (running / total) as f32
            })
            .collect();
        *cdf.last_mut().expect("not empty") = 1.0;
        let mut by_prim = vec![NOT_SAMPLED; geometry.primitives.len()];
        for (i, e) in list.iter().enumerate() {
            by_prim[e.prim as usize] = i as u32;
        }
        let mut emitters = Emitters { list, cdf, by_prim };
        for i in 0..emitters.list.len() {
            emitters.list[i].pdf_area = emitters.probability(i) / emitters.list[i].area;
        }
        emitters
    }

    /// Whether there is any area light to sample.
    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    fn probability(&self, i: usize) -> f32 {
        let below = if i == 0 { 0.0 } else { self.cdf[i - 1] };
        self.cdf[i] - below
    }

    /// The density per unit area with which `sample` picks a point on primitive `prim`;
    /// 0 for primitives it never picks.
    pub fn pdf_area(&self, prim: u32) -> f32 {
        match self.by_prim.get(prim as usize) {
            Some(&i) if i != NOT_SAMPLED => self.list[i as usize].pdf_area,
            _ => 0.0,
        }
    }

    /// A point on an area light: `u` chooses the light, `(u1, u2)` the point on it.
    pub fn sample(&self, scene: &Scene, u: f32, u1: f32, u2: f32) -> Option<EmitterSample> {
        if self.list.is_empty() {
            return None;
        }
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.list.len() - 1);
        let emitter = self.list[i];
        let pdf_area = emitter.pdf_area;
        if pdf_area <= 0.0 {
            return None;
        }
        if let Some(t) = &emitter.flat {
            // `TriangleMesh::surface_point`'s arithmetic on the kept corners.
            let (b1, b2) = uniform_triangle(u1, u2);
            let (p, p_error) = TriangleMesh::flat_point(t.corners, b1, b2);
            return Some(EmitterSample {
                p,
                p_error,
                n: t.n,
                radiance: t.radiance,
                pdf_area,
            });
        }
        let prim = &scene.geometry.primitives[emitter.prim as usize];
        let material = &scene.materials[prim.material as usize];
        let (p, p_error, n, uv) = match &prim.shape {
            Shape::Triangle { mesh, index } => {
                let (b1, b2) = uniform_triangle(u1, u2);
                // The mesh's own surface rule: the same point, error bound and front
                // side (vertex normals decide it) as a ray hitting there would get; the
                // uv only for an emissive texture.
                let mesh = &scene.geometry.meshes[*mesh as usize];
                match &material.emission_map {
                    Some(_) => {
                        let hit = ShapeHit {
                            t: 0.0,
                            u: b1,
                            v: b2,
                        };
                        let sp = mesh.surface(*index, &hit);
                        (sp.p, sp.p_error, sp.ng, sp.uv)
                    }
                    None => {
                        let (p, p_error, ng) = mesh.surface_point(*index, b1, b2);
                        (p, p_error, ng, Vec2::ZERO)
                    }
                }
            }
            Shape::Sphere(s) => {
                let d = uniform_sphere(u1, u2);
                let p = s.center + s.radius * d;
                let p_error = gamma(5) * (s.center.abs() + (s.radius * d).abs());
                // The sphere's own uv of the point, as a ray from its centre finds it.
                let uv = match &material.emission_map {
                    Some(_) => {
                        let hit = ShapeHit {
                            t: s.radius,
                            u: 0.0,
                            v: 0.0,
                        };
                        s.surface_with(&Ray::new(s.center, d), &hit, Uv::Compute).uv
                    }
                    None => Vec2::ZERO,
                };
                (p, p_error, if s.inside_out { -d } else { d }, uv)
            }
            _ => return None,
        };
        Some(EmitterSample {
            p,
            p_error,
            n,
            radiance: material.emission_at(uv),
            pdf_area,
        })
    }
}

/// The area of a shape light samples can aim at; `None` for the others.
fn area(geometry: &Geometry, shape: &Shape) -> Option<f32> {
    match shape {
        Shape::Triangle { mesh, index } => {
            let [a, b, c] = geometry.meshes[*mesh as usize].vertices(*index);
            Some(0.5 * (b - a).cross(c - a).length())
        }
        Shape::Sphere(s) => Some(4.0 * std::f32::consts::PI * s.radius * s.radius),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin;

    /// A sample on a kept flat triangle is the one the scene's own lookup draws, bit for
    /// bit: the Cornell box's light (a quad of a mesh without vertex normals) sampled with
    /// the kept corners and without them.
    #[test]
    fn flat_triangles_sample_as_the_scene_does() {
        let scene = builtin::find("cornell-light").expect("a built-in");
        let kept = Emitters::new(&scene);
        assert!(kept.list.iter().all(|e| e.flat.is_some()), "{kept:?}");
        let mut looked_up = kept.clone();
        for e in &mut looked_up.list {
            e.flat = None;
        }
        let bits = |s: EmitterSample| {
            [s.p, s.p_error, s.n, s.radiance]
                .map(|v| v.to_array().map(f32::to_bits))
                .concat()
                .into_iter()
                .chain([s.pdf_area.to_bits()])
                .collect::<Vec<u32>>()
        };
        let mut drawn = 0;
        for i in 0..=16 {
            for j in 0..=16 {
                let (u, u1, u2) = ((i as f32 + 0.5) / 17.5, i as f32 / 16.0, j as f32 / 16.0);
                let a = kept.sample(&scene, u, u1, u2).map(bits);
                let b = looked_up.sample(&scene, u, u1, u2).map(bits);
                assert_eq!(a, b, "u {u}, u1 {u1}, u2 {u2}");
                drawn += usize::from(a.is_some());
            }
        }
        assert_eq!(drawn, 17 * 17);
    }
}
