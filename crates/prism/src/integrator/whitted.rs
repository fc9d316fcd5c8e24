//! Whitted ray tracing (Whitted 1980), step by step:
//!
//! TraceRay(R, depth): find the nearest hit; on a miss return the background. For every
//! light, cast a shadow ray and keep only lights it reaches; add the local illumination
//! from those. If depth < max depth, trace the reflected and the refracted ray. Result:
//! I = Le + Ia·ka·C + Σ (Id + Is) + wr·I_R + wt·I_T, with (wr, wt) from the material
//! (constant, or split by Fresnel reflectance). Shadow rays are `shadow.rs`: those that
//! meet a transparent surface continue through it, filtered by its kt (a colour), as
//! POV-Ray does. Weights are colours too: red glass passes red light only.

use super::area_lights::AreaLights;
use super::shadow::Shadows;
use crate::accel::{Hit, PACKET_MAX};
use crate::geometry::SurfacePoint;
use crate::light::LightSample;
use crate::math::robust::offset_ray_origin;
use crate::math::Vec3;
use crate::math::{Color, Ray};
use crate::options::RenderOptions;
use crate::scene::PreparedScene;
use crate::shading::optics::{reflect, refract};
use crate::shading::{normal_map, Coefficients, Material};
use crate::stats::Stats;
use arrayvec::ArrayVec;

/// Whitted's recursive ray tracer over one prepared scene: local shading with shadow rays, plus the
/// reflected and refracted rays, to a depth and weight limit.
pub struct Whitted<'a> {
    scene: &'a PreparedScene<'a>,
    shadows: Shadows<'a>,
    /// The emitting surfaces as lights sampled by shadow rays; None without any.
    area: Option<AreaLights>,
    max_depth: u32,
    min_weight: f32,
    spd_rules: bool,
    /// Whether every light in front of a surface is tested (`min_weight` 0, or the SPD
    /// rules): then no light is faint, and nothing is kept for Ward's estimate.
    tests_every_light: bool,
}

impl<'a> Whitted<'a> {
    /// The integrator for `scene` with the depth, weight and shadow settings of `options`; builds
    /// light buffers when the shadow method asks for them.
    pub fn new(scene: &'a PreparedScene<'a>, options: &RenderOptions) -> Self {
        Whitted {
            scene,
            shadows: Shadows::new(scene, options.shadows),
            area: AreaLights::new(scene.scene, options.area_samples, options.seed),
            max_depth: options.max_depth,
            min_weight: options.min_weight,
            spd_rules: options.spd_rules,
            tests_every_light: options.spd_rules || options.min_weight <= 0.0,
        }
    }

    /// Whether a secondary ray of weight `w` (in its parent) is traced. `present` says the
    /// material has the term at all (kr or kt > 0), which is all SPD's rules ask. Rays the
    /// static limit would trace but adaptive depth control drops are counted. A coloured
    /// weight counts by its largest channel: the most the ray can change any channel.
    fn spawns(&self, present: bool, w: Color, weight: Color, stats: &mut Stats) -> bool {
        super::spawns((self.spd_rules, self.min_weight), present, w, weight, stats)
    }

