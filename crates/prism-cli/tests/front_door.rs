//! The front door: what a newcomer types works, fails early and cleanly, or says
//! why. Each test names the case it holds; all of them failed on the main branch before.

use crate::common;

use common::{expect_exit, prism, words};
use std::fs;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::Duration;

fn work_dir(test: &str) -> PathBuf {
    common::work_dir("front-door", test)
}

/// The names in `dir`, sorted (hidden temporary files included).
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

// 1. A huge thread count is refused, and a render never starts more workers than tiles.
#[test]
fn a_huge_thread_count_is_refused_with_the_limit() {
    let dir = work_dir("threads");
    let out = prism(&dir, &["render", "--threads", "1000000000000", "-q"]);
    let err = expect_exit(&out, 1, "--threads 1e12");
    assert!(err.contains("threads must be between 0"), "{err}");
    assert!(err.contains("1024"), "{err}");
    assert!(
        listing(&dir).is_empty(),
        "nothing written: {:?}",
        listing(&dir)
    );
}

#[test]
fn more_threads_than_cores_get_a_note_and_still_render() {
    let dir = work_dir("threads-note");
    let out = prism(
        &dir,
        &words("render -b cornell -W 8 -H 8 --threads 1024 -q"),
    );
    let err = expect_exit(&out, 0, "--threads 1024 on an 8×8 image");
    assert!(err.contains("1024 worker threads on"), "{err}");
}

// 2. An image too large for memory is refused with the bytes it needs, not an abort.
#[test]
fn an_image_too_large_for_memory_names_the_bytes_needed() {
    let dir = work_dir("memory");
    let out = prism(&dir, &["render", "-W", "65536", "-H", "65536", "-q"]);
    let err = expect_exit(&out, 1, "-W 65536 -H 65536");
    assert!(err.contains("render needs about"), "{err}");
    assert!(err.contains("GB"), "{err}");
    assert!(err.contains("film"), "{err}");
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
}

// 3. `prism` alone is `prism render`.
#[test]
fn no_arguments_render_the_default_scene_like_render() {
    let bare = work_dir("bare");
    let out = prism(&bare, &[]);
    expect_exit(&out, 0, "prism");
    let typed = work_dir("bare-typed");
    let out = prism(&typed, &["render"]);
    expect_exit(&out, 0, "prism render");
    let a = fs::read(bare.join("prism.png")).expect("prism alone writes prism.png");
    let b = fs::read(typed.join("prism.png")).unwrap();
    assert!(a == b, "`prism` and `prism render` write the same image");
}

// 4. A closed standard output ends the program quietly.
#[test]
fn a_closed_stdout_ends_quietly() {
    let dir = work_dir("pipe");
    for args in [
        &["info", "builtin:cornell"][..],
        &["list"][..],
        &[
            "bench",
            "--quick",
            "--scenes",
            "cornell",
            "--methods",
            "bvh",
        ][..],
    ] {
        let mut child = Command::new(common::bin())
            .args(args)
            .current_dir(&dir)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // Close the reading end before prism writes: every write meets a broken pipe.
        drop(child.stdout.take());
        let mut err = String::new();
        child
            .stderr
            .take()
            .unwrap()
            .read_to_string(&mut err)
            .unwrap();
        let status = child.wait().unwrap();
        assert!(!err.contains("panicked"), "prism {args:?} panicked:\n{err}");
        assert_ne!(status.code(), Some(101), "prism {args:?}: {err}");
        #[cfg(unix)]
        {
            use std::os::unix::process::ExitStatusExt;
            // Ended by SIGPIPE, as `cat` and `grep` are, or done before writing at all.
            assert!(
                status.signal() == Some(13) || status.success(),
                "prism {args:?}: {status:?} {err}"
            );
        }
    }
}

// 5. Outputs are checked before any work; one bad extra output means nothing is written.
#[test]
fn unwritable_outputs_fail_before_the_render_and_write_nothing() {
    let dir = work_dir("outputs");
    fs::create_dir(dir.join("folder")).unwrap();
    fs::write(dir.join("plain-file"), b"").unwrap();
    let base = ["render", "-b", "sphereflake", "-q", "-W", "64", "-H", "64"];
    let cases: &[(&[&str], &str)] = &[
        (
            &["-o", "missing/out.png"],
            "the directory missing does not exist",
        ),
        (&["-o", "folder"], "it is a directory"),
        (&["-o", "plain-file/out.png"], "does not exist"),
        (&["--cost", "missing/cost.png"], "missing does not exist"),
        (&["--density", "folder"], "the density view"),
        (
            &["--stats-json", "missing/stats.json"],
            "missing does not exist",
        ),
        (&["--cost", "prism.png"], "named twice"),
        #[cfg(target_os = "linux")]
        (
            &["-o", "/proc/prism-out.png"],
            "cannot write /proc/prism-out.png",
        ),
    ];
    for (extra, expected) in cases {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        let out = prism(&dir, &args);
        let err = expect_exit(&out, 1, &format!("{extra:?}"));
        assert!(err.contains(expected), "{extra:?}: {err}");
        assert_eq!(
            listing(&dir),
            ["folder", "plain-file"],
            "{extra:?} wrote something"
        );
    }
}

