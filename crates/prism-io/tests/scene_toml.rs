//! The TOML scene format end to end: the example scenes load and render, scenes/whitted.toml
//! is the built-in Whitted scene, malformed files give errors that point at the right line
//! with a useful phrase, and no mutation of a valid file makes the loader panic.

use crate::common;

use common::mesh_files::render_at;
use common::mutate::{self, apply, Mutation};
use common::scratch::ScratchDir;
use prism::geometry::ShapeHit;
use prism::math::{Color, Vec3};
use prism::scene::builtin;
use prism::shading::Texture;
use prism::Scene;
use prism_io::scene::{load, parse_toml, LoadError};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn scene_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(scenes_dir())
        .expect("the scenes folder exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

/// Parses `text` as if it were a file in scenes/ (so relative texture paths resolve).
fn parse(text: &str) -> Result<Scene, LoadError> {
    parse_toml(text, &scenes_dir().join("test.toml"))
}

#[test]
fn every_example_scene_loads_and_renders() {
    let files = scene_files();
    assert!(
        files.len() >= 2,
        "expected at least whitted.toml and shapes.toml, found {files:?}"
    );
    for file in files {
        let scene = load(&file).unwrap_or_else(|e| panic!("{e}"));
        let film = render_at(&scene, 32, 24);
        assert!(
            film.pixels
                .iter()
                .all(|p| p.is_finite() && p.min_element() >= 0.0),
            "{}: non-finite or negative pixels",
            file.display()
        );
        let first = film.pixels[0];
        assert!(
            film.pixels
                .iter()
                .any(|&p| (p - first).abs().max_element() > 0.01),
            "{}: the image is one flat colour",
            file.display()
        );
    }
}

#[test]
fn whitted_toml_renders_the_builtin_whitted_image() {
    let from_file = load(&scenes_dir().join("whitted.toml")).unwrap_or_else(|e| panic!("{e}"));
    let built_in = builtin::find("whitted").expect("the built-in exists");
    assert_eq!(from_file.options, built_in.options);
    assert_eq!(from_file.camera, built_in.camera);
    assert_eq!(from_file.lights, built_in.lights);
    assert_eq!(
        from_file.geometry.primitives.len(),
        built_in.geometry.primitives.len()
    );
    let (a, b) = (
        render_at(&from_file, 320, 240),
        render_at(&built_in, 320, 240),
    );
    let mut worst = 0.0f32;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        worst = worst.max((*p - *q).abs().max_element());
    }
    assert!(worst <= 1e-4, "largest pixel difference {worst}");
}

#[test]
fn the_worked_example_in_the_docs_renders() {
    let doc = include_str!("../../../docs/scene-format.md");
    let section = doc
        .split("## A worked example")
        .nth(1)
        .expect("the docs have a worked example");
    let example = section
        .split("```toml\n")
        .nth(1)
        .and_then(|s| s.split("```").next())
        .expect("the example is a toml block");
    let scene = parse(example).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.geometry.primitives.len(), 2);
    let film = render_at(&scene, 32, 24);
    assert!(film.pixels.iter().all(|p| p.is_finite()));
}

