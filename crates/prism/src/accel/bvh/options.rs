//! How a BVH is built: which builder, its SAH parameters, leaf size, the optional
//! reinsertion pass and when subtrees are built in parallel; the `bvh:` keys.

use super::Bvh;
use crate::accel::volumes::{self, NodeVolume};
use crate::accel::Accel;
use crate::accel::Method;
use crate::choices::{Key, Keyed};
use crate::field_key;
use crate::geometry::Geometry;

/// The construction algorithm.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BvhBuilder {
    /// Object median along the longest axis of the centroid bounds: fast, SAH-blind.
    Median,
    /// Binned SAH (Wald 2007), `bins` candidate planes per axis.
    #[default]
    Binned,
    /// Full-sweep SAH: every split between sorted centroids on every axis is evaluated.
    Sweep,
    /// Linear BVH from sorted 63-bit Morton codes of the centroids (Lauterbach et al. 2009).
    Lbvh,
    /// Parallel locally-ordered clustering (Meister & Bittner 2018): Morton-ordered
    /// clusters merged bottom up with their nearest neighbours within `radius`.
    Ploc,
    /// Spatial-split BVH (Stich, Friedrich & Dietrich 2009): binned SAH choosing between
    /// object splits and splits of space that clip triangles, within a duplication
    /// `budget`.
    Sbvh,
    /// Progressive hierarchical refinement (Hendrich, Meister & Bittner 2017): top-down
    /// SAH splits over a cut of an auxiliary LBVH, refined as the nodes get smaller
    /// (`cut` sets the first cut's size, `refine` how fast it is refined).
    Phr,
    /// Whichever of LBVH, binned SAH and binned SAH with reinsertion should cost the
    /// render least, build and trace together, by a cost model of counts
    /// (`build/auto.rs`): a preview of few rays per primitive gets the fastest build, a
    /// render of many the best tree.
    Auto,
}

impl BvhBuilder {
    /// Whether the builder reads its primitives' boxes only from the references it moves,
    /// never by build position.
    pub(super) fn moves_references_only(self) -> bool {
        matches!(self, BvhBuilder::Median | BvhBuilder::Binned)
    }

    /// Whether the builder clips triangles (and so may list a primitive more than once).
    pub(super) fn clips_triangles(self) -> bool {
        self == BvhBuilder::Sbvh
    }
}

named_kinds! {
    BvhBuilder, "BVH builder" {
        Median => "median",
        Binned => "binned",
        Sweep => "sweep",
        Lbvh => "lbvh",
        Ploc => "ploc",
        Sbvh => "sbvh",
        Phr => "phr",
        Auto => "auto",
    }
}

impl BvhBuilder {
    /// The method as `prism info` names it, e.g. "full-sweep SAH".
    pub fn description(self) -> &'static str {
        match self {
            BvhBuilder::Median => "object median",
            BvhBuilder::Binned => "binned SAH",
            BvhBuilder::Sweep => "full-sweep SAH",
            BvhBuilder::Lbvh => "LBVH, 63-bit Morton",
            BvhBuilder::Ploc => "PLOC",
            BvhBuilder::Sbvh => "SBVH, spatial splits",
            BvhBuilder::Phr => "PHR, progressive hierarchical refinement",
            BvhBuilder::Auto => "auto",
        }
    }
}

/// The traversal layout derived from the built tree (`wide.rs`, `simd8.rs`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum NodeWidth {
    /// 8-wide nodes tested with AVX2 where the CPU has it (detected at run time), else
    /// 4-wide nodes.
    #[default]
    Auto,
    /// 4-wide nodes (SSE) on every CPU.
    Four,
}

named_kinds! {
    NodeWidth, "node width" {
        Auto => "auto",
        Four => "4",
    }
}

/// Whether packets of rays use AVX-512 where the CPU has it (`simd8/per_ray.rs` in sixteen
/// lanes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Avx512 {
    /// Sixteen rays per step in the 8-wide packet kernels where the CPU has AVX-512F
    /// (detected at run time), else eight with AVX2.
    #[default]
    Auto,
    /// Eight rays per step with AVX2 even where AVX-512 is available.
    Off,
}

named_kinds! {
    Avx512, "AVX-512 use" {
        Auto => "auto",
        Off => "off",
    }
}

/// Where the SAH expects rays to start (`build/binned.rs`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum RayOrigins {
    /// Whatever the renderer traces: inside for the path integrator, whose rays start on
    /// surfaces, outside for the others (`RenderOptions::accel_to_build`). A tree built
    /// with no renderer to ask (`prism bench`, `prism info`) takes `Outside`.
    #[default]
    Auto,
    /// Outside the scene: a child is entered with its share of its parent's surface area
    /// (the SAH as MacDonald and Booth have it).
    Outside,
    /// On surfaces inside the scene, as a path tracer's rays in a closed room: a child is
    /// entered with half its parent's area share plus half its volume share (rays from
    /// uniform points inside the parent, in uniform directions), and subtrees small
    /// enough for a leaf are built and then collapsed where the leaf costs less.
    Inside,
}

