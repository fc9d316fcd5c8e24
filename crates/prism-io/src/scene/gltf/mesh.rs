//! Mesh primitives: decoded once per glTF mesh into triangles in the mesh's own space, then
//! placed (copied and transformed) for every node that shows the mesh.
//!
//! Triangle lists, strips and fans become triangles; points and lines have no area for a
//! ray to hit and are skipped.

use super::accessor::Accessors;
use super::transform::Placement;
use crate::scene::faces::any_with_area;
use gltf::json::mesh::{Mode, Semantic};
use gltf::json::validation::Checked;
use gltf::json::Root;
use prism::geometry::TriangleMesh;
use prism::math::{Vec2, Vec3, Vec4};

/// One primitive of a mesh, in the mesh's coordinates.
pub(super) struct Primitive {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    /// Per-vertex tangents (xyz, handedness w): the file's TANGENT, or MikkTSpace's.
    tangents: Option<Vec<Vec4>>,
    triangles: Vec<[u32; 3]>,
    /// The glTF material index (`None`: the glTF default material).
    pub material: Option<usize>,
}

/// Decodes the triangle primitives of mesh `index`. `uv_set` says which TEXCOORD_n set a
/// material's base colour texture reads. A primitive whose triangles all have zero area is
/// left out with a warning. A primitive whose material has a normal texture, with normals
/// and uvs but no TANGENT, gets MikkTSpace tangents (`tangents`).
pub(super) fn decode(
    root: &Root,
    accessors: &Accessors,
    index: usize,
    uv_set: impl Fn(Option<usize>) -> u32,
    warnings: &mut Vec<String>,
) -> Result<Vec<Primitive>, String> {
    let mesh = root.meshes.get(index).ok_or_else(|| {
        format!(
            "mesh {index} does not exist (the file has {} meshes)",
            root.meshes.len()
        )
    })?;
    let name = mesh
        .name
        .as_deref()
        .map_or(String::new(), |n| format!(" ('{n}')"));
    let mut out = Vec::new();
    for (p, prim) in mesh.primitives.iter().enumerate() {
        let material = prim.material.map(|m| m.value());
        let decoded = primitive(accessors, prim, uv_set(material))
            .map_err(|e| format!("mesh {index}{name}, primitive {p}: {e}"))?;
        if let Some((mut positions, mut normals, mut uvs, mut tangents, mut triangles)) = decoded {
            if !triangles.is_empty() && !any_with_area(&positions, &triangles) {
                warnings.push(format!(
                    "mesh {index}{name}, primitive {p} has only faces of zero area ({}); it \
                     is left out",
                    triangles.len()
                ));
                continue;
            }
            let normal_mapped = material
                .and_then(|m| root.materials.get(m))
                .is_some_and(|m| m.normal_texture.is_some());
            if let (true, None, Some(ns), Some(ts)) =
                (normal_mapped, &tangents, &mut normals, &mut uvs)
            {
                tangents = super::tangents::generate(&mut positions, ns, ts, &mut triangles);
            }
            out.push(Primitive {
                positions,
                normals,
                uvs,
                tangents,
                triangles,
                material,
            });
        }
    }
    Ok(out)
}

type Decoded = (
    Vec<Vec3>,
    Option<Vec<Vec3>>,
    Option<Vec<Vec2>>,
    Option<Vec<Vec4>>,
    Vec<[u32; 3]>,
);

/// `None` for primitives without triangles (points, lines).
fn primitive(
    accessors: &Accessors,
    prim: &gltf::json::mesh::Primitive,
    uv_set: u32,
) -> Result<Option<Decoded>, String> {
    let mode = match prim.mode {
        Checked::Valid(m) => m,
        Checked::Invalid => return Err("invalid mode".into()),
    };
    if matches!(
        mode,
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip
    ) {
        return Ok(None);
    }
    let attribute = |s: Semantic| prim.attributes.get(&Checked::Valid(s)).map(|a| a.value());
    let position_accessor = attribute(Semantic::Positions)
        .ok_or("no POSITION attribute: expected the vertex positions (compressed meshes are not supported)")?;
    let positions: Vec<Vec3> = accessors
        .floats::<3>(position_accessor)
        .map_err(|e| format!("POSITION: {e}"))?
        .into_iter()
        .map(Vec3::from)
        .collect();
    let count = positions.len();
    let normals = per_vertex::<3>(accessors, attribute(Semantic::Normals), "NORMAL", count)?
        .map(|n| n.into_iter().map(Vec3::from).collect::<Vec<_>>());
    let tangents = per_vertex::<4>(accessors, attribute(Semantic::Tangents), "TANGENT", count)?
        .map(|t| t.into_iter().map(Vec4::from).collect::<Vec<_>>());
    let uv_name = format!("TEXCOORD_{uv_set}");
    let uv_accessor = attribute(Semantic::TexCoords(uv_set));
    // glTF's v runs down the image, prism's up.
    let uvs = per_vertex::<2>(accessors, uv_accessor, &uv_name, count)?
        .map(|uv| uv.into_iter().map(|[u, v]| Vec2::new(u, 1.0 - v)).collect());
    let order: Vec<u32> = match prim.indices {
        Some(a) => accessors
            .indices(a.value())
            .map_err(|e| format!("indices: {e}"))?,
        None => (0..count as u32).collect(),
    };
    if let Some((k, &v)) = order.iter().enumerate().find(|(_, &v)| v as usize >= count) {
        return Err(format!(
            "index {k} is {v}, but POSITION has {count} vertices: expected indices from 0 to {}",
            count as i64 - 1
        ));
    }
    let triangles = assemble(mode, &order)?;
    Ok(Some((positions, normals, uvs, tangents, triangles)))
}

