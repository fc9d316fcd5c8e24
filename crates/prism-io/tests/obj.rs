//! The OBJ and MTL reader: the Stanford bunny's counts, objects and materials as parts,
//! the MTL illumination models, smooth normals and uvs, concave faces, OBJ files as
//! scenes and as TOML includes, errors located in the OBJ or MTL file for every kind of
//! bad input, and no panic or runaway work on mutated files.

use crate::common;

use common::mesh_files::{render_at, temp_dir, write, TestMesh};
use common::mutate::{self, apply, Mutation};
use common::work::allocated_by;

/// What parsing an OBJ text may allocate per byte of it: tobj's vectors of positions,
/// normals, uvs and indices (f32 or u32 from as little as two bytes each), prism's mesh
/// built from them and the growth of the vectors, with room to spare.
const BYTES_PER_INPUT_BYTE: usize = 512;

/// Allowance for fixed costs (a default material, small tables) on top of that.
const BASE_BYTES: usize = 1 << 20;
use common::scratch::ScratchDir;
use prism::math::{Color, Vec3};
use prism::shading::{FresnelMode, Highlight, Texture};
use prism_io::scene::mesh_file::{load_mesh_file, Materials, MeshFile};
use prism_io::scene::{load, obj, parse_toml, LoadError};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn the_stanford_bunny_loads_with_its_counts() {
    let Some(path) = common::shared_data("meshes/stanford-bunny.obj") else {
        return;
    };
    let (file, allocated) = allocated_by(|| load_mesh_file(&path, Materials::Read));
    let file = file.unwrap_or_else(|e| panic!("{e}"));
    let size = std::fs::metadata(&path).unwrap().len() as usize;
    assert_eq!(file.defined_vertices, 35_947);
    assert_eq!(file.triangle_count(), 69_451);
    // 1,113 of the file's vertices belong to no face; tobj keeps only the used ones.
    assert_eq!(file.vertex_count(), 34_834);
    assert_eq!((file.parts.len(), file.parts[0].material), (1, None));
    assert!(
        allocated <= BASE_BYTES + BYTES_PER_INPUT_BYTE * size,
        "{allocated} bytes allocated for a {size}-byte file"
    );

    let scene = load(&path).expect("the bunny is a scene");
    assert!(scene.camera.validate().is_ok());
    let film = render_at(&scene, 64, 48);
    let background = film.pixels[0];
    let covered = film.pixels.iter().filter(|&&p| p != background).count();
    assert!(
        covered > 64 * 48 / 10 && covered < 64 * 48 * 9 / 10,
        "the bunny fills part of the view: {covered} pixels"
    );
}

fn example_gems() -> MeshFile {
    load_mesh_file(&repo().join("scenes/meshes/gems.obj"), Materials::Read)
        .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn objects_and_materials_become_parts() {
    let file = example_gems();
    let names: Vec<&str> = file.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["ruby", "glass", "gold", "card"]);
    let used: Vec<Option<usize>> = file.parts.iter().map(|p| p.material).collect();
    assert_eq!(used, [Some(0), Some(1), Some(2), Some(3)]);
    let tris: Vec<usize> = file.parts.iter().map(|p| p.mesh.triangle_count()).collect();
    // Icosahedron, geosphere, star (two concave 10-gons of 8 triangles, 10 side quads),
    // card.
    assert_eq!(tris, [20, 320, 2 * 8 + 10 * 2, 2]);
    let smooth: Vec<bool> = file.parts.iter().map(|p| p.mesh.has_normals()).collect();
    assert_eq!(smooth, [false, true, false, false]);

    let card = &file.materials[3];
    let Texture::Image(_) = &card.color else {
        panic!("map_Kd makes an image texture, got {:?}", card.color);
    };
    let glass = &file.materials[1];
    assert_eq!((glass.fresnel, glass.ior), (FresnelMode::Exact, 1.5));
    assert!(glass.transmit.min_element() > 0.6 && glass.reflect > 0.0);
    assert_eq!(glass.highlight, Highlight::BlinnPhong);
}

#[test]
fn the_star_caps_are_ear_clipped_not_fanned() {
    let file = example_gems();
    let star = &file.parts[2].mesh;
    // The area of a five-pointed star (outer radius 0.9, inner 0.38) is 10 triangles of
    // the centre and two neighbouring ring points.
    let angle = std::f32::consts::PI / 5.0;
    let cap_area = 10.0 * 0.5 * 0.9 * 0.38 * angle.sin();
    let facing_z: f32 = (0..star.triangle_count() as u32)
        .map(|t| {
            let [a, b, c] = star.vertices(t);
            let n = (b - a).cross(c - a);
            if n.z.abs() > 0.99 * n.length() {
                0.5 * n.length()
            } else {
                0.0
            }
        })
        .sum();
    assert!(
        (facing_z - 2.0 * cap_area).abs() < 1e-4,
        "cap area {facing_z}, expected {}",
        2.0 * cap_area
    );
}

