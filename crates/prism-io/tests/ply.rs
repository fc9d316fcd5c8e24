//! The PLY reader: one mesh renders the same from OBJ, ASCII PLY, binary PLY of both byte
//! orders and an inline TOML mesh; other elements and properties are skipped by type;
//! malformed headers and bodies give errors that name the line (or byte) and what was
//! expected; and no mutation of a valid file makes the reader panic or work without bound.

use crate::common;

use common::mesh_files::{max_difference, render_at, temp_dir, write, TestMesh};
use common::mutate::{self, apply, Mutation};
use common::work::allocated_by;

/// What refusing a small hostile file may allocate: a few pages, whatever the header claims.
const REFUSAL_BYTES: usize = 1 << 20;

/// What parsing a damaged file may allocate per byte of it: the values of every property
/// as f64 (8 bytes from as little as one), the mesh built from them and the growth of the
/// vectors, with room to spare.
const BYTES_PER_INPUT_BYTE: usize = 512;
use prism_io::scene::mesh_file::{load_mesh_file, Materials};
use prism_io::scene::{load, ply, LoadError};
use proptest::prelude::*;

const SCENE: &str = r#"
[render]
width = 96
height = 72

[camera]
eye = [0.6, 1.1, 3.2]
look_at = [0, 0, 0]
fov = 42

[materials.m]
texture = { type = "checker", a = [0.9, 0.2, 0.1], b = [0.95, 0.9, 0.3], size = 0.125, space = "uv" }
specular = 0.4
shininess = 30

[[lights]]
type = "point"
position = [2, 3, 4]

[[objects]]
type = "mesh"
material = "m"
transform = { rotate = [10, 30, 0], scale = [1, 0.8, 1] }
"#;

