//! The `prism` binary as a user meets it: exit codes (0 success, 1 bad input, 2 bad usage),
//! messages instead of panics, and output files that decode to the requested size with
//! nothing left beside them.

use crate::common;

use common::{expect_exit, prism, run, stdout, words};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Output;

fn work_dir(test: &str) -> PathBuf {
    common::work_dir("cli", test)
}

/// The directory holds exactly `names`: no temporary or partial files beside the output.
#[track_caller]
fn assert_dir_holds(dir: &Path, names: &[&str]) {
    let mut found: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    found.sort();
    let mut expected: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    expected.sort();
    assert_eq!(found, expected, "files in {}", dir.display());
}

/// A small render of the Cornell box (fast, and every pixel is lit), quietly.
fn small_render(dir: &Path, output: &str, size: (u32, u32), extra: &[&str]) -> Output {
    let (w, h) = (size.0.to_string(), size.1.to_string());
    let mut args = vec!["render", "--builtin", "cornell", "-q", "-W", &w, "-H", &h];
    args.extend(["-o", output]);
    args.extend(extra);
    prism(dir, &args)
}

const SIZE: (u32, u32) = (24, 16);

#[test]
fn bad_usage_exits_2_with_usage_text() {
    let dir = work_dir("usage");
    // Malformed command lines: clap prints the usage line.
    for args in [
        &["render", "--no-such-flag"][..],
        &["frobnicate"],
        &["render", "a.toml", "--builtin", "whitted"],
    ] {
        let (_, err) = run(&dir, args, 2);
        assert!(
            err.contains("Usage: prism"),
            "prism {args:?}: no usage text:\n{err}"
        );
    }
    // Bad or missing values: clap names the option and the value, and points to --help
    // (it prints no usage line for these).
    for (args, names) in [
        (&["render", "-W", "wide"][..], &["'wide'", "--width"][..]),
        (&["render", "-W"], &["--width"]),
        (
            &["render", "--accel", "octree-of-doom"],
            &["'octree-of-doom'", "bvh"],
        ),
        (
            &["render", "--accel", "kdtree:isect=-1"],
            &["'kdtree:isect=-1'", "expected a number from 0.001"],
        ),
        (
            &["render", "--transfer", "gamma"],
            &["'gamma'", "expected srgb or display"],
        ),
    ] {
        let (_, err) = run(&dir, args, 2);
        for name in names {
            assert!(
                err.contains(name),
                "prism {args:?}: '{name}' not in:\n{err}"
            );
        }
        assert!(
            err.contains("--help"),
            "prism {args:?}: no pointer to --help:\n{err}"
        );
    }
    assert_dir_holds(&dir, &[]);
}

#[test]
fn bad_input_exits_1_with_a_clear_message() {
    let dir = work_dir("input");
    fs::write(dir.join("scene.xyz"), "not a scene").unwrap();
    let cases: [(&[&str], &str); 9] = [
        (&["render", "missing.toml", "-o", "a.png"], "missing.toml"),
        (
            &["render", "missing.nff", "-o", "a.png"],
            "cannot read missing.nff",
        ),
        (
            &["render", "scene.xyz", "-o", "a.png"],
            "unknown scene format 'xyz'",
        ),
        (
            &["render", "--builtin", "nope", "-o", "a.png"],
            "no built-in scene named 'nope'",
        ),
        (
            &["render", "--builtin", "sphereflake:99", "-o", "a.png"],
            "sphereflake:99",
        ),
        (
            &["render", "--builtin", "cornell", "-o", "a.bmp"],
            "unknown image format '.bmp'",
        ),
        (
            &["render", "--builtin", "cornell", "-o", "noextension"],
            "no file extension",
        ),
        (
            &["render", "--builtin", "cornell", "-W", "0", "-o", "a.png"],
            "image size must be at least 1×1",
        ),
        (
            &[
                "render",
                "--builtin",
                "cornell",
                "-W",
                "4",
                "-H",
                "4",
                "-o",
                "no/a.png",
            ],
            "cannot write no/a.png",
        ),
    ];
    for (args, message) in cases {
        let (_, err) = run(&dir, args, 1);
        assert!(
            err.starts_with("prism: error:") && err.contains(message),
            "prism {args:?}: expected '{message}' in:\n{err}"
        );
        assert!(!err.contains("Usage"), "prism {args:?}: not a usage error");
    }
    // Nothing was written for any of them.
    assert_dir_holds(&dir, &["scene.xyz"]);
}

