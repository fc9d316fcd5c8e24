//! BVH construction: per-primitive boxes and centroids, the chosen builder (one file each),
//! the optional reinsertion pass, and the mapping from build positions to primitive ids.

mod auto;
mod binned;
mod lbvh;
mod median;
mod phr;
mod ploc;
mod presplit;
mod prim_ref;
mod sbvh;
mod stitch;
mod sweep;
mod topdown;
mod triangle_cut;

use super::{reinsert, Bvh, BvhBuilder, BvhOptions, Node};
use crate::geometry::Geometry;
use crate::math::{Aabb, Vec3};
use prim_ref::PrimRef;
use rayon::prelude::*;

/// The boxes a build starts from.
enum Boxes {
    /// By build position (0..n), as every builder can read them.
    Bounds(Vec<Aabb>),
    /// Already the references that the top-down builders move (`moves_references_only`).
    References(Vec<PrimRef>),
}

/// What the builders see of the primitives, indexed by build position (0..n).
pub(super) struct BuildPrims {
    /// Empty where the build started from references, which the builders that read
    /// boxes by build position never do.
    pub bounds: Vec<Aabb>,
    /// How many primitives a leaf tests in one step: 4 when every primitive is a triangle
    /// (the leaves become `TrianglePack`s, `leaves.rs`), else 1.
    pub test_block: usize,
    /// The corners of the triangles by build position, for the builders that clip them
    /// (SBVH); empty for the others.
    pub triangles: Vec<Option<[Vec3; 3]>>,
}

impl BuildPrims {
    /// The corners of the primitive at build position `index`, if it is a triangle that
    /// the build may clip.
    pub(super) fn triangle(&self, index: u32) -> Option<[Vec3; 3]> {
        self.triangles.get(index as usize).copied().flatten()
    }

    /// The SAH cost of testing `n` primitives in a leaf, in units of one test step: packs
    /// of triangles cost a step per four, so leaves of up to four triangles are as cheap
    /// as leaves of one (what makes the binned builder fill the packs).
    #[inline(always)]
    pub(super) fn leaf_cost(&self, n: usize) -> f32 {
        // A block of 1 or 4: a shift, not the division `div_ceil` makes of a run-time
        // divisor (the SAH sweep asks twice per candidate split).
        debug_assert!(self.test_block.is_power_of_two());
        let shift = self.test_block.trailing_zeros();
        ((n + self.test_block - 1) >> shift) as f32
    }
}

/// The chance that a ray from a uniform point inside a parent box, in a uniform
/// direction, enters a child box of `area` and `volume` (the parent's `parent_area` and
/// `parent_volume`): a line through the child is met by the part of its chord through the
/// parent that lies before the child's far end, in either direction, so integrating over
/// lines (Crofton) gives half the area share (with the parent's mean chord) plus half the
/// volume share. A flat parent (no volume) falls back to the area share.
#[inline(always)]
pub(super) fn inside_share(area: f32, volume: f32, parent_area: f32, parent_volume: f32) -> f32 {
    if parent_volume > 0.0 {
        0.5 * (area / parent_area) + 0.5 * (volume / parent_volume)
    } else {
        area / parent_area
    }
}

impl Bvh {
    /// Builds over `prims`, which must all be bounded.
    pub fn build(geometry: &Geometry, prims: Vec<u32>, options: &BvhOptions) -> Bvh {
        let bound = |p: u32| geometry.bounds(p).expect("BVH primitives must be bounded");
        // Pre-splitting duplicates ids, never adds a kind of primitive.
        let all_triangles = prims.par_iter().all(|&p| {
            matches!(
                geometry.primitives[p as usize].shape,
                crate::geometry::Shape::Triangle { .. }
            )
        });
        if options.builder == BvhBuilder::Auto {
            let choice = auto::choose(prims.len(), all_triangles, options.expected_rays);
            let chosen = BvhOptions {
                builder: choice.builder,
                reinsert: options.reinsert || choice.reinsert,
                ..options.clone()
            };
            let mut bvh = Bvh::build(geometry, prims, &chosen);
            bvh.auto = Some(choice.reason);
            return bvh;
        }
        let test_block = if all_triangles { 4 } else { 1 };
        let (prims, boxes) = if options.presplit == 0.0 && options.builder.moves_references_only() {
            // The default build: its references straight from the geometry, without the
            // array of boxes by build position that it would read only to make them (on a
            // million triangles a pass and 24 MiB of fresh pages, a twentieth of the build).
            let refs = (prims.par_iter().enumerate())
                .map(|(i, &p)| PrimRef::new(i as u32, &bound(p)))
                .collect();
            (prims, Boxes::References(refs))
        } else {
            let bounds: Vec<Aabb> = prims.par_iter().map(|&p| bound(p)).collect();
            let (prims, bounds) = if options.presplit > 0.0 {
                presplit::presplit(geometry, prims, bounds, options.presplit)
            } else {
                (prims, bounds)
            };
            (prims, Boxes::Bounds(bounds))
        };
        let triangles = if options.builder.clips_triangles() {
            prims
                .par_iter()
                .map(|&p| presplit::triangle(geometry, p))
                .collect()
        } else {
            Vec::new()
        };
        let mut bvh = Bvh::build_blocks(prims, boxes, options, test_block, triangles);
        bvh.pack(geometry);
        bvh
    }

