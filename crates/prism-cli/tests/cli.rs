//! The `prism` binary as a user meets it: exit codes (0 success, 1 bad input, 2 bad usage),
//! messages instead of panics, and output files that decode to the requested size with
//! nothing left beside them.

use crate::common;

use common::{expect_exit, prism, run, stdout};
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