named_kinds! {
    RayOrigins, "ray origins" {
        Auto => "auto",
        Outside => "outside",
        Inside => "inside",
    }
}

/// How a BVH is built; also the `bvh:` keys of `--accel` (see `Method`).
#[derive(Clone, Debug, PartialEq)]
pub struct BvhOptions {
    /// The construction algorithm.
    pub builder: BvhBuilder,
    /// Bins per axis for the binned SAH sweep.
    pub bins: usize,
    /// How many clusters each way PLOC searches for a cluster's nearest neighbour.
    pub radius: usize,
    /// SBVH's duplicated references at most, per primitive.
    pub budget: f32,
    /// SBVH costs a spatial split where an object split's children overlap by more than
    /// this share of the root's surface area. The default, 10^-4 (the paper's 10^-5 before),
    /// builds embree-bench's sphereflake in three quarters of the time for a lower SAH cost
    /// and the same rays, and changes no tree's cost on its other meshes by 0.01
    /// (docs/journal/bvh-frontier.md).
    pub alpha: f32,
    /// SBVH costs a spatial split only where an object split's children also overlap by at
    /// least this share of the node's own surface area (Embree's second test; 0 = off) or
    /// 0.3 of the node's references touch the overlap (slivers crossing the node): at 0.1,
    /// the default, surface meshes build 0.8x as long as with 0, with the same rays, and a
    /// knot crossed by slivers and a torus crossed by chords keep their spatial splits
    /// (docs/acceleration.md).
    pub overlap: f32,
    /// PHR's first cut: the auxiliary nodes of at most 2^-cut of the root's area (the
    /// paper's δ; about 2^cut nodes on a surface mesh).
    pub cut: f32,
    /// How fast PHR's refinement threshold falls per level of the tree: the area 2^-(cut
    /// + refine·depth) of the root's (the paper's α).
    pub refine: f32,
    /// Leaves never hold more primitives than this (unless they cannot be split).
    pub max_leaf_size: usize,
    /// Cost of a binary node relative to one primitive test, for rays from outside; a
    /// tree for rays from inside weighs its nodes at `INSIDE_NODE_SCALE` of it
    /// (`node_cost`).
    pub traversal_cost: f32,
    /// Improve the built tree by reinserting badly placed subtrees (Bittner et al. 2013).
    pub reinsert: bool,
    /// Pre-split triangles whose boxes are mostly empty into up to 16 references, this
    /// many extra references per primitive in all (0 = off; `build/presplit.rs`).
    pub presplit: f32,
    /// The volume the nodes carry when built through `Method::build` (`AccelSpec`): boxes
    /// are this `Bvh`, other kinds a `VolumeBvh` on the same tree. `Bvh::build` itself
    /// always builds boxes.
    pub volume: NodeVolume,
    /// Subtrees with more primitives than this are built on separate threads. The tree does
    /// not depend on it (or on the thread count); `usize::MAX` builds on one thread.
    pub parallel_threshold: usize,
    /// The traversal layout: 8-wide where AVX2 is available, or always 4-wide. The tree,
    /// and so every answer, is the same either way.
    pub width: NodeWidth,
    /// Whether the 8-wide packet kernels take sixteen rays per step with AVX-512 where the
    /// CPU has it. Answers are the same either way.
    pub avx512: Avx512,
    /// Where the binned SAH expects rays to start (the other builders ignore it).
    pub rays: RayOrigins,
    /// Rays the render is expected to trace, which `build=auto` weighs against the build
    /// (`RenderOptions::accel_to_build` settles it); 0 when no render is known, and then
    /// `auto` takes the fastest build.
    pub expected_rays: f64,
}

impl Default for BvhOptions {
    fn default() -> Self {
        BvhOptions {
            builder: BvhBuilder::Binned,
            bins: 16,
            radius: 16,
            budget: 0.3,
            alpha: 1e-4,
            overlap: 0.1,
            cut: 9.0,
            refine: 0.5,
            max_leaf_size: 8,
            traversal_cost: 1.0,
            reinsert: false,
            presplit: 0.0,
            volume: NodeVolume::Aabb,
            parallel_threshold: 4096,
            width: NodeWidth::Auto,
            avx512: Avx512::Auto,
            rays: RayOrigins::Auto,
            expected_rays: 0.0,
        }
    }
}

