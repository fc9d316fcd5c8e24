//! Helpers shared by the mesh-file tests: one small mesh written out in every format
//! prism reads (OBJ, ASCII and binary PLY, inline TOML), the GLB container, temporary
//! folders, rendering, and the numbers the fuzzing properties write into mesh files (the
//! mutations are `mutate.rs`).

use prism::render::{render, Film};
use prism::Scene;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// A mesh with normals and uvs whose faces are triangles and convex quads.
pub(crate) struct TestMesh {
    pub positions: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub uvs: Vec<[f32; 2]>,
    pub faces: Vec<Vec<u32>>,
}

impl TestMesh {
    /// A latitude-longitude sphere: triangle fans at the poles, quads between, the seam's
    /// vertices doubled so that uvs run from 0 to 1.
    pub(crate) fn sphere(segments: u32, rings: u32) -> TestMesh {
        let mut m = TestMesh {
            positions: Vec::new(),
            normals: Vec::new(),
            uvs: Vec::new(),
            faces: Vec::new(),
        };
        for j in 0..=rings {
            let theta = std::f32::consts::PI * j as f32 / rings as f32;
            for i in 0..=segments {
                let phi = 2.0 * std::f32::consts::PI * i as f32 / segments as f32;
                let n = [
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    -theta.sin() * phi.sin(),
                ];
                m.positions.push(n);
                m.normals.push(n);
                m.uvs
                    .push([i as f32 / segments as f32, 1.0 - j as f32 / rings as f32]);
            }
        }
        let at = |j: u32, i: u32| j * (segments + 1) + i;
        for j in 0..rings {
            for i in 0..segments {
                let (a, b, c, d) = (at(j, i), at(j + 1, i), at(j + 1, i + 1), at(j, i + 1));
                m.faces.push(if j == 0 {
                    vec![a, b, c]
                } else if j == rings - 1 {
                    vec![a, b, d]
                } else {
                    vec![a, b, c, d]
                });
            }
        }
        m
    }

    pub(crate) fn triangle_count(&self) -> usize {
        self.faces.iter().map(|f| f.len() - 2).sum()
    }

    pub(crate) fn obj(&self) -> String {
        let mut s = String::from("# a test sphere\no sphere\n");
        for p in &self.positions {
            let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
        }
        for t in &self.uvs {
            let _ = writeln!(s, "vt {} {}", t[0], t[1]);
        }
        for n in &self.normals {
            let _ = writeln!(s, "vn {} {} {}", n[0], n[1], n[2]);
        }
        for f in &self.faces {
            s.push('f');
            for i in f {
                let _ = write!(s, " {0}/{0}/{0}", i + 1);
            }
            s.push('\n');
        }
        s
    }

    fn ply_header(&self, format: &str) -> String {
        format!(
            "ply\nformat {format} 1.0\ncomment a test sphere\nelement vertex {}\n\
             property float x\nproperty float y\nproperty float z\n\
             property float nx\nproperty float ny\nproperty float nz\n\
             property float u\nproperty float v\n\
             element face {}\nproperty list uchar int vertex_indices\nend_header\n",
            self.positions.len(),
            self.faces.len()
        )
    }

    pub(crate) fn ply_ascii(&self) -> Vec<u8> {
        let mut s = self.ply_header("ascii");
        for k in 0..self.positions.len() {
            let (p, n, t) = (self.positions[k], self.normals[k], self.uvs[k]);
            let _ = writeln!(
                s,
                "{} {} {} {} {} {} {} {}",
                p[0], p[1], p[2], n[0], n[1], n[2], t[0], t[1]
            );
        }
        for f in &self.faces {
            let _ = write!(s, "{}", f.len());
            for i in f {
                let _ = write!(s, " {i}");
            }
            s.push('\n');
        }
        s.into_bytes()
    }