#[test]
fn one_mesh_renders_the_same_from_every_format() {
    let mesh = TestMesh::sphere(16, 8);
    let dir = temp_dir("every-format");
    let files: [(&str, Vec<u8>); 4] = [
        ("mesh.obj", mesh.obj().into_bytes()),
        ("ascii.ply", mesh.ply_ascii()),
        ("le.ply", mesh.ply_binary(false)),
        ("be.ply", mesh.ply_binary(true)),
    ];
    let mut films = Vec::new();
    for (name, bytes) in &files {
        write(&dir, name, bytes);
        let scene_path = write(
            &dir,
            &format!("{name}.toml"),
            format!("{SCENE}file = \"{name}\"\n"),
        );
        let scene = load(&scene_path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(
            scene.geometry.primitives.len(),
            mesh.triangle_count(),
            "{name}"
        );
        films.push((name.to_string(), render_at(&scene, 96, 72)));
    }
    let inline = prism_io::scene::parse_toml(
        &format!("{SCENE}{}", mesh.toml_inline()),
        &dir.join("inline.toml"),
    )
    .expect("inline mesh");
    let inline_film = render_at(&inline, 96, 72);

    let (first_name, first) = &films[0];
    let lit = first
        .pixels
        .iter()
        .filter(|p| p.max_element() > 0.05)
        .count();
    assert!(
        lit > 96 * 72 / 8,
        "the sphere covers the image: {lit} lit pixels"
    );
    for (name, film) in &films[1..] {
        assert_eq!(
            max_difference(first, film),
            0.0,
            "{name} differs from {first_name}"
        );
    }
    // TOML normalises its directions by another route (largest component first), so
    // shading normals may differ in the last bit.
    let d = max_difference(first, &inline_film);
    assert!(d <= 1e-3, "inline TOML differs from {first_name} by {d}");
}

/// id, position, a list of tags, uv, red.
type BusyVertex = (i16, [f32; 3], Vec<u8>, [f32; 2], u8);

/// A PLY file with everything the reader must step over: comments, an element before the
/// vertices, list properties on vertices and faces, other scalar types, and a trailing
/// element.
fn busy_ply(format: &str) -> Vec<u8> {
    let header = format!(
        "ply\nformat {format} 1.0\ncomment made by hand\nobj_info nothing\n\
         element material 2\nproperty list uchar float weights\nproperty double shine\n\
         element vertex 4\nproperty short id\nproperty float x\nproperty float y\nproperty float z\n\
         property list ushort uchar tags\nproperty float s\nproperty float t\nproperty uchar red\n\
         element face 2\nproperty uchar flags\nproperty list uchar uint vertex_index\n\
         property list int float texcoord\n\
         element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
    );
    let materials: [(Vec<f32>, f64); 2] = [(vec![0.5, 0.25, 1.0], 3.0), (vec![], 7.5)];
    let vertices: [BusyVertex; 4] = [
        (10, [0.0, 0.0, 0.0], vec![1, 2], [0.0, 0.0], 255),
        (11, [1.0, 0.0, 0.0], vec![], [1.0, 0.0], 0),
        (12, [1.0, 1.0, 0.0], vec![9], [1.0, 1.0], 7),
        (13, [0.0, 1.0, 0.0], vec![3, 4, 5], [0.0, 1.0], 8),
    ];
    let faces: [(u8, Vec<u32>, Vec<f32>); 2] = [
        (1, vec![0, 1, 2], vec![0.1, 0.2]),
        (2, vec![0, 2, 3], vec![]),
    ];
    if format == "ascii" {
        let mut s = header;
        for (w, shine) in &materials {
            s += &format!("{} {} {shine}\n", w.len(), join(w));
        }
        for (id, p, tags, uv, red) in &vertices {
            s += &format!(
                "{id} {} {} {} {} {} {} {} {red}\n",
                p[0],
                p[1],
                p[2],
                tags.len(),
                join(tags),
                uv[0],
                uv[1]
            );
        }
        for (flags, idx, tc) in &faces {
            s += &format!(
                "{flags} {} {} {} {}\n",
                idx.len(),
                join(idx),
                tc.len(),
                join(tc)
            );
        }
        s += "0 1\n";
        return s.into_bytes();
    }
    let be = format == "binary_big_endian";
    let mut out = header.into_bytes();
    let mut put = |bytes: &[u8]| {
        let mut b = bytes.to_vec();
        if be {
            b.reverse();
        }
        out.extend(b);
    };
    for (w, shine) in &materials {
        put(&[w.len() as u8]);
        for v in w {
            put(&v.to_le_bytes());
        }
        put(&shine.to_le_bytes());
    }
    for (id, p, tags, uv, red) in &vertices {
        put(&id.to_le_bytes());
        for v in p {
            put(&v.to_le_bytes());
        }
        put(&(tags.len() as u16).to_le_bytes());
        for t in tags {
            put(&[*t]);
        }
        put(&uv[0].to_le_bytes());
        put(&uv[1].to_le_bytes());
        put(&[*red]);
    }
    for (flags, idx, tc) in &faces {
        put(&[*flags]);
        put(&[idx.len() as u8]);
        for i in idx {
            put(&i.to_le_bytes());
        }
        put(&(tc.len() as i32).to_le_bytes());
        for v in tc {
            put(&v.to_le_bytes());
        }
    }
    put(&0i32.to_le_bytes());
    put(&1i32.to_le_bytes());
    out
}

fn join<T: std::fmt::Display>(v: &[T]) -> String {
    v.iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

#[test]
fn other_elements_and_properties_are_skipped_by_type() {
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let file = ply::parse(&busy_ply(format), "busy.ply").unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(file.parts.len(), 1, "{format}");
        let mesh = &file.parts[0].mesh;
        assert_eq!(
            mesh.positions(),
            &[
                prism::math::Vec3::new(0.0, 0.0, 0.0),
                prism::math::Vec3::new(1.0, 0.0, 0.0),
                prism::math::Vec3::new(1.0, 1.0, 0.0),
                prism::math::Vec3::new(0.0, 1.0, 0.0),
            ],
            "{format}"
        );
        assert_eq!(mesh.indices(), &[[0, 1, 2], [0, 2, 3]], "{format}");
        assert!(!mesh.has_normals());
        assert_eq!(file.parts[0].material, None);
    }
}

#[test]
fn polygons_of_any_size_are_triangulated_concave_ones_exactly() {
    // An L-shaped hexagon: a fan from its first corner would cover the notch.
    let ply = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n\
               property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
               end_header\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n6 0 1 2 3 4 5\n";
    let file = ply::parse(ply.as_bytes(), "l.ply").expect("valid");
    let mesh = &file.parts[0].mesh;
    assert_eq!(mesh.triangle_count(), 4);
    let area: f32 = (0..4)
        .map(|t| {
            let [a, b, c] = mesh.vertices(t);
            let n = (b - a).cross(c - a);
            assert!(n.z > 0.0, "winding kept");
            0.5 * n.length()
        })
        .sum();
    assert!((area - 3.0).abs() < 1e-5, "area {area}");
}

/// A text PLY file of three vertices and one face whose lines after the vertices are
/// `rest` (line 13 on): where the cases of faces differ.
macro_rules! triangle_then {
    ($rest:literal) => {
        concat!(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n",
            "property float z\nelement face 1\nproperty list uchar int vertex_indices\n",
            "end_header\n0 0 0\n1 0 0\n0 1 0\n",
            $rest
        )
    };
}

/// (what, file text, line, column, phrase): ASCII files whose errors have a line.
const MALFORMED_TEXT: &[(&str, &str, usize, usize, &str)] = &[
    ("not ply", "plx\n", 1, 1, "expected 'ply' on the first line"),
    ("empty", "", 1, 1, "expected 'ply'"),
    (
        "no end_header",
        "ply\nformat ascii 1.0\nelement vertex 0\n",
        3,
        1,
        "the file ends inside the header",
    ),
    (
        "unknown format",
        "ply\nformat binary 1.0\nend_header\n",
        2,
        8,
        "expected ascii, binary_little_endian or binary_big_endian",
    ),
    (
        "wrong version",
        "ply\nformat ascii 2.0\nend_header\n",
        2,
        14,
        "expected the version 1.0",
    ),
    (
        "no format",
        "ply\nelement vertex 0\nend_header\n",
        3,
        1,
        "no format line",
    ),
    (
        "negative count",
        "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n",
        3,
        16,
        "expected the element count, a whole number ≥ 0",
    ),
    (
        "property first",
        "ply\nformat ascii 1.0\nproperty float x\nend_header\n",
        3,
        1,
        "a property before any element",
    ),
    (
        "unknown type",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty real x\nend_header\n",
        4,
        10,
        "expected a property type",
    ),
    (
        "float list count",
        "ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\n\
         end_header\n",
        4,
        15,
        "a list's count must be an integer type",
    ),
    (
        "unknown statement",
        "ply\nformat ascii 1.0\nelements vertex 1\nend_header\n",
        3,
        1,
        "unknown header statement 'elements'",
    ),
    (
        "no z",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
         element face 0\nproperty list uchar int vertex_indices\nend_header\n",
        4,
        1,
        "element vertex has x but no z",
    ),
    (
        "no faces",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
         property float z\nend_header\n0 0 0\n",
        7,
        1,
        "no 'element face'",
    ),
    (
        "float indices",
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
         property float z\nelement face 0\nproperty list uchar float vertex_indices\n\
         end_header\n",
        8,
        1,
        "expected an integer type",
    ),
    (
        "counts beyond the file",
        "ply\nformat ascii 1.0\nelement vertex 1000000000\nproperty float x\n\
         property float y\nproperty float z\nelement face 0\n\
         property list uchar int vertex_indices\nend_header\n0 0 0\n",
        3,
        16,
        "declares 1000000000 instances",
    ),
    (
        "not a number",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
         property float z\nelement face 0\nproperty list uchar int vertex_indices\n\
         end_header\n0 zero 0\n",
        10,
        3,
        "vertex 0, property y: expected a number (float), found 'zero'",
    ),
    (
        "nan",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
         property float z\nelement face 0\nproperty list uchar int vertex_indices\n\
         end_header\n0 0 nan\n",
        10,
        5,
        "vertex 0, property z: NaN is not a finite 32-bit number",
    ),
    (
        "double beyond f32",
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\n\
         property double z\nelement face 0\nproperty list uchar int vertex_indices\n\
         end_header\n1e300 0 0\n",
        10,
        1,
        "1e300 is not a finite 32-bit number",
    ),
    (
        "index out of range",
        triangle_then!("3 0 1 3\n"),
        13,
        7,
        "face 0, property vertex_indices: vertex index 3, but the file has 3 vertices",
    ),
    (
        "two corners",
        triangle_then!("2 0 1\n"),
        13,
        1,
        "a face of 2 corners; expected at least 3",
    ),
    (
        "uchar out of range",
        triangle_then!("300 0 1 2\n"),
        13,
        1,
        "300 is out of range for uchar",
    ),
    (
        "truncated",
        triangle_then!("3 0 1\n"),
        13,
        6,
        "the file ends here: expected a int value",
    ),
    (
        "trailing data",
        triangle_then!("3 0 1 2\n4 5\n"),
        14,
        1,
        "expected the end of the file after the last element, found '4'",
    ),
];

#[test]
fn malformed_text_names_the_line_column_and_expectation() {
    for &(what, text, line, column, phrase) in MALFORMED_TEXT {
        let error = match ply::parse(text.as_bytes(), "bad.ply") {
            Err(e) => e,
            Ok(_) => panic!("{what}: loaded without error"),
        };
        let message = error.to_string();
        match &error {
            LoadError::Syntax {
                line: l, column: c, ..
            } => {
                assert_eq!((*l, *c), (line, column), "{what}: `{message}`");
                assert!(
                    message.starts_with(&format!("bad.ply:{line}:{column}: ")),
                    "{what}: `{message}`"
                );
            }
            other => panic!("{what}: expected a located error, got {other:?}"),
        }
        assert!(
            message.contains(phrase),
            "{what}: `{message}` does not say `{phrase}`"
        );
    }
}

fn binary_header(vertices: usize, faces: usize, count_type: &str) -> Vec<u8> {
    format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {vertices}\nproperty float x\n\
         property float y\nproperty float z\nelement face {faces}\n\
         property list {count_type} int vertex_indices\nend_header\n"
    )
    .into_bytes()
}

