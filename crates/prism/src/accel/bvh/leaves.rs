//! Leaves as traversal reads them. A leaf holding only mesh triangles is stored as
//! `TrianglePack`s, its triangles' vertices copied in leaf order, four to a pack: a visit
//! reads the leaf's vertices from one place and rejects four triangles per SIMD step,
//! instead of following primitive → mesh → index triple → three vertices per triangle.
//! Other leaves keep primitive ids into `Bvh::prims`.

use super::wide::LeafSlots;
use crate::geometry::{Geometry, Shape, TrianglePack};
use crate::math::Vec3;
use rayon::prelude::*;

/// Marks a wide node's leaf child whose `child` is its first pack (into `Bvh::packs`) and
/// whose `count`, without this bit, is its number of packs.
pub(super) const PACKED: u32 = 1 << 31;

/// Every primitive's corners if it is a mesh triangle, by primitive id: read in
/// primitive order (mesh order), so that packing, which meets triangles in leaf order,
/// makes one scattered read per triangle rather than following primitive, index triple
/// and three vertices (on a million scattered triangles, a fifth of the build).
pub(super) fn triangle_corners(geometry: &Geometry) -> Vec<Option<[Vec3; 3]>> {
    geometry
        .primitives
        .par_iter()
        .map(|p| match p.shape {
            Shape::Triangle { mesh, index } => Some(geometry.meshes[mesh as usize].vertices(index)),
            _ => None,
        })
        .collect()
}

/// Rewrites the leaf children of `wide` that hold only triangles into packs, in the order
/// the nodes lie in memory (so neighbouring leaves' packs are neighbours too), and returns
/// the packs. `prims` are the leaves' primitive ids, as `child`/`count` index them;
/// `corners` is `triangle_corners`. Chunks of nodes find their packs in parallel, and the
/// packs are then made in parallel straight into one vector, each written once (per-chunk
/// vectors, grown and then joined, wrote them two or three times into fresh pages); the
/// result does not depend on the thread count.
pub(super) fn pack_triangles<N: LeafSlots>(
    wide: &mut [N],
    prims: &[u32],
    corners: &[Option<[Vec3; 3]>],
) -> Vec<TrianglePack> {
    let chunks: Vec<Vec<PackJob>> = wide
        .par_chunks_mut(1024)
        .map(|nodes| plan_chunk(nodes, prims, corners))
        .collect();
    // Each chunk numbered its packs from 0; shift them to where the chunk's packs land.
    let mut first = 0u32;
    for (nodes, jobs) in wide.chunks_mut(1024).zip(&chunks) {
        if first > 0 {
            for node in nodes {
                let (child, count) = node.slots();
                for (c, &n) in child.iter_mut().zip(count.iter()) {
                    if n & PACKED != 0 {
                        *c += first;
                    }
                }
            }
        }
        first += jobs.len() as u32;
    }
    let jobs = chunks.concat();
    let mut packs = Vec::new();
    jobs.par_iter()
        .map(|job| {
            let ids = &prims[job.start as usize..][..job.len as usize];
            let mut lanes = [([Vec3::ZERO; 3], 0u32); 4];
            for (lane, &p) in lanes.iter_mut().zip(ids) {
                *lane = (corners[p as usize].expect("planned on triangles"), p);
            }
            TrianglePack::new(&lanes[..ids.len()])
        })
        .collect_into_vec(&mut packs);
    packs
}

/// One pack to make: up to four triangles at `prims[start..start + len]`.
#[derive(Clone, Copy)]
struct PackJob {
    start: u32,
    len: u32,
}

/// The packs of the triangle leaves of `nodes`, numbered from 0, with the leaves rewritten
/// to point at them.
fn plan_chunk<N: LeafSlots>(
    nodes: &mut [N],
    prims: &[u32],
    corners: &[Option<[Vec3; 3]>],
) -> Vec<PackJob> {
    let mut jobs = Vec::new();
    for node in nodes {
        let (child, counts) = node.slots();
        for k in 0..child.len() {
            let count = counts[k];
            if count == 0 {
                continue;
            }
            let ids = &prims[child[k] as usize..][..count as usize];
            if !ids.iter().all(|&p| corners[p as usize].is_some()) {
                continue;
            }
            let first = jobs.len();
            for start in (child[k]..child[k] + count).step_by(4) {
                let len = (child[k] + count - start).min(4);
                jobs.push(PackJob { start, len });
            }
            child[k] = first as u32;
            counts[k] = PACKED | (jobs.len() - first) as u32;
        }
    }
    jobs
}