/// Writes `files` into a fresh folder and loads `main` from it.
fn load_files(test: &str, files: &[(&str, &str)], main: &str) -> Result<MeshFile, LoadError> {
    let dir = temp_dir(test);
    for (name, text) in files {
        write(&dir, name, text);
    }
    load_mesh_file(&dir.join(main), Materials::Read)
}

const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn mtl_statements_map_onto_whitted_materials() {
    let mtl = "newmtl flat\nKd 0.5\nillum 1\n\
               newmtl shiny\nKa 0.2 0.2 0.2\nKd 0.8 0.1 0.1\nKs 0.6 0.3 0.3\nNs 40\nillum 2\n\
               newmtl mirror\nKs 0.9 0.9 0.9\nillum 3\n\
               newmtl veil\nKd 1 1 1\nKs 0.3 0.3 0.3\nd 0.25\nillum 4\n\
               newmtl fresnel\nKs 1 1 1\nNi 1.8\nillum 5\n\
               newmtl glass\nKs 0.2 0.2 0.2\nNi 1.45\nTf 0.5 0.25 1\nillum 6\n\
               newmtl dielectric\nKs 0 0 0\nNi 1.33\nillum 7\n\
               newmtl tr\nTr 0.4\n";
    let mut obj = format!("mtllib m.mtl\n{TRIANGLE}");
    for name in [
        "flat",
        "shiny",
        "mirror",
        "veil",
        "fresnel",
        "glass",
        "dielectric",
        "tr",
    ] {
        obj += &format!("usemtl {name}\nf 1 2 3\n");
    }
    let file = load_files("illum", &[("m.obj", &obj), ("m.mtl", mtl)], "m.obj")
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(file.parts.len(), 8);
    let m = |name: &str| {
        file.materials
            .iter()
            .find(|m| m.name == name)
            .unwrap_or_else(|| panic!("{name}"))
    };
    let close = |a: f32, b: f32| (a - b).abs() < 1e-6;
    let close_rgb = |a: Color, b: Color| a.abs_diff_eq(b, 1e-6);

    let flat = m("flat");
    assert_eq!(
        flat.color,
        Texture::Solid(Color::splat(0.5)),
        "Kd r is a grey"
    );
    assert_eq!(
        (flat.specular, flat.reflect, flat.transmit),
        (0.0, 0.0, Color::ZERO)
    );
    let shiny = m("shiny");
    assert!(close(shiny.ambient, 0.2) && close(shiny.specular, 0.4));
    assert_eq!((shiny.shininess, shiny.reflect), (40.0, 0.0));
    let mirror = m("mirror");
    assert!(close(mirror.reflect, 0.9) && close(mirror.specular, 0.9));
    let veil = m("veil");
    assert!(close_rgb(veil.transmit, Color::splat(0.75)) && close(veil.diffuse, 0.25));
    assert_eq!(veil.ior, 1.0, "dissolve passes light straight through");
    let fresnel = m("fresnel");
    assert_eq!(
        (fresnel.fresnel, fresnel.ior, fresnel.reflect),
        (FresnelMode::Exact, 1.8, 1.0)
    );
    let glass = m("glass");
    // (1 − Ks)·Tf per channel: the filter's colour is kept.
    assert!(close_rgb(glass.transmit, 0.8 * Color::new(0.5, 0.25, 1.0)));
    assert!(close(glass.reflect, 0.2));
    assert_eq!((glass.ior, glass.fresnel), (1.45, FresnelMode::Off));
    let dielectric = m("dielectric");
    assert_eq!(
        (dielectric.transmit, dielectric.fresnel, dielectric.ior),
        (Color::ONE, FresnelMode::Exact, 1.33)
    );
    assert!(close_rgb(m("tr").transmit, Color::splat(0.4)));
}

#[test]
fn normals_uvs_and_relative_indices() {
    // Negative indices count back from the latest vertex; w divides the coordinates.
    let obj = "v 0 0 0\nv 2 0 0 2\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 2\n\
               f -3/-3/-1 -2/-2/-1 -1/-1/-1\n";
    let file = load_files("relative", &[("r.obj", obj)], "r.obj").expect("valid");
    let mesh = &file.parts[0].mesh;
    assert_eq!(
        mesh.positions(),
        &[
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0)
        ]
    );
    assert!(mesh.has_normals());
    let hit = prism::geometry::ShapeHit {
        t: 1.0,
        u: 1.0,
        v: 0.0,
    };
    let surface = mesh.surface(0, &hit);
    assert!((surface.uv - prism::math::Vec2::new(1.0, 0.0)).length() < 1e-6);
    assert!((surface.ns - Vec3::Z).length() < 1e-6);
}