#[test]
fn other_commands_check_their_outputs_first() {
    let dir = work_dir("outputs-other");
    let a = dir.join("a.pfm");
    let out = prism(&dir, &["render", "-q", "-W", "8", "-H", "8", "-o", "a.pfm"]);
    expect_exit(&out, 0, "render a.pfm");
    assert!(a.exists());
    let out = prism(
        &dir,
        &words("compare a.pfm a.pfm --flip-map missing/flip.png"),
    );
    let err = expect_exit(&out, 1, "compare --flip-map into a missing folder");
    assert!(err.contains("does not exist"), "{err}");
    let out = prism(
        &dir,
        &["reference", "-o", "missing/ref.exr", "-W", "8", "-H", "8"],
    );
    let err = expect_exit(&out, 1, "reference into a missing folder");
    assert!(err.contains("does not exist"), "{err}");
}

// 6. A write that fails half way (a full disk, a file-size limit) leaves no temporary file.
#[cfg(unix)]
#[test]
fn a_failed_write_leaves_no_temporary_file() {
    let dir = work_dir("full-disk");
    for (output, extra) in [
        ("out.exr", ""),
        ("out.png", ""),
        ("out.pfm", "--stats-json s.json"),
    ] {
        // ulimit -f 1: no file may grow past 1 KiB, as on a disk that is full.
        let script = format!(
            "ulimit -f 1; exec \"{}\" render -b cornell -q -W 96 -H 96 -o {output} {extra}",
            common::bin().to_string_lossy()
        );
        let out = Command::new("sh")
            .args(["-c", &script])
            .current_dir(&dir)
            .output()
            .unwrap();
        let err = expect_exit(&out, 1, output);
        assert!(err.contains(&format!("cannot write {output}")), "{err}");
        assert!(
            listing(&dir).is_empty(),
            "{output}: files left: {:?}",
            listing(&dir)
        );
    }
}

// 7. SIGTERM stops like Ctrl-C, keeps the rows its finished tiles reached and exits with 143. (A
// second signal while writing: the long tier's `a_second_ctrl_c_while_writing_leaves_no_temporary_file`;
// two at once counted as one and a stop inside a large tile: the signals suite.)
/// A render of minutes on a terminal, so that the signal always arrives mid-render; it
/// returns once the progress bar shows finished tiles, so there are rows to write.
#[cfg(unix)]
fn long_render_started(dir: &Path, output: &str) -> common::terminal::OnTerminal {
    let line = format!("render -b sphereflake -W 1600 -H 1600 --spp 64 --threads 1 -o {output}");
    let mut render = common::terminal::OnTerminal::spawn(dir, &words(&line));
    assert!(render.wait_for_work_done(), "no progress: {}", render.seen);
    render
}

#[cfg(unix)]
#[test]
fn sigterm_writes_the_finished_tiles_and_exits_143() {
    let dir = work_dir("sigterm");
    let render = long_render_started(&dir, "out.pfm");
    render.signal("TERM");
    let (code, err) = render.finish();
    assert_eq!(code, Some(143), "{err}");
    assert!(err.contains("terminated (SIGTERM)"), "{err}");
    assert!(err.contains("prism: wrote out.pfm"), "{err}");
    let bytes = fs::read(dir.join("out.pfm")).unwrap();
    assert!(bytes.starts_with(b"PF\n1600 "), "the image's full width");
    assert_eq!(listing(&dir), ["out.pfm"]);
}

// 8. PLY triangle strips render.
const STRIP_PLY: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n\
                         property float y\nproperty float z\nelement tristrips 1\n\
                         property list int int vertex_indices\nend_header\n\
                         0 0 0\n0 1 0\n1 0 0\n1 1 0\n4 0 1 2 3\n";

#[test]
fn a_ply_of_triangle_strips_renders() {
    let dir = work_dir("tristrips");
    fs::write(dir.join("strip.ply"), STRIP_PLY).unwrap();
    let out = prism(&dir, &["render", "strip.ply", "-q", "-W", "16", "-H", "16"]);
    expect_exit(&out, 0, "render strip.ply");
    let out = prism(&dir, &["info", "strip.ply"]);
    expect_exit(&out, 0, "info strip.ply");
    let text = String::from_utf8_lossy(&out.stdout);
    let triangles = text
        .lines()
        .find(|l| l.trim_start().starts_with("triangle "))
        .unwrap_or_default();
    assert_eq!(triangles.split_whitespace().last(), Some("2"), "{text}");
}

// 9. A missing MTL file is a warning; --strict makes it an error.
#[test]
fn an_obj_without_its_mtl_renders_with_a_warning_unless_strict() {
    let dir = work_dir("missing-mtl");
    let obj = "mtllib gone.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    fs::write(dir.join("model.obj"), obj).unwrap();
    let out = prism(&dir, &["render", "model.obj", "-q", "-W", "16", "-H", "16"]);
    let err = expect_exit(&out, 0, "model.obj without its MTL");
    assert!(
        err.contains("warning: model.obj:1:8: the material library"),
        "{err}"
    );
    assert!(err.contains("gone.mtl is missing"), "{err}");
    assert!(dir.join("prism.png").exists());
    fs::remove_file(dir.join("prism.png")).unwrap();
    let out = prism(
        &dir,
        &["render", "model.obj", "--strict", "-q", "-o", "s.png"],
    );
    let err = expect_exit(&out, 1, "--strict");
    assert!(err.contains("--strict"), "{err}");
    assert_eq!(listing(&dir), ["model.obj"]);
}