fn triangle_body() -> Vec<u8> {
    let mut b = Vec::new();
    for v in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        b.extend(v.to_le_bytes());
    }
    b
}

#[test]
fn malformed_binary_names_the_byte_and_expectation() {
    let header = binary_header(3, 1, "uchar");
    let body_start = header.len();
    let with = |tail: &[u8]| {
        let mut bytes = header.clone();
        bytes.extend(triangle_body());
        bytes.extend(tail);
        bytes
    };
    let mut face = vec![3u8];
    for i in [0i32, 1, 2] {
        face.extend(i.to_le_bytes());
    }
    assert!(ply::parse(&with(&face), "ok.ply").is_ok());

    let mut out_of_range = face.clone();
    out_of_range[9..13].copy_from_slice(&7i32.to_le_bytes());
    let mut negative = face.clone();
    negative[1..5].copy_from_slice(&(-1i32).to_le_bytes());
    let mut nan = header.clone();
    nan.extend(triangle_body());
    nan[body_start + 16..body_start + 20].copy_from_slice(&f32::NAN.to_le_bytes());
    nan.extend(&face);
    // A face property after the list: only that can still be missing when the header's
    // counts and the list's length have been checked against the size.
    let flagged = String::from_utf8(header.clone())
        .expect("text")
        .replace("end_header", "property uchar flags\nend_header");
    let mut truncated = flagged.into_bytes();
    let flagged_start = truncated.len();
    truncated.extend(triangle_body());
    truncated.extend(&face);
    let cases: Vec<(&str, Vec<u8>, usize, &str)> = vec![
        (
            "list longer than the file",
            with(&face[..7]),
            body_start + 36,
            "face 0, property vertex_indices): a list of 3 int values, but the rest of the file \
             holds at most 1",
        ),
        (
            "index out of range",
            with(&out_of_range),
            body_start + 36 + 9,
            "vertex index 7, but the file has 3 vertices",
        ),
        (
            "negative index",
            with(&negative),
            body_start + 36 + 1,
            "vertex index -1",
        ),
        (
            "nan",
            nan,
            body_start + 16,
            "vertex 1, property y): NaN is not a finite 32-bit number",
        ),
        (
            "truncated after a list",
            truncated,
            flagged_start + 36 + 13,
            "face 0, property flags): the file ends here: expected 1 more uchar value (0 bytes \
             left)",
        ),
    ];
    for (what, bytes, byte, phrase) in cases {
        let message = match ply::parse(&bytes, "bad.ply") {
            Err(e @ LoadError::Invalid { .. }) => e.to_string(),
            Err(other) => panic!("{what}: expected an error with a byte offset, got {other:?}"),
            Ok(_) => panic!("{what}: loaded without error"),
        };
        assert!(
            message.starts_with(&format!("bad.ply: byte {byte} (")),
            "{what}: `{message}`"
        );
        assert!(
            message.contains(phrase),
            "{what}: `{message}` does not say `{phrase}`"
        );
    }
}

