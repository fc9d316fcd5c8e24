//! The sampling side of the command line: --spp and --sampler checks, the density view,
//! `prism compare`, `prism reference`, `prism sweep` and `prism patterns`; and `prism serve`
//! (the viewer itself has its suites in crates/prism-serve/tests).

use crate::common;

use common::{run, words};
use std::fs;
use std::path::PathBuf;

fn work_dir(test: &str) -> PathBuf {
    common::work_dir("commands", test)
}

const SMALL: [&str; 7] = ["render", "-b", "cornell", "-q", "-W", "20", "-H"];

fn render_args<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut args: Vec<&str> = SMALL.to_vec();
    args.push("14");
    args.extend(extra);
    args
}

#[test]
fn spp_must_be_square_and_fit_the_sampler() {
    let dir = work_dir("spp");
    let (_, err) = run(&dir, &render_args(&["--spp", "8", "-o", "a.png"]), 1);
    assert!(
        err.contains("--spp 8 is not a square number") && err.contains("try 4 or 9"),
        "{err}"
    );
    let (_, err) = run(
        &dir,
        &render_args(&["--sampler", "adaptive", "--spp", "4", "-o", "a.png"]),
        1,
    );
    assert!(err.contains("chooses its own sample count"), "{err}");
    let (_, err) = run(
        &dir,
        &render_args(&["--sampler", "stratified", "-o", "a.png"]),
        2,
    );
    assert!(err.contains("jittered") && err.contains("relaxed"), "{err}");
    assert!(!dir.join("a.png").exists());
    let (json, _) = run(
        &dir,
        &render_args(&[
            "--sampler",
            "jittered",
            "--spp",
            "9",
            "-o",
            "a.png",
            "--stats-json",
            "-",
        ]),
        0,
    );
    let json: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(json["rays"]["primary"], 20 * 14 * 9);
    assert_eq!(json["options"]["sampler"], "jittered");
    assert_eq!(json["rays"]["camera_per_pixel"], 9.0);
}

#[test]
fn the_stats_table_shows_rays_per_pixel_and_pruned_rays() {
    let dir = work_dir("stats");
    let (table, _) = run(
        &dir,
        &render_args(&["--sampler", "corners", "-o", "a.png", "--stats"]),
        0,
    );
    assert!(
        table.contains("sampling           corners, box filter"),
        "{table}"
    );
    let per_pixel = table
        .lines()
        .find(|l| l.starts_with("per pixel"))
        .unwrap_or_else(|| panic!("no per-pixel line:\n{table}"));
    // (21·15 corners + 20·14 centres) / (20·14) camera rays.
    assert!(per_pixel.contains("(2.125 camera)"), "{per_pixel}");
    assert!(table.contains("pruned"), "{table}");
}

#[test]
fn the_density_view_is_a_png_with_a_colour_bar() {
    let dir = work_dir("density");
    run(
        &dir,
        &render_args(&["--sampler", "adaptive", "-o", "a.png", "--density", "d.png"]),
        0,
    );
    let img = image::open(dir.join("d.png")).unwrap();
    assert!(
        img.width() > 20 && img.height() > 14,
        "enlarged, with bar and caption"
    );
    // A wrong format fails before rendering: no image is written.
    let (_, err) = run(
        &dir,
        &render_args(&["-o", "b.png", "--density", "d.jpg"]),
        1,
    );
    assert!(err.contains("written as PNG"), "{err}");
    assert!(!dir.join("b.png").exists());
    // PFM keeps the raw counts: the corners pattern's (21·15 + 20·14) camera rays.
    run(
        &dir,
        &render_args(&[
            "--sampler",
            "corners",
            "-o",
            "c.png",
            "--density",
            "c.pfm",
            "--density-rays",
            "camera",
        ]),
        0,
    );
    let counts = prism_io::output::read_image(&dir.join("c.pfm")).unwrap();
    assert_eq!((counts.width, counts.height), (20, 14));
    let sum: f32 = counts.pixels.iter().map(|c| c.x).sum();
    assert_eq!(sum, (21 * 15 + 20 * 14) as f32);
}

