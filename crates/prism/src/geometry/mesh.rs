//! Indexed triangle meshes with optional per-vertex normals (smooth shading), uvs and
//! tangents (the frame of normal maps).

use super::{ShapeHit, SurfacePoint};
use crate::math::robust::gamma;
use crate::math::{Vec2, Vec3, Vec4};

/// Triangles over shared vertices: positions, index triples and optional normals and uvs, checked
/// once by `new` so that lookups during rendering need no checks.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct TriangleMesh {
    positions: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    /// Per-vertex tangents for normal maps, as glTF's TANGENT: xyz a unit direction in the
    /// surface, w (±1) the handedness, the bitangent being w · (n × t).
    tangents: Option<Vec<Vec4>>,
    /// Each triangle's geometric normal (`face_normal`), kept so that `surface` need not
    /// normalise it at every hit; made again whenever positions or winding change.
    face_normals: Vec<Vec3>,
}

/// Why `TriangleMesh::new` refused its input.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    /// An index triple names a vertex that does not exist.
    #[error("triangle {triangle} refers to vertex {index}, but the mesh has {count} vertices")]
    IndexOutOfRange {
        /// The offending triangle.
        triangle: usize,
        /// The vertex index it names.
        index: u32,
        /// How many vertices the mesh has.
        count: usize,
    },
    /// Normals, uvs or tangents are given, but not one per position.
    #[error("the mesh has {positions} positions but {count} {what}")]
    AttributeCount {
        /// Which attribute ("normals", "uvs" or "tangents").
        what: &'static str,
        /// How many positions the mesh has.
        positions: usize,
        /// How many values of the attribute were given.
        count: usize,
    },
    /// A position is NaN or infinite, which no bounding box can hold.
    #[error("vertex {index} has a non-finite coordinate")]
    NonFinite {
        /// The vertex.
        index: usize,
    },
}