    /// The shadow-ray machinery this render built (light buffers and why some lights have
    /// none), for reports.
    pub fn shadows(&self) -> &Shadows<'a> {
        &self.shadows
    }

    /// Radiance along a camera ray (depth 1).
    pub fn trace_camera_ray(&self, ray: &Ray, stats: &mut Stats) -> Color {
        stats.primary_rays += 1;
        self.trace(ray, 1, Color::ONE, stats)
    }

    /// The first hits of a packet of camera rays (at most `accel::PACKET_MAX`), walked
    /// together; `shade_camera_packet` continues them. Exactly the hits
    /// `trace_camera_ray` finds.
    pub fn camera_hits(&self, rays: &[Ray], hits: &mut [Option<Hit>], stats: &mut Stats) {
        stats.primary_rays += rays.len() as u64;
        let s = self.scene;
        s.intersector
            .intersect_packet(&s.scene.geometry, rays, f32::INFINITY, hits, stats);
    }

    /// Radiance along a packet of camera rays (at most `accel::PACKET_MAX`) whose first
    /// hits `camera_hits` found: `colors[i]` is exactly what `trace_camera_ray` gives ray
    /// i. The ray tree is traced breadth first, a packet per depth: the shadow rays of a
    /// packet's hits to each light go as one packet, and so do its reflected rays and its
    /// refracted rays.
    /// `rays_of[i]` gains the rays of ray i's tree after the camera ray itself.
    pub fn shade_camera_packet(
        &self,
        rays: &[Ray],
        hits: &[Option<Hit>],
        colors: &mut [Color],
        rays_of: &mut [u32; PACKET_MAX],
        stats: &mut Stats,
    ) {
        let n = rays.len();
        let owners: ArrayVec<usize, PACKET_MAX> = (0..n).collect();
        let weights = [Color::ONE; PACKET_MAX];
        let tree = Tree {
            owners: &owners,
            rays_of,
        };
        self.shade_packet(rays, hits, 1, &weights[..n], tree, colors, stats);
    }

    /// `shade` for a packet of rays at `depth`, each with its weight in the pixel.
    #[allow(clippy::too_many_arguments)]
    fn shade_packet(
        &self,
        rays: &[Ray],
        hits: &[Option<Hit>],
        depth: u32,
        weights: &[Color],
        mut tree: Tree,
        colors: &mut [Color],
        stats: &mut Stats,
    ) {
        let scene = self.scene.scene;
        let n = rays.len();
        // Per lane: the surface its ray hit (None on a miss), written in its slot. Copies
        // of these 120-byte structs, pushed through `Option` and `ArrayVec`, were a tenth
        // of `shade_packet`'s time in a viewer frame (stores forwarded into wider loads
        // that stalled).
        let mut surfaces = [None::<Surface>; PACKET_MAX];
        for (i, (ray, hit)) in rays.iter().zip(hits).enumerate() {
            colors[i] = match hit {
                None => scene.background,
                Some(h) => {
                    let s = surfaces[i].insert(self.surface(ray, *h, depth, stats));
                    self.own_radiance(s)
                }
            };
        }
        let surfaces = &surfaces[..n];
        let surface = |i: usize| surfaces[i].as_ref().expect("lit surfaces exist");
        // Local illumination as `local` sums it, light by light: each light's shadow rays
        // go as one packet, whichever shadow method answers them.
        let mut batch = Batch::new();
        // The surfaces a light reaches (`lit_by`), in lane order, and its sample there.
        let mut lit: ArrayVec<u8, PACKET_MAX> = ArrayVec::new();
        // Written in place by `lit_by`: returned by value, the samples were copied through
        // the stack in pieces whose loads stalled on the stores before them (a tenth of
        // `shade_packet`'s time in a viewer frame).
        let mut samples = [Lit::NONE; PACKET_MAX];
        let mut faint = [FaintLights::default(); PACKET_MAX];
        for j in 0..self.sources() {
            let index = self.shadow_index(j);
            lit.clear();
            for (i, s) in surfaces.iter().enumerate() {
                let Some(s) = s else { continue };
                let sample = &mut samples[i];
                match self.lit_by(s, j, weights[i], sample, stats) {
                    Some(Seen::ByShadowRay) => lit.push(i as u8),
                    Some(Seen::Estimated) => faint[i].add_faint(&sample.ls, sample.reflected),
                    None => {}
                }
            }
            let sample = |i: usize| {
                let Lit { ls, reflected } = samples[i];
                (ls, reflected)
            };
            batch.clear();
            for &i in &lit {
                let i = usize::from(i);
                let (s, (ls, _)) = (surface(i), sample(i));
                // The ray `Shadows::visibility` casts.
                let origin = offset_ray_origin(s.sp.p, s.sp.p_error, s.ng, ls.to_light);
                batch.push(i, Ray::new(origin, ls.to_light), ls.distance);
                tree.count(i, 1);
            }
            let m = batch.rays.len();
            // With transparent surfaces the packet walks through them; otherwise whether
            // anything blocks the ray settles it (a blocked ray sees nothing).
            let mut seen = [Color::ONE; PACKET_MAX];
            if self.scene.has_transmissive {
                let mut segments = [0u32; PACKET_MAX];
                self.shadows.transmittance_packet(
                    index,
                    &batch.rays,
                    &batch.t_max,
                    &mut seen[..m],
                    &mut segments[..m],
                    stats,
                );
                for (&i, &n) in lit.iter().zip(&segments[..m]) {
                    tree.count(usize::from(i), n);
                }
            } else {
                let mut blocked = [false; PACKET_MAX];
                let (rays, t_max) = (&batch.rays, &batch.t_max);
                let blocked = &mut blocked[..m];
                (self.shadows).blocked_packet(index, depth, rays, t_max, blocked, stats);
                for (seen, &b) in seen.iter_mut().zip(blocked.iter()) {
                    if b {
                        *seen = Color::ZERO;
                    }
                }
            }
            for (&i, &seen) in lit.iter().zip(&seen[..m]) {
                let (i, (ls, reflected)) = (usize::from(i), sample(usize::from(i)));
                if !self.tests_every_light {
                    faint[i].add_tested(&ls, reflected, seen);
                }
                colors[i] += self.light_term(surface(i), &ls, reflected, seen);
            }
        }
        if !self.tests_every_light {
            for (color, faint) in colors.iter_mut().zip(&faint[..n]) {
                faint.add_estimate(color);
            }
        }
        if depth >= self.max_depth {
            return;
        }

        // The recursive terms, as `recurse` decides them, reflected rays first.
        let mut split = [None::<(crate::shading::SpecularWeights, f32)>; PACKET_MAX];
        batch.clear();
        let mut next_weights: ArrayVec<Color, PACKET_MAX> = ArrayVec::new();
        for (i, surface) in surfaces.iter().enumerate() {
            let Some(s) = surface else {
                continue;
            };
            let eta = if s.entering { 1.0 / s.k.ior } else { s.k.ior };
            let cos_i = s.to_eye.dot(s.ns).clamp(0.0, 1.0);
            let w = s.k.specular_weights(cos_i, eta);
            if w.total_internal_reflection {
                stats.total_internal_reflections += 1;
            }
            let has_specular = s.k.reflect > 0.0 || s.k.is_transmissive();
            let w_reflect = Color::splat(w.reflect);
            if self.spawns(has_specular, w_reflect, weights[i], stats) {
                let dir = self.reflected_dir(&rays[i], s);
                let origin = offset_ray_origin(s.sp.p, s.sp.p_error, s.ng, dir);
                stats.reflected_rays += 1;
                tree.count(i, 1);
                batch.push(i, Ray::new(origin, dir), f32::INFINITY);
                next_weights.push(weights[i] * w_reflect);
            }
            split[i] = Some((w, eta));
        }
        let reflected = |i: usize| split[i].map_or(Color::ZERO, |(w, _)| Color::splat(w.reflect));
        self.trace_batch(
            &batch,
            depth,
            &next_weights,
            &mut tree,
            colors,
            stats,
            reflected,
        );

        batch.clear();
        next_weights.clear();
        for (i, surface) in surfaces.iter().enumerate() {
            let (Some(s), Some((w, eta))) = (surface, split[i]) else {
                continue;
            };
            let transmissive = s.k.is_transmissive();
            if !w.total_internal_reflection
                && self.spawns(transmissive, w.transmit, weights[i], stats)
            {
                if let Some(dir) = refract(rays[i].dir, s.ns, eta) {
                    let origin = offset_ray_origin(s.sp.p, s.sp.p_error, s.ng, dir);
                    stats.refracted_rays += 1;
                    tree.count(i, 1);
                    batch.push(i, Ray::new(origin, dir), f32::INFINITY);
                    next_weights.push(weights[i] * w.transmit);
                }
            }
        }
        let refracted = |i: usize| split[i].map_or(Color::ZERO, |(w, _)| w.transmit);
        self.trace_batch(
            &batch,
            depth,
            &next_weights,
            &mut tree,
            colors,
            stats,
            refracted,
        );
    }

    /// Traces `batch`'s secondary rays (spawned at `depth`) as a packet and adds each
    /// one's radiance, times `factor(i)`, to `colors[i]` of the ray it came from. Deep
    /// trees go on ray by ray (`PACKET_DEPTH`), so the stack stays small.
    #[allow(clippy::too_many_arguments)]
    fn trace_batch(
        &self,
        batch: &Batch,
        depth: u32,
        weights: &[Color],
        tree: &mut Tree,
        colors: &mut [Color],
        stats: &mut Stats,
        factor: impl Fn(usize) -> Color,
    ) {
        let m = batch.rays.len();
        if m == 0 {
            return;
        }
        let mut radiance = [Color::ZERO; PACKET_MAX];
        if depth < PACKET_DEPTH {
            let mut hits = [None; PACKET_MAX];
            let s = self.scene;
            s.intersector.intersect_packet(
                &s.scene.geometry,
                &batch.rays,
                f32::INFINITY,
                &mut hits[..m],
                stats,
            );
            let sub_owners: ArrayVec<usize, PACKET_MAX> =
                batch.from.iter().map(|&i| tree.owners[i]).collect();
            let tree = Tree {
                owners: &sub_owners,
                rays_of: &mut *tree.rays_of,
            };
            self.shade_packet(
                &batch.rays,
                &hits[..m],
                depth + 1,
                weights,
                tree,
                &mut radiance[..m],
                stats,
            );
        } else {
            for k in 0..m {
                let before = stats.total_rays();
                radiance[k] = self.trace(&batch.rays[k], depth + 1, weights[k], stats);
                tree.count(batch.from[k], (stats.total_rays() - before) as u32);
            }
        }
        for (k, &i) in batch.from.iter().enumerate() {
            colors[i] += factor(i) * radiance[k];
        }
    }

    /// The mirror direction at `s` for `ray`: about the shading normal, or about the
    /// geometric one where an interpolated normal would send it below the true surface.
    fn reflected_dir(&self, ray: &Ray, s: &Surface) -> Vec3 {
        let dir = reflect(ray.dir, s.ns);
        if dir.dot(s.ng) <= 0.0 {
            reflect(ray.dir, s.ng)
        } else {
            dir
        }
    }

    fn nearest(&self, ray: &Ray, t_max: f32, stats: &mut Stats) -> Option<Hit> {
        let s = self.scene;
        s.intersector
            .intersect(&s.scene.geometry, ray, t_max, stats)
    }

    /// `weight` is the product of reflection and transmission weights from the eye to this
    /// ray, per channel: what its radiance is worth in the pixel (for adaptive depth
    /// control).
    pub fn trace(&self, ray: &Ray, depth: u32, weight: Color, stats: &mut Stats) -> Color {
        let hit = self.nearest(ray, f32::INFINITY, stats);
        self.shade(ray, hit, depth, weight, stats)
    }

    /// Radiance along `ray` given its nearest hit (the background on a miss).
    fn shade(
        &self,
        ray: &Ray,
        hit: Option<Hit>,
        depth: u32,
        weight: Color,
        stats: &mut Stats,
    ) -> Color {
        let Some(hit) = hit else {
            return self.scene.scene.background;
        };
        let surface = self.surface(ray, hit, depth, stats);
        let radiance = self.local(&surface, weight, stats, |index, ls, stats| {
            self.shadows
                .visibility(index, depth, &surface.sp, surface.ng, ls, stats)
        });
        self.recurse(ray, &surface, radiance, depth, weight, stats)
    }

    /// What shading needs of a hit: the surface point, its normals facing the incoming
    /// ray, the material and its colour there. Inlined so that the packet loop builds the
    /// surface in its slot rather than copying it there from a return value.
    #[inline(always)]
    fn surface(&self, ray: &Ray, hit: Hit, depth: u32, stats: &mut Stats) -> Surface<'a> {
        let scene = self.scene.scene;
        if depth == 1 {
            stats.primary_hits += 1;
        }
        let prim = &scene.geometry.primitives[hit.prim as usize];
        let material = &scene.materials[prim.material as usize];
        let mut sp =
            (scene.geometry).surface_with(hit.prim, ray, &hit.shape_hit(), material.uv_need());
        normal_map::apply(material, &scene.geometry, hit.prim, &mut sp);
        // Face the normals towards the incoming ray; `entering` says which side it came from.
        let (entering, ng, ns) = sp.facing(ray.dir);
        Surface {
            color: material.color_at(sp.uv, sp.p),
            k: material.coefficients_at(sp.uv),
            sp,
            ng,
            ns,
            entering,
            material,
            to_eye: -ray.dir,
        }
    }

    /// The sources of light a surface is lit by, one shadow ray each: the scene's lights,
    /// then the area lights' points.
    fn sources(&self) -> usize {
        self.scene.scene.lights.len() + self.area.as_ref().map_or(0, |a| a.samples() as usize)
    }

    /// The light index whose shadow method answers source `j`'s shadow rays: the light's
    /// own for the scene's lights, one past them (no light buffer) for the area lights.
    fn shadow_index(&self, j: usize) -> usize {
        j.min(self.scene.scene.lights.len())
    }

    /// What source `j` sends towards `surface`: None when it sends nothing there or lies
    /// behind the surface (SPD rule 10: then no shadow ray is cast).
    #[inline]
    fn light_sample(&self, surface: &Surface, j: usize) -> Option<LightSample> {
        let lights = &self.scene.scene.lights;
        let ls = match lights.get(j) {
            Some(light) => light.sample(surface.sp.p)?,
            None => {
                let area = self.area.as_ref()?;
                let k = (j - lights.len()) as u32;
                area.sample(self.scene.scene, surface.sp.p, surface.ng, k)?
            }
        };
        (surface.ng.dot(ls.to_light) > 0.0).then_some(ls)
    }

    /// Local illumination: ambient, plus diffuse and highlight from every light that
    /// `visibility(light index, sample)` says reaches the surface, whose ray has `weight`
    /// in the pixel.
    fn local(
        &self,
        surface: &Surface,
        weight: Color,
        stats: &mut Stats,
        mut visibility: impl FnMut(usize, &LightSample, &mut Stats) -> Color,
    ) -> Color {
        let mut radiance = self.own_radiance(surface);
        let mut faint = FaintLights::default();
        for j in 0..self.sources() {
            let index = self.shadow_index(j);
            let mut sample = Lit::NONE;
            let Some(seen) = self.lit_by(surface, j, weight, &mut sample, stats) else {
                continue;
            };
            let Lit { ls, reflected } = sample;
            if let Seen::Estimated = seen {
                faint.add_faint(&ls, reflected);
                continue;
            }
            let visibility = visibility(index, &ls, stats);
            if !self.tests_every_light {
                faint.add_tested(&ls, reflected, visibility);
            }
            radiance += self.light_term(surface, &ls, reflected, visibility);
        }
        if !self.tests_every_light {
            faint.add_estimate(&mut radiance);
        }
        radiance
    }

    /// The surface's own radiance: ambient light, and the emission of an area light (seen
    /// directly; its light on other surfaces comes by the area lights' shadow rays).
    fn own_radiance(&self, surface: &Surface) -> Color {
        let k = &surface.k;
        let ambient = k.ambient * surface.material.ambient_occlusion(surface.sp.uv);
        let mut radiance = ambient * surface.color * self.scene.scene.ambient;
        if surface.entering && k.is_emissive() {
            radiance += k.emission;
        }
        radiance
    }

    /// What `light` sends towards `surface`, whose ray has `weight` in the pixel, and how
    /// much of it gets there is to be found out: its sample (written to `out`), and what is
    /// known of the fraction of it the surface sends to the eye (diffuse plus highlight),
    /// where the light is in front of the surface (SPD rule 10) and that fraction is not
    /// exactly zero (a glass's highlight far from the mirror direction underflows to 0, and
    /// adds nothing however much light gets through). A light that could change the pixel
    /// by less than `min_weight` even unblocked casts no shadow ray: how much of it gets
    /// through is estimated from the lights tested at the point (`FaintLights`, adaptive
    /// shadow testing after Ward 1991, as adaptive depth control prunes reflected and
    /// refracted rays). With `min_weight` 0 and under SPD's rules (which cast every shadow
    /// ray) every other light is tested. Where the diffuse term alone settles that the ray
    /// is cast, the highlight's power function waits until the light is seen to get
    /// through; where it does not, the highlight is worked out here (exactly, as
    /// `light_term` would), mostly decided to be zero from bounds
    /// (`Coefficients::highlight_unless_nonzero`).
    #[inline]
    fn lit_by(
        &self,
        surface: &Surface,
        source: usize,
        weight: Color,
        out: &mut Lit,
        stats: &mut Stats,
    ) -> Option<Seen> {
        let ls = self.light_sample(surface, source)?;
        out.ls = ls;
        let Surface {
            k,
            color,
            ns,
            to_eye,
            ..
        } = *surface;
        let diffuse = k.diffuse * ns.dot(ls.to_light).max(0.0) * color;
        // What the light could add to the pixel at most, per unit of reflected fraction.
        let reach = weight * ls.color;
        if self.spd_rules
            || (diffuse != Color::ZERO && super::changes_pixel(self.min_weight, reach, diffuse))
        {
            out.reflected = Reflected {
                diffuse,
                highlight: None,
            };
            return Some(Seen::ByShadowRay);
        }
        let highlight = if diffuse != Color::ZERO {
            k.highlight_term(ns, ls.to_light, to_eye)
        } else {
            match k.highlight_unless_nonzero(ns, ls.to_light, to_eye) {
                Some(0.0) => return None,
                Some(h) => h,
                // Not zero: with no threshold the ray is cast, and the power can wait.
                None if self.tests_every_light => {
                    out.reflected = Reflected {
                        diffuse,
                        highlight: None,
                    };
                    return Some(Seen::ByShadowRay);
                }
                None => k.highlight_term(ns, ls.to_light, to_eye),
            }
        };
        let faint =
            !super::changes_pixel(self.min_weight, reach, diffuse + Color::splat(highlight));
        let seen = if faint {
            stats.pruned_shadow_rays += 1;
            Seen::Estimated
        } else {
            Seen::ByShadowRay
        };
        out.reflected = Reflected {
            diffuse,
            highlight: Some(highlight),
        };
        Some(seen)
    }

    /// The light a sample adds to `surface`, which reflects `reflected` of it towards the
    /// eye, when `visibility` of it gets through (nothing when none does).
    #[inline]
    fn light_term(
        &self,
        surface: &Surface,
        ls: &LightSample,
        reflected: Reflected,
        visibility: Color,
    ) -> Color {
        if visibility.max_element() <= 0.0 {
            return Color::ZERO;
        }
        let highlight = reflected.highlight.unwrap_or_else(|| {
            surface
                .k
                .highlight_term(surface.ns, ls.to_light, surface.to_eye)
        });
        visibility * ls.color * (reflected.diffuse + Color::splat(highlight))
    }

    /// Adds the reflected and refracted rays' radiance to `radiance`, the surface's own.
    fn recurse(
        &self,
        ray: &Ray,
        surface: &Surface,
        mut radiance: Color,
        depth: u32,
        weight: Color,
        stats: &mut Stats,
    ) -> Color {
        let Surface {
            sp,
            ng,
            ns,
            entering,
            k,
            to_eye,
            ..
        } = *surface;
        if depth >= self.max_depth {
            return radiance;
        }

        // Recursive terms. η_io = η_incident / η_transmitted; the outside is vacuum.
        let eta = if entering { 1.0 / k.ior } else { k.ior };
        let cos_i = to_eye.dot(ns).clamp(0.0, 1.0);
        let w = k.specular_weights(cos_i, eta);
        if w.total_internal_reflection {
            stats.total_internal_reflections += 1;
        }
        let transmissive = k.is_transmissive();
        let has_specular = k.reflect > 0.0 || transmissive;
        let w_reflect = Color::splat(w.reflect);
        if self.spawns(has_specular, w_reflect, weight, stats) {
            let dir = self.reflected_dir(ray, surface);
            let origin = offset_ray_origin(sp.p, sp.p_error, ng, dir);
            stats.reflected_rays += 1;
            let r = self.trace(&Ray::new(origin, dir), depth + 1, weight * w_reflect, stats);
            radiance += w.reflect * r;
        }
        if !w.total_internal_reflection && self.spawns(transmissive, w.transmit, weight, stats) {
            if let Some(dir) = refract(ray.dir, ns, eta) {
                let origin = offset_ray_origin(sp.p, sp.p_error, ng, dir);
                stats.refracted_rays += 1;
                let t = self.trace(
                    &Ray::new(origin, dir),
                    depth + 1,
                    weight * w.transmit,
                    stats,
                );
                radiance += w.transmit * t;
            }
        }
        radiance
    }
}