/// A missing texture image, in an MTL library or a TOML scene, is a warning naming the
/// file, line and column; the material keeps its colour (the MTL's Kd: a red triangle
/// stays red), and --strict makes it an error that writes nothing.
#[test]
fn a_missing_texture_warns_keeps_the_colour_and_fails_under_strict() {
    let dir = work_dir("missing-texture");
    let obj = "mtllib m.mtl\nusemtl red\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n\
               f 1/1 2/2 3/3\n";
    fs::write(dir.join("tri.obj"), obj).unwrap();
    fs::write(dir.join("m.mtl"), "newmtl red\nKd 1 0 0\nmap_Kd gone.png\n").unwrap();
    let toml = "[materials.m]\ntexture = { type = \"image\", path = \"gone.png\" }\n\n\
                [[objects]]\ntype = \"sphere\"\ncenter = [0, 0, -5]\nradius = 1\nmaterial = \"m\"\n";
    fs::write(dir.join("s.toml"), toml).unwrap();
    let out = prism(
        &dir,
        &["tri.obj", "-q", "-W", "9", "-H", "9", "-o", "t.pfm"],
    );
    let err = expect_exit(&out, 0, "tri.obj without its texture");
    assert!(
        err.contains("warning: m.mtl:3:8: the map_Kd image gone.png is missing"),
        "{err}"
    );
    // The centre pixel, on the triangle, is red: Kd kept.
    let pfm = fs::read(dir.join("t.pfm")).unwrap();
    let floats: Vec<f32> = pfm[pfm.len() - 9 * 9 * 12..]
        .chunks(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let centre = &floats[(4 * 9 + 4) * 3..][..3];
    assert!(
        centre[0] > 0.1 && centre[1] == 0.0 && centre[2] == 0.0,
        "{centre:?}"
    );
    let out = prism(&dir, &["s.toml", "-q", "-W", "9", "-H", "9", "-o", "s.png"]);
    let err = expect_exit(&out, 0, "s.toml without its texture");
    assert!(
        err.contains("warning: s.toml:2:36: the texture image")
            && err.contains("gone.png is missing"),
        "{err}"
    );
    for scene in ["tri.obj", "s.toml"] {
        let out = prism(&dir, &[scene, "--strict", "-q", "-o", "strict.png"]);
        let err = expect_exit(&out, 1, "--strict");
        assert!(err.contains("gone.png is missing"), "{err}");
        assert!(err.contains("1 warning and --strict"), "{err}");
    }
    assert_eq!(
        listing(&dir),
        ["m.mtl", "s.png", "s.toml", "t.pfm", "tri.obj"]
    );
}

/// An OBJ object whose faces all have zero area is left out with a warning; --strict
/// makes it an error.
#[test]
fn an_object_of_zero_area_faces_warns_unless_strict() {
    let dir = work_dir("zero-area");
    let obj = "o flat\nv 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n\
               o real\nv 0 0 1\nv 1 0 1\nv 0 1 1\nf 4 5 6\n";
    fs::write(dir.join("model.obj"), obj).unwrap();
    let out = prism(&dir, &["render", "model.obj", "-q", "-W", "16", "-H", "16"]);
    let err = expect_exit(&out, 0, "an object of zero area");
    assert!(
        err.contains("warning: model.obj: object 'flat' has only faces of zero area (1)"),
        "{err}"
    );
    let out = prism(
        &dir,
        &["render", "model.obj", "--strict", "-q", "-o", "s.png"],
    );
    let err = expect_exit(&out, 1, "--strict");
    assert!(
        err.contains("zero area") && err.contains("--strict"),
        "{err}"
    );
    assert!(!dir.join("s.png").exists());
}

// 10. A file whose content does not match its extension is named for what it is.
#[test]
fn a_file_that_is_not_what_its_extension_says_is_named() {
    let dir = work_dir("sniff");
    fs::write(
        dir.join("page.glb"),
        "<!DOCTYPE html>\n<html><body>Not found</body></html>",
    )
    .unwrap();
    let noise: Vec<u8> = (0..600u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 11) as u8)
        .collect();
    fs::write(dir.join("noise.nff"), &noise).unwrap();
    fs::write(dir.join("noise.glb"), &noise).unwrap();
    let lfs = "version https://git-lfs.github.com/spec/v1\noid sha256:0123\nsize 4096\n";
    fs::write(dir.join("mesh.bin"), lfs).unwrap();
    let gltf = r#"{"asset":{"version":"2.0"},"buffers":[{"uri":"mesh.bin","byteLength":4096}]}"#;
    fs::write(dir.join("scene.gltf"), gltf).unwrap();
    fs::write(dir.join("scene.obj"), lfs).unwrap();
    let cases = [
        ("page.glb", "an HTML page"),
        ("noise.nff", "binary data"),
        ("noise.glb", "does not start like a glTF file"),
        ("scene.gltf", "Git LFS pointer"),
        ("scene.obj", "Git LFS pointer"),
    ];
    for (file, expected) in cases {
        let out = prism(&dir, &["render", file, "-q", "-o", "x.png"]);
        let err = expect_exit(&out, 1, file);
        assert!(err.contains(expected), "{file}: {err}");
    }
    assert!(!dir.join("x.png").exists());
}

