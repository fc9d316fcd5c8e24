//! Shapes: the things rays hit. Each shape answers three questions: where does a ray hit it
//! (`intersect`, the hot path, returning only a distance and two parameters), what does the
//! surface look like there (`surface`, called once for the nearest hit), and what box bounds
//! it (`bounds`, for the accelerators; `None` for unbounded shapes such as planes).

mod aabox;
mod cone;
pub mod generate;
mod mesh;
mod plane;
pub mod polygon;
mod sphere;
mod triangle;
mod triangle_lanes;
mod triangle_pack;

pub use aabox::AaBox;
pub use cone::Cone;
pub(crate) use cone::ConeTerms;
pub use mesh::{MeshError, TriangleMesh};
pub use plane::Plane;
pub(crate) use sphere::sphere_lanes;
pub use sphere::Sphere;
pub use triangle::{intersect_triangle, TriangleHit};
pub(crate) use triangle_lanes::{LaneHits, Sheared};
pub use triangle_pack::{DecidedHit, PackRay, TrianglePack};

use crate::math::{Aabb, Ray, TraceRay, Vec2, Vec3};

/// What an intersection routine reports: the distance and two shape-specific parameters
/// (barycentrics for triangles, the hit face for boxes, the part hit for cones).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    /// Distance along the ray.
    pub t: f32,
    /// First shape-specific parameter (a barycentric weight, a face, a part).
    pub u: f32,
    /// Second shape-specific parameter.
    pub v: f32,
}

/// Whether a surface description includes the uv parameters. They cost an arc tangent
/// and an arc cosine on spheres and cones, and only textures read them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Uv {
    /// Compute them.
    Compute,
    /// Leave them zero.
    Skip,
}

/// Local surface description at a hit, computed once for the nearest hit only.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    /// The hit point, and a conservative bound on its per-axis floating-point error.
    pub p: Vec3,
    /// Per-axis bound on the error of `p`, from which the offset of secondary rays follows.
    pub p_error: Vec3,
    /// Geometric normal, unit length, facing the shape's outside (the side a ray enters
    /// from). For meshes the winding decides (counter-clockwise = front).
    pub ng: Vec3,
    /// Shading normal (interpolated vertex normals where present), in ng's hemisphere.
    pub ns: Vec3,
    /// Surface parameters, for textures (zero where `Uv::Skip` left them out).
    pub uv: Vec2,
}

impl SurfacePoint {
    /// A point of a shape without vertex normals: the shading normal is the geometric one.
    #[inline(always)]
    pub fn flat(p: Vec3, p_error: Vec3, n: Vec3, uv: Vec2) -> SurfacePoint {
        SurfacePoint {
            p,
            p_error,
            ng: n,
            ns: n,
            uv,
        }
    }

    /// Whether a ray along `dir` arrives from the side `ng` faces (enters the shape), and
    /// the geometric and shading normals turned towards that ray, as every integrator
    /// shades a hit.
    #[inline(always)]
    pub fn facing(&self, dir: Vec3) -> (bool, Vec3, Vec3) {
        let entering = dir.dot(self.ng) < 0.0;
        if entering {
            (true, self.ng, self.ns)
        } else {
            (false, -self.ng, -self.ns)
        }
    }
}

/// The shape kinds prism renders. Triangles live in meshes and are referenced by index so a
/// million-triangle mesh costs 12 bytes of vertex indices per triangle, not a copy. The
/// large, rare shapes are boxed so that a `Primitive` stays at 32 bytes.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A sphere.
    Sphere(Sphere),
    /// Triangle `index` of mesh `mesh` in `Geometry::meshes`.
    Triangle {
        /// Index into `Geometry::meshes`.
        mesh: u32,
        /// Triangle index within that mesh.
        index: u32,
    },
    /// An infinite plane (unbounded: kept beside the accelerator).
    Plane(Box<Plane>),
    /// A cone or cylinder.
    Cone(Box<Cone>),
    /// A solid axis-aligned box.
    Box(Box<AaBox>),
}