/// A hit as shading sees it.
#[derive(Clone, Copy)]
struct Surface<'a> {
    sp: SurfacePoint,
    /// Normals turned to face the incoming ray.
    ng: Vec3,
    ns: Vec3,
    /// Whether the ray came from the side `sp.ng` faces.
    entering: bool,
    material: &'a Material,
    /// The material's colour at the hit.
    color: Color,
    /// The material's coefficients at the hit.
    k: Coefficients,
    to_eye: Vec3,
}

/// Where the rays of a packet's trees are counted: ray i of the packet belongs to camera
/// ray `owners[i]`, whose slot in `rays_of` counts them.
struct Tree<'t> {
    owners: &'t [usize],
    rays_of: &'t mut [u32; PACKET_MAX],
}

impl Tree<'_> {
    /// Counts `rays` more for the camera ray that packet ray `i` belongs to.
    fn count(&mut self, i: usize, rays: u32) {
        self.rays_of[self.owners[i]] += rays;
    }
}

/// Rays gathered from a packet's hits: each with its bound and the ray it came from.
struct Batch {
    rays: ArrayVec<Ray, PACKET_MAX>,
    t_max: ArrayVec<f32, PACKET_MAX>,
    from: ArrayVec<usize, PACKET_MAX>,
}

impl Batch {
    fn new() -> Batch {
        Batch {
            rays: ArrayVec::new(),
            t_max: ArrayVec::new(),
            from: ArrayVec::new(),
        }
    }

