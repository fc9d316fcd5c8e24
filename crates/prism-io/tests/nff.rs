//! The NFF loader on small texts of its own: what each entity becomes, and a clear error
//! (file, line, column, what was expected) for every kind of bad input.

use prism::geometry::{Shape, ShapeKind};
use prism::math::Color;
use prism::transfer::Transfer;
use prism_io::scene::nff::parse;
use prism_io::scene::LoadError;

const VIEW: &str = "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 64 48\n";

fn load(body: &str) -> Result<prism::Scene, LoadError> {
    parse(&format!("{VIEW}{body}"), "test.nff")
}

fn error(body: &str) -> (usize, usize, String) {
    match load(body) {
        Err(LoadError::Syntax {
            line,
            column,
            message,
            path,
        }) => {
            assert_eq!(path, "test.nff");
            (line, column, message)
        }
        Err(e) => panic!("expected a syntax error, got {e}"),
        Ok(_) => panic!("expected an error for {body:?}"),
    }
}

#[test]
fn entities_become_shapes_materials_and_lights() {
    let scene = load(
        "b 0.1 0.2 0.3\nl 1 2 3\nl 4 5 6 0.5 0.5 0.5\n\
         f 1 0 0 0.7 0.3 20 0 1\ns 0 0 0 1\ns 2 0 0 -0.5\n\
         f 0 1 0 0.5 0 1 0.8 1.5\nc 0 0 0 1 0 1 0 0.5\n\
         p 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n\
         pp 3\n0 0 1 0 0 1\n1 0 1 0 0 1\n0 1 1 0 0 1\n",
    )
    .unwrap();
    assert_eq!(scene.background, prism::math::Vec3::new(0.1, 0.2, 0.3));
    assert_eq!((scene.options.width, scene.options.height), (64, 48));
    assert_eq!(scene.lights.len(), 2);
    let kinds: Vec<ShapeKind> = scene
        .geometry
        .primitives
        .iter()
        .map(|p| p.shape.kind())
        .collect();
    assert_eq!(kinds.iter().filter(|&&k| k == ShapeKind::Sphere).count(), 2);
    assert_eq!(kinds.iter().filter(|&&k| k == ShapeKind::Cone).count(), 1);
    assert_eq!(
        kinds.iter().filter(|&&k| k == ShapeKind::Triangle).count(),
        3
    );
    // A negative radius is an inside-out sphere.
    assert!(scene
        .geometry
        .primitives
        .iter()
        .any(|p| matches!(p.shape, Shape::Sphere(s) if s.inside_out)));
    assert_eq!(scene.materials.len(), 2);
    let glass = &scene.materials[1];
    assert_eq!(
        (glass.transmit, glass.ior, glass.reflect),
        (Color::splat(0.8), 1.5, 0.0)
    );
    let red = &scene.materials[0];
    assert_eq!((red.diffuse, red.reflect, red.shininess), (0.7, 0.3, 20.0));
    // Lights without colour get SPD's 1/√N; with colour keep it. No ambient light.
    let expected = 1.0 / 2f32.sqrt();
    assert_eq!(scene.ambient, Color::ZERO);
    assert_eq!(scene.options.transfer, Transfer::Display);
    match scene.lights[0] {
        prism::light::Light::Point { color, .. } => assert!((color.x - expected).abs() < 1e-6),
        _ => panic!("point light expected"),
    }
    match scene.lights[1] {
        prism::light::Light::Point { color, .. } => assert_eq!(color.x, 0.5),
        _ => panic!("point light expected"),
    }
}

#[test]
fn entities_may_span_lines_and_carry_comments() {
    let scene =
        load("# a comment\nf 1 1 1 1 0 1 0 1 # trailing\ns 0 0\n0 1\nc 0 0 0 1 0 1 0 1\n").unwrap();
    assert_eq!(scene.geometry.primitives.len(), 2);
}

#[test]
fn identical_fills_share_a_material() {
    let scene = load("f 1 1 1 1 0 1 0 1\ns 0 0 0 1\nf 1 1 1 1 0 1 0 1\ns 3 0 0 1\n").unwrap();
    assert_eq!(scene.materials.len(), 1);
}

#[test]
fn bad_input_names_line_column_and_expectation() {
    // (body, line of the error, phrase the message must contain); the view takes lines 1–7.
    let cases: &[(&str, usize, &str)] = &[
        ("s 0 0 0 abc\n", 8, "sphere radius"),
        ("s 0 0 0 nan\n", 8, "finite"),
        ("s 0 0 0 inf\n", 8, "finite"),
        ("s 0 0 0 0\n", 8, "must not be 0"),
        ("q 1 2 3\n", 8, "unknown NFF entity 'q'"),
        ("f 1 1 1 1 0\n", 8, "file ends"),
        ("s 0 0 0 1\np 2\n0 0 0\n1 0 0\n", 9, "at least 3 vertices"),
        ("p 1000000000\n0 0 0\n", 8, "announces 1000000000 vertices"),
        ("p -3\n", 8, "whole number"),
        (
            "pp 3\n0 0 0 0 0 0\n1 0 0 0 0 1\n0 1 0 0 0 1\n",
            9,
            "normal must not be zero",
        ),
        ("c 0 0 0 1 0 0 0 1\n", 8, "distinct base and apex"),
        ("l 1 2\n", 8, "file ends"),
    ];
    for &(body, line, phrase) in cases {
        let (l, column, message) = error(body);
        assert_eq!(l, line, "{body:?}: line ({message})");
        assert!(column >= 1);
        assert!(
            message.contains(phrase),
            "{body:?}: '{message}' lacks '{phrase}'"
        );
    }
}

