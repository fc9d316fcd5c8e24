//! What a beam does with its visible fragments: each is cut into its pixel pieces, which
//! are shaded at their centroids and added to their pixels weighted by area and by the
//! beam's weight there; and each fragment of a mirror or a transmitter spawns a child beam
//! with the fragment as its cross-section.

use super::checker::{self, ProjectiveUv};
use super::convex::Convex;
use super::raster::pixel_pieces;
use super::shade;
use super::tree::{depth_scale, Beam, Interface, Link};
use super::visibility::Cells;
use super::{BeamTracer, Seen, TileImage};
use crate::math::Color;
use crate::shading::{CheckerSpace, Texture};
use crate::stats::Stats;
use glam::{DVec2, DVec3};

fn to_d(c: Color) -> DVec3 {
    DVec3::new(c.x as f64, c.y as f64, c.z as f64)
}

impl BeamTracer<'_> {
    /// Adds the beam's cells to the tile's pixels.
    pub(super) fn raster(
        &self,
        beam: &Beam,
        cells: &Cells,
        seen: &[Seen],
        image: &mut TileImage,
        stats: &mut Stats,
    ) {
        let scene = self.scene.scene;
        let to_real = beam.to_virtual.inverse();
        let apex = to_real.transform_point3(self.view.eye);
        // The checker's uv on the film, per facet seen, made when first needed.
        let mut uvs: Vec<Option<Option<ProjectiveUv>>> = vec![None; seen.len()];
        let background = to_d(scene.background);
        for cell in &cells.cells {
            pixel_pieces(&cell.poly, self.width, self.height, |x, y, piece| {
                if x < image.x0 || y < image.y0 {
                    return;
                }
                let (lx, ly) = (x - image.x0, y - image.y0);
                if lx >= image.width || ly >= image.height {
                    return;
                }
                let slot = (ly * image.width + lx) as usize;
                let area = piece.area();
                let centre = piece.centroid();
                if beam.depth == 1 {
                    image.coverage[slot] += area;
                }
                image.pieces += 1;
                let weight = to_d(beam.weight(&self.view, &scene.materials, centre));
                let Some(owner) = cell.owner else {
                    image.colors[slot] += weight * background * area;
                    return;
                };
                let s = &seen[owner as usize];
                let facet = &self.facets[s.facet as usize];
                let material = &scene.materials[facet.material as usize];
                let dir = self.view.dir(centre);
                let t = (s.k - s.normal.dot(self.view.eye)) / s.normal.dot(dir);
                let point = to_real.transform_point3(self.view.eye + t * dir);
                let local = shade::local(
                    scene,
                    &self.shadows,
                    facet,
                    material,
                    point,
                    apex,
                    beam.depth,
                    stats,
                );
                let (k1, k2) = (to_d(local.k1), to_d(local.k2));
                let uv = uvs[owner as usize].get_or_insert_with(|| self.checker_uv(beam, s));
                let (integral, bound) = match (&material.color, uv) {
                    (Texture::Checker(c), Some(uv)) => {
                        // A pixel's error: at most √2·delta of it lies in the horizon's
                        // sliver (a sixth of the tolerance at half the colour difference),
                        // and its other pieces may spend two thirds by area.
                        let diff = (to_d(c.a) - to_d(c.b)).abs().max_element().max(1e-300);
                        let delta = self.tolerance / (3.0 * diff * std::f64::consts::SQRT_2);
                        let budget = self.tolerance * 2.0 / 3.0;
                        let r = checker::integrate(&piece, uv, c, budget, delta);
                        (r.sum, r.bound)
                    }
                    _ => (to_d(local.color) * area, 0.0),
                };
                let value = k1 * integral + k2 * area;
                image.colors[slot] += weight * value;
                image.bound[slot] += bound * (weight * k1).abs().max_element();
            });
        }
    }

    /// A checker texture's uv on the film for facet `s` seen in `beam`, in squares; None
    /// when the facet's colour is not a uv checker.
    fn checker_uv(&self, beam: &Beam, s: &Seen) -> Option<ProjectiveUv> {
        let facet = &self.facets[s.facet as usize];
        let material = &self.scene.scene.materials[facet.material as usize];
        let Texture::Checker(c) = &material.color else {
            return None;
        };
        if c.space != CheckerSpace::Uv {
            return None;
        }
        // X_real(x, y) = apex + h·A⁻¹D/(n·D): u·(n·D) = c_u·(n·D) + h·(A⁻ᵀg_u)·D.
        let to_real = beam.to_virtual.inverse();
        let apex = to_real.transform_point3(self.view.eye);
        let h = s.k - s.normal.dot(self.view.eye);
        let den = self.view.along(s.normal);
        let inv_t = to_real.matrix3.transpose();
        let size = c.size as f64;
        let numerator = |g: DVec3, uv0: f64| {
            let c0 = uv0 + g.dot(apex - facet.origin);
            let along = self.view.along(inv_t * g);
            super::Affine2 {
                a: (c0 * den.a + h * along.a) / size,
                b: (c0 * den.b + h * along.b) / size,
                c: (c0 * den.c + h * along.c) / size,
            }
        };
        Some(ProjectiveUv {
            nu: numerator(facet.uv.gu, facet.uv.uv0.x),
            nv: numerator(facet.uv.gv, facet.uv.uv0.y),
            den,
        })
    }

    /// Pushes the reflected and refracted beams of the beam's fragments onto `stack`.
    pub(super) fn spawn(
        &self,
        beam: &Beam,
        cells: Cells,
        seen: &[Seen],
        stack: &mut Vec<Beam>,
        stats: &mut Stats,
    ) {
        let materials = &self.scene.scene.materials;
        let mut windows: Vec<Vec<Convex>> = vec![Vec::new(); seen.len()];
        for cell in cells.cells {
            if let Some(o) = cell.owner {
                windows[o as usize].push(cell.poly);
            }
        }
        let to_real = beam.to_virtual.inverse();
        for (s, window) in seen.iter().zip(windows) {
            let facet = &self.facets[s.facet as usize];
            let material = &materials[facet.material as usize];
            let transmissive = material.is_transmissive();
            let has_specular = material.reflect > 0.0 || transmissive;
            if window.is_empty() || !(has_specular || self.spd_rules) {
                continue;
            }
            // The fragment's centroid and its ray: where the beam's weights are judged.
            let (mut sum, mut area) = (DVec2::ZERO, 0.0);
            for c in &window {
                let a = c.area();
                sum += c.centroid() * a;
                area += a;
            }
            if area <= 0.0 {
                continue;
            }
            let centre = sum / area;
            let dir = self.view.dir(centre).normalize();
            let cos_i = dir.dot(s.normal).abs().min(1.0);
            let real_dir = to_real.matrix3 * dir;
            let entering = real_dir.dot(facet.normal) < 0.0;
            let eta = if entering {
                1.0 / material.ior
            } else {
                material.ior
            };
            let w = material.specular_weights(cos_i as f32, eta);
            if w.total_internal_reflection {
                stats.total_internal_reflections += 1;
            }
            let parent = beam.weight(&self.view, materials, centre);
            let plane = Interface {
                normal: s.normal,
                k: s.k,
                w: s.w,
                facet: s.facet,
            };
            let link = |reflect| Link {
                normal: s.normal,
                material: facet.material,
                reflect,
                eta,
            };
            if self.spawns(has_specular, Color::splat(w.reflect), parent, stats) {
                stats.reflected_rays += 1;
                stack.push(beam.reflected(window.clone(), plane, link(true)));
            }
            if !w.total_internal_reflection && self.spawns(transmissive, w.transmit, parent, stats)
            {
                if let Some(scale) = depth_scale(cos_i, eta as f64) {
                    stats.refracted_rays += 1;
                    stack.push(beam.refracted(window, plane, link(false), scale));
                }
            }
        }
    }

    /// The ray tracer's rule (`Whitted::spawns`), per fragment: a child of weight `w` in a
    /// beam worth `weight` is traced when it can change the pixel by `min_weight`.
    fn spawns(&self, present: bool, w: Color, weight: Color, stats: &mut Stats) -> bool {
        crate::integrator::spawns((self.spd_rules, self.min_weight), present, w, weight, stats)
    }
}