#[test]
fn counts_the_file_cannot_hold_are_refused_before_allocating() {
    // A header that declares a billion vertices over a ten-byte body.
    let mut bytes = binary_header(1_000_000_000, 0, "uchar");
    bytes.extend([0u8; 10]);
    let (result, allocated) = allocated_by(|| ply::parse(&bytes, "huge.ply"));
    let error = result.expect_err("cannot hold them");
    assert!(allocated < REFUSAL_BYTES, "allocated {allocated} bytes");
    let message = error.to_string();
    assert!(
        message.starts_with(
            "huge.ply:3:16: element vertex declares 1000000000 instances of at \
                             least 12 bytes each, more than the 10 bytes"
        ),
        "{message}"
    );

    // Vertex data cut short is caught by the same check.
    let mut bytes = binary_header(3, 0, "uchar");
    bytes.extend(&triangle_body()[..30]);
    let message = ply::parse(&bytes, "short.ply")
        .expect_err("truncated")
        .to_string();
    assert!(
        message.starts_with(
            "short.ply:3:16: element vertex declares 3 instances of at least 12 \
                             bytes each, more than the 30 bytes"
        ),
        "{message}"
    );

    // A list that claims four billion items.
    let mut bytes = binary_header(3, 1, "uint");
    bytes.extend(triangle_body());
    bytes.extend(u32::MAX.to_le_bytes());
    bytes.extend([0u8; 12]);
    let message = ply::parse(&bytes, "list.ply")
        .expect_err("cannot hold it")
        .to_string();
    assert!(
        message
            .contains("a list of 4294967295 int values, but the rest of the file holds at most 3"),
        "{message}"
    );

    // An element with no properties costs nothing, whatever its count.
    let mut bytes =
        b"ply\nformat binary_little_endian 1.0\nelement nothing 18446744073709551615\n".to_vec();
    let header = binary_header(3, 1, "uchar");
    let after_format = "ply\nformat binary_little_endian 1.0\n".len();
    bytes.extend(&header[after_format..]);
    bytes.extend(triangle_body());
    bytes.push(3);
    for i in [0i32, 1, 2] {
        bytes.extend(i.to_le_bytes());
    }
    let (result, allocated) = allocated_by(|| ply::parse(&bytes, "empty-element.ply"));
    let file = result.unwrap_or_else(|e| panic!("{e}"));
    assert!(allocated < REFUSAL_BYTES, "allocated {allocated} bytes");
    assert_eq!(file.triangle_count(), 1);
}