    /// Rewrites the triangle leaves of a tree built over a scene's primitives into packs.
    fn pack(&mut self, geometry: &Geometry) {
        if geometry.meshes.is_empty() {
            return;
        }
        let corners = super::leaves::Corners::of(geometry, &self.prims);
        self.packs = if self.wide8.is_empty() {
            super::leaves::pack_triangles(&mut self.wide, &self.prims, &corners)
        } else {
            super::leaves::pack_triangles(&mut self.wide8, &self.prims, &corners)
        };
    }

    /// Builds over items known only by their boxes (`bounds[i]` bounds `prims[i]`), for
    /// hierarchies whose leaves are not single primitives.
    pub(crate) fn build_over_bounds(
        prims: Vec<u32>,
        bounds: Vec<Aabb>,
        options: &BvhOptions,
    ) -> Bvh {
        Bvh::build_blocks(prims, Boxes::Bounds(bounds), options, 1, Vec::new())
    }

    /// `build_over_bounds` for leaves that test `test_block` primitives in one step (the
    /// binned builder's SAH counts steps; the other builders ignore it).
    fn build_blocks(
        prims: Vec<u32>,
        boxes: Boxes,
        options: &BvhOptions,
        test_block: usize,
        triangles: Vec<Option<[Vec3; 3]>>,
    ) -> Bvh {
        let (bounds, mut refs) = match boxes {
            Boxes::Bounds(bounds) => (bounds, None),
            Boxes::References(refs) => (Vec::new(), Some(refs)),
        };
        let input = BuildPrims {
            bounds,
            test_block,
            triangles,
        };
        let threshold = options.parallel_threshold.max(1);
        let max_leaf_size = options.max_leaf_size.max(1);
        // The builders work on build positions 0..n; `ids` maps leaf order back to
        // primitive ids. The top-down builders move references (box and position).
        let mut top_down = |rule: &dyn Fn(&mut [PrimRef]) -> Vec<Node>| {
            let mut refs: Vec<PrimRef> = refs.take().unwrap_or_else(|| {
                (input.bounds.par_iter().enumerate())
                    .map(|(i, b)| PrimRef::new(i as u32, b))
                    .collect()
            });
            let nodes = rule(&mut refs);
            let ids = refs.par_iter().map(|r| prims[r.index() as usize]).collect();
            (nodes, ids)
        };
        // The Morton-ordered builders read boxes by build position and order positions.
        let bottom_up = |rule: &dyn Fn(&mut [u32]) -> Vec<Node>| {
            let mut order: Vec<u32> = (0..prims.len() as u32).collect();
            let nodes = rule(&mut order);
            let ids = order.par_iter().map(|&i| prims[i as usize]).collect();
            (nodes, ids)
        };
        let (mut nodes, ids): (Vec<Node>, Vec<u32>) = if prims.is_empty() {
            (Vec::new(), Vec::new())
        } else {
            match options.builder {
                BvhBuilder::Median => {
                    let rule = median::ObjectMedian { max_leaf_size };
                    top_down(&|refs| topdown::build(&rule, &input, refs, threshold))
                }
                // Trees over boxes alone (`build_over_bounds`) have no model of their
                // own for `auto`: they take the default.
                BvhBuilder::Binned | BvhBuilder::Auto => {
                    let rule = binned::BinnedSah::new(options);
                    top_down(&|refs| topdown::build(&rule, &input, refs, threshold))
                }
                BvhBuilder::Sweep => {
                    let rule = sweep::FullSweepSah {
                        max_leaf_size,
                        traversal_cost: options.node_cost(),
                        parallel_threshold: threshold,
                    };
                    top_down(&|refs| topdown::build(&rule, &input, refs, threshold))
                }
                BvhBuilder::Lbvh => bottom_up(&|order| {
                    lbvh::build(&input, order, max_leaf_size, options.node_cost(), threshold)
                }),
                BvhBuilder::Ploc => {
                    let ploc = ploc::Ploc {
                        radius: options.radius,
                        max_leaf_size,
                        traversal_cost: options.node_cost(),
                        parallel_threshold: threshold,
                    };
                    bottom_up(&|order| ploc.build(&input, order))
                }
                BvhBuilder::Phr => {
                    let phr = phr::Phr {
                        alpha: options.refine,
                        delta: options.cut,
                        max_leaf_size,
                        traversal_cost: options.node_cost(),
                        parallel_threshold: threshold,
                    };
                    bottom_up(&|order| phr.build(&input, order))
                }
                BvhBuilder::Sbvh => {
                    let rule = sbvh::Sbvh {
                        object: binned::BinnedSah::new(options),
                        bins: options.bins,
                        traversal_cost: options.node_cost(),
                        alpha: options.alpha,
                        overlap: options.overlap,
                        parallel_threshold: threshold,
                    };
                    let refs: Vec<PrimRef> = (input.bounds.par_iter().enumerate())
                        .map(|(i, b)| PrimRef::new(i as u32, b))
                        .collect();
                    let budget = (options.budget as f64 * prims.len() as f64) as usize;
                    let (nodes, refs) = rule.build(&input, refs, budget);
                    let ids = refs.par_iter().map(|r| prims[r.index() as usize]).collect();
                    (nodes, ids)
                }
            }
        };
        if options.reinsert {
            nodes = reinsert::optimize(nodes);
        }
        Bvh::from_tree(nodes, ids, options)
    }
}