#[test]
fn png_output_has_the_requested_size() {
    let dir = work_dir("png");
    let out = small_render(&dir, "out.png", SIZE, &[]);
    expect_exit(&out, 0, "out.png");
    let img = image::open(dir.join("out.png"))
        .expect("a valid PNG")
        .to_rgb8();
    assert_eq!((img.width(), img.height()), (24, 16));
    // The Cornell box is lit everywhere: not a black image.
    let lit = img.pixels().filter(|p| p.0.iter().any(|&c| c > 20)).count();
    assert!(lit > 24 * 16 / 2, "only {lit} lit pixels");
    assert_dir_holds(&dir, &["out.png"]);
    // Overwriting an existing file also leaves nothing else behind.
    let out = small_render(&dir, "out.png", (8, 5), &[]);
    expect_exit(&out, 0, "out.png again");
    let img = image::open(dir.join("out.png")).unwrap();
    assert_eq!((img.width(), img.height()), (8, 5));
    assert_dir_holds(&dir, &["out.png"]);
}

/// Reads a PFM (header `PF`, `width height`, negative scale for little-endian; rows from
/// the bottom) into rows from the top.
fn read_pfm(path: &Path) -> (usize, usize, Vec<[f32; 3]>) {
    let bytes = fs::read(path).unwrap();
    let mut lines = bytes.splitn(4, |&b| b == b'\n');
    let magic = lines.next().unwrap();
    assert_eq!(magic, b"PF", "colour PFM magic");
    let size = std::str::from_utf8(lines.next().unwrap()).unwrap();
    let mut dims = size.split_whitespace().map(|s| s.parse::<usize>().unwrap());
    let (w, h) = (dims.next().unwrap(), dims.next().unwrap());
    let scale: f32 = std::str::from_utf8(lines.next().unwrap())
        .unwrap()
        .trim()
        .parse()
        .unwrap();
    assert!(
        scale < 0.0,
        "little-endian PFM has a negative scale, got {scale}"
    );
    let data = lines.next().unwrap();
    assert_eq!(data.len(), w * h * 12, "PFM payload size");
    let floats: Vec<f32> = data
        .chunks(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect();
    let mut rows: Vec<Vec<[f32; 3]>> = floats
        .chunks(3 * w)
        .map(|row| row.chunks(3).map(|p| [p[0], p[1], p[2]]).collect())
        .collect();
    rows.reverse();
    (w, h, rows.concat())
}

fn read_exr(path: &Path) -> (usize, usize, Vec<[f32; 3]>) {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |size, _| {
            (
                size.width(),
                vec![[0.0f32; 3]; size.width() * size.height()],
            )
        },
        |(w, px): &mut (usize, Vec<[f32; 3]>), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            px[pos.y() * *w + pos.x()] = [r, g, b];
        },
    )
    .expect("a valid EXR");
    let size = image.layer_data.size;
    let (_, pixels) = image.layer_data.channel_data.pixels;
    (size.width(), size.height(), pixels)
}

#[test]
fn exr_and_pfm_outputs_are_readable_and_agree() {
    let dir = work_dir("float");
    for (name, extra) in [
        ("out.pfm", &[][..]),
        ("out.exr", &[]),
        ("half.exr", &["--half"]),
    ] {
        expect_exit(&small_render(&dir, name, SIZE, extra), 0, name);
    }
    let (w, h, pfm) = read_pfm(&dir.join("out.pfm"));
    assert_eq!((w, h), (24, 16));
    assert!(
        pfm.iter().flatten().all(|v| v.is_finite() && *v >= 0.0),
        "linear radiance is finite and non-negative"
    );
    assert!(pfm.iter().flatten().any(|v| *v > 0.05), "not a black image");
    let (ew, eh, exr) = read_exr(&dir.join("out.exr"));
    assert_eq!((ew, eh), (24, 16));
    assert_eq!(exr, pfm, "32-bit EXR and PFM hold the same floats");
    let (hw, hh, half) = read_exr(&dir.join("half.exr"));
    assert_eq!((hw, hh), (24, 16));
    for (a, b) in half.iter().flatten().zip(pfm.iter().flatten()) {
        assert!(
            (a - b).abs() <= 1e-3 * b.abs().max(1e-2),
            "half {a} vs float {b}"
        );
    }
    assert_dir_holds(&dir, &["out.pfm", "out.exr", "half.exr"]);
}