impl Shape {
    /// Nearest hit with `0 < t < t_max`.
    #[inline]
    pub fn intersect(
        &self,
        meshes: &[TriangleMesh],
        ray: &TraceRay,
        t_max: f32,
    ) -> Option<ShapeHit> {
        match self {
            Shape::Sphere(s) => s.intersect(&ray.ray, t_max),
            Shape::Triangle { mesh, index } => {
                let [a, b, c] = meshes[*mesh as usize].vertices(*index);
                intersect_triangle(ray, a, b, c, t_max).map(|h| ShapeHit {
                    t: h.t,
                    u: h.b1,
                    v: h.b2,
                })
            }
            Shape::Plane(p) => p.intersect(&ray.ray, t_max),
            Shape::Cone(c) => c.intersect(&ray.ray, t_max),
            Shape::Box(b) => b.intersect(ray, t_max),
        }
    }

    /// The surface description of a hit that `intersect` found on this shape.
    pub fn surface(
        &self,
        meshes: &[TriangleMesh],
        ray: &Ray,
        hit: &ShapeHit,
        uv: Uv,
    ) -> SurfacePoint {
        match self {
            Shape::Sphere(s) => s.surface_with(ray, hit, uv),
            Shape::Triangle { mesh, index } => meshes[*mesh as usize].surface(*index, hit),
            Shape::Plane(p) => p.surface(ray, hit),
            Shape::Cone(c) => c.surface_with(ray, hit, uv),
            Shape::Box(b) => b.surface(ray, hit),
        }
    }

    /// Whether `bounds` is `Some`, without computing the box.
    pub fn is_bounded(&self) -> bool {
        !matches!(self, Shape::Plane(_))
    }

    /// World-space bounds; `None` for unbounded shapes, which accelerators keep aside.
    pub fn bounds(&self, meshes: &[TriangleMesh]) -> Option<Aabb> {
        match self {
            Shape::Sphere(s) => Some(s.bounds()),
            Shape::Triangle { mesh, index } => {
                Some(Aabb::from_points(meshes[*mesh as usize].vertices(*index)))
            }
            Shape::Plane(_) => None,
            Shape::Cone(c) => Some(c.bounds()),
            Shape::Box(b) => Some(b.bounds()),
        }
    }

    /// The kind of shape, for per-kind statistics.
    pub fn kind(&self) -> ShapeKind {
        match self {
            Shape::Sphere(_) => ShapeKind::Sphere,
            Shape::Triangle { .. } => ShapeKind::Triangle,
            Shape::Plane(_) => ShapeKind::Plane,
            Shape::Cone(_) => ShapeKind::Cone,
            Shape::Box(_) => ShapeKind::Box,
        }
    }
}

impl From<Sphere> for Shape {
    fn from(s: Sphere) -> Shape {
        Shape::Sphere(s)
    }
}

impl From<Plane> for Shape {
    fn from(p: Plane) -> Shape {
        Shape::Plane(Box::new(p))
    }
}

impl From<Cone> for Shape {
    fn from(c: Cone) -> Shape {
        Shape::Cone(Box::new(c))
    }
}

impl From<AaBox> for Shape {
    fn from(b: AaBox) -> Shape {
        Shape::Box(Box::new(b))
    }
}

/// Shape kinds, for statistics by primitive type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeKind {
    /// Spheres.
    Sphere,
    /// Mesh triangles.
    Triangle,
    /// Infinite planes.
    Plane,
    /// Cones and cylinders.
    Cone,
    /// Axis-aligned boxes.
    Box,
}

named_kinds! {
    ShapeKind, "shape kind" {
        Sphere => "sphere",
        Triangle => "triangle",
        Plane => "plane",
        Cone => "cone",
        Box => "box",
    }
}

impl ShapeKind {
    /// How many kinds there are (the length of per-kind counters).
    pub const COUNT: usize = ShapeKind::ALL.len();
}

/// A shape with its material: the unit every accelerator indexes.
#[derive(Clone, Debug, PartialEq)]
pub struct Primitive {
    /// What the primitive is.
    pub shape: Shape,
    /// Index into `Scene::materials`.
    pub material: u32,
}

