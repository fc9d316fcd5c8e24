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

/// Where packing reads a triangle's corners.
pub(super) enum Corners<'a> {
    /// Every primitive's corners if it is a mesh triangle, by primitive id: read in
    /// primitive order (mesh order), so that packing, which meets triangles in leaf order,
    /// makes one scattered read per triangle rather than following primitive, index
    /// triple and three vertices (on a million scattered triangles, a fifth of the build).
    Gathered(Vec<Option<[Vec3; 3]>>),
    /// Straight from the geometry: where its primitives and meshes fit in the cache (there
    /// the array above costs more, a pass over the meshes and fresh pages to write, than
    /// the reads it saves), and where the leaves' triangles lie near each other in their
    /// meshes (a tessellated or scanned surface, whose neighbouring triangles are stored
    /// near each other), so that packing reads the meshes almost in order.
    Direct(&'a Geometry),
}

/// Geometry up to this size (primitives, index triples and positions) is read straight
/// by packing (`Corners::Direct`).
const DIRECT_BYTES: usize = 8 << 20;

/// Leaf-order neighbours this many primitives or vertices apart or closer count as near:
/// a few kilobytes of primitives (32 bytes each) or positions (12 bytes each).
const NEAR: u32 = 128;

/// Neighbouring pairs of leaf positions sampled to judge the leaves' locality.
const LOCALITY_SAMPLES: usize = 4096;

impl<'a> Corners<'a> {
    /// The way to read `geometry`'s corners that costs its build the least, for leaves
    /// holding `prims` (primitive ids in leaf order).
    pub(super) fn of(geometry: &'a Geometry, prims: &[u32]) -> Corners<'a> {
        use std::mem::size_of;
        let meshes: usize = (geometry.meshes.iter())
            .map(|m| {
                m.triangle_count() * size_of::<[u32; 3]>() + m.vertex_count() * size_of::<Vec3>()
            })
            .sum();
        let bytes = meshes + std::mem::size_of_val(&geometry.primitives[..]);
        if bytes <= DIRECT_BYTES || leaves_are_local(geometry, prims) {
            return Corners::Direct(geometry);
        }
        Corners::gathered(geometry)
    }

    fn gathered(geometry: &Geometry) -> Corners<'a> {
        let direct = Corners::Direct(geometry);
        let ids = 0..geometry.primitives.len() as u32;
        Corners::Gathered(ids.into_par_iter().map(|p| direct.get(p)).collect())
    }

    /// Whether primitive `p` is a mesh triangle (without reading its corners).
    #[inline(always)]
    fn is_triangle(&self, p: u32) -> bool {
        match self {
            Corners::Gathered(corners) => corners[p as usize].is_some(),
            Corners::Direct(geometry) => matches!(
                geometry.primitives[p as usize].shape,
                Shape::Triangle { .. }
            ),
        }
    }

    /// Primitive `p`'s corners if it is a mesh triangle.
    #[inline(always)]
    fn get(&self, p: u32) -> Option<[Vec3; 3]> {
        match self {
            Corners::Gathered(corners) => corners[p as usize],
            Corners::Direct(geometry) => match geometry.primitives[p as usize].shape {
                Shape::Triangle { mesh, index } => {
                    Some(geometry.meshes[mesh as usize].vertices(index))
                }
                _ => None,
            },
        }
    }
}

/// Rewrites the leaf children of `wide` that hold only triangles into packs, in the order
/// the nodes lie in memory (so neighbouring leaves' packs are neighbours too), and returns
/// the packs. `prims` are the leaves' primitive ids, as `child`/`count` index them;
/// `corners` gives their corners. Chunks of nodes find their packs in parallel, and the
/// packs are then made in parallel straight into one vector, each written once (per-chunk
/// vectors, grown and then joined, wrote them two or three times into fresh pages); the
/// result does not depend on the thread count.
pub(super) fn pack_triangles<N: LeafSlots>(
    wide: &mut [N],
    prims: &[u32],
    corners: &Corners,
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
                *lane = (corners.get(p).expect("planned on triangles"), p);
            }
            TrianglePack::new(&lanes[..ids.len()])
        })
        .collect_into_vec(&mut packs);
    packs
}

/// Whether most leaf-order neighbours in `prims` (sampled evenly) are near each other in
/// the geometry: the same mesh, primitive ids and first vertices at most `NEAR` apart.
/// Then reading corners straight from the meshes in leaf order stays within a few pages
/// at a time: on the million-triangle sphereflake packing takes 34 ms instead of 45 (the
/// gathered array is 42 MB of fresh pages), while on a million scattered triangles it
/// would take twice as long as with the array (docs/journal/performance.md).
fn leaves_are_local(geometry: &Geometry, prims: &[u32]) -> bool {
    if prims.len() < 2 {
        return true;
    }
    let first_vertex = |p: u32| match geometry.primitives[p as usize].shape {
        Shape::Triangle { mesh, index } => Some((
            mesh,
            geometry.meshes[mesh as usize].indices()[index as usize][0],
        )),
        _ => None,
    };
    let pairs = prims.len() - 1;
    let step = (pairs / LOCALITY_SAMPLES).max(1);
    let (mut near, mut sampled) = (0usize, 0usize);
    for k in (0..pairs).step_by(step) {
        let (a, b) = (prims[k], prims[k + 1]);
        sampled += 1;
        let close = match (first_vertex(a), first_vertex(b)) {
            (Some((ma, va)), Some((mb, vb))) => {
                ma == mb && a.abs_diff(b) <= NEAR && va.abs_diff(vb) <= NEAR
            }
            _ => false,
        };
        near += usize::from(close);
    }
    // Three in four: a leaf's triangles are neighbours, and so are most leaves'.
    4 * near >= 3 * sampled
}

