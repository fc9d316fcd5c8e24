//! The four meshes of the comparison: the Stanford bunny read from disk and three made
//! here, deterministically, each normalised (centred on the origin, largest extent 100).
//! Beside them `cornell`: the triangles of prism's built-in `cornell-light` as they are (in
//! millimetres), seen by its own camera and lit at its ceiling light (`workload::View`), for
//! the rays of a path tracer in a small closed room (docs/path-tracing.md).

use prism::math::{Frame, Vec3};
use prism_io::scene::mesh_file::Materials;
use std::collections::HashMap;
use std::f32::consts::{PI, TAU};
use std::path::Path;

/// Triangles as both libraries receive them.
pub struct Mesh {
    pub name: &'static str,
    pub positions: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
}

pub const NAMES: [&str; 4] = ["bunny", "blob", "sphereflake", "soup"];

/// The small room: not one of `NAMES` (the tables of `run.sh`), asked for by name.
pub const CORNELL: &str = "cornell";

/// Why a mesh cannot be had.
pub enum MeshError {
    /// Its file is absent (the bunny outside this workplace): the run skips it.
    Absent(String),
    /// No mesh has that name, or its file cannot be read: an error.
    Failed(String),
}

impl From<MeshError> for String {
    fn from(e: MeshError) -> String {
        match e {
            MeshError::Absent(why) | MeshError::Failed(why) => why,
        }
    }
}

impl Mesh {
    fn empty(name: &'static str) -> Mesh {
        Mesh {
            name,
            positions: Vec::new(),
            indices: Vec::new(),
        }
    }

    /// Appends a triangle mesh's vertices and triangles (its indices shifted past the
    /// vertices already here), so that triangle indices mean the same in both libraries.
    fn append(&mut self, part: &prism::geometry::TriangleMesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(part.positions());
        self.indices
            .extend(part.indices().iter().map(|t| t.map(|i| i + base)));
    }
}

/// The mesh called `name`.
pub fn make(name: &str, meshes_dir: &Path) -> Result<Mesh, MeshError> {
    let mut mesh = match name {
        "bunny" => bunny(meshes_dir)?,
        "blob" => blob(92),
        "sphereflake" => sphereflake(4, 12, 7),
        "soup" => soup(1_000_000, 0x5eed),
        CORNELL => return Ok(cornell()),
        _ => {
            return Err(MeshError::Failed(format!(
                "unknown mesh '{name}', expected one of {NAMES:?} or {CORNELL}"
            )))
        }
    };
    normalise(&mut mesh);
    Ok(mesh)
}

/// The 32 triangles of the built-in `cornell-light` (room, blocks and light), in its own
/// coordinates, so that its camera and light apply.
fn cornell() -> Mesh {
    let mut mesh = Mesh::empty(CORNELL);
    for part in &cornell_light().geometry.meshes {
        mesh.append(part);
    }
    mesh
}

/// prism's built-in `cornell-light`, whose triangles and camera `cornell` takes.
pub fn cornell_light() -> prism::scene::Scene {
    prism::scene::builtin::BUILTINS
        .iter()
        .find(|b| b.name == "cornell-light")
        .expect("prism has the built-in cornell-light")
        .build()
}

/// Centres the bounds on the origin and scales the largest extent to 100, so every mesh
/// meets the same camera and the same ray offsets.
fn normalise(mesh: &mut Mesh) {
    let lo = mesh.positions.iter().fold(Vec3::INFINITY, |a, &p| a.min(p));
    let hi = mesh
        .positions
        .iter()
        .fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
    let centre = 0.5 * (lo + hi);
    let scale = 100.0 / (hi - lo).max_element();
    for p in &mut mesh.positions {
        *p = (*p - centre) * scale;
    }
}

/// The Stanford bunny (69,451 triangles), all parts of the file in one mesh so that
/// triangle indices mean the same in both libraries.
fn bunny(dir: &Path) -> Result<Mesh, MeshError> {
    let path = dir.join("stanford-bunny.obj");
    if !path.exists() {
        return Err(MeshError::Absent(format!("{} is absent", path.display())));
    }
    let file = prism_io::scene::load_mesh_file(&path, Materials::Ignore)
        .map_err(|e| MeshError::Failed(e.to_string()))?;
    let mut mesh = Mesh::empty("bunny");
    for part in &file.parts {
        mesh.append(&part.mesh);
    }
    Ok(mesh)
}

/// A closed, lumpy sphere: the six faces of a cube, each an `n` × `n` grid of quads,
/// welded along the cube's edges, projected onto the sphere and displaced radially
/// (radial displacement keeps it free of self-intersections). 12·n² triangles: n = 92
/// gives 101,568.
fn blob(n: u32) -> Mesh {
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
    Mesh {
        name: "blob",
        positions,
        indices,
    }
}

/// Haines's sphereflake to `level` (1 + 9 + … + 9^level spheres: 7,381 at level 4), each
/// sphere a UV sphere of `nu` segments and `rings` rings (2·nu·(rings−1) triangles):
/// 144 per sphere, 1,062,864 in all at level 4.
fn sphereflake(level: u32, nu: u32, rings: u32) -> Mesh {
    let mut mesh = Mesh {
        name: "sphereflake",
        positions: Vec::new(),
        indices: Vec::new(),
    };
    flake(&mut mesh, Vec3::ZERO, 1.0, Vec3::Y, level, nu, rings);
    mesh
}

fn flake(mesh: &mut Mesh, centre: Vec3, radius: f32, axis: Vec3, level: u32, nu: u32, rings: u32) {
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
fn uv_sphere(mesh: &mut Mesh, centre: Vec3, radius: f32, nu: u32, rings: u32) {
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
fn soup(count: u32, seed: u64) -> Mesh {
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
    Mesh {
        name: "soup",
        positions,
        indices,
    }
}

/// The step of the SplitMix64 generator: a well-mixed 64-bit hash of its input.
pub fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}