/// (what, file text, line the error must name, phrase the message must contain)
const MALFORMED: &[(&str, &str, usize, &str)] = &[
    (
        "unknown sampler",
        "[render]\nsampler = \"stratified\"\n",
        2,
        "`jittered`",
    ),
    (
        "unknown filter",
        "[render]\n\nfilter = \"lanczos\"\n",
        3,
        "`mitchell`",
    ),
    (
        "filter radius out of range",
        "\n[render]\nfilter_radius = 0.1\n",
        2,
        "filter_radius must be between 0.5 and 8",
    ),
    (
        "adaptive depth out of range",
        "\n[render]\nadaptive_depth = 9\n",
        2,
        "adaptive_depth must be between 0 and 6",
    ),
    (
        "adaptive texture spp not a square",
        "\n[render]\nadaptive_texture_spp = 8\n",
        2,
        "adaptive_texture_spp must be 0 or a square number up to 1024, got 8",
    ),
    (
        "adaptive rule",
        "[render]\nadaptive_rule = \"edges\"\n",
        2,
        "`neighbourhood`",
    ),
    (
        "TOML syntax",
        "[camera]\neye = [0, 1, 2\n",
        2,
        "expected `]`",
    ),
    (
        "text after a value",
        "[world]\nambient = [0.2, 0.2, 0.2] 0.3\n",
        2,
        "expected newline",
    ),
    (
        "duplicate key",
        "[camera]\nfov = 40\nfov = 50\n",
        3,
        "duplicate key",
    ),
    (
        "unknown table",
        "[render]\nwidth = 8\n\n[camra]\nfov = 40\n",
        4,
        "unknown key `camra`",
    ),
    (
        "unknown render option",
        "[render]\nwidht = 8\n",
        2,
        "unknown key `widht`",
    ),
    (
        "render option of the wrong type",
        "[render]\nwidth = \"big\"\n",
        2,
        "expected a whole number",
    ),
    (
        "render option out of range",
        "\n[render]\nsamples = 0\n",
        2,
        "samples must be between 1 and 64",
    ),
    (
        "unknown accelerator",
        "[render]\naccel = \"kd-tree\"\n",
        2,
        "expected one of: brute-force, bvh, grid, kdtree, octree",
    ),
    (
        "accelerator parameter out of range",
        "[render]\n\naccel = \"bvh:leaf=0\"\n",
        3,
        "bad value '0' for 'leaf': expected an integer from 1 to 1024",
    ),
    (
        "accelerator parameter of another method",
        "[render]\naccel = \"grid:leaf=2\"\n",
        2,
        "unknown parameter 'leaf' for grid",
    ),
    (
        "vector of the wrong length",
        "[camera]\neye = [0, 1]\n",
        2,
        "expected an array of 3 numbers",
    ),
    (
        "nan",
        "[camera]\n\neye = [0, nan, 1]\n",
        3,
        "expected a finite number, got nan",
    ),
    (
        "infinity",
        "[world]\nambient = inf\n",
        2,
        "expected a finite number",
    ),
    (
        "beyond f32",
        "[camera]\nfov = 1e39\n",
        2,
        "beyond the ±3.4e38 range",
    ),
    (
        "string for a number",
        "[materials.m]\nshininess = \"high\"\n",
        2,
        "expected a finite number",
    ),
    (
        "eye at look_at",
        "[camera]\neye = [1, 2, 3]\nlook_at = [1, 2, 3]\n",
        3,
        "expected look_at to differ from eye",
    ),
    (
        "up along the view",
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\n",
        4,
        "not parallel",
    ),
    (
        "field of view",
        "[camera]\nfov = 0\n",
        2,
        "greater than 0 and less than 180",
    ),
    (
        "negative colour",
        "[world]\nbackground = [0.1, -0.2, 0.3]\n",
        2,
        "colour components ≥ 0",
    ),
    (
        "unknown transfer",
        "[render]\ntransfer = \"gamma\"\n",
        2,
        "unknown variant `gamma`",
    ),
    (
        "transmit of two channels",
        "[materials.m]\ntransmit = [1, 0.2]\n",
        2,
        "a colour: [r, g, b] or one number for a grey",
    ),
    (
        "negative transmit channel",
        "[materials.m]\ntransmit = [1, -0.2, 0]\n",
        2,
        "colour components ≥ 0",
    ),
    (
        "unknown material key",
        "[materials.m]\ncolour = [1, 0, 0]\n",
        2,
        "unknown key `colour`",
    ),
    (
        "negative weight",
        "[materials.m]\nreflect = -0.5\n",
        2,
        "expected a number ≥ 0",
    ),
    (
        "zero ior",
        "[materials.m]\nior = 0\n",
        2,
        "expected a number > 0",
    ),
    (
        "unknown highlight",
        "[materials.m]\nhighlight = \"blinn\"\n",
        2,
        "expected `phong` or `blinn-phong`",
    ),
    (
        "fresnel of the wrong type",
        "[materials.m]\nfresnel = true\n",
        2,
        "expected a quoted name",
    ),
    (
        "colour and texture",
        "[materials.m]\ncolor = 1\ntexture = { type = \"solid\", color = 1 }\n",
        3,
        "either `color` or `texture`",
    ),
    (
        "texture without type",
        "[materials.m]\ntexture = { a = 1, b = 0 }\n",
        2,
        "needs a `type`",
    ),
    (
        "unknown texture type",
        "[materials.m]\ntexture = { type = \"marble\" }\n",
        2,
        "unknown variant `marble`",
    ),
    (
        "checker without b",
        "[materials.m]\ntexture = { type = \"checker\", a = 1 }\n",
        2,
        "missing key `b`",
    ),
    (
        "unreadable image file",
        "[materials.m]\n\ntexture = { type = \"image\", path = \".\" }\n",
        3,
        "expected a readable PNG or JPEG image",
    ),
    (
        "unknown light type",
        "[[lights]]\ntype = \"area\"\nposition = [0, 0, 0]\n",
        2,
        "`directional`, `spot`",
    ),
    (
        "light without position",
        "[world]\nambient = 0.1\n\n[[lights]]\ntype = \"point\"\n",
        4,
        "missing key `position`",
    ),
    (
        "zero light direction",
        "[[lights]]\ntype = \"directional\"\ndirection = [0, 0, 0]\n",
        3,
        "non-zero length",
    ),
    (
        "negative intensity",
        "[[lights]]\ntype = \"point\"\nposition = [0, 1, 0]\nintensity = -2\n",
        4,
        "expected a number ≥ 0",
    ),
    (
        "object that is not a table",
        "# objects\nobjects = [\n  3,\n]\n",
        3,
        "expected an object as a table with a `type`",
    ),
    (
        "camera that is not a table",
        "camera = \"front\"\n",
        1,
        "invalid type: string \"front\", expected a table",
    ),
    (
        "object without type",
        "[[objects]]\ncenter = [0, 0, 0]\nradius = 1\n",
        1,
        "needs a `type`",
    ),
    (
        "unknown object type",
        "[[objects]]\ntype = \"torus\"\n",
        2,
        "unknown variant `torus`",
    ),
    (
        "key of another object type",
        "[[objects]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nnormal = [0, 1, 0]\n",
        5,
        "unknown key `normal`",
    ),
    (
        "negative radius",
        "[[objects]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = -1\n",
        4,
        "expected a number > 0",
    ),
    (
        "missing radius in the second object",
        "[[objects]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n\n[[objects]]\n\
         type = \"sphere\"\ncenter = [0, 0, 0]\n",
        6,
        "missing key `radius`",
    ),
    (
        "unknown material name",
        "[materials.red]\n[materials.blue]\n\n[[objects]]\ntype = \"sphere\"\n\
         center = [0, 0, 0]\nradius = 1\nmaterial = \"green\"\n",
        8,
        "unknown material \"green\": expected one of \"blue\", \"red\"",
    ),
    (
        "zero plane normal",
        "[[objects]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, 0]\n",
        4,
        "non-zero length",
    ),
    (
        "cylinder of no length",
        "[[objects]]\ntype = \"cylinder\"\nbase = [1, 1, 1]\ntop = [1, 1, 1]\nradius = 1\n",
        1,
        "base and top coincide",
    ),
    (
        "negative cone radius",
        "[[objects]]\ntype = \"cone\"\nbase = [0, 0, 0]\nbase_radius = -1\napex = [0, 1, 0]\n",
        4,
        "expected a number ≥ 0",
    ),
    (
        "cone of no width",
        "[[objects]]\ntype = \"cone\"\nbase = [0, 0, 0]\nbase_radius = 0\napex = [0, 1, 0]\n",
        1,
        "expected base_radius or apex_radius > 0",
    ),
    (
        "inverted box",
        "[[objects]]\ntype = \"box\"\nmin = [0, 0, 0]\nmax = [1, -1, 1]\n",
        1,
        "expected min ≤ max",
    ),
    (
        "mesh index out of range",
        "[[objects]]\ntype = \"mesh\"\npositions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n\
         indices = [\n  [0, 1, 2],\n  [0, 2, 3],\n]\n",
        6,
        "face 1 refers to vertex 3, but the mesh has 3 positions",
    ),
    (
        "polygon of two vertices",
        "[[objects]]\ntype = \"mesh\"\npositions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n\
         indices = [[0, 1]]\n",
        4,
        "face 0 has 2 vertices; expected at least 3",
    ),
    (
        "negative mesh index",
        "[[objects]]\ntype = \"mesh\"\npositions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n\
         indices = [[0, 1, -2]]\n",
        4,
        "expected a whole number ≥ 0",
    ),
    (
        "mesh without faces",
        "[[objects]]\ntype = \"mesh\"\npositions = [[0, 0, 0]]\nindices = []\n",
        1,
        "at least one face",
    ),
    (
        "normal count",
        "[[objects]]\ntype = \"mesh\"\npositions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n\
         normals = [[0, 0, 1]]\nindices = [[0, 1, 2]]\n",
        4,
        "expected one normal per position (3), got 1",
    ),
    (
        "zero mesh normal",
        "[[objects]]\ntype = \"mesh\"\npositions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n\
         normals = [[0, 0, 1], [0, 0, 0], [0, 0, 1]]\nindices = [[0, 1, 2]]\n",
        4,
        "non-zero length",
    ),
    (
        "zero scale",
        "[[objects]]\ntype = \"mesh\"\npositions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n\
         indices = [[0, 1, 2]]\ntransform = { scale = [1, 0, 1] }\n",
        5,
        "non-zero scale factors",
    ),
    (
        "unknown transform key",
        "[[objects]]\ntype = \"mesh\"\npositions = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n\
         indices = [[0, 1, 2]]\ntransform = { rotation = [0, 90, 0] }\n",
        5,
        "unknown key `rotation`",
    ),
    (
        "transform overflows",
        "[[objects]]\ntype = \"mesh\"\npositions = [[0, 0, 0], [1, 0, 0], [0, 1, 3e38]]\n\
         indices = [[0, 1, 2]]\ntransform = { scale = 1e10 }\n",
        1,
        "expected finite positions after the transform",
    ),
];