#[test]
fn an_obj_file_renders_as_a_scene_like_its_ply_twin() {
    let mesh = TestMesh::sphere(12, 6);
    let dir = temp_dir("obj-scene");
    let obj = write(&dir, "s.obj", mesh.obj());
    let ply = write(&dir, "s.ply", mesh.ply_binary(false));
    let a = load(&obj).expect("obj scene");
    let b = load(&ply).expect("ply scene");
    assert_eq!(a.camera, b.camera);
    assert_eq!(a.lights, b.lights);
    assert_eq!(
        common::mesh_files::max_difference(&render_at(&a, 64, 48), &render_at(&b, 64, 48)),
        0.0
    );
}

#[test]
fn toml_includes_keep_the_files_materials_or_replace_them() {
    let dir = temp_dir("include");
    write(&dir, "m.mtl", "newmtl red\nKd 1 0 0\n");
    write(
        &dir,
        "m.obj",
        format!("mtllib m.mtl\n{TRIANGLE}f 3 2 1\ng painted\nusemtl red\nf 1 2 3\n"),
    );
    let scene_at = |text: &str| parse_toml(text, &dir.join("scene.toml"));

    let own = scene_at("[[objects]]\ntype = \"mesh\"\nfile = \"m.obj\"\n").expect("valid");
    let names: Vec<&str> = own
        .geometry
        .primitives
        .iter()
        .map(|p| own.materials[p.material as usize].name.as_str())
        .collect();
    // Faces before any usemtl take the scene's default material.
    assert_eq!(names, ["default", "red"]);

    let replaced = scene_at(
        "[materials.blue]\ncolor = [0, 0, 1]\n[[objects]]\ntype = \"mesh\"\nfile = \"m.obj\"\n\
         material = \"blue\"\ntransform = { scale = [-2, 1, 1], translate = [0, 0, 5] }\n",
    )
    .expect("valid");
    assert_eq!(
        replaced.materials.len(),
        1,
        "the file's library is not read"
    );
    assert!(replaced.geometry.primitives.iter().all(|p| p.material == 0));
    // The second part is the face `f 1 2 3`, counter-clockwise seen from +z.
    let mesh = &replaced.geometry.meshes[1];
    assert_eq!(mesh.positions()[1], Vec3::new(-2.0, 0.0, 5.0));
    // The mirroring scale turned the winding around: the face still faces +z.
    let [a, b, c] = mesh.vertices(0);
    assert!((b - a).cross(c - a).z > 0.0);

    // A library that is missing does not matter when the scene gives the material.
    write(
        &dir,
        "lost.obj",
        format!("mtllib nowhere.mtl\n{TRIANGLE}usemtl x\nf 1 2 3\n"),
    );
    let text =
        "[materials.m]\n[[objects]]\ntype = \"mesh\"\nfile = \"lost.obj\"\nmaterial = \"m\"\n";
    assert!(scene_at(text).is_ok());
    // Without one, the faces take the default material and the scene says why (other
    // viewers do the same: downloaded models often come without their library).
    let scene = scene_at("[[objects]]\ntype = \"mesh\"\nfile = \"lost.obj\"\n")
        .expect("a missing library is a warning");
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    let warning = &scene.warnings[0];
    assert!(
        warning.contains("lost.obj:1:8: the material library")
            && warning.contains("nowhere.mtl is missing"),
        "{warning}"
    );
    assert_eq!(
        scene.materials[scene.geometry.primitives[0].material as usize].name,
        "default"
    );
}

