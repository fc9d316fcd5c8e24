//! Helpers shared by the integration tests: a small seeded RNG, closed test meshes with
//! exactly shared vertices, ray builders and tolerance assertions.
//!
//! Each crate's test binary uses a different subset, hence the `dead_code` allow.
#![allow(dead_code)]

pub(crate) mod mesh_files;
pub(crate) mod mutate;
pub(crate) mod oracle;
pub(crate) mod scratch;
pub(crate) mod work;

use prism::geometry::TriangleMesh;
use prism::math::{Ray, TraceRay, Vec3};
use prism::render::Film;
use std::collections::HashMap;

/// SplitMix64 (Steele, Lea, Flood 2014): tiny, seedable, and good enough to spray rays.
pub(crate) struct Rng(u64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1), 24 random bits.
    pub(crate) fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    pub(crate) fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f32()
    }

    /// Uniform in 0..n.
    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    pub(crate) fn chance(&mut self, p: f32) -> bool {
        self.f32() < p
    }

    pub(crate) fn point_in(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        Vec3::new(
            self.range(lo.x, hi.x),
            self.range(lo.y, hi.y),
            self.range(lo.z, hi.z),
        )
    }

    /// Uniform on the unit sphere (rejection from the cube).
    pub(crate) fn unit_vector(&mut self) -> Vec3 {
        loop {
            let v = self.point_in(Vec3::splat(-1.0), Vec3::ONE);
            let l2 = v.length_squared();
            if l2 > 1e-4 && l2 <= 1.0 {
                return v / l2.sqrt();
            }
        }
    }

    /// One of the six axis directions, with an exact zero (of either sign) elsewhere.
    pub(crate) fn axis_direction(&mut self) -> Vec3 {
        let axis = self.below(3);
        let mut d = Vec3::new(
            if self.chance(0.5) { 0.0 } else { -0.0 },
            if self.chance(0.5) { 0.0 } else { -0.0 },
            if self.chance(0.5) { 0.0 } else { -0.0 },
        );
        d[axis] = if self.chance(0.5) { 1.0 } else { -1.0 };
        d
    }
}

/// The bits of every channel of every pixel, for images that must be identical to the bit.
pub(crate) fn film_bits(film: &Film) -> Vec<u32> {
    film.pixels
        .iter()
        .flat_map(|c| [c.x.to_bits(), c.y.to_bits(), c.z.to_bits()])
        .collect()
}

pub(crate) fn trace_ray(origin: Vec3, dir: Vec3) -> TraceRay {
    TraceRay::new(Ray::new(origin, dir))
}

/// `|actual − expected| ≤ tol · max(|expected|, floor)`.
#[track_caller]
pub(crate) fn assert_rel(actual: f32, expected: f64, tol: f64, floor: f64, what: &str) {
    let err = (actual as f64 - expected).abs();
    let bound = tol * expected.abs().max(floor);
    assert!(
        err <= bound,
        "{what}: got {actual:e}, expected {expected:e} (error {err:e} > {bound:e})"
    );
}

#[track_caller]
pub(crate) fn assert_vec_close(actual: Vec3, expected: Vec3, tol: f32, what: &str) {
    let err = (actual - expected).abs().max_element();
    assert!(
        err <= tol,
        "{what}: got {actual:?}, expected {expected:?} (error {err:e} > {tol:e})"
    );
}

/// An icosphere: the icosahedron subdivided `levels` times, vertices pushed onto the sphere.
/// Every vertex is stored once, so shared edges use bit-identical endpoints (what a
/// watertight intersector needs to seal them). Counter-clockwise seen from outside.
pub(crate) fn icosphere(center: Vec3, radius: f32, levels: u32) -> TriangleMesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut unit: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, unit: &mut Vec<Vec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                unit.push((unit[a as usize] + unit[b as usize]).normalize());
                unit.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let ab = mid(a, b, &mut unit);
            let bc = mid(b, c, &mut unit);
            let ca = mid(c, a, &mut unit);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    let positions = unit.iter().map(|&u| center + radius * u).collect();
    TriangleMesh::new(positions, faces, None, None).expect("indices are in range")
}

/// The surface of a box split into an `n × n` grid of quads per face, two triangles each,
/// with every lattice point stored once and mapped through `place` (e.g. a rotation).
/// Counter-clockwise seen from outside when `place` preserves orientation.
pub(crate) fn lattice_cube(n: u32, place: impl Fn(Vec3) -> Vec3) -> TriangleMesh {
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let mut positions = Vec::new();
    let mut vertex = |key: [u32; 3]| {
        *index.entry(key).or_insert_with(|| {
            let unit = Vec3::new(key[0] as f32, key[1] as f32, key[2] as f32) / n as f32;
            positions.push(place(unit * 2.0 - Vec3::ONE));
            positions.len() as u32 - 1
        })
    };
    let mut faces = Vec::new();
    for axis in 0..3 {
        let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let key = |di: u32, dj: u32| {
                        let mut k = [0u32; 3];
                        k[axis] = side;
                        k[a1] = i + di;
                        k[a2] = j + dj;
                        k
                    };
                    let q = [key(0, 0), key(1, 0), key(1, 1), key(0, 1)].map(&mut vertex);
                    // (a1, a2, axis) is right-handed, so this winding faces +axis.
                    if side == n {
                        faces.push([q[0], q[1], q[2]]);
                        faces.push([q[0], q[2], q[3]]);
                    } else {
                        faces.push([q[0], q[2], q[1]]);
                        faces.push([q[0], q[3], q[2]]);
                    }
                }
            }
        }
    }
    TriangleMesh::new(positions, faces, None, None).expect("indices are in range")
}

/// A rotation about an arbitrary axis (Rodrigues), so test meshes have no axis-aligned edges.
pub(crate) fn rotate(v: Vec3, axis: Vec3, angle: f32) -> Vec3 {
    let k = axis.normalize();
    let (s, c) = angle.sin_cos();
    v * c + k.cross(v) * s + k * k.dot(v) * (1.0 - c)
}

/// A file or folder of `../shared` (the data beside the repository: the SPD scenes, the
/// Stanford bunny), given relative to it. Where it is absent the test is skipped with a
/// line on the terminal (written past the test harness's capture, so it shows even when
/// the test passes), except under CI (`CI` set), where data that should be there is
/// missing and the test fails instead.
pub(crate) fn shared_data(relative: &str) -> Option<std::path::PathBuf> {
    use std::io::Write;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared")
        .join(relative);
    if path.exists() {
        return Some(path);
    }
    let reason = format!(
        "{} is absent (../shared sits beside the repository)",
        path.display()
    );
    if std::env::var_os("CI").is_some() {
        panic!("{reason}, and CI must not skip tests");
    }
    let _ = writeln!(std::io::stderr(), "skipped: {reason}");
    None
}
