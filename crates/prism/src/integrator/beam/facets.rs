//! The scene as beam tracing needs it: planar facets. Mesh triangles (NFF polygons arrive
//! as triangles), the six faces of boxes and infinite planes are planar; spheres, cones and
//! cylinders are not, and a scene holding them is refused with a message naming them,
//! since a beam reflected by a curved mirror is no longer a beam with one apex.

use crate::geometry::{Shape, ShapeHit};
use crate::math::{Ray, Vec2, Vec3};
use crate::scene::Scene;
use glam::DVec3;

/// What a facet is in the scene, to rebuild the hit the shape's own `surface` expects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum FacetKind {
    /// A mesh triangle (`ShapeHit` u, v = barycentrics of its second and third vertex).
    Triangle,
    /// An infinite plane.
    Plane,
    /// Face `face` of a box (`ShapeHit::u` = axis + 3 for the max side).
    BoxFace(u8),
}

/// One planar polygon of the scene (or an infinite plane), in f64.
#[derive(Clone, Debug)]
pub(crate) struct Facet {
    /// Vertices in order (empty for an infinite plane).
    pub(crate) points: Vec<DVec3>,
    /// Unit normal (the shape's own geometric normal, before facing the viewer).
    pub(crate) normal: DVec3,
    /// A point of the plane (the first vertex, or the plane's point).
    pub(crate) origin: DVec3,
    /// Its primitive in `Geometry::primitives`.
    pub(crate) prim: u32,
    /// Its material.
    pub(crate) material: u32,
    /// What shape it comes from.
    pub(crate) kind: FacetKind,
    /// Texture coordinates as an affine map of the point on the plane.
    pub(crate) uv: UvMap,
    /// Axis-aligned bounds (None for an infinite plane).
    pub(crate) bounds: Option<(DVec3, DVec3)>,
}

/// uv(X) = uv0 + (gu·(X − origin), gv·(X − origin)) for X on the facet's plane: a surface's
/// uv is affine over a planar facet for every planar shape prism has.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct UvMap {
    /// uv at the facet's origin.
    pub(crate) uv0: glam::DVec2,
    /// Gradient of u (in the plane).
    pub(crate) gu: DVec3,
    /// Gradient of v (in the plane).
    pub(crate) gv: DVec3,
}

impl UvMap {
    /// The affine map through three points and their uvs (None if they are collinear).
    fn through(p: [DVec3; 3], uv: [Vec2; 3]) -> Option<UvMap> {
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let det = g11 * g22 - g12 * g12;
        if det <= 0.0 || !det.is_finite() {
            return None;
        }
        // X − p0 = α·e1 + β·e2 with α = a·(X − p0), β = b·(X − p0).
        let a = (g22 * e1 - g12 * e2) / det;
        let b = (g11 * e2 - g12 * e1) / det;
        let uv: [glam::DVec2; 3] = uv.map(|t| glam::DVec2::new(t.x as f64, t.y as f64));
        let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
        Some(UvMap {
            uv0: uv[0],
            gu: a * d1.x + b * d2.x,
            gv: a * d1.y + b * d2.y,
        })
    }
}

/// Why a scene cannot be beam traced.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum FacetError {
    /// Curved shapes are not planar polygons.
    #[error(
        "beam tracing takes planar polygons only (triangle meshes, NFF polygons, boxes, \
         planes); this scene has {0}: render it with --integrator whitted"
    )]
    Curved(String),
}

fn d(v: Vec3) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