    pub(crate) fn ply_binary(&self, big_endian: bool) -> Vec<u8> {
        let format = if big_endian {
            "binary_big_endian"
        } else {
            "binary_little_endian"
        };
        let mut out = self.ply_header(format).into_bytes();
        let f32_bytes = |v: f32| {
            if big_endian {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            }
        };
        for k in 0..self.positions.len() {
            let (p, n, t) = (self.positions[k], self.normals[k], self.uvs[k]);
            for v in p.iter().chain(&n).chain(&t) {
                out.extend(f32_bytes(*v));
            }
        }
        for f in &self.faces {
            out.push(f.len() as u8);
            for &i in f {
                out.extend(if big_endian {
                    (i as i32).to_be_bytes()
                } else {
                    (i as i32).to_le_bytes()
                });
            }
        }
        out
    }

    /// The keys of an inline TOML mesh.
    pub(crate) fn toml_inline(&self) -> String {
        let list3 = |v: &[[f32; 3]]| {
            v.iter()
                .map(|p| format!("[{}, {}, {}]", p[0], p[1], p[2]))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let uvs = self
            .uvs
            .iter()
            .map(|t| format!("[{}, {}]", t[0], t[1]))
            .collect::<Vec<_>>()
            .join(", ");
        let faces = self
            .faces
            .iter()
            .map(|f| format!("{f:?}"))
            .collect::<Vec<_>>()
            .join(", ");
        format!(
            "positions = [{}]\nnormals = [{}]\nuvs = [{uvs}]\nindices = [{faces}]\n",
            list3(&self.positions),
            list3(&self.normals)
        )
    }
}

/// A GLB container: header, JSON chunk (space-padded), BIN chunk (zero-padded).
pub(crate) fn glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |v: &mut Vec<u8>, with: u8| {
        while !v.len().is_multiple_of(4) {
            v.push(with);
        }
    };
    let mut json = json.to_vec();
    pad(&mut json, b' ');
    let mut bin = bin.to_vec();
    pad(&mut bin, 0);
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((12 + 8 + json.len() + 8 + bin.len()) as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin);
    out
}

/// A fresh folder for one test's files, removed when the test ends.
pub(crate) fn temp_dir(name: &str) -> super::scratch::ScratchDir {
    super::scratch::ScratchDir::new("mesh-tests", name)
}

pub(crate) fn write(dir: &Path, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("temp file");
    path
}

/// `scene` rendered with its own options at `width` × `height`.
pub(crate) fn render_at(scene: &Scene, width: u32, height: u32) -> Film {
    let mut options = scene.options.clone();
    options.width = width;
    options.height = height;
    let prepared = scene.prepare(&options.accel);
    render(&prepared, &options, &|_| {}, &AtomicBool::new(false))
        .expect("the scene renders")
        .film
}

/// `scene` with nothing in it lit but by `lights`, `ambient` and `background`, seen head
/// on from z = 5 (a 20° view, 1.76 units wide at z = 0) looking at the origin: where the
/// loader suites' per-texel tests put a unit quad in the z = 0 plane, so that its pixels
/// have closed forms.
pub(crate) fn head_on(
    scene: &mut Scene,
    lights: Vec<prism::light::Light>,
    ambient: f32,
    background: f32,
) {
    use prism::math::{Color, Vec3};
    scene.lights = lights;
    scene.ambient = Color::splat(ambient);
    scene.background = Color::splat(background);
    scene.camera = prism::camera::Camera {
        eye: Vec3::new(0.0, 0.0, 5.0),
        look_at: Vec3::ZERO,
        up: Vec3::Y,
        fov_degrees: 20.0,
        projection: prism::camera::Projection::Perspective,
    };
}

/// The largest difference of any channel of any pixel.
pub(crate) fn max_difference(a: &Film, b: &Film) -> f32 {
    assert_eq!(a.pixels.len(), b.pixels.len());
    a.pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (*p - *q).abs().max_element())
        .fold(0.0, f32::max)
}

/// Numbers that break a mesh file's rules: huge counts and indices, zero, negatives, NaN.
pub(crate) const MUTATION_VALUES: &[&str] = &[
    "0",
    "-1",
    "2",
    "255",
    "4294967295",
    "1000000000",
    "99999999999999999999",
    "nan",
    "inf",
    "1e39",
    "-0",
];