#[test]
fn malformed_files_name_the_line_and_what_was_expected() {
    for &(what, text, line, phrase) in MALFORMED {
        let Err(error) = parse(text) else {
            panic!("{what}: loaded without error:\n{text}");
        };
        let message = error.to_string();
        match &error {
            LoadError::Syntax {
                path,
                line: l,
                column,
                ..
            } => {
                assert!(path.ends_with("test.toml"), "{what}: path {path}");
                assert_eq!(*l, line, "{what}: wrong line in `{message}`");
                assert!(*column >= 1, "{what}: column {column}");
                assert!(
                    message.starts_with(&format!("{path}:{line}:{column}: ")),
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

#[test]
fn sampling_keys_fill_the_render_options() {
    let scene = parse(
        "[render]\nsampler = \"adaptive\"\nfilter = \"gaussian\"\nfilter_radius = 2\n\
         adaptive_threshold = 0.2\nadaptive_depth = 2\nadaptive_rule = \"corners\"\n\
         adaptive_jitter = 0\nadaptive_texture_spp = 9\nmin_weight = 0.01\n",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let o = &scene.options;
    assert_eq!(o.sampler, prism::sampling::SamplerKind::Adaptive);
    assert_eq!(o.filter, prism::render::FilterKind::Gaussian);
    assert_eq!(o.filter_radius, Some(2.0));
    assert_eq!((o.adaptive.threshold, o.adaptive.depth), (0.2, 2));
    assert_eq!(o.adaptive.rule, prism::sampling::AdaptiveRule::Corners);
    assert_eq!((o.adaptive.jitter, o.min_weight), (0.0, 0.01));
    assert_eq!(o.adaptive.texture_spp, 9);
    // Left out, the defaults: the grid, the box, adaptive depth control at 1/255.
    let plain = parse("[render]\nwidth = 8\n").unwrap();
    assert_eq!(plain.options.sampler, prism::sampling::SamplerKind::Grid);
    assert_eq!(plain.options.filter, prism::render::FilterKind::Box);
    assert_eq!(plain.options.min_weight, 1.0 / 255.0);
}

#[test]
fn the_accel_key_takes_a_method_and_its_parameters() {
    use prism::accel::{AccelSpec, KdTreeOptions};
    let scene = parse("[render]\naccel = \"kdtree:isect=80,depth=20\"\n").unwrap();
    let expected = AccelSpec::KdTree(KdTreeOptions {
        intersection_cost: 80.0,
        max_depth: 20,
        ..KdTreeOptions::default()
    });
    assert_eq!(scene.options.accel, expected);
    let plain = parse("[render]\naccel = \"grid\"\n").unwrap();
    assert_eq!(plain.options.accel, prism::accel::AccelKind::Grid.into());
    assert_eq!(parse("").unwrap().options.accel, AccelSpec::default());
}

#[test]
fn column_points_at_the_offending_value() {
    let error = parse("[[objects]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = -1\n")
        .expect_err("negative radius");
    let LoadError::Syntax { line, column, .. } = error else {
        panic!("expected a located error");
    };
    assert_eq!((line, column), (4, 10));
}

/// A file in a scratch folder that lives as long as the returned guard.
fn temp_file(name: &str, bytes: &[u8]) -> (ScratchDir, PathBuf) {
    let dir = ScratchDir::new("scene-toml", name);
    let path = dir.join(name);
    std::fs::write(&path, bytes).expect("temp file");
    (dir, path)
}

#[test]
fn a_file_that_is_not_utf8_is_located() {
    let (_dir, path) = temp_file("latin1.toml", b"[world]\nambient = 0.2 # caf\xe9\n");
    match load(&path) {
        Err(LoadError::Syntax {
            line,
            column,
            message,
            ..
        }) => {
            assert_eq!((line, column), (2, 20));
            assert!(message.contains("UTF-8"), "{message}");
        }
        other => panic!("expected a located error, got {other:?}"),
    }
}

#[test]
fn a_missing_file_is_an_io_error() {
    let path = scenes_dir().join("no-such-scene.toml");
    assert!(matches!(load(&path), Err(LoadError::Io { .. })));
}

#[test]
fn an_empty_file_is_the_default_scene() {
    let scene = parse("# nothing here\n").expect("empty scenes are valid");
    let default = Scene::default();
    assert_eq!(scene.options, default.options);
    assert_eq!(scene.camera, default.camera);
    assert_eq!(
        (scene.background, scene.ambient),
        (default.background, default.ambient)
    );
    assert!(scene.lights.is_empty() && scene.geometry.primitives.is_empty());
}

#[test]
fn objects_without_a_material_use_default() {
    let sphere = "[[objects]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n";
    let scene = parse(sphere).expect("valid");
    let m = &scene.materials[scene.geometry.primitives[0].material as usize];
    assert_eq!(*m, prism::shading::Material::default());

    let with_own = format!("[materials.default]\ncolor = [1, 0, 0]\n\n{sphere}");
    let scene = parse(&with_own).expect("valid");
    let m = &scene.materials[scene.geometry.primitives[0].material as usize];
    assert_eq!(m.color, Texture::Solid(Color::new(1.0, 0.0, 0.0)));
    assert_eq!(scene.materials.len(), 1, "no second default material");
}

#[test]
fn material_keys_fill_the_material() {
    let scene = parse(
        "[materials.glass]\ncolor = [0.9, 1, 0.8]\nambient = 0.05\ndiffuse = 0.1\n\
         specular = 0.7\nshininess = 200\nhighlight = \"blinn-phong\"\nreflect = 0.1\n\
         transmit = 0.9\nior = 1.33\nfresnel = \"schlick\"\n",
    )
    .expect("valid");
    let m = &scene.materials[0];
    assert_eq!(m.name, "glass");
    assert_eq!(m.color, Texture::Solid(Color::new(0.9, 1.0, 0.8)));
    assert_eq!(
        (m.ambient, m.diffuse, m.specular, m.shininess),
        (0.05, 0.1, 0.7, 200.0)
    );
    assert_eq!(
        (m.reflect, m.transmit, m.ior),
        (0.1, Color::splat(0.9), 1.33),
        "one number is a grey filter"
    );
    assert_eq!(m.highlight, prism::shading::Highlight::BlinnPhong);
    assert_eq!(m.fresnel, prism::shading::FresnelMode::Schlick);
}

#[test]
fn render_transfer_names_what_pixel_values_mean() {
    let scene = parse("[render]\ntransfer = \"display\"\n").expect("valid");
    assert_eq!(scene.options.transfer, prism::transfer::Transfer::Display);
    let scene = parse("[render]\nwidth = 8\n").expect("valid");
    assert_eq!(scene.options.transfer, prism::transfer::Transfer::Srgb);
}

#[test]
fn transmit_takes_a_colour_filter() {
    let scene = parse("[materials.ruby]\ntransmit = [0.9, 0.1, 0.05]\nior = 1.5\n").expect("valid");
    assert_eq!(scene.materials[0].transmit, Color::new(0.9, 0.1, 0.05));
}

#[test]
fn light_intensity_scales_its_colour_and_directions_are_normalised() {
    let scene = parse(
        "[[lights]]\ntype = \"point\"\nposition = [1, 2, 3]\ncolor = [1, 0.5, 0]\n\
         intensity = 2\n\n[[lights]]\ntype = \"directional\"\ndirection = [0, -3, 0]\n",
    )
    .expect("valid");
    assert_eq!(
        scene.lights[0],
        prism::light::Light::Point {
            position: Vec3::new(1.0, 2.0, 3.0),
            color: Color::new(2.0, 1.0, 0.0)
        }
    );
    assert_eq!(
        scene.lights[1],
        prism::light::Light::Directional {
            direction: Vec3::new(0.0, -1.0, 0.0),
            color: Color::ONE
        }
    );
}

#[test]
fn polygons_are_fanned_into_triangles() {
    let scene = parse(
        "[[objects]]\ntype = \"mesh\"\n\
         positions = [[0, 0, 0], [1, 0, 0], [2, 1, 0], [1, 2, 0], [0, 1, 0]]\n\
         indices = [[0, 1, 2, 3, 4]]\n",
    )
    .expect("valid");
    let mesh = &scene.geometry.meshes[0];
    assert_eq!(mesh.indices(), &[[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
    assert_eq!(scene.geometry.primitives.len(), 3);
}

/// One triangle with the vertex normal (1, 1, 0) everywhere, under `transform`.
fn transformed_triangle(transform: &str) -> prism::geometry::TriangleMesh {
    let scene = parse(&format!(
        "[[objects]]\ntype = \"mesh\"\npositions = [[1, 0, 0], [0, 1, 0], [0, 0, 0]]\n\
         normals = [[1, 1, 0], [1, 1, 0], [1, 1, 0]]\nindices = [[0, 1, 2]]\n\
         transform = {transform}\n"
    ))
    .expect("valid");
    scene.geometry.meshes[0].clone()
}

#[test]
fn mesh_transform_scales_then_rotates_then_translates() {
    let mesh =
        transformed_triangle("{ scale = [2, 1, 1], rotate = [0, 0, 90], translate = [1, 2, 3] }");
    // (1, 0, 0) → scaled (2, 0, 0) → rotated 90° about z (0, 2, 0) → moved (1, 4, 3).
    let p = mesh.positions()[0];
    assert!((p - Vec3::new(1.0, 4.0, 3.0)).length() < 1e-5, "{p}");
    // Normals go through the inverse transpose: (1, 1, 0) / scale = (0.5, 1, 0), rotated
    // to (−1, 0.5, 0). A plain transform would give (−1, 2, 0) instead.
    let hit = ShapeHit {
        t: 1.0,
        u: 0.0,
        v: 0.0,
    };
    let ns = mesh.surface(0, &hit).ns;
    let expected = Vec3::new(-1.0, 0.5, 0.0).normalize();
    assert!((ns - expected).length() < 1e-5, "{ns}");
}

#[test]
fn a_mirroring_transform_keeps_the_outside_outside() {
    let hit = ShapeHit {
        t: 1.0,
        u: 0.3,
        v: 0.3,
    };
    // Counter-clockwise seen from +z: the front faces +z.
    let plain = transformed_triangle("{ }").surface(0, &hit).ng;
    assert!(plain.z > 0.99, "{plain}");
    // Mirrored in x the triangle still lies in z = 0 and its outside is still +z.
    let mirrored = transformed_triangle("{ scale = [-1, 1, 1] }");
    let flat = mirrored.surface(0, &hit).ng;
    assert!(flat.z > 0.99, "{flat}");
}

#[test]
fn image_textures_resolve_against_the_scene_folder() {
    let scene = parse(
        "[materials.card]\ntexture = { type = \"image\", path = \"textures/testcard.png\", scale = 2 }\n",
    )
    .expect("the test card exists");
    let Texture::Image(image) = &scene.materials[0].color else {
        panic!("expected an image texture");
    };
    assert_eq!(image.scale, prism::math::Vec2::splat(2.0));
}

const MUTATION_BYTES: &[u8] = b"[]{}=\",.#-+_ \n\t0123456789eainftrusphx";

/// Well-formed TOML values that break the scene's rules, to get past the TOML parser.
const MUTATION_VALUES: &[&str] = &[
    "-1",
    "0",
    "nan",
    "-inf",
    "1e39",
    "4294967296",
    "\"x\"",
    "[]",
    "{}",
    "true",
    "[0, 0, 0]",
    "[1, 2]",
    "-0.0",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    mutate::text_damage(24, 48, MUTATION_BYTES, MUTATION_VALUES)
}

proptest! {
    #![proptest_config(mutate::config(768))]

    #[test]
    fn mutated_scenes_never_panic(
        which in 0usize..2,
        mutations in prop::collection::vec(mutation(), 1..6),
    ) {
        let original: &[u8] = if which == 0 {
            include_bytes!("../../../scenes/whitted.toml")
        } else {
            include_bytes!("../../../scenes/shapes.toml")
        };
        let mut bytes = original.to_vec();
        for m in &mutations {
            apply(&mut bytes, m);
        }
        let text = String::from_utf8_lossy(&bytes);
        match parse(&text) {
            Ok(scene) => prop_assert!(scene.validate().is_ok()),
            Err(LoadError::Syntax { line, column, message, .. }) => {
                prop_assert!(line >= 1 && line <= text.lines().count() + 1, "line {line}");
                prop_assert!(column >= 1);
                prop_assert!(!message.is_empty());
            }
            Err(other) => prop_assert!(false, "unlocated error: {other}"),
        }
    }
}

#[test]
fn spot_lights_read_their_cone_in_degrees_and_refuse_an_inverted_one() {
    let scene = parse(
        "[[lights]]\ntype = \"spot\"\nposition = [0, 5, 0]\ndirection = [0, -2, 0]\n\
         inner_angle = 20\nouter_angle = 30\nintensity = 2\n",
    )
    .unwrap();
    match scene.lights[..] {
        [prism::light::Light::Spot {
            position,
            direction,
            color,
            cos_inner,
            cos_outer,
        }] => {
            assert_eq!(position, prism::math::Vec3::new(0.0, 5.0, 0.0));
            assert_eq!(direction, prism::math::Vec3::NEG_Y);
            assert_eq!(color, prism::math::Color::splat(2.0));
            assert!((cos_inner - 20f32.to_radians().cos()).abs() < 1e-6);
            assert!((cos_outer - 30f32.to_radians().cos()).abs() < 1e-6);
        }
        ref other => panic!("expected one spot light, got {other:?}"),
    }
    let err = parse(
        "[[lights]]\ntype = \"spot\"\nposition = [0, 5, 0]\ndirection = [0, -1, 0]\n\
         inner_angle = 40\nouter_angle = 30\n",
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains(":5:"), "names the inner_angle line: {err}");
    assert!(err.contains("expected inner ≤ outer"), "{err}");
    let err = parse(
        "[[lights]]\ntype = \"spot\"\nposition = [0, 5, 0]\ndirection = [0, -1, 0]\n\
         outer_angle = 120\n",
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("expected 0 to 90 degrees"), "{err}");
}

#[test]
fn an_orthographic_camera_reads_its_window_and_refuses_an_empty_one() {
    let scene = parse(
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\northographic = 3.5\n\n\
         [[lights]]\ntype = \"directional\"\ndirection = [0, 0, -1]\n\n[[objects]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n",
    )
    .unwrap();
    assert_eq!(
        scene.camera.projection,
        prism::camera::Projection::Orthographic { size: 3.5 }
    );
    // The sphere of radius 1 fills 2/3.5 of the view's height, whatever the distance.
    let film = render_at(&scene, 70, 70);
    let lit = (0..70)
        .filter(|&y| film.get(35, y) != film.get(0, 0))
        .count();
    assert!(
        (39..=41).contains(&lit),
        "{lit} rows show the sphere, expected about 40"
    );
    let err = parse("[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\northographic = 0\n")
        .unwrap_err()
        .to_string();
    assert!(err.contains(":4:"), "{err}");
    assert!(err.contains("expected orthographic ="), "{err}");
}

#[test]
fn a_material_may_emit() {
    let scene = parse(
        "[render]\nintegrator = \"path\"\n\
         [materials.lamp]\nemission = [4, 2, 1]\n[materials.grey]\ncolor = 0.5\n\
         [[objects]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"lamp\"\n",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        scene.options.integrator,
        prism::options::IntegratorKind::Path
    );
    let m = |name: &str| scene.materials.iter().find(|m| m.name == name).unwrap();
    assert_eq!(m("lamp").emission, Color::new(4.0, 2.0, 1.0));
    assert_eq!(m("grey").emission, Color::ZERO);
    assert!(parse("[materials.lamp]\nemission = [-1, 0, 0]\n").is_err());
    assert!(parse("[render]\nintegrator = \"photon\"\n").is_err());
}

/// A load lists every file it read, so a scene can be shipped with its meshes, material
/// libraries and textures to a machine without this file system (prism's Python package
/// does that for Dask workers); a glTF's image counts as much as a TOML mesh include.
#[test]
fn a_load_lists_the_files_it_read() {
    use prism_io::scene::load_listing_files;
    use std::path::PathBuf;
    let root = PathBuf::from("../../scenes");
    let names = |path: &str| -> Vec<String> {
        let (scene, files) = load_listing_files(&root.join(path));
        scene.unwrap_or_else(|e| panic!("{path}: {e}"));
        let mut names: Vec<String> = (files.iter())
            .map(|f| {
                let f = f
                    .strip_prefix(&root)
                    .unwrap_or_else(|_| panic!("{}", f.display()));
                f.to_string_lossy()
                    .replace('\\', "/")
                    .replace("meshes/../", "")
            })
            .collect();
        names.sort();
        names
    };
    assert_eq!(
        names("mesh-room.toml"),
        [
            "mesh-room.toml",
            "meshes/gems.mtl",
            "meshes/gems.obj",
            "meshes/torus.ply",
            "textures/testcard.png"
        ]
    );
    assert_eq!(
        names("shapes.toml"),
        ["shapes.toml", "textures/testcard.png"]
    );
    assert_eq!(
        names("spheres.gltf"),
        ["spheres.gltf", "textures/testcard.png"]
    );
    assert_eq!(names("whitted.toml"), ["whitted.toml"]);
    // Outside such a load nothing is recorded, and a failed load still lists what it tried.
    let (scene, files) = load_listing_files(&root.join("no-such-scene.toml"));
    assert!(scene.is_err());
    assert_eq!(files, [root.join("no-such-scene.toml")]);
}

/// A texture image that is not there is a warning naming the file, line and column (as a
/// missing MTL library or map_Kd image is): the material keeps the default colour.
#[test]
fn a_missing_texture_image_is_a_warning() {
    let text = "[materials.m]\n\ntexture = { type = \"image\", path = \"textures/no-such.png\" }\n";
    let scene = parse(text).unwrap();
    assert_eq!(scene.warnings.len(), 1, "{:?}", scene.warnings);
    let w = &scene.warnings[0];
    assert!(w.contains("test.toml:3:"), "{w}");
    assert!(w.contains("no-such.png is missing"), "{w}");
    assert_eq!(
        scene.materials[0].color,
        prism::shading::Material::default().color
    );
}