/// The scene's facets, in primitive order; degenerate triangles (no area) are left out,
/// as no ray can hit them either.
pub(crate) fn facets(scene: &Scene) -> Result<Vec<Facet>, FacetError> {
    let geometry = &scene.geometry;
    let mut curved = [0usize; 2];
    let mut out = Vec::with_capacity(geometry.primitives.len());
    for (prim, primitive) in geometry.primitives.iter().enumerate() {
        let prim = prim as u32;
        let material = primitive.material;
        match &primitive.shape {
            Shape::Sphere(_) => curved[0] += 1,
            Shape::Cone(_) => curved[1] += 1,
            Shape::Triangle { mesh, index } => {
                let m = &geometry.meshes[*mesh as usize];
                let v = m.vertices(*index);
                let p = v.map(d);
                let Some(normal) = (p[1] - p[0]).cross(p[2] - p[0]).try_normalize() else {
                    continue;
                };
                // The mesh's own uv at the three corners (barycentric hits at the vertices).
                let corner = |b1: f32, b2: f32| {
                    m.surface(
                        *index,
                        &ShapeHit {
                            t: 0.0,
                            u: b1,
                            v: b2,
                        },
                    )
                    .uv
                };
                let uv = [corner(0.0, 0.0), corner(1.0, 0.0), corner(0.0, 1.0)];
                let Some(uv) = UvMap::through(p, uv) else {
                    continue;
                };
                out.push(Facet {
                    bounds: Some((p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))),
                    points: p.to_vec(),
                    normal,
                    origin: p[0],
                    prim,
                    material,
                    kind: FacetKind::Triangle,
                    uv,
                });
            }
            Shape::Plane(plane) => {
                let n = plane.normal();
                let o = plane.point;
                // Two directions in the plane; uv from the plane's own frame.
                let t1 = n.any_orthonormal_vector();
                let t2 = n.cross(t1);
                let pts = [o, o + t1, o + t2];
                let uv = pts.map(|p| {
                    plane
                        .surface(
                            &Ray::new(p, -n),
                            &ShapeHit {
                                t: 0.0,
                                u: 0.0,
                                v: 0.0,
                            },
                        )
                        .uv
                });
                let Some(uvmap) = UvMap::through(pts.map(d), uv) else {
                    continue;
                };
                out.push(Facet {
                    points: Vec::new(),
                    normal: d(n).normalize(),
                    origin: d(o),
                    prim,
                    material,
                    kind: FacetKind::Plane,
                    uv: uvmap,
                    bounds: None,
                });
            }
            Shape::Box(b) => {
                let (lo, hi) = (d(b.min), d(b.max));
                for axis in 0..3 {
                    for max_side in [false, true] {
                        let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
                        let at = |s1: bool, s2: bool| {
                            let mut p = if max_side { hi } else { lo };
                            p[a1] = if s1 { hi[a1] } else { lo[a1] };
                            p[a2] = if s2 { hi[a2] } else { lo[a2] };
                            p
                        };
                        let points = vec![
                            at(false, false),
                            at(true, false),
                            at(true, true),
                            at(false, true),
                        ];
                        let mut normal = DVec3::ZERO;
                        normal[axis] = if max_side { 1.0 } else { -1.0 };
                        let face = axis as u8 + 3 * max_side as u8;
                        // The box's own uv at three corners (hits at t = 0 from the corner).
                        let uv3 = [points[0], points[1], points[3]].map(|p| {
                            let pf = Vec3::new(p.x as f32, p.y as f32, p.z as f32);
                            b.surface(
                                &Ray::new(pf, -normal.as_vec3()),
                                &ShapeHit {
                                    t: 0.0,
                                    u: face as f32,
                                    v: 0.0,
                                },
                            )
                            .uv
                        });
                        let Some(uv) = UvMap::through([points[0], points[1], points[3]], uv3)
                        else {
                            continue;
                        };
                        out.push(Facet {
                            bounds: Some((
                                points.iter().fold(points[0], |m, p| m.min(*p)),
                                points.iter().fold(points[0], |m, p| m.max(*p)),
                            )),
                            origin: points[0],
                            points,
                            normal,
                            prim,
                            material,
                            kind: FacetKind::BoxFace(face),
                            uv,
                        });
                    }
                }
            }
        }
    }
    let names: Vec<String> = [
        (curved[0], "sphere", "spheres"),
        (curved[1], "cone or cylinder", "cones or cylinders"),
    ]
    .iter()
    .filter(|(n, _, _)| *n > 0)
    .map(|&(n, one, many)| format!("{n} {}", if n == 1 { one } else { many }))
    .collect();
    if !names.is_empty() {
        return Err(FacetError::Curved(names.join(" and ")));
    }
    Ok(out)
}

impl Facet {
    /// The hit that the shape's `surface` turns into this facet's surface point at `p` (on
    /// the facet), for a ray from `origin` along unit `dir`.
    pub(crate) fn shape_hit(&self, p: DVec3, origin: DVec3, dir: DVec3) -> ShapeHit {
        let t = (p - origin).dot(dir) as f32;
        match self.kind {
            FacetKind::Triangle => {
                let [a, b, c] = [self.points[0], self.points[1], self.points[2]];
                let n = (b - a).cross(c - a);
                let nn = n.length_squared();
                let b1 = (p - a).cross(c - a).dot(n) / nn;
                let b2 = (b - a).cross(p - a).dot(n) / nn;
                ShapeHit {
                    t,
                    u: b1.clamp(0.0, 1.0) as f32,
                    v: b2.clamp(0.0, 1.0 - b1.clamp(0.0, 1.0)) as f32,
                }
            }
            FacetKind::Plane => ShapeHit { t, u: 0.0, v: 0.0 },
            FacetKind::BoxFace(face) => ShapeHit {
                t,
                u: face as f32,
                v: 0.0,
            },
        }
    }
}
