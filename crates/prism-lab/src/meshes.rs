//! The procedural meshes of the lab's comparisons (embree-bench's, the builders'
//! examples): made deterministically, so every program that measures them measures the
//! same triangles. `blob` is a closed lumpy sphere, `sphereflake` Haines's sphereflake of
//! UV spheres, `soup` a million crossing random triangles at its usual size.

use prism::math::{Frame, Vec3};
use std::collections::HashMap;
use std::f32::consts::{PI, TAU};

/// Triangles by vertex index.
#[derive(Clone, Debug, Default)]
pub struct Triangles {
    /// The vertices.
    pub positions: Vec<Vec3>,
    /// Each triangle's three vertex indices.
    pub indices: Vec<[u32; 3]>,
}

impl Triangles {
    /// Appends `positions` and their `indices` (shifted past the vertices already here).
    pub fn append(&mut self, positions: &[Vec3], indices: &[[u32; 3]]) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(positions);
        self.indices
            .extend(indices.iter().map(|t| t.map(|i| i + base)));
    }
}

/// Centres the bounds of `positions` on the origin and scales their largest extent to
/// 100, so every mesh meets the same camera and the same ray offsets.
pub fn normalise(positions: &mut [Vec3]) {
    let lo = positions.iter().fold(Vec3::INFINITY, |a, &p| a.min(p));
    let hi = positions.iter().fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
    let centre = 0.5 * (lo + hi);
    let scale = 100.0 / (hi - lo).max_element();
    for p in positions {
        *p = (*p - centre) * scale;
    }
}

/// A closed, lumpy sphere: the six faces of a cube, each an `n` × `n` grid of quads,
/// welded along the cube's edges, projected onto the sphere and displaced radially
/// (radial displacement keeps it free of self-intersections). 12·n² triangles: n = 92
/// gives 101,568.
pub fn blob(n: u32) -> Triangles {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    // Vertices by their integer lattice point on the cube's surface, so that faces sharing
    // an edge share its vertices and the mesh is closed.
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let mut vertex = |lattice: [u32; 3]| -> u32 {
        *ids.entry(lattice).or_insert_with(|| {
            let c = Vec3::from_array(lattice.map(|l| 2.0 * l as f32 / n as f32 - 1.0));
            let d = c.normalize();
            let r = 1.0
                + 0.12 * (5.0 * d.x).sin() * (4.0 * d.y + 1.0).sin() * (6.0 * d.z + 2.0).sin()
                + 0.04 * (17.0 * d.x + 3.0 * d.z).sin() * (13.0 * d.y).cos();
            positions.push(d * r);
            positions.len() as u32 - 1
        })
    };
    for axis in 0..3 {
        for side in [0, n] {
            // (u, v, normal axis) is right-handed for the +side face; the other face swaps
            // u and v, so every face winds counter-clockwise seen from outside.
            let (mut ua, mut va) = ((axis + 1) % 3, (axis + 2) % 3);
            if side == 0 {
                std::mem::swap(&mut ua, &mut va);
            }
            let at = |u: u32, v: u32| {
                let mut l = [0; 3];
                l[axis] = side;
                l[ua] = u;
                l[va] = v;
                l
            };
            for v in 0..n {
                for u in 0..n {
                    let a = vertex(at(u, v));
                    let b = vertex(at(u + 1, v));
                    let c = vertex(at(u + 1, v + 1));
                    let d = vertex(at(u, v + 1));
                    indices.push([a, b, c]);
                    indices.push([a, c, d]);
                }
            }
        }
    }
    Triangles { positions, indices }
}

/// Haines's sphereflake to `level` (1 + 9 + … + 9^level spheres: 7,381 at level 4), each
/// sphere a UV sphere of `nu` segments and `rings` rings (2·nu·(rings−1) triangles):
/// 144 per sphere, 1,062,864 in all at level 4.
pub fn sphereflake(level: u32, nu: u32, rings: u32) -> Triangles {
    let mut mesh = Triangles::default();
    flake(&mut mesh, Vec3::ZERO, 1.0, Vec3::Y, level, nu, rings);
    mesh
}

fn flake(
    mesh: &mut Triangles,
    centre: Vec3,
    radius: f32,
    axis: Vec3,
    level: u32,
    nu: u32,
    rings: u32,
) {
    uv_sphere(mesh, centre, radius, nu, rings);
    if level == 0 {
        return;
    }
    // Nine children of a third the radius, touching the parent: six around its equator
    // (relative to `axis`, the direction from its own parent) and three above at 60°.
    let frame = Frame::from_z(axis);
    let child = radius / 3.0;
    for k in 0..9 {
        let (elevation, phi) = if k < 6 {
            (0.0f32, k as f32 * TAU / 6.0)
        } else {
            (60f32.to_radians(), (k - 6) as f32 * TAU / 3.0 + TAU / 12.0)
        };
        let local = Vec3::new(
            elevation.cos() * phi.cos(),
            elevation.cos() * phi.sin(),
            elevation.sin(),
        );
        let dir = frame.to_world(local).normalize();
        flake(
            mesh,
            centre + (radius + child) * dir,
            child,
            dir,
            level - 1,
            nu,
            rings,
        );
    }
}

