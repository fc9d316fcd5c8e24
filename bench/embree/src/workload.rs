//! The rays both libraries trace: 1024 × 1024 camera rays in tile order, one
//! cosine-distributed ray from each primary hit, and a shadow ray from each primary hit
//! that faces the light. Hit points come from prism (untimed), so both libraries get
//! exactly the same arrays.

use crate::embree;
use prism::accel::SceneIntersector;
use prism::camera::{Camera, Projection};
use prism::geometry::Geometry;
use prism::math::robust::offset_ray_origin;
use prism::math::{Frame, Ray, Vec3};
use prism::Stats;

pub const SIZE: u32 = 1024;
/// From the centre of the bounds towards the eye: in front, right and above (as
/// `prism render mesh.obj` frames a mesh, with y up).
const VIEW_DIRECTION: Vec3 = Vec3::new(0.35, 0.3, 1.0);
/// The field of view that fits the bounding sphere, narrowed by this zoom so that the
/// object fills the frame.
const FOV_DEGREES: f32 = 45.0;
const ZOOM: f32 = 2.0;

/// One kind of ray, in both libraries' formats.
pub struct RaySet {
    pub name: &'static str,
    /// Whether neighbouring rays are coherent (Embree's context hint).
    pub coherent: bool,
    /// Any hit (shadow rays) rather than nearest hit.
    pub any_hit: bool,
    pub rays: Vec<Ray>,
    pub t_max: Vec<f32>,
    pub embree: Vec<embree::Ray>,
}

impl RaySet {
    fn new(name: &'static str, coherent: bool, any_hit: bool) -> Self {
        RaySet {
            name,
            coherent,
            any_hit,
            rays: Vec::new(),
            t_max: Vec::new(),
            embree: Vec::new(),
        }
    }

    fn push(&mut self, ray: Ray, t_max: f32) {
        self.rays.push(ray);
        self.t_max.push(t_max);
        self.embree.push(embree::Ray {
            org: ray.origin.to_array(),
            tnear: 0.0,
            dir: ray.dir.to_array(),
            tfar: t_max,
        });
    }

    pub fn len(&self) -> usize {
        self.rays.len()
    }
}

/// Pixels of a `SIZE`² image in tile order: 16 × 16 tiles, in each 4 × 4 blocks of 4 × 4
/// pixels, all row by row, so that 8, 16 and 256 consecutive rays are neighbours.
fn tile_order() -> impl Iterator<Item = (u32, u32)> {
    let tiles = SIZE / 16;
    (0..tiles * tiles).flat_map(move |tile| {
        let (tx, ty) = (tile % tiles * 16, tile / tiles * 16);
        (0..256u32).map(move |k| {
            let (block, pixel) = (k / 16, k % 16);
            (
                tx + block % 4 * 4 + pixel % 4,
                ty + block / 4 * 4 + pixel / 4,
            )
        })
    })
}

/// A number in [0, 1) from a pixel and a dimension.
fn hash01(pixel: u64, dimension: u64) -> f32 {
    let h = crate::meshes::splitmix64(pixel.wrapping_mul(0x2545_f491_4f6c_dd1d) ^ dimension);
    (h >> 40) as f32 / (1u64 << 24) as f32
}

/// Where the rays come from: the camera and the point light the shadow rays go to.
pub struct View {
    camera: Camera,
    light: Vec3,
}

impl View {
    /// The view of a mesh called `name`: `cornell` from the built-in's own camera with the
    /// light just below the centre of its ceiling light; the others framed (`framing`).
    pub fn of(name: &str, geometry: &Geometry) -> View {
        if name == crate::meshes::CORNELL {
            View::cornell()
        } else {
            View::framing(geometry)
        }
    }

    /// A camera looking at the bounds' centre from `VIEW_DIRECTION`, the bounding sphere
    /// filling the frame, and a point light above and in front of the object.
    fn framing(geometry: &Geometry) -> View {
        let bounds = geometry.world_bounds();
        let (centre, radius) = (bounds.center(), 0.5 * bounds.extent().length());
        let view = VIEW_DIRECTION.normalize();
        let half = (0.5 * FOV_DEGREES).to_radians();
        View {
            camera: Camera {
                // The bounding sphere just fits the 45° view; the zoom then halves its tangent.
                eye: centre + view * (radius / half.sin()),
                look_at: centre,
                up: Vec3::Y,
                fov_degrees: 2.0 * (half.tan() / ZOOM).atan().to_degrees(),
                projection: Projection::Perspective,
            },
            light: centre + radius * (1.5 * Vec3::Y + view),
        }
    }

