//! The BVH as an `Accel`: a query's start at the root (a tree of one leaf tested directly),
//! the single-ray walk below a root of either layout (`walk_from`, the 4-wide one through
//! `traverse.rs`, the 8-wide one through `simd8.rs`), the leaf tests it hands the walk, and
//! packets through `packet.rs`.

use super::traverse::{walk, LeafQuery, Visit};
use super::wide::{Wide8Node, WideNode, WideRay};
use super::{Bvh, Node};
use crate::accel::query::HitSearch;
use crate::accel::{Accel, AccelInfo, Hit, PacketQuery, QueryMode, RayQuery};
use crate::geometry::{Geometry, PackRay};
use crate::math::{Aabb, TraceRay};
use crate::stats::Stats;
use glam::Vec4;

#[inline(always)]
fn node_hit(node: &Node, ray: &TraceRay, t_max: f32) -> Option<f32> {
    Aabb {
        min: node.min,
        max: node.max,
    }
    .hit(ray.ray.origin, ray.inv_dir, t_max)
}

impl Accel for Bvh {
    #[inline(always)]
    fn query(&self, query: &RayQuery, stats: &mut Stats) -> Option<Hit> {
        let ray = query.ray;
        let root = self.nodes.first()?;
        // A tree of one leaf: its box, then its primitives. Otherwise the walk's first
        // step tests the root's children's boxes in one SIMD step, which a ray that misses
        // the scene fails as well; the binary root's own box, tested first with scalar
        // code, cost a twentieth of a single ray's instructions and never changed an
        // answer (a box test only decides which primitives are tested).
        if root.is_leaf() {
            stats.node_visits += 1;
            node_hit(root, ray, query.t_max)?;
            let mut search = HitSearch::new(query.t_max, query.mode);
            let pack_ray = PackRay::new(ray);
            let leaf = self.leaf_query(query.geometry, ray, &pack_ray);
            leaf.test(root.first, root.count, &mut search, stats);
            return search.best();
        }
        let root = if self.wide8.is_empty() {
            Root::Four(&self.wide[0])
        } else {
            Root::Eight(&self.wide8[0])
        };
        self.walk_from(root, query.geometry, ray, query.t_max, query.mode, stats)
    }

    fn query_packet(&self, packet: &PacketQuery, answers: &mut [Option<Hit>], stats: &mut Stats) {
        super::packet::query(self, None, packet, answers, stats)
    }

    fn info(&self) -> AccelInfo {
        self.info()
    }

    fn as_bvh(&self) -> Option<&Bvh> {
        Some(self)
    }
}

/// Where a walk starts: a node of the tree's own layout (its root, or an entry node made of
/// some of its subtrees, `subtree.rs`).
#[derive(Clone, Copy)]
pub(super) enum Root<'a> {
    Four(&'a WideNode),
    Eight(&'a Wide8Node),
}

impl Bvh {
    /// The query below `root`: what `query` answers over the primitives of the subtrees
    /// `root` holds.
    #[inline(always)]
    pub(super) fn walk_from(
        &self,
        root: Root,
        geometry: &Geometry,
        ray: &TraceRay,
        t_max: f32,
        mode: QueryMode,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let mut search = HitSearch::new(t_max, mode);
        let pack_ray = PackRay::new(ray);
        let leaf = self.leaf_query(geometry, ray, &pack_ray);
        let (wide8, any) = (&self.wide8, mode == QueryMode::Any);
        // The 8-wide walks make their leaf closures themselves, inside their AVX2
        // compilation (a leaf closure per walk, each used once: one closure shared by the
        // walks stayed a function call, the path tracer's cornell box 8 % slower).
        match root {
            Root::Eight(node) if any => {
                super::simd8::traverse::<false>(wide8, node, ray, &mut search, stats, &leaf)
            }
            Root::Eight(node) => {
                super::simd8::traverse::<true>(wide8, node, ray, &mut search, stats, &leaf)
            }
            Root::Four(node) => {
                // The 4-wide layout (CPUs without AVX2) keeps one walk, ordered.
                let wide_ray = WideRay::new(ray);
                walk::<_, _, true>(
                    &self.wide,
                    node,
                    |node: &WideNode, s: &HitSearch, ()| {
                        let t = node.hit(&wide_ray, s.t_max());
                        let mut entries = [0.0; 8];
                        entries[..4].copy_from_slice(&t.to_array());
                        Visit {
                            children: node.children(),
                            hit: t.cmplt(Vec4::INFINITY).bitmask(),
                            entries,
                            rays: [(); 8],
                        }
                    },
                    &mut search,
                    stats,
                    |c, n, _, (), s: &mut HitSearch, st: &mut Stats| leaf.test(c, n, s, st),
                );
            }
        }
        search.best()
    }
}

impl Bvh {
    /// The leaf tests of this tree for `ray` (`pack_ray` its constants for the packs).
    #[inline(always)]
    pub(super) fn leaf_query<'a>(
        &'a self,
        geometry: &'a Geometry,
        ray: &'a TraceRay,
        pack_ray: &'a PackRay,
    ) -> LeafQuery<'a> {
        LeafQuery {
            prims: &self.prims,
            packs: &self.packs,
            geometry,
            ray,
            pack_ray,
        }
    }
}