#[test]
fn huge_nonconvex_faces_are_refused_with_the_face_named() {
    // A zigzag polygon of 2000 corners: not convex, too large to ear-clip.
    let n = 2000;
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex {n}\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list ushort int vertex_indices\nend_header\n"
    );
    for i in 0..n - 2 {
        s += &format!("{i} {} 0\n", if i % 2 == 0 { 0.0 } else { 0.5 });
    }
    s += &format!("{} 2 0\n0 2 0\n{n}", n - 2);
    for i in 0..n {
        s += &format!(" {i}");
    }
    s.push('\n');
    let message = ply::parse(s.as_bytes(), "zigzag.ply")
        .expect_err("too large")
        .to_string();
    assert!(
        message.contains("face 0: a non-convex face has 2000 corners"),
        "{message}"
    );
}

#[test]
fn a_ply_file_is_a_scene_with_a_camera_and_light() {
    let dir = temp_dir("ply-scene");
    let path = write(
        &dir,
        "sphere.ply",
        TestMesh::sphere(12, 6).ply_binary(false),
    );
    let scene = load(&path).expect("a scene");
    assert_eq!(scene.lights.len(), 1);
    assert!(scene.camera.validate().is_ok());
    let film = render_at(&scene, 48, 36);
    let centre = film.pixels[18 * 48 + 24];
    let corner = film.pixels[0];
    assert!(centre != corner, "the mesh is in view");
    let file = load_mesh_file(&path, Materials::Read).expect("mesh");
    assert_eq!(file.defined_vertices, 13 * 7);
}