// 11. What prism reads but cannot render gets a warning.
#[test]
fn features_read_but_not_rendered_are_warned_about() {
    let dir = work_dir("unrendered");
    fs::write(
        dir.join("glow.mtl"),
        "newmtl glow\nKd 0.5 0.5 0.5\nKe 1 0.5 0\n",
    )
    .unwrap();
    fs::write(
        dir.join("glow.obj"),
        "mtllib glow.mtl\nusemtl glow\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let out = prism(&dir, &["render", "glow.obj", "-q", "-W", "8", "-H", "8"]);
    let err = expect_exit(&out, 0, "MTL Ke");
    // Ke was warned about while prism had no emitters; it is an area light now.
    assert!(!err.contains("Ke"), "{err}");

    let ortho = r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],
        "nodes":[{"camera":0}],
        "cameras":[{"type":"orthographic","orthographic":{"xmag":1,"ymag":1,"znear":0.1,"zfar":10}}]}"#;
    fs::write(dir.join("ortho.gltf"), ortho).unwrap();
    // Orthographic cameras were skipped without a word; now they render as such.
    let out = prism(&dir, &["info", "ortho.gltf"]);
    expect_exit(&out, 0, "orthographic camera");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("orthographic, 2 across"), "{text}");

    let out = prism(
        &dir,
        &[
            "render", "-q", "-W", "8", "-H", "8", "--half", "-o", "h.png",
        ],
    );
    let err = expect_exit(&out, 0, "--half with PNG");
    assert!(err.contains("--half applies to EXR output only"), "{err}");
}

// 12. An empty scene warns; a directory as the scene says so.
#[test]
fn an_empty_scene_warns_and_a_directory_is_named() {
    let dir = work_dir("empty");
    fs::write(
        dir.join("empty.toml"),
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n",
    )
    .unwrap();
    let out = prism(&dir, &["render", "empty.toml", "-q", "-W", "8", "-H", "8"]);
    let err = expect_exit(&out, 0, "empty scene");
    assert!(err.contains("empty.toml has no objects"), "{err}");
    fs::create_dir(dir.join("scenes")).unwrap();
    let out = prism(&dir, &["render", "scenes", "-q"]);
    let err = expect_exit(&out, 1, "a directory as the scene");
    assert!(err.contains("is a directory"), "{err}");
}

// Small things people notice.
#[test]
fn numbers_are_echoed_as_typed_and_negative_ones_reach_the_range_check() {
    let dir = work_dir("numbers");
    let out = prism(&dir, &["render", "--spp", "1000000", "-q"]);
    let err = expect_exit(&out, 1, "--spp 1000000");
    assert!(err.contains("--spp 1000000"), "{err}");
    assert!(!err.contains("got 1000\n"), "{err}");
    for (flag, value) in [
        ("--adaptive-threshold", "-0.5"),
        ("--min-weight", "-1"),
        ("--filter-radius", "-2"),
        ("--adaptive-jitter", "-0.25"),
    ] {
        let out = prism(&dir, &["render", flag, value, "-q"]);
        let err = expect_exit(&out, 1, flag);
        assert!(
            err.contains(&format!("got {value}")),
            "{flag} {value}: {err}"
        );
    }
}

#[test]
fn the_closing_line_names_every_file_written() {
    let dir = work_dir("closing");
    let out = prism(
        &dir,
        &words(
            "render -b cornell -W 16 -H 16 -o a.png --cost c.png --density d.pfm \
             --stats-json s.json",
        ),
    );
    let err = expect_exit(&out, 0, "render with every output");
    assert!(
        err.contains("prism: wrote a.png, d.pfm, c.png and s.json (16×16"),
        "{err}"
    );
}

#[test]
fn exr_files_are_byte_identical_for_any_thread_count() {
    let dir = work_dir("exr-threads");
    let mut files = Vec::new();
    for threads in ["1", "2", "3"] {
        let name = format!("t{threads}.exr");
        // Large enough for many chunks: at 200 × 150 even the old writer happened to agree.
        let line = format!("render -b cornell -q -W 640 -H 480 --threads {threads} -o {name}");
        let out = prism(&dir, &words(&line));
        expect_exit(&out, 0, &name);
        files.push(fs::read(dir.join(&name)).unwrap());
    }
    assert!(
        files[0] == files[1] && files[1] == files[2],
        "EXR bytes differ between thread counts"
    );
}