/// All shapes of a scene. Accelerators refer to primitives by their index in `primitives`.
#[derive(Clone, Debug, Default)]
pub struct Geometry {
    /// The meshes that triangle primitives refer to.
    pub meshes: Vec<TriangleMesh>,
    /// Every primitive; its index here is its id in accelerators, hits and statistics.
    pub primitives: Vec<Primitive>,
}

impl Geometry {
    /// Adds a mesh and one primitive per triangle, all with `material`.
    pub fn add_mesh(&mut self, mesh: TriangleMesh, material: u32) {
        let mesh_id = self.meshes.len() as u32;
        for index in 0..mesh.triangle_count() as u32 {
            self.primitives.push(Primitive {
                shape: Shape::Triangle {
                    mesh: mesh_id,
                    index,
                },
                material,
            });
        }
        self.meshes.push(mesh);
    }

    /// Adds one primitive that is not a mesh triangle.
    pub fn add(&mut self, shape: Shape, material: u32) {
        self.primitives.push(Primitive { shape, material });
    }

    /// Nearest hit of primitive `prim` with `0 < t < t_max`.
    #[inline]
    pub fn intersect(&self, prim: u32, ray: &TraceRay, t_max: f32) -> Option<ShapeHit> {
        self.primitives[prim as usize]
            .shape
            .intersect(&self.meshes, ray, t_max)
    }

    /// The box around primitive `prim`; `None` when it is unbounded (a plane).
    pub fn bounds(&self, prim: u32) -> Option<Aabb> {
        self.primitives[prim as usize].shape.bounds(&self.meshes)
    }

    /// The surface description of a hit on primitive `prim`.
    pub fn surface(&self, prim: u32, ray: &Ray, hit: &ShapeHit) -> SurfacePoint {
        self.surface_with(prim, ray, hit, Uv::Compute)
    }

    /// `surface`, with the uv parameters only if `uv` asks for them.
    pub fn surface_with(&self, prim: u32, ray: &Ray, hit: &ShapeHit, uv: Uv) -> SurfacePoint {
        self.primitives[prim as usize]
            .shape
            .surface(&self.meshes, ray, hit, uv)
    }

    /// Bounds of every bounded primitive.
    pub fn world_bounds(&self) -> Aabb {
        (0..self.primitives.len() as u32)
            .filter_map(|i| self.bounds(i))
            .fold(Aabb::EMPTY, |a, b| a.union(&b))
    }
}

#[cfg(test)]
mod tests {
    /// Millions of primitives are stored; keep each one to half a cache line.
    #[test]
    fn primitive_is_compact() {
        assert!(std::mem::size_of::<super::Primitive>() <= 32);
    }

    /// Accelerators sort primitives by `is_bounded` and then ask for `bounds`.
    #[test]
    fn is_bounded_says_whether_there_are_bounds() {
        use super::*;
        let mut g = Geometry::default();
        g.add(Shape::from(Sphere::new(Vec3::ZERO, 1.0)), 0);
        let plane = Plane::new(Vec3::ZERO, Vec3::Y).expect("a plane");
        g.add(Shape::Plane(Box::new(plane)), 0);
        g.add(Shape::Box(Box::new(AaBox::new(Vec3::ZERO, Vec3::ONE))), 0);
        let mesh = TriangleMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            vec![[0, 1, 2]],
            None,
            None,
        )
        .expect("a mesh");
        g.add_mesh(mesh, 0);
        let cone = Cone::cylinder(Vec3::ZERO, Vec3::Y, 0.5, true).expect("a cylinder");
        g.add(Shape::Cone(Box::new(cone)), 0);
        let bounded: Vec<bool> = g.primitives.iter().map(|p| p.shape.is_bounded()).collect();
        assert_eq!(bounded, [true, false, true, true, true]);
        for (i, p) in g.primitives.iter().enumerate() {
            assert_eq!(p.shape.is_bounded(), g.bounds(i as u32).is_some());
        }
    }
}