    fn clear(&mut self) {
        self.rays.clear();
        self.t_max.clear();
        self.from.clear();
    }

    fn push(&mut self, from: usize, ray: Ray, t_max: f32) {
        self.rays.push(ray);
        self.t_max.push(t_max);
        self.from.push(from);
    }
}

/// The deepest level of the ray tree traced as packets; deeper rays go on one by one,
/// since every level of packets keeps a few kilobytes on the stack.
const PACKET_DEPTH: u32 = 8;

/// How much of a light sample reaches a shading point is found (`Whitted::lit_by`).
#[derive(Clone, Copy)]
enum Seen {
    /// By a shadow ray.
    ByShadowRay,
    /// Not at all: the light is too faint to be worth a ray, and gets through as much as
    /// the tested lights do (`FaintLights`).
    Estimated,
}

/// Ward's estimate for the lights at one shading point too faint to be worth a shadow ray
/// ("Adaptive Shadow Testing for Ray Tracing", 1991): their light as if unblocked, scaled by
/// the fraction of the tested lights' light that got through there (all of it where no
/// light was tested). Where every tested light is seen, or blocked, the faint ones are
/// taken to be too, which is what makes the estimate good: shadows are mostly shared.
#[derive(Clone, Copy, Default)]
struct FaintLights {
    /// The faint lights' terms, unblocked.
    unblocked: Color,
    /// The tested lights' terms unblocked, over the three channels (the diffuse part alone
    /// where the highlight waits for the shadow ray), and the part of that seen.
    tested: f32,
    seen: f32,
}