/// An optional attribute of N floats a vertex; an error unless it has one per vertex.
fn per_vertex<const N: usize>(
    accessors: &Accessors,
    accessor: Option<usize>,
    name: &str,
    count: usize,
) -> Result<Option<Vec<[f32; N]>>, String> {
    let Some(a) = accessor else {
        return Ok(None);
    };
    let values = accessors
        .floats::<N>(a)
        .map_err(|e| format!("{name}: {e}"))?;
    if values.len() != count {
        return Err(format!(
            "{name} has {} elements but POSITION has {count}: expected one per vertex",
            values.len()
        ));
    }
    Ok(Some(values))
}

/// Triangles of a list, strip or fan (glTF 2.0 §3.7.2.1), without degenerate ones.
fn assemble(mode: Mode, v: &[u32]) -> Result<Vec<[u32; 3]>, String> {
    let n = v.len();
    let triangles: Vec<[u32; 3]> = match mode {
        Mode::Triangles => {
            if !n.is_multiple_of(3) {
                return Err(format!(
                    "{n} vertex indices in TRIANGLES mode: expected a multiple of 3"
                ));
            }
            v.chunks_exact(3).map(|t| [t[0], t[1], t[2]]).collect()
        }
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .map(|i| {
                let odd = i % 2;
                [v[i], v[i + 1 + odd], v[i + 2 - odd]]
            })
            .collect(),
        Mode::TriangleFan => (0..n.saturating_sub(2))
            .map(|i| [v[i + 1], v[i + 2], v[0]])
            .collect(),
        _ => Vec::new(),
    };
    Ok(triangles
        .into_iter()
        .filter(|[a, b, c]| a != b && b != c && a != c)
        .collect())
}

impl Primitive {
    pub(super) fn is_empty(&self) -> bool {
        self.triangles.is_empty()
    }

    pub(super) fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// A world-space copy. Normals go through the inverse transpose, tangents through the
    /// linear part; a mirroring transform reverses the winding so the outside stays outside
    /// and turns the tangents' handedness around; a flattening one (a zero scale) keeps the
    /// flat triangles but drops the vertex normals and tangents, which it leaves undefined.
    pub(super) fn place(&self, at: &Placement) -> Result<TriangleMesh, String> {
        let positions = self.positions.iter().map(|&p| at.point(p)).collect();
        let normals = match &self.normals {
            Some(ns) if !at.flattens() => Some(
                ns.iter()
                    .map(|&n| at.normal(n).unwrap_or(Vec3::ZERO))
                    .collect(),
            ),
            _ => None,
        };
        let triangles = if at.mirrors() {
            self.triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
        } else {
            self.triangles.clone()
        };
        let handedness = if at.mirrors() { -1.0 } else { 1.0 };
        let tangents = match &self.tangents {
            Some(ts) if !at.flattens() => Some(
                ts.iter()
                    .map(|t| {
                        let xyz = at.direction(t.truncate()).unwrap_or(Vec3::ZERO);
                        xyz.extend(t.w * handedness)
                    })
                    .collect(),
            ),
            _ => None,
        };
        let mesh = TriangleMesh::new(positions, triangles, normals, self.uvs.clone());
        match tangents {
            Some(ts) => mesh.and_then(|m| m.with_tangents(ts)),
            None => mesh,
        }
        .map_err(|e| format!("{e} after the node transform"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_follow_the_specification() {
        assert_eq!(
            assemble(Mode::TriangleStrip, &[0, 1, 2, 3, 4]).unwrap(),
            vec![[0, 1, 2], [1, 3, 2], [2, 3, 4]]
        );
        assert_eq!(
            assemble(Mode::TriangleFan, &[0, 1, 2, 3]).unwrap(),
            vec![[1, 2, 0], [2, 3, 0]]
        );
        // A strip's restart trick repeats vertices; those triangles have no area.
        assert_eq!(
            assemble(Mode::TriangleStrip, &[0, 1, 2, 2, 3]).unwrap(),
            vec![[0, 1, 2]]
        );
        assert!(assemble(Mode::Triangles, &[0, 1, 2, 3]).is_err());
    }
}