#[test]
fn view_errors() {
    let bad_view = "v\nfrom 0 0 5\nat 0 0 5\nup 0 1 0\nangle 40\nhither 1\nresolution 64 48\n";
    let e = parse(bad_view, "v.nff").unwrap_err().to_string();
    assert!(e.contains("v.nff:1:1") && e.contains("coincide"), "{e}");
    let e = parse("v\nfrom 0 0 5\nto 0 0 0\n", "v.nff")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("v.nff:3:1") && e.contains("expected 'at'"),
        "{e}"
    );
    let e = parse("s 0 0 0 1\n", "v.nff").unwrap_err().to_string();
    assert!(e.contains("no view"), "{e}");
    let e = parse(&VIEW.replace("64 48", "0 48"), "v.nff")
        .unwrap_err()
        .to_string();
    assert!(e.contains("resolution"), "{e}");
}

#[test]
fn mutated_text_never_panics() {
    // Deterministic byte-level mutations of a valid file: deletions, duplications and
    // replacements at every position class. Only errors or scenes may come back.
    let valid = format!(
        "{VIEW}b 0.1 0.2 0.3\nl 1 2 3\nf 1 0 0 0.7 0.3 20 0 1\ns 0 0 0 1\n\
         c 0 0 0 1 0 1 0 0.5\np 4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
    );
    let bytes = valid.as_bytes();
    let replacements = [b'-', b'9', b'p', b' ', b'\n', b'e', b'.', b'#'];
    for i in 0..bytes.len() {
        let mut deleted = bytes.to_vec();
        deleted.remove(i);
        let mut duplicated = bytes.to_vec();
        duplicated.insert(i, bytes[i]);
        for text in [deleted, duplicated] {
            let _ = parse(&String::from_utf8_lossy(&text), "m.nff");
        }
        for r in replacements {
            let mut replaced = bytes.to_vec();
            replaced[i] = r;
            let _ = parse(&String::from_utf8_lossy(&replaced), "m.nff");
        }
    }
}

/// Renders an NFF text at its own resolution; the 8-bit pixels as the PNG holds them.
fn render_bytes(text: &str, transfer: Option<Transfer>) -> (Vec<u8>, u32) {
    let scene = parse(text, "look.nff").unwrap();
    let mut options = scene.options.clone();
    if let Some(t) = transfer {
        options.transfer = t;
    }
    let prepared = scene.prepare(&options.accel);
    let result = prism::render::render(
        &prepared,
        &options,
        &|_| {},
        &std::sync::atomic::AtomicBool::new(false),
    )
    .unwrap();
    (prism_io::output::to_rgb8(&result.film), options.width)
}

#[test]
fn nff_renders_like_the_spds_own_pictures() {
    // Looking straight down at a floor lit by two lights far above it, with a sphere out
    // of view (beside and above the eye) casting a shadow, and the sky at the top edge. SPD lights are
    // 1/√N each and there is no ambient light; values are written as they are.
    let text = "b 0.078 0.361 0.753\n\
                v\nfrom 0 -0.3 5\nat 0 0 0\nup 0 1 0\nangle 60\nhither 1\nresolution 33 33\n\
                l 0 0 1000\nl 0 0 1000\n\
                f 1 0.2 0.2 0.6 0 100000 0 1\n\
                p 4\n-2 -2 0\n2 -2 0\n2 2 0\n-2 2 0\n\
                s 1.2 0 5.5 0.5\n";
    let (display, w) = render_bytes(text, None);
    let pixel = |img: &[u8], x: u32, y: u32| {
        let i = 3 * (y * w + x) as usize;
        [img[i], img[i + 1], img[i + 2]]
    };
    // The centre sees the floor at (0, 0, 0), lit from straight above (n·l = 1, within
    // 1e-6 for a light 1000 units up): kd·C·(2 · 1/√2) per channel.
    let lit = |c: f64| ((0.6 * c * 2.0 / 2f64.sqrt()).min(1.0) * 255.0 + 0.5) as u8;
    assert_eq!(pixel(&display, 16, 16), [lit(1.0), lit(0.2), lit(0.2)]);
    // Under the sphere: both lights blocked, and no ambient light fills the shadow.
    let (sx, sy) = (
        16 + (1.2 / (5.0 * (30f64).to_radians().tan()) * 16.0).round() as u32,
        16,
    );
    assert_eq!(pixel(&display, sx, sy), [0, 0, 0], "shadow at ({sx}, {sy})");
    // The top row looks past the floor's far edge at the sky, written as it is.
    assert_eq!(pixel(&display, 16, 0), [20, 92, 192]);

    // The same scene through the sRGB curve, on request.
    let (srgb, _) = render_bytes(text, Some(Transfer::Srgb));
    assert_eq!(pixel(&srgb, 16, 0), [79, 162, 225]);
}