/// (what, TOML text, line, column, phrase) for includes that go wrong.
const BAD_INCLUDES: &[(&str, &str, usize, usize, &str)] = &[
    (
        "missing file",
        "[[objects]]\ntype = \"mesh\"\nfile = \"no-such.obj\"\n",
        3,
        8,
        "cannot load the mesh file: ",
    ),
    (
        "wrong extension",
        "[[objects]]\ntype = \"mesh\"\nfile = \"mesh.stl\"\n",
        3,
        8,
        "expected a mesh file ending in .obj or .ply, found \"mesh.stl\"",
    ),
    (
        "file and positions",
        "[[objects]]\ntype = \"mesh\"\nfile = \"m.obj\"\npositions = [[0, 0, 0]]\n",
        3,
        8,
        "either `file` or `positions`",
    ),
    (
        "neither",
        "[[objects]]\ntype = \"mesh\"\nmaterial = \"x\"\n",
        3,
        12,
        "unknown material",
    ),
    (
        "nothing",
        "[[objects]]\ntype = \"mesh\"\n",
        1,
        1,
        "a mesh needs `positions` and `indices` (a mesh written out) or `file`",
    ),
    (
        "error inside the mesh file",
        "[[objects]]\ntype = \"mesh\"\nfile = \"bad.obj\"\n",
        3,
        8,
        "bad.obj:2:5: expected y (a number), found 'x'",
    ),
];

#[test]
fn bad_includes_point_at_the_scene_and_into_the_mesh_file() {
    let dir = temp_dir("bad-includes");
    write(&dir, "m.obj", format!("{TRIANGLE}f 1 2 3\n"));
    write(&dir, "bad.obj", "v 0 0 0\nv 1 x 0\n");
    for &(what, text, line, column, phrase) in BAD_INCLUDES {
        let error = parse_toml(text, &dir.join("scene.toml")).expect_err(what);
        let message = error.to_string();
        match error {
            LoadError::Syntax {
                line: l, column: c, ..
            } => assert_eq!((l, c), (line, column), "{what}: `{message}`"),
            other => panic!("{what}: expected a located error, got {other}"),
        }
        assert!(
            message.contains(phrase),
            "{what}: `{message}` lacks `{phrase}`"
        );
    }
}