#[test]
fn compare_measures_the_difference_of_two_images() {
    let dir = work_dir("compare");
    run(&dir, &render_args(&["-o", "a.exr"]), 0);
    run(&dir, &render_args(&["-o", "b.pfm", "--spp", "4"]), 0);
    let (same, _) = run(&dir, &["compare", "a.exr", "a.exr"], 0);
    assert!(
        same.contains("RMSE   0.000000") && same.contains("inf dB"),
        "{same}"
    );
    let (json, _) = run(
        &dir,
        &["compare", "a.exr", "b.pfm", "--json", "--flip-map", "f.png"],
        0,
    );
    let json: serde_json::Value = serde_json::from_str(&json).unwrap();
    let rmse = json["rmse"].as_f64().unwrap();
    assert!(rmse > 0.0 && rmse < 0.2, "{json}");
    assert!(json["ssim"].as_f64().unwrap() < 1.0);
    assert!(dir.join("f.png").exists());
    run(
        &dir,
        &[
            "render", "-b", "cornell", "-q", "-W", "8", "-H", "8", "-o", "c.png",
        ],
        0,
    );
    let (_, err) = run(&dir, &["compare", "a.exr", "c.png"], 1);
    assert!(err.contains("differ in size: 20×14 and 8×8"), "{err}");
    let (_, err) = run(&dir, &["compare", "a.exr", "missing.png"], 1);
    assert!(err.contains("missing.png"), "{err}");
}

#[test]
fn reference_writes_the_exact_checkerboard_and_refuses_other_scenes() {
    let dir = work_dir("reference");
    run(&dir, &words("reference -q -W 32 -H 18 -o ref.pfm"), 0);
    run(
        &dir,
        &words("render -b checkerboard -q -W 32 -H 18 -o one.pfm"),
        0,
    );
    let (text, _) = run(&dir, &["compare", "ref.pfm", "one.pfm"], 0);
    assert!(
        !text.contains("RMSE   0.000000"),
        "one sample per pixel is not exact"
    );
    let (_, err) = run(&dir, &["reference", "-b", "whitted", "-o", "w.exr"], 1);
    assert!(err.contains("no exact reference"), "{err}");
}