/// A mesh whose faces all have zero area (collinear corners, a corner repeated) shows
/// nothing: it is left out with a warning, and a file with nothing else is the empty-mesh
/// error, which says zero-area faces may be why. Faces with area beside them keep it in.
#[test]
fn a_mesh_of_zero_area_faces_is_left_out_with_a_warning() {
    let header = |faces: usize| {
        format!(
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
             property float z\nelement face {faces}\nproperty list uchar int vertex_indices\n\
             end_header\n0 0 0\n1e-3 0 0\n2e-3 0 0\n0 1e-3 0\n"
        )
    };
    let flat = format!("{}3 0 1 2\n3 0 0 3\n", header(2));
    let file = ply::parse(flat.as_bytes(), "flat.ply").expect("read");
    assert_eq!(file.triangle_count(), 0);
    let w = file.warnings.join("\n");
    assert!(
        w.contains("flat.ply: the mesh has only faces of zero area (2); it is left out"),
        "{w}"
    );
    let dir = temp_dir("ply-zero-area");
    let path = write(&dir, "flat.ply", flat.into_bytes());
    let err = load(&path).unwrap_err().to_string();
    assert!(err.contains("only faces of zero area"), "{err}");
    let mixed = format!("{}3 0 1 2\n3 0 1 3\n", header(2));
    let file = ply::parse(mixed.as_bytes(), "mixed.ply").expect("read");
    assert_eq!(file.triangle_count(), 2);
    assert!(file.warnings.is_empty(), "{:?}", file.warnings);
}