impl TriangleMesh {
    /// Checks indices and attribute counts so that later lookups cannot go out of range.
    pub fn new(
        positions: Vec<Vec3>,
        indices: Vec<[u32; 3]>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
    ) -> Result<Self, MeshError> {
        if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFinite { index });
        }
        let count = positions.len();
        for (triangle, tri) in indices.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= count) {
                return Err(MeshError::IndexOutOfRange {
                    triangle,
                    index,
                    count,
                });
            }
        }
        // Each attribute given has one value per position.
        for (what, given) in [
            ("normals", normals.as_ref().map(Vec::len)),
            ("uvs", uvs.as_ref().map(Vec::len)),
        ] {
            if let Some(given) = given.filter(|&n| n != count) {
                return Err(MeshError::AttributeCount {
                    what,
                    positions: count,
                    count: given,
                });
            }
        }
        // Zero-length normals would shade as NaN; normalise and fall back to flat shading.
        let normals = normals.map(|n| {
            n.into_iter()
                .map(|v| v.try_normalize().unwrap_or(Vec3::ZERO))
                .collect()
        });
        let mut mesh = TriangleMesh {
            positions,
            indices,
            normals,
            uvs,
            tangents: None,
            face_normals: Vec::new(),
        };
        mesh.make_face_normals();
        Ok(mesh)
    }

    /// The mesh with per-vertex tangents for normal maps: xyz a direction in the surface, w
    /// its handedness (the bitangent is w · (n × t), as glTF's TANGENT). One per vertex;
    /// xyz is normalised (zero where it cannot be, which leaves those triangles the uv
    /// frame) and w taken by its sign.
    pub fn with_tangents(mut self, tangents: Vec<Vec4>) -> Result<Self, MeshError> {
        if tangents.len() != self.positions.len() {
            return Err(MeshError::AttributeCount {
                what: "tangents",
                positions: self.positions.len(),
                count: tangents.len(),
            });
        }
        self.tangents = Some(
            tangents
                .into_iter()
                .map(|t| {
                    let xyz = t.truncate().try_normalize().unwrap_or(Vec3::ZERO);
                    xyz.extend(if t.w < 0.0 { -1.0 } else { 1.0 })
                })
                .collect(),
        );
        Ok(self)
    }

    /// The per-vertex tangents, where the mesh has them.
    pub fn tangents(&self) -> Option<&[Vec4]> {
        self.tangents.as_deref()
    }

    /// `face_normals` for the current positions and winding.
    fn make_face_normals(&mut self) {
        self.face_normals = (0..self.indices.len() as u32)
            .map(|tri| {
                let [p0, p1, p2] = self.vertices(tri);
                face_normal(p0, p1, p2)
            })
            .collect();
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Vertex positions, in the order the indices refer to.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// One `[a, b, c]` triple of vertex indices per triangle, counter-clockwise seen from the
    /// front.
    pub fn indices(&self) -> &[[u32; 3]] {
        &self.indices
    }

    /// Whether the mesh carries vertex normals (smooth shading).
    pub fn has_normals(&self) -> bool {
        self.normals.is_some()
    }

    /// The three corner positions of triangle `tri`.
    #[inline(always)]
    pub fn vertices(&self, tri: u32) -> [Vec3; 3] {
        let [a, b, c] = self.indices[tri as usize];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// The directions in which the surface point of triangle `tri` moves as u and as v
    /// grow (∂p/∂u, ∂p/∂v, constant over the triangle), for a tangent frame; None without
    /// uvs or where the triangle's uvs are degenerate.
    pub fn uv_derivatives(&self, tri: u32) -> Option<(Vec3, Vec3)> {
        let uvs = self.uvs.as_ref()?;
        let [a, b, c] = self.indices[tri as usize];
        let [pa, pb, pc] = self.vertices(tri);
        let (ta, tb, tc) = (uvs[a as usize], uvs[b as usize], uvs[c as usize]);
        let (e1, e2) = (pb - pa, pc - pa);
        let (d1, d2) = (tb - ta, tc - ta);
        let det = d1.x * d2.y - d1.y * d2.x;
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = 1.0 / det;
        let dpdu = (e1 * d2.y - e2 * d1.y) * inv;
        let dpdv = (e2 * d1.x - e1 * d2.x) * inv;
        (dpdu.is_finite() && dpdv.is_finite()).then_some((dpdu, dpdv))
    }

    /// Applies `f` to every position and `g` to every normal (an affine transform and its
    /// inverse transpose). Tangents, directions in the surface, go through `f`'s linear
    /// part, and a mirroring `f` turns their handedness around.
    pub fn transform(&mut self, f: impl Fn(Vec3) -> Vec3, g: impl Fn(Vec3) -> Vec3) {
        if let Some(ts) = &mut self.tangents {
            let origin = f(Vec3::ZERO);
            let linear = |d: Vec3| f(d) - origin;
            let det = linear(Vec3::X).dot(linear(Vec3::Y).cross(linear(Vec3::Z)));
            let flip = if det < 0.0 { -1.0 } else { 1.0 };
            for t in ts {
                let xyz = linear(t.truncate()).try_normalize().unwrap_or(Vec3::ZERO);
                *t = xyz.extend(t.w * flip);
            }
        }
        for p in &mut self.positions {
            *p = f(*p);
        }
        if let Some(ns) = &mut self.normals {
            for n in ns {
                *n = g(*n).try_normalize().unwrap_or(Vec3::ZERO);
            }
        }
        self.make_face_normals();
    }

    /// Turns every triangle's winding around (its front becomes its back), as a mirroring
    /// transform must to keep the outside outside.
    pub fn reverse_winding(&mut self) {
        for t in &mut self.indices {
            t.swap(1, 2);
        }
        self.make_face_normals();
    }

    /// The tangent frame of a normal map at point `p` of triangle `tri` whose shading
    /// normal is `ns`: x the tangent interpolated at `p` made orthogonal to `ns` and
    /// normalised, y = w · (ns × x). None without tangents or where x degenerates.
    pub fn tangent_frame(&self, tri: u32, p: Vec3, ns: Vec3) -> Option<(Vec3, Vec3)> {
        let tangents = self.tangents.as_ref()?;
        let idx = self.indices[tri as usize].map(|i| i as usize);
        let [p0, p1, p2] = idx.map(|i| self.positions[i]);
        // Barycentrics of p, which lies on the triangle (or within rounding of it).
        let (e1, e2, d) = (p1 - p0, p2 - p0, p - p0);
        let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (dp1, dp2) = (d.dot(e1), d.dot(e2));
        let det = d11 * d22 - d12 * d12;
        let (b1, b2) = if det > 0.0 && det.is_finite() {
            ((d22 * dp1 - d12 * dp2) / det, (d11 * dp2 - d12 * dp1) / det)
        } else {
            (1.0 / 3.0, 1.0 / 3.0)
        };
        let b0 = 1.0 - b1 - b2;
        let t = b0 * tangents[idx[0]] + b1 * tangents[idx[1]] + b2 * tangents[idx[2]];
        let x = (t.truncate() - ns * ns.dot(t.truncate())).try_normalize()?;
        let w = if t.w < 0.0 { -1.0 } else { 1.0 };
        Some((x, w * ns.cross(x)))
    }

    /// `surface`'s point, error bound and geometric normal at barycentric `(b1, b2)` of
    /// triangle `tri`, without the shading normal and uv where it needs neither: the
    /// same bits as `surface` gives (the light samples' points, `integrator/emitters.rs`).
    #[inline]
    pub fn surface_point(&self, tri: u32, b1: f32, b2: f32) -> (Vec3, Vec3, Vec3) {
        if self.normals.is_some() {
            // The vertex normals decide the side of ng: `surface`'s own rule.
            let sp = self.surface(
                tri,
                &ShapeHit {
                    t: 0.0,
                    u: b1,
                    v: b2,
                },
            );
            return (sp.p, sp.p_error, sp.ng);
        }
        let idx = self.indices[tri as usize].map(|i| i as usize);
        let (p, p_error) = Self::flat_point(idx.map(|i| self.positions[i]), b1, b2);
        (p, p_error, self.face_normals[tri as usize])
    }

    /// Triangle `tri`'s corners and face normal where the mesh has no vertex normals
    /// (`None` where they decide the side): what `surface_point` reads, for a caller that
    /// keeps them (`integrator/emitters.rs`) and draws its points with `flat_point`.
    pub fn flat_triangle(&self, tri: u32) -> Option<([Vec3; 3], Vec3)> {
        self.normals
            .is_none()
            .then(|| (self.vertices(tri), self.face_normals[tri as usize]))
    }

    /// `surface_point`'s point and error bound in the triangle of `corners`, where the
    /// mesh has no vertex normals.
    #[inline(always)]
    pub fn flat_point(corners: [Vec3; 3], b1: f32, b2: f32) -> (Vec3, Vec3) {
        barycentric_point(corners, 1.0 - b1 - b2, b1, b2)
    }

    /// The point, normals (interpolated where the mesh has them) and uv of a hit on triangle `tri`.
    pub fn surface(&self, tri: u32, hit: &ShapeHit) -> SurfacePoint {
        let idx = self.indices[tri as usize].map(|i| i as usize);
        let (b1, b2) = (hit.u, hit.v);
        let b0 = 1.0 - b1 - b2;
        let (p, p_error) = barycentric_point(idx.map(|i| self.positions[i]), b0, b1, b2);
        let mut ng = self.face_normals[tri as usize];
        let mut ns = ng;
        if let Some(normals) = &self.normals {
            let n = b0 * normals[idx[0]] + b1 * normals[idx[1]] + b2 * normals[idx[2]];
            if let Some(n) = n.try_normalize() {
                ns = n;
                // Vertex normals express the intended outside; keep ng on their side.
                if ng.dot(ns) < 0.0 {
                    ng = -ng;
                }
            }
        }
        let uv = match &self.uvs {
            Some(uvs) => b0 * uvs[idx[0]] + b1 * uvs[idx[1]] + b2 * uvs[idx[2]],
            None => Vec2::new(b1, b2),
        };
        SurfacePoint {
            p,
            p_error,
            ng,
            ns,
            uv,
        }
    }
}

/// The point of barycentric weights `b0`, `b1`, `b2` in the triangle of `corners`, and
/// its per-axis error bound.
#[inline(always)]
fn barycentric_point(corners: [Vec3; 3], b0: f32, b1: f32, b2: f32) -> (Vec3, Vec3) {
    let [p0, p1, p2] = corners;
    // Barycentric interpolation rather than o + t·d: its error is bounded by the vertex
    // magnitudes (pbrt's γ₇ bound), independent of how far the ray travelled.
    // Rounding can carry p past the triangle's bounds, e.g. one ulp beyond a wall that
    // shares the edge, which a shadow ray then crosses at t ≈ 0 (acne along the edges of
    // an axis-aligned room). The true point lies within the bounds, so clamping only
    // shrinks the error.
    let p = (b0 * p0 + b1 * p1 + b2 * p2).clamp(p0.min(p1).min(p2), p0.max(p1).max(p2));
    let p_error = gamma(7) * ((b0 * p0).abs() + (b1 * p1).abs() + (b2 * p2).abs());
    (p, p_error)
}

/// The unit geometric normal of the triangle `p0`, `p1`, `p2`, facing the side from which
/// its corners run counter-clockwise; +z for a degenerate triangle.
#[inline]
fn face_normal(p0: Vec3, p1: Vec3, p2: Vec3) -> Vec3 {
    (p1 - p0).cross(p2 - p0).try_normalize().unwrap_or(Vec3::Z)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The geometric normal `surface` reports, against the one its corners give now.
    fn assert_face_normal_current(mesh: &TriangleMesh) {
        let hit = ShapeHit {
            t: 1.0,
            u: 0.25,
            v: 0.25,
        };
        let [p0, p1, p2] = mesh.vertices(0);
        let want = (p1 - p0).cross(p2 - p0).try_normalize().unwrap_or(Vec3::Z);
        assert_eq!(mesh.surface(0, &hit).ng.to_array(), want.to_array());
    }

    /// `surface_point` is `surface`'s point, error bound and geometric normal, bit for
    /// bit, with vertex normals (one of which turns ng around) and without.
    #[test]
    fn surface_point_is_surfaces_point() {
        let positions = vec![
            Vec3::new(-1.5, 2.0, 0.25),
            Vec3::new(3.0, -0.5, 1.0),
            Vec3::new(0.5, 4.0, -2.0),
        ];
        let flipped = -face_normal(positions[0], positions[1], positions[2]);
        let normals = vec![flipped, flipped + Vec3::X * 0.3, flipped - Vec3::Y * 0.2];
        let meshes = [
            TriangleMesh::new(positions.clone(), vec![[0, 1, 2]], None, None).unwrap(),
            TriangleMesh::new(positions, vec![[0, 1, 2]], Some(normals), None).unwrap(),
        ];
        for mesh in &meshes {
            for i in 0..=16 {
                for j in 0..=16 - i {
                    let (b1, b2) = (i as f32 / 16.0, j as f32 / 16.0 + 1e-3 * i as f32);
                    let sp = mesh.surface(
                        0,
                        &ShapeHit {
                            t: 0.0,
                            u: b1,
                            v: b2,
                        },
                    );
                    let (p, p_error, ng) = mesh.surface_point(0, b1, b2);
                    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                    assert_eq!(bits(p), bits(sp.p));
                    assert_eq!(bits(p_error), bits(sp.p_error));
                    assert_eq!(bits(ng), bits(sp.ng));
                }
            }
        }
        // The vertex normals did turn ng around: the second mesh tests that rule.
        let hit = ShapeHit {
            t: 0.0,
            u: 0.25,
            v: 0.25,
        };
        assert!(
            meshes[1]
                .surface(0, &hit)
                .ng
                .dot(meshes[0].surface(0, &hit).ng)
                < 0.0
        );
    }

    /// The kept face normals follow the positions and the winding.
    #[test]
    fn face_normals_follow_transforms_and_winding() {
        let mut mesh = TriangleMesh::new(
            vec![
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 3.0, 0.5),
            ],
            vec![[0, 1, 2]],
            None,
            None,
        )
        .unwrap();
        assert_face_normal_current(&mesh);
        mesh.transform(|p| Vec3::new(p.z, 2.0 * p.x, -p.y), |n| n);
        assert_face_normal_current(&mesh);
        mesh.reverse_winding();
        assert_face_normal_current(&mesh);
        let degenerate = TriangleMesh::new(vec![Vec3::ONE; 3], vec![[0, 1, 2]], None, None);
        assert_face_normal_current(&degenerate.unwrap());
    }

    /// Tangents are one per vertex, normalised, their handedness a sign; a transform turns
    /// them by its linear part (not the inverse transpose) and a mirror turns w around.
    #[test]
    fn tangents_are_checked_and_follow_transforms() {
        let quad = || {
            TriangleMesh::new(
                vec![Vec3::ZERO, Vec3::X, Vec3::Y],
                vec![[0, 1, 2]],
                None,
                None,
            )
            .unwrap()
        };
        assert_eq!(
            quad().with_tangents(vec![Vec4::X; 2]),
            Err(MeshError::AttributeCount {
                what: "tangents",
                positions: 3,
                count: 2,
            })
        );
        let mut mesh = quad()
            .with_tangents(vec![Vec4::new(2.0, 2.0, 0.0, -0.5); 3])
            .unwrap();
        let h = std::f32::consts::FRAC_1_SQRT_2;
        assert_eq!(mesh.tangents().unwrap()[0], Vec4::new(h, h, 0.0, -1.0));
        // Shearing x by y: a direction (1, 1) becomes (2, 1); a normal would not.
        mesh.transform(|p| Vec3::new(p.x + p.y, p.y, p.z) + Vec3::Z, |n| n);
        let t = mesh.tangents().unwrap()[1];
        assert!((t.truncate() - Vec3::new(2.0, 1.0, 0.0).normalize()).length() < 1e-6);
        assert_eq!(t.w, -1.0);
        mesh.transform(|p| Vec3::new(-p.x, p.y, p.z), |n| n);
        assert_eq!(mesh.tangents().unwrap()[2].w, 1.0);
        let (x, y) = mesh.tangent_frame(0, Vec3::ZERO, Vec3::Z).unwrap();
        assert!((x - Vec3::new(-2.0, 1.0, 0.0).normalize()).length() < 1e-6);
        assert!((y - Vec3::Z.cross(x)).length() < 1e-6);
    }
}