    /// `cornell-light`'s camera, and a point 1 mm below the middle of its ceiling light
    /// (x 213-343, z 227-332 mm at y 548.7), where a path's light samples go.
    fn cornell() -> View {
        View {
            camera: crate::meshes::cornell_light().camera,
            light: Vec3::new(278.0, 547.7, 279.5),
        }
    }
}

/// The three ray sets for a geometry and its prism BVH, seen from `view`.
pub fn generate(geometry: &Geometry, intersector: &SceneIntersector, view: &View) -> [RaySet; 3] {
    let camera = view.camera.setup(SIZE, SIZE).expect("a valid camera");
    let light = view.light;

    let mut primary = RaySet::new("primary", true, false);
    let mut incoherent = RaySet::new("incoherent", false, false);
    let mut shadow = RaySet::new("shadow", true, true);
    let mut stats = Stats::default();
    for (x, y) in tile_order() {
        let ray = camera.ray(x as f32 + 0.5, y as f32 + 0.5);
        primary.push(ray, f32::INFINITY);
        let Some(hit) = intersector.intersect(geometry, &ray, f32::INFINITY, &mut stats) else {
            continue;
        };
        let sp = geometry.surface(hit.prim, &ray, &hit.shape_hit());
        // The geometric normal on the side the ray arrived from.
        let ng = if ray.dir.dot(sp.ng) < 0.0 {
            sp.ng
        } else {
            -sp.ng
        };

        // Cosine-distributed about ng (Malley's method), from a hash of the pixel.
        let pixel = (y * SIZE + x) as u64;
        let (u1, u2) = (hash01(pixel, 1), hash01(pixel, 2));
        let r = u1.sqrt();
        let phi = std::f32::consts::TAU * u2;
        let local = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt());
        let dir = Frame::from_z(ng).to_world(local).normalize();
        let origin = offset_ray_origin(sp.p, sp.p_error, ng, dir);
        incoherent.push(Ray::new(origin, dir), f32::INFINITY);

        // Surfaces facing away from the light are in shadow without a ray (as in prism's
        // integrator), so only the others get one.
        let to_light = light - sp.p;
        if ng.dot(to_light) > 0.0 {
            let dir = to_light.normalize();
            let origin = offset_ray_origin(sp.p, sp.p_error, ng, dir);
            shadow.push(Ray::new(origin, dir), (light - origin).length());
        }
    }
    [primary, incoherent, shadow]
}

/// Rays read from `path` (another renderer's, e.g. `bench/mitsuba-anatomy.py`'s): per ray its
/// origin and direction, six little-endian f32s, traced for the nearest hit without a
/// bound, as incoherent rays.
pub fn from_file(path: &std::path::Path) -> Result<RaySet, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    const RAY_BYTES: usize = 6 * 4;
    if bytes.is_empty() || bytes.len() % RAY_BYTES != 0 {
        return Err(format!(
            "{}: {} bytes, expected a positive multiple of {RAY_BYTES} (origin and direction as six f32s per ray)",
            path.display(),
            bytes.len()
        ));
    }
    let mut set = RaySet::new("from file", false, false);
    for (k, ray) in bytes.chunks_exact(RAY_BYTES).enumerate() {
        let f: [f32; 6] = std::array::from_fn(|i| {
            f32::from_le_bytes([ray[4 * i], ray[4 * i + 1], ray[4 * i + 2], ray[4 * i + 3]])
        });
        let (origin, dir) = (Vec3::new(f[0], f[1], f[2]), Vec3::new(f[3], f[4], f[5]));
        if !origin.is_finite() || !dir.is_finite() || dir == Vec3::ZERO {
            return Err(format!(
                "{}: ray {k}: origin {origin} and direction {dir}, expected finite numbers and a non-zero direction",
                path.display()
            ));
        }
        set.push(Ray::new(origin, dir), f32::INFINITY);
    }
    Ok(set)
}