#[test]
fn list_names_every_builtin() {
    let dir = work_dir("list");
    let out = prism(&dir, &["list"]);
    expect_exit(&out, 0, "list");
    let text = stdout(&out);
    for name in prism::scene::builtin::names() {
        assert!(
            text.lines()
                .any(|l| l.split_whitespace().next() == Some(name)),
            "`prism list` does not name '{name}':\n{text}"
        );
    }
    assert!(text.contains("sphereflake:N"));
}

#[test]
fn stats_json_to_stdout_is_valid_json_with_ray_counts() {
    let dir = work_dir("json");
    let out = small_render(&dir, "out.png", SIZE, &["--stats-json", "-", "-s", "2"]);
    expect_exit(&out, 0, "--stats-json -");
    let json: serde_json::Value =
        serde_json::from_str(&stdout(&out)).expect("stdout is one JSON document");
    let rays = &json["rays"];
    let count = |k: &str| {
        rays[k]
            .as_u64()
            .unwrap_or_else(|| panic!("rays.{k}: {json}"))
    };
    assert_eq!(count("primary"), 24 * 16 * 4, "one primary ray per sample");
    assert!(count("shadow") > 0);
    assert!(
        count("reflected") > 0 && count("refracted") > 0,
        "mirror and glass"
    );
    assert_eq!(
        count("total"),
        [
            "primary",
            "shadow",
            "shadow_continuations",
            "reflected",
            "refracted"
        ]
        .iter()
        .map(|k| count(k))
        .sum::<u64>()
    );
    assert_eq!(json["options"]["width"], 24);
    assert_eq!(json["complete"], true);
    assert_dir_holds(&dir, &["out.png"]);
}

#[test]
fn transfer_chooses_how_pixel_values_are_written() {
    // The same film values written through the sRGB curve or as they are: the curve
    // brightens every value in (0, 1), and every pixel of the Cornell box is lit.
    let dir = work_dir("transfer");
    for (name, transfer) in [("srgb.png", "srgb"), ("display.png", "display")] {
        expect_exit(
            &small_render(&dir, name, SIZE, &["--transfer", transfer]),
            0,
            transfer,
        );
    }
    let srgb = image::open(dir.join("srgb.png")).unwrap().to_rgb8();
    let display = image::open(dir.join("display.png")).unwrap().to_rgb8();
    let mut brighter = 0;
    for (s, d) in srgb.pixels().zip(display.pixels()) {
        for c in 0..3 {
            assert!(s[c] >= d[c], "sRGB {s:?} darker than display {d:?}");
            brighter += usize::from(s[c] > d[c]);
        }
    }
    assert!(brighter > srgb.len() / 2, "only {brighter} channels differ");
    assert_dir_holds(&dir, &["display.png", "srgb.png"]);
}

