//! The four meshes of the comparison: the Stanford bunny read from disk and three made
//! by the lab (`prism_lab::meshes`), deterministically, each normalised (centred on the origin, largest extent 100).
//! Beside them `cornell`: the triangles of prism's built-in `cornell-light` as they are (in
//! millimetres), seen by its own camera and lit at its ceiling light (`workload::View`), for
//! the rays of a path tracer in a small closed room (docs/path-tracing.md).

use prism::math::Vec3;
use prism_io::scene::mesh_file::Materials;
use prism_lab::meshes::{self, Triangles};
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
    let made = |name, t: Triangles| Mesh {
        name,
        positions: t.positions,
        indices: t.indices,
    };
    let mut mesh = match name {
        "bunny" => bunny(meshes_dir)?,
        "blob" => made("blob", meshes::blob(92)),
        "sphereflake" => made("sphereflake", meshes::sphereflake(4, 12, 7)),
        "soup" => made("soup", meshes::soup(1_000_000, 0x5eed)),
        CORNELL => return Ok(cornell()),
        _ => {
            return Err(MeshError::Failed(format!(
                "unknown mesh '{name}', expected one of {NAMES:?} or {CORNELL}"
            )))
        }
    };
    meshes::normalise(&mut mesh.positions);
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

/// The step of the SplitMix64 generator, as the lab's meshes use it.
pub use prism_lab::meshes::splitmix64;