/// One pack to make: up to four triangles at `prims[start..start + len]`.
#[derive(Clone, Copy)]
struct PackJob {
    start: u32,
    len: u32,
}

/// The packs of the triangle leaves of `nodes`, numbered from 0, with the leaves rewritten
/// to point at them.
fn plan_chunk<N: LeafSlots>(nodes: &mut [N], prims: &[u32], corners: &Corners) -> Vec<PackJob> {
    let mut jobs = Vec::new();
    for node in nodes {
        let (child, counts) = node.slots();
        for k in 0..child.len() {
            let count = counts[k];
            if count == 0 {
                continue;
            }
            let ids = &prims[child[k] as usize..][..count as usize];
            if !ids.iter().all(|&p| corners.is_triangle(p)) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Sphere, TriangleMesh};

    #[test]
    fn both_ways_to_read_corners_agree() {
        let mut g = Geometry::default();
        g.add(Shape::from(Sphere::new(Vec3::ZERO, 1.0)), 0);
        let positions: Vec<Vec3> = (0..40)
            .map(|i| Vec3::new(i as f32, (i * 7 % 11) as f32, (i * 3 % 5) as f32))
            .collect();
        let indices: Vec<[u32; 3]> = (0..30u32).map(|i| [i, (i * 13 + 5) % 40, 39 - i]).collect();
        let mesh = TriangleMesh::new(positions, indices, None, None).expect("a mesh");
        g.add_mesh(mesh, 0);
        g.add(Shape::from(Sphere::new(Vec3::ONE, 2.0)), 0);
        let (direct, gathered) = (Corners::Direct(&g), Corners::gathered(&g));
        assert!(
            matches!(Corners::of(&g, &[]), Corners::Direct(_)),
            "a small scene reads directly"
        );
        let mut triangles = 0;
        for p in 0..g.primitives.len() as u32 {
            assert_eq!(direct.get(p), gathered.get(p), "primitive {p}");
            for corners in [&direct, &gathered] {
                assert_eq!(corners.is_triangle(p), corners.get(p).is_some(), "{p}");
            }
            if let Shape::Triangle { mesh, index } = g.primitives[p as usize].shape {
                assert_eq!(direct.get(p), Some(g.meshes[mesh as usize].vertices(index)));
                triangles += 1;
            } else {
                assert_eq!(direct.get(p), None);
            }
        }
        assert_eq!(triangles, 30);
    }

    /// The leaves count as local when most leaf-order neighbours are near in primitive
    /// ids and in vertices; a shuffled order, or near ids whose triangles use scattered
    /// vertices, is not.
    #[test]
    fn locality_is_judged_on_primitives_and_vertices() {
        use crate::math::hash::uniform;
        let n = 20_000u32;
        let strip = |vertex_of: &dyn Fn(u32) -> u32| {
            let positions: Vec<Vec3> = (0..n + 2)
                .map(|i| Vec3::new(i as f32, (i % 2) as f32, 0.0))
                .collect();
            let indices: Vec<[u32; 3]> = (0..n)
                .map(|t| [vertex_of(t), vertex_of(t) + 1, vertex_of(t) + 2])
                .collect();
            let mut g = Geometry::default();
            let mesh = TriangleMesh::new(positions, indices, None, None).expect("a mesh");
            g.add_mesh(mesh, 0);
            g
        };
        let in_order: Vec<u32> = (0..n).collect();
        // A permutation of 0..n: sorted by a hash of each id.
        let mut shuffled = in_order.clone();
        shuffled.sort_by(|&a, &b| uniform(a, 3, 0, 0, 1).total_cmp(&uniform(b, 3, 0, 0, 1)));
        let ordered_mesh = strip(&|t| t);
        assert!(leaves_are_local(&ordered_mesh, &in_order));
        assert!(!leaves_are_local(&ordered_mesh, &shuffled));
        // Triangles stored in order, but each on vertices far from its neighbours'.
        let scattered_vertices = strip(&|t| (t * 7919) % n);
        assert!(!leaves_are_local(&scattered_vertices, &in_order));
        // Runs of 64 in order, the runs shuffled: far jumps between runs only.
        let mut starts: Vec<u32> = (0..n / 64).map(|r| r * 64).collect();
        starts.sort_by(|&a, &b| uniform(a, 4, 0, 0, 1).total_cmp(&uniform(b, 4, 0, 0, 1)));
        let runs: Vec<u32> = starts.iter().flat_map(|&s| s..s + 64).collect();
        assert!(leaves_are_local(&ordered_mesh, &runs));
    }
}
