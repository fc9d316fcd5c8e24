//! Beam tracing (Heckbert & Hanrahan 1986) with exact visible-area antialiasing.
//!
//! Instead of rays, whole beams: the view frustum is cut into tile beams (16 × 16 pixels
//! each, for the thread pool), and each beam finds the exact visible parts of the scene's
//! planar facets in its cross-section (`visibility.rs`), as convex polygons on the film.
//! Every visible fragment of a mirror spawns a reflected beam whose cross-section is that
//! fragment, and every fragment of a transmitter a refracted one (`tree.rs`), to the depth
//! limit and the minimum weight as the ray tracer does. Each fragment is cut along the pixel
//! grid (`raster.rs`), and a pixel's value is the area-weighted sum over its pieces: the
//! box filter, exactly. Shading is evaluated once per piece at its centroid (with shadow
//! rays from there, `shade.rs`), except the texture colour of a checker, whose squares are
//! cut out exactly (`checker.rs`): so where the shading is constant over a polygon (flat
//! colours, checker squares under ambient light) the image is exact up to rounding, and
//! elsewhere the lighting's variation within a piece is what is approximated.
//!
//! Facets come from `facets.rs` (curved shapes are refused); `cull.rs` keeps each beam's
//! facet list short; `view.rs` is the camera in f64; `convex.rs` the polygon clipping.

mod checker;
mod convex;
mod cull;
mod facets;
mod fragment;
mod raster;
mod shade;
mod tree;
mod view;
mod visibility;

pub use convex::{Affine2, Convex};
pub use facets::FacetError;
pub use view::ViewError;

use super::shadow::Shadows;
use crate::camera::CameraError;
use crate::options::RenderOptions;
use crate::scene::PreparedScene;
use crate::stats::Stats;
use cull::Cull;
use facets::Facet;
use glam::{DVec2, DVec3};
use tree::Beam;
use view::View;
use visibility::Cells;

/// Tile beams are this many pixels on a side.
pub const TILE: u32 = 16;

/// The most fragments (convex cells) one tile's beam tree may hold before tracing stops
/// with `BeamError::Budget`: about 150 MB, the size of a scene whose polygons are far
/// smaller than its pixels, where beam tracing has lost to ray tracing long before.
pub const DEFAULT_BUDGET: usize = 1 << 20;

/// The default largest error of a pixel from the checker's horizon (linear units), as the
/// analytic checkerboard reference uses.
pub const DEFAULT_TOLERANCE: f64 = 1e-4;

/// Why a beam-traced image cannot be made.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum BeamError {
    /// The scene has shapes that are not planar.
    #[error(transparent)]
    Facets(#[from] FacetError),
    /// The camera has no apex.
    #[error(transparent)]
    View(#[from] ViewError),
    /// The camera cannot make rays.
    #[error(transparent)]
    Camera(#[from] CameraError),
    /// A tile's beam tree grew past the budget.
    #[error(
        "the beam tree of the tile at pixel ({x}, {y}) grew past {budget} fragments: the \
         scene's polygons are too small or too many for exact beam tracing (render it with \
         --integrator whitted and enough samples)"
    )]
    Budget {
        /// The tile's left column.
        x: u32,
        /// Its top row.
        y: u32,
        /// The budget.
        budget: usize,
    },
}

/// A traced tile: per pixel (rows of the tile), the colour, the area the view's beam
/// covered (1 for every pixel, up to rounding) and a bound on the colour's error from
/// checker integration near a horizon.
#[derive(Clone, Debug, Default)]
pub struct TileImage {
    /// The tile's film rectangle.
    pub x0: u32,
    /// Top row.
    pub y0: u32,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Colour per pixel.
    pub colors: Vec<DVec3>,
    /// Area of the pixel covered by the view beam's fragments (background included).
    pub coverage: Vec<f64>,
    /// Error bound per pixel (per channel).
    pub bound: Vec<f64>,
    /// Beams traced, the view's included.
    pub beams: u64,
    /// Visible fragments (convex cells) over all beams.
    pub fragments: u64,
    /// Fragment ∩ pixel pieces shaded.
    pub pieces: u64,
    /// The deepest beam.
    pub deepest: u32,
}

/// The beam tracer of one render.
pub struct BeamTracer<'a> {
    scene: &'a PreparedScene<'a>,
    facets: Vec<Facet>,
    cull: Cull,
    view: View,
    shadows: Shadows<'a>,
    width: u32,
    height: u32,
    max_depth: u32,
    min_weight: f32,
    spd_rules: bool,
    tolerance: f64,
    /// Fragments one tile's beam tree may hold.
    pub budget: usize,
}

/// What a beam knows of a facet it sees.
struct Seen {
    facet: u32,
    /// The facet's plane in the beam's virtual space: unit normal and offset.
    normal: DVec3,
    k: f64,
    /// Its inverse depth on the film.
    w: Affine2,
}