/// A small valid binary PLY (both byte orders) and ASCII PLY to damage.
fn fuzz_seed(which: u8) -> Vec<u8> {
    let mesh = TestMesh::sphere(4, 3);
    match which {
        0 => mesh.ply_binary(false),
        1 => mesh.ply_binary(true),
        2 => mesh.ply_ascii(),
        _ => busy_ply("binary_little_endian"),
    }
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        mutate::deletions(16),
        mutate::duplications(32),
        mutate::any_bytes(),
        (any::<usize>(), any::<u32>()).prop_map(|(at, word)| Mutation::Word { at, word }),
        (
            any::<usize>(),
            prop::sample::select(vec![0x7fff_ffffu32, u32::MAX, 0x7fc0_0000, 255, 3])
        )
            .prop_map(|(at, word)| Mutation::Word { at, word }),
        mutate::truncations(),
        mutate::numbers_from(common::mesh_files::MUTATION_VALUES),
    ]
}

proptest! {
    #![proptest_config(mutate::config(1024))]

    #[test]
    fn mutated_ply_files_never_panic_and_stay_bounded(
        which in 0u8..4,
        mutations in prop::collection::vec(mutation(), 1..5),
    ) {
        let mut bytes = fuzz_seed(which);
        for m in &mutations {
            apply(&mut bytes, m);
        }
        let (result, allocated) = allocated_by(|| ply::parse(&bytes, "fuzz.ply"));
        prop_assert!(
            allocated <= REFUSAL_BYTES + BYTES_PER_INPUT_BYTE * bytes.len(),
            "{} bytes allocated for a {}-byte file", allocated, bytes.len()
        );
        match result {
            Ok(file) => {
                // Nothing is made from nothing: every vertex and corner came from the file.
                prop_assert!(file.vertex_count() <= bytes.len());
                prop_assert!(file.triangle_count() <= bytes.len());
                for part in &file.parts {
                    prop_assert!(part.mesh.positions().iter().all(|p| p.is_finite()));
                }
            }
            Err(LoadError::Syntax { line, column, message, .. }) => {
                prop_assert!(line >= 1 && column >= 1 && !message.is_empty());
            }
            Err(LoadError::Invalid { message, .. }) => prop_assert!(!message.is_empty()),
            Err(other) => prop_assert!(false, "unexpected error kind: {other}"),
        }
    }
}

/// `element tristrips` (the Georgia Tech / Cyberware models such as igea.ply): strips
/// separated by -1, every other triangle turned back to keep the winding, zero-area joins
/// left out.
#[test]
fn triangle_strips_are_read_as_triangles_with_one_winding() {
    // A 3×2 grid of vertices in the z = 0 plane as a strip of two triangles, then a
    // restart and a strip that repeats a vertex (degenerate joins, to be dropped).
    let text = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n\
                property float z\nelement tristrips 1\nproperty list int int vertex_indices\n\
                end_header\n0 0 0\n0 1 0\n1 0 0\n1 1 0\n2 0 0\n2 1 0\n\
                11 0 1 2 3 -1 2 2 2 3 4 5\n";
    let file = ply::parse(text.as_bytes(), "strips.ply").unwrap();
    let mesh = &file.parts[0].mesh;
    // Strip 1: (0,1,2), (1,2,3)→(2,1,3). Strip 2 starts with two zero-area triangles,
    // (2,2,2) and (2,2,3), which still count for the parity: (2,3,4), then (3,4,5)→(4,3,5).
    assert_eq!(mesh.triangle_count(), 4);
    let normals: Vec<f32> = (0..mesh.triangle_count())
        .map(|t| {
            let [a, b, c] = mesh.vertices(t as u32);
            (b - a).cross(c - a).z
        })
        .collect();
    assert!(
        normals.iter().all(|&z| z < 0.0),
        "every triangle faces the same way: {normals:?}"
    );
}

#[test]
fn a_strip_index_out_of_range_names_the_strip_and_the_rule() {
    let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                property float z\nelement tristrips 1\nproperty list int int vertex_indices\n\
                end_header\n0 0 0\n0 1 0\n1 0 0\n4 0 1 2 7\n";
    let err = ply::parse(text.as_bytes(), "bad.ply")
        .unwrap_err()
        .to_string();
    assert!(err.contains("strip list 0"), "{err}");
    assert!(err.contains("or -1 between strips"), "{err}");
}