impl FaintLights {
    /// A light's term as if nothing blocked it (without the highlight where that waits).
    #[inline]
    fn unblocked(ls: &LightSample, reflected: Reflected) -> Color {
        ls.color * (reflected.diffuse + Color::splat(reflected.highlight.unwrap_or(0.0)))
    }

    #[inline]
    fn add_faint(&mut self, ls: &LightSample, reflected: Reflected) {
        self.unblocked += Self::unblocked(ls, reflected);
    }

    #[inline]
    fn add_tested(&mut self, ls: &LightSample, reflected: Reflected, visibility: Color) {
        let unblocked = Self::unblocked(ls, reflected);
        self.tested += unblocked.element_sum();
        self.seen += (unblocked * visibility).element_sum();
    }

    /// Adds the faint lights' estimated light to `radiance` (nothing without faint lights,
    /// so that renders that test every light keep their sums as they were).
    #[inline]
    fn add_estimate(&self, radiance: &mut Color) {
        if self.unblocked == Color::ZERO {
            return;
        }
        let through = if self.tested > 0.0 {
            self.seen / self.tested
        } else {
            1.0
        };
        *radiance += self.unblocked * through;
    }
}

/// A light's sample at a shading point and what the surface reflects of it, as
/// `Whitted::lit_by` writes them.
#[derive(Clone, Copy)]
struct Lit {
    ls: LightSample,
    reflected: Reflected,
}

impl Lit {
    /// A slot before `lit_by` fills it.
    const NONE: Lit = Lit {
        ls: LightSample {
            to_light: Vec3::ZERO,
            distance: 0.0,
            color: Color::ZERO,
        },
        reflected: Reflected {
            diffuse: Color::ZERO,
            highlight: None,
        },
    };
}

/// What a surface reflects of a light sample towards the eye: its diffuse term, and its
/// highlight where `Whitted::lit_by` worked it out (to see whether it is zero, or whether
/// the light is faint).
#[derive(Clone, Copy)]
struct Reflected {
    diffuse: Color,
    highlight: Option<f32>,
}