#[test]
fn render_help_names_the_default_scene_and_defaults() {
    let dir = work_dir("help");
    let out = prism(&dir, &["render", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("the built-in `whitted` scene"), "{text}");
    assert!(
        text.contains("Seed for random decisions [default: 0]"),
        "{text}"
    );
    assert!(
        text.contains("obb|dop14"),
        "no stray space in the volume list: {text}"
    );
    let out = prism(&dir, &["sweep", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        text.matches("[default: neighbourhood:1]").count(),
        1,
        "one default for --adaptive-variants: {text}"
    );
}

#[test]
fn info_takes_a_built_in_scene_as_render_does() {
    let dir = work_dir("info-builtin");
    let flag = prism(&dir, &["info", "-b", "cornell"]);
    expect_exit(&flag, 0, "info -b cornell");
    let prefixed = prism(&dir, &["info", "builtin:cornell"]);
    expect_exit(&prefixed, 0, "info builtin:cornell");
    let text = |o: &Output| {
        // The build time differs from run to run; everything else is the same.
        String::from_utf8_lossy(&o.stdout)
            .lines()
            .filter(|l| !l.starts_with("accelerator"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(text(&flag), text(&prefixed));
    let out = prism(&dir, &["info"]);
    let err = expect_exit(&out, 2, "info without a scene");
    assert!(err.contains("<SCENE>"), "{err}");
}

#[test]
fn a_busy_port_is_reported_with_its_cause_once() {
    let dir = work_dir("busy-port");
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let out = prism(&dir, &["serve", "--port", &port]);
    let err = expect_exit(&out, 1, "serve on a busy port");
    assert!(
        err.contains(&format!("cannot listen on 127.0.0.1:{port}")),
        "{err}"
    );
    assert_eq!(
        err.matches("(os error").count(),
        1,
        "the cause once:\n{err}"
    );
    drop(taken);
}

#[test]
fn compare_names_images_and_sizes_in_the_same_order() {
    let dir = work_dir("compare-order");
    for (name, w, h) in [("big.pfm", "16", "12"), ("small.pfm", "8", "6")] {
        let out = prism(
            &dir,
            &[
                "render", "-b", "cornell", "-W", w, "-H", h, "-q", "-o", name,
            ],
        );
        expect_exit(&out, 0, name);
    }
    let out = prism(&dir, &["compare", "big.pfm", "small.pfm"]);
    let err = expect_exit(&out, 1, "compare of two sizes");
    assert!(
        err.contains(
            "cannot compare big.pfm (the reference) with small.pfm (the test): the images \
             differ in size: 16×12 and 8×6"
        ),
        "{err}"
    );
}

/// A PNG's width and height, from its header.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (word(16), word(20))
}

#[test]
fn render_arguments_work_without_the_command_name() {
    let dir = work_dir("bare-flags");
    let out = prism(&dir, &["-W", "20", "-H", "14", "-q", "-o", "bare.png"]);
    expect_exit(&out, 0, "prism -W 20 -H 14");
    let out = prism(
        &dir,
        &["render", "-W", "20", "-H", "14", "-q", "-o", "typed.png"],
    );
    expect_exit(&out, 0, "prism render -W 20 -H 14");
    assert_eq!(png_size(&dir.join("bare.png")), (20, 14));
    assert!(fs::read(dir.join("bare.png")).unwrap() == fs::read(dir.join("typed.png")).unwrap());
    // A scene in the command's place too.
    let out = prism(
        &dir,
        &["builtin:cornell", "-W", "8", "-H", "6", "-q", "-o", "c.png"],
    );
    expect_exit(&out, 0, "prism builtin:cornell");
    assert_eq!(png_size(&dir.join("c.png")), (8, 6));
}

#[test]
fn render_takes_a_built_in_scene_in_the_files_place() {
    let dir = work_dir("render-builtin");
    let size = ["-W", "16", "-H", "12", "-q"];
    let out = prism(
        &dir,
        &[&["render", "builtin:cornell", "-o", "a.png"], &size[..]].concat(),
    );
    expect_exit(&out, 0, "render builtin:cornell");
    let out = prism(
        &dir,
        &[
            &["render", "--builtin", "cornell", "-o", "b.png"],
            &size[..],
        ]
        .concat(),
    );
    expect_exit(&out, 0, "render --builtin cornell");
    assert!(fs::read(dir.join("a.png")).unwrap() == fs::read(dir.join("b.png")).unwrap());
    let out = prism(&dir, &["render", "builtin:nope", "-q", "-o", "n.png"]);
    let err = expect_exit(&out, 1, "render builtin:nope");
    assert!(err.contains("no built-in scene named 'nope'"), "{err}");
}

#[test]
fn info_help_says_the_scene_is_required_unless_builtin_is_given() {
    let dir = work_dir("info-help");
    let out = prism(&dir, &["info", "--help"]);
    expect_exit(&out, 0, "info --help");
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(
        help.contains("Required unless --builtin is given"),
        "{help}"
    );
    assert!(help.contains("prism info [OPTIONS] <SCENE>"), "{help}");
    assert!(
        help.contains("prism info [OPTIONS] --builtin <NAME>"),
        "{help}"
    );
    // The argument list shows it as required too, not as `[SCENE]`.
    assert!(help.contains("\n  <SCENE>  "), "{help}");
    assert!(!help.contains("[SCENE]"), "{help}");
}

/// `prism --help`'s one-line summaries of `reference` and `sweep` say what they take, and
/// each command's scene argument names that command's own default scene.
#[test]
fn reference_and_sweep_say_what_they_take() {
    let dir = work_dir("summaries");
    let out = prism(&dir, &["--help"]);
    expect_exit(&out, 0, "--help");
    let help = String::from_utf8_lossy(&out.stdout).to_string();
    let summary = |command: &str| {
        help.lines()
            .find(|l| l.trim_start().starts_with(&format!("{command} ")))
            .unwrap_or_else(|| panic!("no {command} in {help}"))
            .to_string()
    };
    assert!(
        summary("reference").contains("of a scene of planar polygons"),
        "{help}"
    );
    assert!(
        summary("sweep").contains("a scene (the checkerboard by default)"),
        "{help}"
    );
    for (command, default) in [
        ("render", "the built-in `whitted` scene"),
        ("serve", "the built-in `whitted` scene"),
        (
            "reference",
            "the built-in `checkerboard` scene. Any scene of planar polygons",
        ),
        (
            "sweep",
            "the built-in `checkerboard` scene, whose reference is exact",
        ),
    ] {
        let out = prism(&dir, &[command, "--help"]);
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        let folded: String = text.split_whitespace().collect::<Vec<_>>().join(" ");
        assert!(folded.contains(default), "{command}: {text}");
        assert!(
            !folded.contains("for reference and sweep"),
            "{command}: {text}"
        );
    }
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
}

#[test]
fn spp_below_one_gets_the_range_not_a_parser_hint() {
    let dir = work_dir("spp-below-one");
    for command in ["render", "patterns"] {
        let out = prism(&dir, &[command, "--spp", "-4", "-q"]);
        let err = expect_exit(&out, 1, "--spp -4");
        assert!(
            err.contains("--spp takes a square number from 1 to 4096, got -4"),
            "{command}: {err}"
        );
        assert!(!err.contains("'-- -4'"), "{command}: {err}");
    }
    let out = prism(&dir, &["render", "--spp", "0", "-q"]);
    let err = expect_exit(&out, 1, "--spp 0");
    assert!(err.contains("at least 1"), "{err}");
    assert!(!err.contains("not a square number"), "{err}");
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
}

/// A negative number for any whole-number flag gets what the flag takes, not clap's hint
/// to write `-- -5` (which would not work either), as `--spp -4` does.
#[test]
fn negative_whole_numbers_get_the_range_not_a_parser_hint() {
    let dir = work_dir("negative-numbers");
    for (args, flag, takes) in [
        (
            &["render", "-W", "-5"][..],
            "--width <PIXELS>",
            "from 1 to 65536",
        ),
        (
            &["render", "-H", "-5"][..],
            "--height <PIXELS>",
            "from 1 to 65536",
        ),
        (&["render", "-d", "-1"][..], "--depth <N>", "from 1 to 256"),
        (&["render", "--seed", "-1"][..], "--seed <N>", "from 0 to"),
        (
            &["render", "-t", "-1"][..],
            "--threads <N>",
            "from 0 to 1024",
        ),
        (
            &["render", "--samples", "-2"][..],
            "--samples <N>",
            "from 1 to 64",
        ),
        (
            &["render", "--tile-size", "-8"][..],
            "--tile-size <PIXELS>",
            "from 1 to",
        ),
        (&["-W", "-5"][..], "--width <PIXELS>", "from 1 to 65536"),
        (
            &["reference", "-W", "-5"][..],
            "--width <PIXELS>",
            "from 1 to 65536",
        ),
        (
            &["serve", "-W", "-5"][..],
            "--width <PIXELS>",
            "from 1 to 65536",
        ),
        (
            &["serve", "-t", "-1"][..],
            "--threads <N>",
            "from 0 to 1024",
        ),
        (
            &["sweep", "--spp", "-4"][..],
            "--spp <LIST>",
            "square number from 1 to 4096",
        ),
        (
            &["sweep", "--spp", "4,-9"][..],
            "--spp <LIST>",
            "square number from 1 to 4096",
        ),
        (
            &["sweep", "--adaptive-depths", "-1"][..],
            "--adaptive-depths <LIST>",
            "from 0",
        ),
        (
            &["sweep", "-t", "-1"][..],
            "--threads <N>",
            "from 0 to 1024",
        ),
        (&["patterns", "--seed", "-1"][..], "--seed <N>", "from 0 to"),
        (
            &["bench", "--size", "-5"][..],
            "--size <PIXELS>",
            "a whole number",
        ),
        (
            &["bench", "--threads", "-1"][..],
            "--threads <N>",
            "from 0 to 1024",
        ),
    ] {
        let out = prism(&dir, args);
        let err = expect_exit(&out, 2, &args.join(" "));
        assert!(!err.contains("'-- -"), "{args:?}: {err}");
        assert!(
            err.contains(&format!("for '{flag}': expected a ")) && err.contains(takes),
            "{args:?}: {err}"
        );
    }
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
}

#[test]
fn a_bad_depth_names_the_flag_not_the_setting_key() {
    let dir = work_dir("depth-flag");
    let out = prism(&dir, &["render", "-d", "0", "-q"]);
    let err = expect_exit(&out, 1, "-d 0");
    assert!(err.contains("--depth must be between 1"), "{err}");
    assert!(!err.contains("max_depth"), "{err}");
    // The viewer checks it as its page's depth control does.
    let out = prism(&dir, &["serve", "-d", "0", "--port", "0"]);
    let err = expect_exit(&out, 1, "serve -d 0");
    assert!(
        err.contains("--depth: depth must be a whole number from 1"),
        "{err}"
    );
    assert!(!err.contains("max_depth"), "{err}");
    let out = prism(&dir, &["render", "--tile-size", "0", "-q"]);
    let err = expect_exit(&out, 1, "--tile-size 0");
    assert!(err.contains("--tile-size must be at least 1"), "{err}");
}

#[test]
fn patterns_says_what_it_wrote_unless_quiet() {
    let dir = work_dir("patterns-says");
    let out = prism(&dir, &["patterns", "-o", "p.svg"]);
    let err = expect_exit(&out, 0, "patterns");
    assert!(err.contains("prism: wrote p.svg"), "{err}");
    let out = prism(&dir, &["patterns", "-o", "q.svg", "--quiet"]);
    let err = expect_exit(&out, 0, "patterns --quiet");
    assert!(err.is_empty(), "{err}");
    assert!(dir.join("q.svg").is_file());
}

#[cfg(unix)]
#[test]
fn an_output_named_by_a_symbolic_link_is_written_to_its_target() {
    let dir = work_dir("output-link");
    fs::create_dir(dir.join("renders")).unwrap();
    std::os::unix::fs::symlink("renders/latest.png", dir.join("latest.png")).unwrap();
    std::os::unix::fs::symlink("renders/stats.json", dir.join("stats.json")).unwrap();
    let out = prism(
        &dir,
        &words("-b cornell -W 8 -H 6 -q -o latest.png --stats-json stats.json"),
    );
    expect_exit(&out, 0, "-o onto a link");
    for link in ["latest.png", "stats.json"] {
        let meta = fs::symlink_metadata(dir.join(link)).unwrap();
        assert!(meta.file_type().is_symlink(), "{link} is still a link");
    }
    assert_eq!(png_size(&dir.join("renders/latest.png")), (8, 6));
    assert!(fs::read_to_string(dir.join("renders/stats.json"))
        .unwrap()
        .contains('{'));
    // Written again through the link, the target is replaced and the link stays.
    let out = prism(&dir, &words("-b cornell -W 10 -H 6 -q -o latest.png"));
    expect_exit(&out, 0, "-o onto a link, again");
    assert!(fs::symlink_metadata(dir.join("latest.png"))
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(png_size(&dir.join("renders/latest.png")), (10, 6));
    let mut names = listing(&dir.join("renders"));
    names.sort();
    assert_eq!(names, ["latest.png", "stats.json"]);
}

/// `prism serve` takes a flag for every render setting its page's controls change, as
/// `render` names it (the settings table's flag, `render`'s short name and value name)
/// with the table's help: a control added to the page without its flag fails here. A value
/// the page would refuse is refused before listening, naming the flag.
#[test]
fn serve_takes_a_flag_for_every_setting_its_page_offers() {
    let dir = work_dir("serve-flags");
    let out = prism(&dir, &["serve", "--help"]);
    expect_exit(&out, 0, "serve --help");
    let help = String::from_utf8_lossy(&out.stdout).to_string();
    // Help texts are wrapped: compare with the line breaks folded.
    let folded: String = help.split_whitespace().collect::<Vec<_>>().join(" ");
    let render = prism(&dir, &["render", "--help"]);
    let render = String::from_utf8_lossy(&render.stdout).to_string();
    let mut offered = Vec::new();
    for c in prism_serve::controls::controls() {
        let Some(key) = prism_serve::controls::setting_key(c.name) else {
            // The viewer's own: what the picture shows, and the size (-W and -H).
            match c.name {
                "resolution" => assert!(
                    help.contains("-W, --width <PIXELS>") && help.contains("-H, --height"),
                    "{help}"
                ),
                other => assert_eq!(other, "view", "a control of no setting"),
            }
            continue;
        };
        let setting = prism::options::setting(key).unwrap();
        let flag = setting.flag.unwrap_or_else(|| panic!("{key} has no flag"));
        // The flag as `render --help` lists it: the same short name and value name.
        let listed = render
            .lines()
            .map(str::trim)
            .find(|l| l.contains(&format!("--{flag} ")))
            .and_then(|l| l.split("  ").next())
            .unwrap_or_else(|| panic!("--{flag} not in render --help"))
            .to_string();
        assert!(
            help.contains(&listed),
            "'{listed}' not in serve --help:\n{help}"
        );
        let sentence: String = setting
            .help
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        assert!(
            folded.contains(&sentence),
            "--{flag}: '{sentence}' not in:\n{help}"
        );
        offered.push(flag);
    }
    for flag in [
        "integrator",
        "accel",
        "sampler",
        "depth",
        "min-weight",
        "shadows",
    ] {
        assert!(
            offered.contains(&flag),
            "the page offers no {flag}: {offered:?}"
        );
    }
    // Checked as the page checks it, before listening, the flag named.
    for (args, said) in [
        (&["--integrator", "beam"][..], "whitted, path"),
        (&["--min-weight", "2"][..], "0 to 1"),
        (&["--shadows", "nope"][..], "nope"),
    ] {
        let out = prism(&dir, &[&["serve", "--port", "0"][..], args].concat());
        let err = expect_exit(&out, 1, &args.join(" "));
        assert!(err.contains(&format!("{}: ", args[0])), "{err}");
        assert!(err.contains(said), "{err}");
    }
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
}

/// What a newcomer reads points only at what a clone has: no command's help and not
/// docs/formats.md name a path in `../shared/`, the data folder beside the maintainers'
/// checkout (the suites that use it skip it with a message).
#[test]
fn help_and_the_formats_page_name_no_path_outside_the_clone() {
    let dir = work_dir("no-shared-paths");
    for command in [
        "render",
        "list",
        "info",
        "bench",
        "compare",
        "reference",
        "sweep",
        "patterns",
        "serve",
    ] {
        let out = prism(&dir, &[command, "--help"]);
        expect_exit(&out, 0, command);
        let help = String::from_utf8_lossy(&out.stdout);
        assert!(!help.contains("shared/"), "{command} --help: {help}");
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let formats = fs::read_to_string(root.join("docs/formats.md")).unwrap();
    for (n, line) in formats.lines().enumerate() {
        assert!(
            !line.contains("shared/"),
            "docs/formats.md:{}: {line}",
            n + 1
        );
    }
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
}

/// Ctrl-C as soon as a 20000 × 20000 render shows its progress bar ends it within about
/// a second, saying what it writes: the film comes zeroed from the allocator, so no
/// seconds of writing gigabytes of zeros stand between the signal and the tiles' stop
/// (on the main branch before, 6 to 8 s on two busy cores), and the pages no tile touched
/// cost nothing to give back.
#[cfg(unix)]
#[test]
fn ctrl_c_in_a_huge_render_exits_within_a_second_saying_what_it_writes() {
    let dir = work_dir("huge-ctrl-c");
    let mut render = common::terminal::OnTerminal::spawn(
        &dir,
        &words("render -W 20000 -H 20000 --threads 2 -o out.png"),
    );
    assert!(render.wait_for("%"), "no progress bar: {}", render.seen);
    let signalled = std::time::Instant::now();
    render.signal("INT");
    let (code, seen) = render.finish();
    let took = signalled.elapsed();
    assert_eq!(code, Some(130), "{seen}");
    assert!(
        took < Duration::from_millis(1500),
        "{took:?} from Ctrl-C to the end: {seen}"
    );
    assert!(
        seen.contains("stopping: keeping the finished tiles"),
        "{seen}"
    );
    assert!(
        seen.contains("rows of 20000 that finished tiles reached")
            || seen.contains("no tile was finished: the image is not written"),
        "{seen}"
    );
}

#[cfg(unix)]
mod long_tier {
    use super::*;

    /// A second Ctrl-C while the first one's image is being written ends the program at
    /// once and leaves no half-written temporary file (on the main branch before, a
    /// gigabyte of `.out.pfm.PID.tmp` stayed behind after "nothing written"). The band
    /// written must take long enough to catch its temporary file: a gigabyte-sized PFM of
    /// an empty scene, some twenty seconds and a gigabyte of disk, hence the long tier.
    #[test]
    #[ignore = "long tier: a second Ctrl-C in the middle of writing a gigabyte image"]
    fn a_second_ctrl_c_while_writing_leaves_no_temporary_file() {
        let dir = work_dir("second-ctrl-c-writing");
        fs::write(
            dir.join("empty.toml"),
            "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n",
        )
        .unwrap();
        let mut render = common::terminal::OnTerminal::spawn(
            &dir,
            &words("empty.toml -W 20000 -H 20000 --threads 2 -o out.pfm"),
        );
        assert!(render.wait_for_work_done(), "no progress: {}", render.seen);
        // Rows enough for a write of seconds.
        std::thread::sleep(Duration::from_secs(4));
        render.signal("INT");
        let first = std::time::Instant::now();
        let writing = |dir: &Path| listing(dir).iter().any(|n| n.ends_with(".tmp"));
        while !writing(&dir) {
            assert!(
                first.elapsed() < Duration::from_secs(120),
                "no temporary file"
            );
            std::thread::sleep(Duration::from_millis(2));
        }
        // The rule: a second signal counts once the first was answered.
        std::thread::sleep(Duration::from_millis(600).saturating_sub(first.elapsed()));
        let seen = render.interrupt();
        assert!(
            seen.contains("stopped at once on a second signal; nothing written"),
            "the write was over before the second signal: {seen}"
        );
        assert_eq!(listing(&dir), ["empty.toml"], "{seen}");
        let _ = fs::remove_dir_all(&dir);
    }
}