/// The share of `traversal_cost` a binary node costs in a tree for rays from inside
/// (`RayOrigins::Inside`). Three binary levels collapse into one 8-wide node, so a binary
/// level costs about a third of a visit. For rays from outside that changed nothing
/// measurable (bench/results/bvh-trav-cost.txt: node costs 0.5 and 0.7 level with 1), but
/// from inside the SAH then parts a room's walls, which at 1 stay in leaves that every
/// path vertex enters (docs/acceleration.md: the path-traced Cornell box renders alike at
/// node costs from 0.25 to 0.5, 1.28x faster than at 1).
pub(super) const INSIDE_NODE_SCALE: f32 = 1.0 / 3.0;

impl BvhOptions {
    /// The cost of a binary node relative to one primitive test that the SAH weighs:
    /// `traversal_cost`, scaled by `INSIDE_NODE_SCALE` for rays from inside.
    pub(super) fn node_cost(&self) -> f32 {
        if self.for_rays_from_inside() {
            self.traversal_cost * INSIDE_NODE_SCALE
        } else {
            self.traversal_cost
        }
    }

    /// Whether the tree is built for rays from inside: `rays=inside` with the binned
    /// builder (the others ignore `rays`).
    pub(super) fn for_rays_from_inside(&self) -> bool {
        self.rays == RayOrigins::Inside && self.builder == BvhBuilder::Binned
    }

    /// These options expecting `rays` rays where the builder is `auto`, which alone reads
    /// them (so that other trees compare equal whatever the render).
    pub fn with_expected_rays(&self, rays: f64) -> BvhOptions {
        let mut options = self.clone();
        if options.builder == BvhBuilder::Auto {
            options.expected_rays = rays;
        }
        options
    }

    /// These options with `rays=auto` settled as `origins` (the others unchanged).
    pub fn with_auto_rays(&self, origins: RayOrigins) -> BvhOptions {
        let mut options = self.clone();
        if options.rays == RayOrigins::Auto {
            options.rays = origins;
        }
        options
    }
}

impl Keyed for BvhOptions {
    const NAME: &'static str = "bvh";
    const SUMMARY: &'static str = "bounding volume hierarchy (the default)";
    const KEYS: &'static [Key<Self>] = &[
        field_key!("bins" => bins, int 2..=256, "candidate planes per axis of the binned SAH"),
        field_key!("radius" => radius, int 1..=256,
            "clusters searched each way for a nearest neighbour by PLOC"),
        field_key!("budget" => budget, number 0.0..=4.0,
            "references SBVH's spatial splits may add, per primitive"),
        field_key!("alpha" => alpha, number 0.0..=1.0,
            "overlap of an object split's children, as a share of the root's area, above which \
             SBVH tries spatial splits"),
        field_key!("overlap" => overlap, number 0.0..=1.0,
            "overlap of an object split's children, as a share of the node's own area, below \
             which SBVH tries no spatial split even above alpha, unless 0.3 of the node's \
             references touch the overlap (0 = alpha alone)"),
        field_key!("cut" => cut, number 0.0..=24.0,
            "PHR's first cut: the auxiliary LBVH's nodes of at most 2^-cut of the root's area \
             (the paper's delta; about 2^cut nodes on a surface mesh)"),
        field_key!("refine" => refine, number 0.0..=1.0,
            "how fast PHR refines its cut: a node at depth d cuts at 2^-(cut + refine*d) of the \
             root's area (the paper's alpha; smaller: smaller cuts below, a faster build)"),
        field_key!("leaf" => max_leaf_size, int 1..=1024, "largest leaf"),
        field_key!("trav" => traversal_cost, number 0.0..=1000.0,
            "binary node cost relative to a primitive test (a third of it for rays from inside)"),
        field_key!("build" => builder, choice BvhBuilder,
            "the builder (auto: the one whose build and trace together cost the render least, by \
             a model of counts)"),
        field_key!("split" => presplit, number 0.0..=4.0,
            "extra references per primitive from pre-splitting triangles (0 = off)"),
        field_key!("volume" => volume, choice NodeVolume, "the node volume"),
        field_key!("width" => width, choice NodeWidth,
            "traversal node width (auto: 8 with AVX2, else 4)"),
        field_key!("avx512" => avx512, choice Avx512,
            "packets of rays with AVX-512 where the CPU has it (auto) or AVX2 only (off)"),
        field_key!("rays" => rays, choice RayOrigins,
            "where the binned SAH expects rays to start: outside the scene (area shares), inside \
             it (half area and half volume shares, for paths in closed scenes), or auto (inside \
             for the path integrator, else outside)"),
        field_key!("reinsert" => reinsert, switch, "optimise the tree by reinsertion"),
    ];
}

impl Method for BvhOptions {
    fn build(&self, geometry: &Geometry, prims: Vec<u32>) -> Box<dyn Accel> {
        match self.volume {
            NodeVolume::Aabb => Box::new(Bvh::build(geometry, prims, self)),
            volume => volumes::build(geometry, prims, self, volume),
        }
    }
}