/// (what, OBJ text, line, column, phrase); `lib.mtl` defines `red` and `green`.
const MALFORMED_OBJ: &[(&str, &str, usize, usize, &str)] = &[
    ("two coordinates", "v 1 2\n", 1, 6, "a vertex takes 3 numbers (x y z), 4 (x y z w) or 6 (x y z r g b); found 2"),
    ("not a number", "v 1 2 x\n", 1, 7, "expected z (a number), found 'x'"),
    ("nan", "v 1 nan 3\n", 1, 5, "expected y (a finite number), found 'nan'"),
    ("zero weight", "v 1 2 3 0\n", 1, 9, "expected a weight w other than 0"),
    ("five numbers", "v 1 2 3 4 5\n", 1, 9, "found 5"),
    ("bad uv", "vt 0.5 x\n", 1, 8, "expected v (a number), found 'x'"),
    ("short normal", "vn 0 1\n", 1, 7, "a normal takes 3 numbers (x y z); found 2"),
    ("two corners", "v 0 0 0\nv 1 0 0\nf 1 2\n", 3, 1, "a face needs at least 3 corners; found 2"),
    (
        "index past the end",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
        4,
        7,
        "the face refers to vertex 4, but only 3 vertices (v) are defined above it: expected 1 to 3",
    ),
    ("index zero", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", 4, 7, "vertex indices start at 1"),
    (
        "vertex defined below the face",
        "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n",
        3,
        7,
        "the face refers to vertex 3, but only 2 vertices (v) are defined above it",
    ),
    (
        "relative index too far back",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n",
        4,
        9,
        "relative vertex index -4 reaches before the first one: only 3 vertices (v) are defined",
    ),
    (
        "uv without any",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n",
        4,
        5,
        "the face refers to texture coordinate 1, but no texture coordinates (vt) are defined above it",
    ),
    (
        "normal index word",
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//n 3//1\n",
        5,
        11,
        "expected a normal index (a whole number), found 'n'",
    ),
    ("four parts", "v 0 0 0\nf 1/1/1/1 1 1\n", 2, 3, "expected a face corner v, v/vt, v//vn or v/vt/vn"),
    (
        "unknown material",
        "mtllib lib.mtl\nusemtl blue\n",
        2,
        8,
        "unknown material 'blue': expected one of 'green', 'red'",
    ),
    (
        "material before its library",
        "usemtl red\nmtllib lib.mtl\n",
        1,
        8,
        "no material library (mtllib) defines materials above this line",
    ),
    (
        "unreadable library",
        "mtllib .\n",
        1,
        8,
        "cannot read the material library",
    ),
    ("empty mtllib", "mtllib\n", 1, 7, "expected a material library file name"),
    ("continuation", "v 1 2 3 \\\n", 1, 9, "line continuation"),
];

#[test]
fn malformed_obj_names_the_line_column_and_expectation() {
    let dir = temp_dir("malformed-obj");
    write(
        &dir,
        "lib.mtl",
        "newmtl red\nKd 1 0 0\nnewmtl green\nKd 0 1 0\n",
    );
    for &(what, text, line, column, phrase) in MALFORMED_OBJ {
        let path = dir.join("bad.obj");
        let error = match obj::parse(text, &path, Materials::Read) {
            Err(e) => e,
            Ok(_) => panic!("{what}: loaded without error"),
        };
        assert_located(&error, "bad.obj", (line, column), phrase, what);
    }
}

/// Asserts that `error` is a syntax error at `line`:`column` of a file whose path ends in
/// `file`, and that its message says `phrase`.
#[track_caller]
fn assert_located(
    error: &LoadError,
    file: &str,
    (line, column): (usize, usize),
    phrase: &str,
    what: &str,
) {
    let message = error.to_string();
    match error {
        LoadError::Syntax {
            path,
            line: l,
            column: c,
            ..
        } => {
            assert!(path.ends_with(file), "{what}: {path}");
            assert_eq!((*l, *c), (line, column), "{what}: `{message}`");
        }
        other => panic!("{what}: expected a located error, got {other:?}"),
    }
    assert!(
        message.contains(phrase),
        "{what}: `{message}` lacks `{phrase}`"
    );
}

#[test]
fn comments_blanks_and_unused_statements_are_accepted() {
    let obj = "# header\n  v 0 0 0 # trailing comment\r\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0\n\
               s 1\nl 1 2 3\np 1\ncstype bezier\n\tg  group   one \nf 1 2 3\n";
    let file =
        obj::parse(obj, Path::new("ok.obj"), Materials::Read).unwrap_or_else(|e| panic!("{e}"));
    // The polyline `l 1 2 3` is not a face.
    assert_eq!(file.triangle_count(), 1);
    assert_eq!(file.parts.len(), 1);
}

/// (what, MTL text, line, column, phrase).
const MALFORMED_MTL: &[(&str, &str, usize, usize, &str)] = &[
    (
        "before newmtl",
        "Kd 1 0 0\n",
        1,
        1,
        "comes before any material: expected newmtl NAME first",
    ),
    (
        "two components",
        "newmtl a\nKd 1 0\n",
        2,
        7,
        "expected Kd r g b (or one number for a grey); found 2",
    ),
    (
        "negative colour",
        "newmtl a\nKs 1 -1 0\n",
        2,
        6,
        "expected a colour component ≥ 0, found -1",
    ),
    (
        "spectral",
        "newmtl a\nKd spectral file.rfl\n",
        2,
        4,
        "'Kd spectral' colours are not supported",
    ),
    (
        "bad exponent",
        "newmtl a\nNs x\n",
        2,
        4,
        "expected the highlight exponent Ns (a finite number), found 'x'",
    ),
    (
        "dissolve range",
        "newmtl a\nd 1.5\n",
        2,
        3,
        "expected the dissolve d (opacity) from 0 to 1, found 1.5",
    ),
    (
        "halo",
        "newmtl a\nd -halo 0.5\n",
        2,
        9,
        "one number; found 2 values",
    ),
    (
        "illum range",
        "newmtl a\nillum 12\n",
        2,
        7,
        "a whole number from 0 to 10; found '12'",
    ),
    (
        "zero ior",
        "newmtl a\nNi 0\n",
        2,
        4,
        "expected the index of refraction Ni > 0, found 0",
    ),
    (
        "no name",
        "newmtl\n",
        1,
        7,
        "expected a material name after newmtl",
    ),
    (
        "unreadable image",
        "newmtl a\nmap_Kd -s 2 2 bad.mtl\n",
        2,
        15,
        "expected a readable PNG or JPEG image for map_Kd",
    ),
    (
        "unknown option",
        "newmtl a\nmap_Kd -q 1 x.png\n",
        2,
        8,
        "unknown map_Kd option '-q'",
    ),
    (
        "bad scale",
        "newmtl a\nmap_Kd -s 0 1 x.png\n",
        2,
        8,
        "expected a map_Kd scale -s > 0",
    ),
];

#[test]
fn malformed_mtl_is_located_in_the_library() {
    let dir = temp_dir("malformed-mtl");
    for &(what, text, line, column, phrase) in MALFORMED_MTL {
        write(&dir, "bad.mtl", text);
        let obj = format!("mtllib bad.mtl\n{TRIANGLE}f 1 2 3\n");
        let error = match obj::parse(&obj, &dir.join("m.obj"), Materials::Read) {
            Err(e) => e,
            Ok(_) => panic!("{what}: loaded without error"),
        };
        assert_located(&error, "bad.mtl", (line, column), phrase, what);
    }
}

#[test]
fn texture_maps_resolve_against_the_library_and_keep_their_scale() {
    let dir = temp_dir("texture");
    std::fs::create_dir_all(dir.join("maps")).expect("dir");
    std::fs::copy(
        repo().join("scenes/textures/testcard.png"),
        dir.join("maps/card.png"),
    )
    .expect("copy");
    std::fs::create_dir_all(dir.join("lib")).expect("dir");
    write(
        &dir.join("lib"),
        "m.mtl",
        "newmtl a\nKd 0.5 0.5 0.5\nmap_Kd -blendu on -s 2 3 1 ..\\maps\\card.png\n",
    );
    let obj = format!("mtllib lib/m.mtl\n{TRIANGLE}usemtl a\nf 1 2 3\n");
    let file =
        obj::parse(&obj, &dir.join("m.obj"), Materials::Read).unwrap_or_else(|e| panic!("{e}"));
    let a = &file.materials[0];
    let Texture::Image(image) = &a.color else {
        panic!("expected an image, got {:?}", a.color);
    };
    assert_eq!(image.scale, prism::math::Vec2::new(2.0, 3.0));
    assert_eq!(a.diffuse, 0.5, "Kd weighs the texture");
}

/// A folder laid out like scenes/ (meshes/ beside textures/), so that a mutated copy of
/// gems.mtl still finds its image; the .mtl goes into `meshes/`.
fn mtl_fuzz_dir() -> ScratchDir {
    let root = temp_dir("mtl-fuzz");
    std::fs::create_dir_all(root.join("meshes")).expect("dir");
    std::fs::create_dir_all(root.join("textures")).expect("dir");
    std::fs::copy(
        repo().join("scenes/textures/testcard.png"),
        root.join("textures/testcard.png"),
    )
    .expect("copy");
    root
}

const MUTATION_BYTES: &[u8] = b"vtnfgo/#-. \n\t0123456789e";

/// The text damages and, as often as each of them, a file cut short.
fn mutation() -> impl Strategy<Value = Mutation> {
    let values = common::mesh_files::MUTATION_VALUES;
    prop_oneof![
        5 => mutate::text_damage(16, 48, MUTATION_BYTES, values),
        1 => mutate::truncations(),
    ]
}

fn check_result(result: Result<MeshFile, LoadError>, size: usize) -> Result<(), TestCaseError> {
    match result {
        Ok(file) => {
            prop_assert!(file.triangle_count() <= size);
            for part in &file.parts {
                prop_assert!(part.mesh.positions().iter().all(|p| p.is_finite()));
            }
        }
        Err(LoadError::Syntax {
            line,
            column,
            message,
            ..
        }) => {
            prop_assert!(line >= 1 && column >= 1 && !message.is_empty());
        }
        Err(LoadError::Invalid { message, .. }) => {
            prop_assert!(
                !message.contains("tobj"),
                "prism's checks missed: {message}"
            );
        }
        Err(other) => prop_assert!(false, "unexpected error kind: {other}"),
    }
    Ok(())
}

proptest! {
    #![proptest_config(mutate::config(512))]

    #[test]
    fn mutated_obj_files_never_panic(
        which in 0usize..2,
        mutations in prop::collection::vec(mutation(), 1..5),
    ) {
        let gems = repo().join("scenes/meshes/gems.obj");
        let original = if which == 0 {
            std::fs::read(&gems).expect("gems.obj")
        } else {
            TestMesh::sphere(5, 4).obj().into_bytes()
        };
        let mut bytes = original;
        for m in &mutations {
            apply(&mut bytes, m);
        }
        let text = String::from_utf8_lossy(&bytes);
        let (result, allocated) = allocated_by(|| obj::parse(&text, &gems, Materials::Read));
        prop_assert!(
            allocated <= BASE_BYTES + BYTES_PER_INPUT_BYTE * bytes.len(),
            "{} bytes allocated for a {}-byte file", allocated, bytes.len()
        );
        check_result(result, bytes.len())?;
    }

    #[test]
    fn mutated_mtl_files_never_panic(mutations in prop::collection::vec(mutation(), 1..4)) {
        let mtl = std::fs::read(repo().join("scenes/meshes/gems.mtl")).expect("gems.mtl");
        let mut bytes = mtl;
        for m in &mutations {
            apply(&mut bytes, m);
        }
        let root = mtl_fuzz_dir();
        let dir = root.join("meshes");
        std::fs::write(dir.join("fuzz.mtl"), &bytes).expect("write");
        let obj = format!("mtllib fuzz.mtl\n{TRIANGLE}usemtl ruby\nf 1 2 3\n");
        let result = obj::parse(&obj, &dir.join("fuzz.obj"), Materials::Read);
        check_result(result, 1)?;
    }
}

#[test]
fn mtl_ke_makes_an_area_light() {
    let mtl = "newmtl lamp\nKd 0.5\nKe 4 2 1\nnewmtl plain\nKd 0.5\n";
    let obj = format!("mtllib m.mtl\n{TRIANGLE}usemtl lamp\nf 1 2 3\nusemtl plain\nf 1 3 2\n");
    let file = load_files("ke", &[("m.obj", &obj), ("m.mtl", mtl)], "m.obj")
        .unwrap_or_else(|e| panic!("{e}"));
    let m = |name: &str| file.materials.iter().find(|m| m.name == name).unwrap();
    assert_eq!(m("lamp").emission, Color::new(4.0, 2.0, 1.0));
    assert_eq!(m("plain").emission, Color::ZERO);
    let bad = load_files(
        "ke-bad",
        &[("m.obj", &obj), ("m.mtl", "newmtl lamp\nKe 1 x 2\n")],
        "m.obj",
    );
    assert!(bad.is_err());
}

/// A missing map_Kd image is a warning naming the library, line and column (as a missing
/// library is): the material keeps its colour. Texture maps prism does not render are named
/// once per library.
#[test]
fn a_missing_texture_is_a_warning_and_unrendered_maps_are_named() {
    let dir = temp_dir("missing-texture");
    write(
        &dir,
        "lib.mtl",
        "newmtl a\nKd 0.2 0.4 0.6\nmap_Kd missing.png\nmap_Bump bumps.png\nnorm -o 1 n.png\n\
         map_Ks spec.png\n",
    );
    let obj = format!("mtllib lib.mtl\nusemtl a\n{TRIANGLE}f 1 2 3\n");
    let scene = obj::parse(&obj, &dir.join("m.obj"), Materials::Read).unwrap();
    let material = scene
        .materials
        .iter()
        .find(|m| m.name == "a")
        .expect("material a");
    assert_eq!(
        material.color,
        prism::shading::Texture::Solid(prism::math::Color::new(0.2, 0.4, 0.6))
    );
    let w = scene.warnings.join("\n");
    assert!(
        w.contains("lib.mtl:3:8: the map_Kd image") && w.contains("missing.png is missing"),
        "{w}"
    );
    assert!(
        w.contains("lib.mtl:4:10: the map_Bump image") && w.contains("lib.mtl:5:11: the norm"),
        "{w}"
    );
    assert!(
        w.contains("read but not rendered: map_Ks, norm -o ("),
        "{w}"
    );
}

/// A quad in the z = 0 plane, u along +x and v along +y, its material `mtl` (which names
/// its images in `images`), seen head on by Whitted's tracer with one directional light
/// from `to_light` and nothing else: the centre pixel, at uv (0.5, 0.5), is the Lambert
/// term of its shading normal.
fn lambert_at_centre(
    test: &str,
    mtl: &str,
    images: &[(&str, image::RgbImage)],
    to_light: Vec3,
) -> f32 {
    let dir = temp_dir(test);
    for (name, img) in images {
        img.save(dir.join(name)).unwrap();
    }
    write(
        &dir,
        "q.mtl",
        format!("newmtl q\nKd 1 1 1\nKa 0 0 0\nillum 1\n{mtl}\n"),
    );
    let obj = "mtllib q.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n\
               vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nusemtl q\n\
               f 1/1/1 2/2/1 3/3/1 4/4/1\n";
    let mut scene = load(&write(&dir, "q.obj", obj)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let sun = prism::light::Light::Directional {
        direction: -to_light.normalize(),
        color: Color::ONE,
    };
    common::mesh_files::head_on(&mut scene, vec![sun], 0.0, 0.0);
    render_at(&scene, 9, 9).get(4, 4).x
}

/// MTL's `norm` is a tangent-space normal map in the frame the triangle's uvs give (OBJ
/// has no tangents), its texels read as data and `-bm` scaling their x and y: a map
/// tilting the normal towards +u gives the Lambert term of the tilted normal.
#[test]
fn mtl_norm_is_a_normal_map() {
    let texel = [191u8, 128, 255];
    let img = image::RgbImage::from_pixel(2, 2, image::Rgb(texel));
    let to_light = Vec3::new(1.0, 0.0, 1.0);
    for (bm, option) in [(1.0, ""), (0.5, "-bm 0.5 ")] {
        let got = lambert_at_centre(
            "norm",
            &format!("norm {option}n.png"),
            &[("n.png", img.clone())],
            to_light,
        );
        let c = texel.map(|v| 2.0 * v as f32 / 255.0 - 1.0);
        let n = Vec3::new(c[0] * bm, c[1] * bm, c[2]).normalize();
        let expected = n.dot(to_light.normalize());
        assert!(
            (got - expected).abs() < 1e-4,
            "-bm {bm}: {got} against {expected}"
        );
    }
    let flat = lambert_at_centre("norm-flat", "", &[], to_light);
    assert!(
        (flat - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-4,
        "{flat}"
    );
}

/// MTL's `bump` and `map_Bump` are height maps: a ramp rising by 1/15 a texel across 16
/// texels, scaled by `-bm 0.5`, on a quad two units wide, rises 4/15 per unit of length, so
/// it tilts the normal by atan(4/15) away from +x: lit along the tilted normal the centre
/// shows exactly 1 (a flat quad shows cos(atan(4/15))), lit from the mirrored side
/// cos(2·atan(4/15)).
#[test]
fn mtl_bump_tilts_the_normal_by_the_ramps_slope() {
    let ramp = image::RgbImage::from_fn(16, 1, |x, _| {
        let v = (x * 17) as u8;
        image::Rgb([v, v, v])
    });
    let tilt = (4.0f32 / 15.0).atan();
    let along = Vec3::new(-tilt.sin(), 0.0, tilt.cos());
    let mirrored = Vec3::new(tilt.sin(), 0.0, tilt.cos());
    for keyword in ["bump", "map_Bump"] {
        let mtl = format!("{keyword} -bm 0.5 ramp.png");
        let images = [("ramp.png", ramp.clone())];
        let lit = lambert_at_centre("bump", &mtl, &images, along);
        assert!((lit - 1.0).abs() < 1e-4, "{keyword}: {lit}");
        let other = lambert_at_centre("bump-mirrored", &mtl, &images, mirrored);
        let expected = (2.0 * tilt).cos();
        assert!(
            (other - expected).abs() < 1e-4,
            "{keyword}: {other} against {expected}"
        );
    }
    let flat = lambert_at_centre("bump-flat", "", &[], along);
    assert!((flat - tilt.cos()).abs() < 1e-4, "{flat}");
}

/// An object whose faces all have zero area (collinear or repeated corners) is left out
/// with a warning naming it; the file's other objects load. A file with nothing else is
/// the empty-mesh error, which says zero-area faces may be why.
#[test]
fn an_object_of_zero_area_faces_is_a_warning() {
    let dir = temp_dir("obj-zero-area");
    let text = "o flat\nv 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nf 1 2 3\nf 1 2 4 3\n\
                o real\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf 5 6 7\n";
    let path = write(&dir, "flat.obj", text);
    let scene = load(&path).unwrap();
    let w = scene.warnings.join("\n");
    assert!(
        w.contains("object 'flat' has only faces of zero area (2); it is left out"),
        "{w}"
    );
    assert!(!w.contains("'real'"), "{w}");
    let only = write(
        &dir,
        "only.obj",
        "v 0 0 0\nv 1e-3 0 0\nv 2e-3 0 0\nf 1 2 3\n",
    );
    let err = load(&only).unwrap_err().to_string();
    assert!(err.contains("only faces of zero area"), "{err}");
}

/// What an OBJ file or its library holds and the picture will not show is named in one
/// warning per file: free-form geometry, smoothing groups (faces without normals stay
/// flat), the PBR extension's scalars; smoothing switched off is nothing dropped.
#[test]
fn statements_read_and_not_rendered_are_named_once_per_file() {
    let dir = temp_dir("obj-unrendered");
    write(&dir, "lib.mtl", "newmtl a\nKd 0.5\nPr 0.3\nPm 1\n");
    let obj = format!(
        "mtllib lib.mtl\nusemtl a\n{TRIANGLE}s 1\nf 1 2 3\ncstype bspline\ncurv 0 1 1 2\n\
         curv 0 1 2 3\ns off\n"
    );
    let scene = load(&write(&dir, "m.obj", &obj)).unwrap();
    let w = scene.warnings.join("\n");
    assert_eq!(scene.warnings.len(), 2, "{w}");
    assert!(
        w.contains("m.obj: read but not rendered: free-form curves and surfaces")
            && w.contains("smoothing groups (s)"),
        "{w}"
    );
    assert!(
        w.contains("lib.mtl: read but not rendered: Pm, Pr ("),
        "{w}"
    );
    let quiet = format!("{TRIANGLE}s off\ns 0\nf 1 2 3\nl 1 2\n");
    let scene = load(&write(&dir, "quiet.obj", &quiet)).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}