/// A UV sphere: two poles and `rings − 1` circles of `nu` vertices.
fn uv_sphere(mesh: &mut Triangles, centre: Vec3, radius: f32, nu: u32, rings: u32) {
    let base = mesh.positions.len() as u32;
    mesh.positions.push(centre + radius * Vec3::Y);
    for j in 1..rings {
        let theta = PI * j as f32 / rings as f32;
        for i in 0..nu {
            let phi = TAU * i as f32 / nu as f32;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            mesh.positions.push(centre + radius * d);
        }
    }
    mesh.positions.push(centre - radius * Vec3::Y);
    let south = mesh.positions.len() as u32 - 1;
    let ring = |j: u32, i: u32| base + 1 + (j - 1) * nu + i % nu;
    for i in 0..nu {
        mesh.indices.push([base, ring(1, i + 1), ring(1, i)]);
        for j in 1..rings - 1 {
            let (a, b) = (ring(j, i), ring(j, i + 1));
            let (c, d) = (ring(j + 1, i + 1), ring(j + 1, i));
            mesh.indices.push([a, b, c]);
            mesh.indices.push([a, c, d]);
        }
        mesh.indices
            .push([ring(rings - 1, i), ring(rings - 1, i + 1), south]);
    }
}

/// `count` independent random triangles: each a centre uniform in a cube of side 100 and
/// three vertices within ±1 of it on every axis (so they overlap and cross each other).
pub fn soup(count: u32, seed: u64) -> Triangles {
    let mut state = seed;
    let mut uniform = move || {
        // SplitMix64: a Weyl sequence, each value hashed.
        let x = splitmix64(state);
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        (x >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut positions = Vec::with_capacity(3 * count as usize);
    for _ in 0..count {
        let c = Vec3::new(uniform(), uniform(), uniform()) * 100.0 - 50.0;
        for _ in 0..3 {
            positions.push(c + Vec3::new(uniform(), uniform(), uniform()) * 2.0 - 1.0);
        }
    }
    let indices = (0..count).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    Triangles { positions, indices }
}

/// The step of the SplitMix64 generator: a well-mixed 64-bit hash of its input.
pub fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each undirected edge's count of triangles.
    fn edge_uses(t: &Triangles) -> HashMap<(u32, u32), u32> {
        let mut uses = HashMap::new();
        for &[a, b, c] in &t.indices {
            for (p, q) in [(a, b), (b, c), (c, a)] {
                *uses.entry((p.min(q), p.max(q))).or_insert(0) += 1;
            }
        }
        uses
    }

    #[test]
    fn the_blob_is_closed_with_twelve_n_squared_triangles() {
        let blob = blob(6);
        assert_eq!(blob.indices.len(), 12 * 36);
        assert!(edge_uses(&blob).values().all(|&n| n == 2));
    }

    #[test]
    fn a_sphereflake_has_its_spheres_of_closed_uv_triangles() {
        // Level 1: the sphere and its nine children, 2·12·6 triangles each.
        let flake = sphereflake(1, 12, 7);
        assert_eq!(flake.indices.len(), 10 * 144);
        assert!(edge_uses(&flake).values().all(|&n| n == 2));
    }

    #[test]
    fn the_soup_is_the_same_for_a_seed_and_other_for_another() {
        let (a, b, c) = (soup(1000, 7), soup(1000, 7), soup(1000, 8));
        assert_eq!(a.positions, b.positions);
        assert_ne!(a.positions, c.positions);
        assert_eq!(a.indices.len(), 1000);
        // Each triangle's corners lie within ±1 of a centre inside the cube of side 100.
        for tri in a.positions.chunks(3) {
            let lo = tri.iter().fold(Vec3::INFINITY, |m, &p| m.min(p));
            let hi = tri.iter().fold(Vec3::NEG_INFINITY, |m, &p| m.max(p));
            assert!((hi - lo).max_element() <= 2.0);
            assert!(lo.min_element() >= -51.0 && hi.max_element() <= 51.0);
        }
    }

    #[test]
    fn normalising_centres_and_scales_the_largest_extent_to_100() {
        let mut p = vec![Vec3::new(1.0, 2.0, 3.0), Vec3::new(3.0, 3.0, 3.5)];
        normalise(&mut p);
        assert_eq!(
            p,
            [Vec3::new(-50.0, -25.0, -12.5), Vec3::new(50.0, 25.0, 12.5)]
        );
    }
}