#[test]
fn sweep_writes_a_table_plots_and_a_summary() {
    let dir = work_dir("sweep");
    let args = [
        "sweep",
        "-q",
        "-W",
        "24",
        "-H",
        "14",
        "--samplers",
        "grid,jittered,relaxed,adaptive",
        "--spp",
        "1,16",
        "--adaptive-depths",
        "1,2",
        "--adaptive-thresholds",
        "0.1",
        "-o",
        "out",
    ];
    let (summary, _) = run(&dir, &args, 0);
    for file in [
        "sweep.csv",
        "sweep-rmse.svg",
        "sweep-flip.svg",
        "sweep-far-rmse.svg",
        "summary.txt",
    ] {
        assert!(dir.join("out").join(file).exists(), "{file}");
    }
    let csv = fs::read_to_string(dir.join("out/sweep.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 2 + 2 + 2 + 2, "{csv}");
    assert!(
        summary.contains("jittered-16") && summary.contains("jittered vs grid"),
        "{summary}"
    );
    let svg = fs::read_to_string(dir.join("out/sweep-rmse.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("adaptive t=0.1"));
    let (_, err) = run(&dir, &["sweep", "--spp", "5", "-o", "x"], 1);
    assert!(err.contains("not a square"), "{err}");
}

/// `reference -o`, `compare --flip-map` and the files of `sweep -o` named by symbolic
/// links are written where the links point, and the links stay.
#[cfg(unix)]
#[test]
fn outputs_named_by_symbolic_links_are_written_to_their_targets() {
    let dir = work_dir("output-links");
    fs::create_dir_all(dir.join("kept/out")).unwrap();
    fs::create_dir(dir.join("out")).unwrap();
    let links = [
        ("ref.pfm", "kept/ref.pfm"),
        ("flip.png", "kept/flip.png"),
        ("out/summary.txt", "../kept/out/summary.txt"),
        ("out/sweep.csv", "../kept/out/sweep.csv"),
    ];
    for (link, target) in links {
        std::os::unix::fs::symlink(target, dir.join(link)).unwrap();
    }
    run(
        &dir,
        &["reference", "-q", "-W", "16", "-H", "8", "-o", "ref.pfm"],
        0,
    );
    let one = [
        "render",
        "-b",
        "checkerboard",
        "-q",
        "-W",
        "16",
        "-H",
        "8",
        "-o",
        "one.pfm",
    ];
    run(&dir, &one, 0);
    run(
        &dir,
        &["compare", "ref.pfm", "one.pfm", "--flip-map", "flip.png"],
        0,
    );
    let sweep = [
        "sweep",
        "-q",
        "-W",
        "12",
        "-H",
        "8",
        "--samplers",
        "grid",
        "--spp",
        "1",
        "-o",
        "out",
    ];
    run(&dir, &sweep, 0);
    for (link, target) in links {
        let meta = fs::symlink_metadata(dir.join(link)).unwrap();
        assert!(meta.file_type().is_symlink(), "{link} is still a link");
        let written = dir.join(link).parent().unwrap().join(target);
        assert!(fs::metadata(&written).unwrap().len() > 0, "{target}");
    }
    let reference = prism_io::output::read_image(&dir.join("kept/ref.pfm")).unwrap();
    assert_eq!((reference.width, reference.height), (16, 8));
}

#[test]
fn patterns_draws_every_sampler() {
    let dir = work_dir("patterns");
    run(&dir, &["patterns", "-o", "p.svg", "--spp", "4"], 0);
    let svg = fs::read_to_string(dir.join("p.svg")).unwrap();
    for name in [
        "centre", "grid", "corners", "random", "jittered", "relaxed", "adaptive",
    ] {
        assert!(svg.contains(&format!("{name}:")), "{name} missing");
    }
}

/// `prism serve` prints the page's address and serves it; the process is ended here by its
/// own handle.
#[test]
fn serve_prints_its_address_and_serves_the_page() {
    use std::io::{BufRead, BufReader, Read, Write};
    /// Ends the server however the test ends.
    struct Running(std::process::Child);
    impl Drop for Running {
        fn drop(&mut self) {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
    let dir = work_dir("serve");
    let mut child = Running(
        std::process::Command::new(common::bin())
            .args([
                "serve", "-b", "cornell", "--port", "0", "-W", "64", "-H", "36",
            ])
            .current_dir(&dir)
            .stdout(std::process::Stdio::piped())
            .spawn()
            .expect("prism serve starts"),
    );
    let mut line = String::new();
    BufReader::new(child.0.stdout.take().unwrap())
        .read_line(&mut line)
        .unwrap();
    let url = line.split_whitespace().last().unwrap_or("").to_string();
    let addr = url
        .strip_prefix("http://")
        .and_then(|a| a.strip_suffix('/'))
        .unwrap_or_else(|| panic!("no address in {line:?}"));
    assert!(
        line.contains("builtin:cornell") && addr.starts_with("127.0.0.1:"),
        "{line}"
    );
    let mut stream = std::net::TcpStream::connect(addr).unwrap();
    write!(
        stream,
        "GET / HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut page = String::new();
    stream.read_to_string(&mut page).unwrap();
    drop(child);
    assert!(
        page.starts_with("HTTP/1.1 200") && page.contains("prism viewer"),
        "{page}"
    );
}

#[test]
fn serve_refuses_bad_settings_before_listening() {
    let dir = work_dir("serve-bad");
    let (_, err) = run(&dir, &["serve", "--port", "0", "-W", "100000"], 1);
    assert!(err.contains("resolution"), "{err}");
    let (_, err) = run(&dir, &["serve", "--port", "0", "--sampler", "adaptive"], 1);
    assert!(err.contains("--sampler"), "{err}");
    let (_, err) = run(&dir, &["serve", "--port", "0", "--min-weight", "2"], 1);
    assert!(
        err.contains("--min-weight") && err.contains("0 to 1"),
        "{err}"
    );
    let (_, err) = run(&dir, &["serve", "--bind", "localhost"], 2);
    assert!(err.contains("--bind"), "{err}");
    // A port that is taken names the way out.
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let (_, err) = run(&dir, &["serve", "--port", &port], 1);
    assert!(
        err.contains("cannot listen") && err.contains("--port 0"),
        "{err}"
    );
}