/// Every render setting of the settings table has its flag in `prism render --help`, with
/// the table's help text: a setting added to the table and not to the command line fails.
#[test]
fn render_help_offers_every_setting_of_the_table() {
    let dir = work_dir("settings-help");
    let out = prism(&dir, &["render", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    // Help texts are wrapped: compare with the line breaks folded.
    let folded: String = text.split_whitespace().collect::<Vec<_>>().join(" ");
    for s in prism::options::SETTINGS {
        let Some(flag) = s.flag else {
            // Set by a preset or the scene file only.
            assert_eq!(s.key, "spd_rules", "{} has no flag", s.key);
            continue;
        };
        assert!(folded.contains(&format!("--{flag}")), "no --{flag}: {text}");
        if s.key != "accel" {
            let first: String = s.help.split_whitespace().collect::<Vec<_>>().join(" ");
            assert!(
                folded.contains(&first),
                "--{flag}: '{first}' not in the help"
            );
        }
    }
    assert_dir_holds(&dir, &[]);
}

/// A Cornell box as McGuire's `CornellBox-Original.obj` is made (y up, open towards +z, a
/// ceiling light that is only an emitting quad, `Ke 17 12 4`, and no light of its own),
/// with a tall box inside; `ke` is the light's MTL line.
fn emitter_lit_box(dir: &Path, ke: &str) {
    let quad = |name: &str, material: &str, corners: [[f32; 3]; 4]| {
        let mut text = format!("o {name}\nusemtl {material}\n");
        for [x, y, z] in corners {
            text += &format!("v {x} {y} {z}\n");
        }
        text + "f -4 -3 -2 -1\n"
    };
    let (a, b, t) = (-0.55f32, -0.15f32, 1.2f32);
    let mut obj = String::from("mtllib box.mtl\n");
    for (name, material, corners) in [
        (
            "floor",
            "white",
            [[-1., 0., 1.], [1., 0., 1.], [1., 0., -1.], [-1., 0., -1.]],
        ),
        (
            "ceiling",
            "white",
            [[-1., 2., -1.], [1., 2., -1.], [1., 2., 1.], [-1., 2., 1.]],
        ),
        (
            "back",
            "white",
            [[-1., 0., -1.], [1., 0., -1.], [1., 2., -1.], [-1., 2., -1.]],
        ),
        (
            "left",
            "red",
            [[-1., 0., 1.], [-1., 0., -1.], [-1., 2., -1.], [-1., 2., 1.]],
        ),
        (
            "right",
            "green",
            [[1., 0., -1.], [1., 0., 1.], [1., 2., 1.], [1., 2., -1.]],
        ),
        (
            "light",
            "light",
            [
                [-0.25, 1.98, -0.25],
                [0.25, 1.98, -0.25],
                [0.25, 1.98, 0.25],
                [-0.25, 1.98, 0.25],
            ],
        ),
        (
            "tall-front",
            "white",
            [[a, 0., b], [-0.15, 0., b], [-0.15, t, b], [a, t, b]],
        ),
        (
            "tall-right",
            "white",
            [
                [-0.15, 0., b],
                [-0.15, 0., -0.55],
                [-0.15, t, -0.55],
                [-0.15, t, b],
            ],
        ),
        (
            "tall-top",
            "white",
            [[a, t, b], [-0.15, t, b], [-0.15, t, -0.55], [a, t, -0.55]],
        ),
    ] {
        obj += &quad(name, material, corners);
    }
    fs::write(dir.join("box.obj"), obj).unwrap();
    let mtl = format!(
        "newmtl white\nKd 0.73 0.73 0.73\nnewmtl red\nKd 0.63 0.06 0.05\n\
         newmtl green\nKd 0.14 0.45 0.09\nnewmtl light\nKd 0.78 0.78 0.78\n{ke}\n"
    );
    fs::write(dir.join("box.mtl"), mtl).unwrap();
}

/// A model lit only by its emitting surfaces renders lit and shaded with the default
/// settings (the Whitted tracer), not as flat ambient grey: its emitters are area lights.
#[test]
fn a_box_lit_only_by_its_emitting_ceiling_renders_lit_and_shaded() {
    let dir = work_dir("emitter-lit-box");
    let mut images = Vec::new();
    for ke in ["Ke 17 12 4", ""] {
        emitter_lit_box(&dir, ke);
        run(&dir, &words("render box.obj -W 48 -H 48 -o out.pfm -q"), 0);
        let (w, h, pixels) = read_pfm(&dir.join("out.pfm"));
        // The middle of the picture: the inside of the box through its open front.
        let inside: Vec<f32> = (h / 3..2 * h / 3)
            .flat_map(|y| (w / 3..2 * w / 3).map(move |x| (x, y)))
            .map(|(x, y)| pixels[y * w + x].iter().sum::<f32>() / 3.0)
            .collect();
        let mean = inside.iter().sum::<f32>() / inside.len() as f32;
        let spread = inside.iter().fold(0f32, |m, &v| m.max((v - mean).abs()));
        images.push((mean, spread));
    }
    let [(lit, lit_spread), (dark, _)] = images[..] else {
        unreachable!()
    };
    assert!(
        lit > 2.0 * dark,
        "inside with its light {lit}, without {dark}"
    );
    // Shaded: light falls off across the walls, floor and tall box, and the box casts a
    // shadow, so the inside is far from one flat value.
    assert!(lit_spread > 0.5 * lit, "spread {lit_spread} around {lit}");
    assert_dir_holds(&dir, &["box.mtl", "box.obj", "out.pfm"]);
}

/// `prism info` lists the emitting surfaces, which light the Whitted render as area
/// lights.
#[test]
fn info_lists_the_emitters() {
    let dir = work_dir("info-emitters");
    let out = prism(&dir, &["info", "-b", "cornell-light"]);
    let text = stdout(&out);
    assert!(
        text.contains("emitters           2 primitives (area lights)"),
        "{text}"
    );
    assert!(
        text.contains("light            emission [17.00, 12.00, 4.00]  (2 primitives)"),
        "{text}"
    );
    let out = prism(&dir, &["info", "-b", "whitted"]);
    assert!(
        stdout(&out).contains("emitters           0 primitives"),
        "{}",
        stdout(&out)
    );
    assert_dir_holds(&dir, &[]);
}