impl<'a> BeamTracer<'a> {
    /// The tracer for `scene` at the size and depth settings of `options`; `tolerance`
    /// bounds each pixel's error from checker squares too small to cut out.
    pub fn new(
        scene: &'a PreparedScene<'a>,
        options: &RenderOptions,
        tolerance: f64,
    ) -> Result<Self, BeamError> {
        scene.scene.camera.validate()?;
        let view = View::new(&scene.scene.camera, options.width, options.height)?;
        let facets = facets::facets(scene.scene)?;
        let cull = Cull::new(&facets);
        Ok(BeamTracer {
            scene,
            facets,
            cull,
            view,
            shadows: Shadows::new(scene, options.shadows),
            width: options.width,
            height: options.height,
            max_depth: options.max_depth,
            min_weight: options.min_weight,
            spd_rules: options.spd_rules,
            tolerance,
            budget: DEFAULT_BUDGET,
        })
    }

    /// The shadow-ray machinery (for reports).
    pub fn shadows(&self) -> &Shadows<'a> {
        &self.shadows
    }

    /// The tiles of the film, row by row.
    pub fn tiles(&self) -> Vec<(u32, u32, u32, u32)> {
        let mut out = Vec::new();
        for y in (0..self.height).step_by(TILE as usize) {
            for x in (0..self.width).step_by(TILE as usize) {
                out.push((
                    x,
                    y,
                    (x + TILE).min(self.width),
                    (y + TILE).min(self.height),
                ));
            }
        }
        out
    }

    /// Traces the beam tree of the film rectangle [x0, x1) × [y0, y1).
    pub fn trace_tile(
        &self,
        (x0, y0, x1, y1): (u32, u32, u32, u32),
        stats: &mut Stats,
    ) -> Result<TileImage, BeamError> {
        let (w, h) = (x1 - x0, y1 - y0);
        let n = (w * h) as usize;
        let mut image = TileImage {
            x0,
            y0,
            width: w,
            height: h,
            colors: vec![DVec3::ZERO; n],
            coverage: vec![0.0; n],
            bound: vec![0.0; n],
            ..TileImage::default()
        };
        let rect = Convex::rect(x0 as f64, y0 as f64, x1 as f64, y1 as f64);
        let mut stack = vec![Beam::view(rect)];
        let mut fragments = 0usize;
        while let Some(beam) = stack.pop() {
            image.beams += 1;
            image.deepest = image.deepest.max(beam.depth);
            let (cells, seen) = self.visible(&beam);
            fragments += cells.cells.len();
            if fragments > self.budget {
                return Err(BeamError::Budget {
                    x: x0,
                    y: y0,
                    budget: self.budget,
                });
            }
            image.fragments += cells.cells.len() as u64;
            self.raster(&beam, &cells, &seen, &mut image, stats);
            if beam.depth < self.max_depth {
                self.spawn(&beam, cells, &seen, &mut stack, stats);
            }
        }
        Ok(image)
    }

    /// The visible cells of a beam and the facets they show.
    fn visible(&self, beam: &Beam) -> (Cells, Vec<Seen>) {
        let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for c in &beam.window {
            let (a, b) = c.bounds();
            lo = lo.min(a);
            hi = hi.max(b);
        }
        let frustum = self.view.frustum(lo, hi);
        let mut candidates = Vec::new();
        self.cull
            .query(&beam.real_planes(&self.view, lo, hi), &mut candidates);
        let t = beam.to_virtual;
        let normal_map = t.matrix3.inverse().transpose();
        let bbox = Convex::rect(lo.x, lo.y, hi.x, hi.y);
        let mut polys: Vec<(Convex, f64, Seen)> = Vec::with_capacity(candidates.len());
        for &fi in &candidates {
            if beam.interface.is_some_and(|i| i.facet == fi) {
                continue;
            }
            let facet = &self.facets[fi as usize];
            let Some(normal) = (normal_map * facet.normal).try_normalize() else {
                continue;
            };
            let k = normal.dot(t.transform_point3(facet.origin));
            let Some(w) = self.view.inverse_depth(normal, k) else {
                continue;
            };
            let mut poly = if facet.points.is_empty() {
                bbox.clip(&w)
            } else {
                let pts: Vec<DVec3> = facet
                    .points
                    .iter()
                    .map(|&p| t.transform_point3(p))
                    .collect();
                let clipped = view::clip_polygon(&pts, &frustum);
                let projected = clipped.iter().map(|&p| self.view.project(p)).collect();
                match Convex::from_points(projected) {
                    Some(c) => c.clip_all(&bbox.edges()),
                    None => continue,
                }
            };
            if let Some(i) = &beam.interface {
                poly = poly.clip(&i.w.minus(&w));
            }
            if poly.area() <= convex::SLIVER_AREA {
                continue;
            }
            let nearest = poly
                .points
                .iter()
                .map(|&p| w.at(p))
                .fold(f64::NEG_INFINITY, f64::max);
            polys.push((
                poly,
                nearest,
                Seen {
                    facet: fi,
                    normal,
                    k,
                    w,
                },
            ));
        }
        // Front to back: a facet hidden by those before it cuts nothing.
        polys.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.2.facet.cmp(&b.2.facet)));
        let mut cells = Cells::new(&beam.window);
        let mut seen = Vec::with_capacity(polys.len());
        for (poly, _, s) in polys {
            if cells.insert(&poly, s.w, seen.len() as u32) {
                seen.push(s);
            }
        }
        (cells, seen)
    }
}
