//! Ctrl-C as `timeout -s INT` and a terminal deliver it: to the process and its group, so
//! one keypress can arrive twice within microseconds. The render says at once that it is
//! stopping, counts the pair as one, and still writes the rows its finished tiles reached.
//! A Ctrl-C answers within a tile, at any size: it stops the tiles in flight and writes
//! only what was reached, rather than a full-size image of black.

#![cfg(unix)]

use crate::common;

use common::terminal::OnTerminal;
use std::fs;
use std::io::{BufRead, BufReader, Read};
use std::process::{Command, Stdio};

#[test]
fn two_signals_at_once_are_one_ctrl_c_and_the_work_is_written() {
    let dir = common::work_dir("signals", "double-int");
    let mut render = OnTerminal::spawn(
        &dir,
        &common::words("render -b sphereflake -W 1200 -H 1200 --spp 64 --threads 1 -o out.pfm"),
    );
    // The progress bar shows once the render listens for Ctrl-C; work done, once there
    // are rows to write.
    assert!(render.wait_for_work_done(), "no progress: {}", render.seen);
    // Two SIGINTs back to back, as `timeout` sends one to the process and one to the group.
    let pid = render.child.id().to_string();
    let ok = Command::new("sh")
        .args(["-c", &format!("kill -INT {pid}; kill -INT {pid}")])
        .status()
        .unwrap()
        .success();
    assert!(ok);
    let (code, seen) = render.finish();
    assert_eq!(code, Some(130), "{seen}");
    // The first thing it says after the signal.
    let said = seen.find("prism: ").map_or("", |at| &seen[at..]);
    assert!(
        said.starts_with("prism: stopping: keeping the finished tiles; Ctrl-C again discards them"),
        "{seen}"
    );
    assert!(!seen.contains("stopped at once"), "{seen}");
    assert!(seen.contains("prism: wrote out.pfm"), "{seen}");
    let bytes = fs::read(dir.join("out.pfm")).unwrap();
    assert!(bytes.starts_with(b"PF\n1200 "), "the image's full width");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn ctrl_c_stops_inside_a_large_tile() {
    // One tile of the whole image on one thread, with packets and without: the tile takes
    // far longer than a Ctrl-C may wait, so the render stops inside it, with no tile
    // finished and nothing written.
    for (name, packets) in [("packets", None), ("single-rays", Some("--no-packets"))] {
        let dir = common::work_dir("signals", &format!("large-tile-{name}"));
        let mut args = common::words(
            "render -b sphereflake -W 2048 -H 2048 --spp 64 --tile-size 2048 --threads 1 \
             -o out.png",
        );
        args.extend(packets);
        let seen = interrupted_at_the_progress_bar(OnTerminal::spawn(&dir, &args));
        assert!(
            seen.contains("no tile was finished: the image is not written"),
            "{seen}"
        );
        assert!(!dir.join("out.png").exists(), "{seen}");
        let _ = fs::remove_dir_all(&dir);
    }
}

/// Presses Ctrl-C once `render`'s progress bar shows; asserts that the run ends as
/// interrupted, keeping the finished tiles, and returns what it showed.
#[track_caller]
fn interrupted_at_the_progress_bar(mut render: OnTerminal) -> String {
    assert!(render.wait_for("%"), "no progress bar: {}", render.seen);
    let seen = render.interrupt();
    assert!(
        seen.contains("stopping: keeping the finished tiles"),
        "{seen}"
    );
    seen
}

#[test]
fn ctrl_c_at_the_start_of_a_huge_render_writes_only_the_rows_reached() {
    let dir = common::work_dir("signals", "huge");
    let render = OnTerminal::spawn(
        &dir,
        &common::words("render -W 20000 -H 20000 --threads 2 -o out.png"),
    );
    let seen = interrupted_at_the_progress_bar(render);
    // What is written is said before it is written, and is a band from the top.
    match seen.find("writing the ") {
        Some(at) => {
            assert!(seen[at..].contains("rows of 20000"), "{seen}");
            let (width, height) = image::image_dimensions(dir.join("out.png")).unwrap();
            assert_eq!(width, 20000);
            assert!(height < 20000, "only the rows reached, not {height}");
            assert!(seen.contains("prism: wrote out.png"), "{seen}");
        }
        None => {
            assert!(seen.contains("no tile was finished"), "{seen}");
            assert!(!dir.join("out.png").exists());
        }
    }
    let _ = fs::remove_dir_all(&dir);
}

/// Renders the sphereflake on one thread at `size`² with `extra` arguments, signals SIGINT
/// once the progress bar shows work done, and returns the folder and what the terminal
/// showed, after checking that the render stopped as interrupted.
fn interrupted_sphereflake(name: &str, size: u32, extra: &[&str]) -> (std::path::PathBuf, String) {
    let dir = common::work_dir("signals", name);
    let size = size.to_string();
    let mut args = vec![
        "render",
        "-b",
        "sphereflake",
        "-W",
        &size,
        "-H",
        &size,
        "--threads",
        "1",
    ];
    args.extend(extra);
    let mut render = OnTerminal::spawn(&dir, &args);
    assert!(render.wait_for_work_done(), "no progress: {}", render.seen);
    (dir, render.interrupt())
}

/// The width and height in a PFM file's header.
fn pfm_size(path: &std::path::Path) -> (u32, u32) {
    let bytes = fs::read(path).unwrap();
    let header = String::from_utf8_lossy(&bytes[..bytes.len().min(64)]).to_string();
    let mut words = header.split_whitespace().skip(1);
    let mut next = || words.next().unwrap().parse::<u32>().unwrap();
    (next(), next())
}

#[test]
fn an_interrupted_render_writes_its_views_with_the_rows_of_its_image() {
    let (dir, seen) = interrupted_sphereflake(
        "views",
        1200,
        &[
            "--spp",
            "16",
            "-o",
            "out.pfm",
            "--density",
            "density.pfm",
            "--cost",
            "cost.png",
        ],
    );
    // Said before anything is written, naming every file it goes to.
    let at = seen.find("writing the ").expect(&seen);
    assert!(
        seen[at..].contains("to out.pfm, density.pfm and cost.png"),
        "{seen}"
    );
    assert!(
        seen.contains("prism: wrote out.pfm, density.pfm and cost.png"),
        "{seen}"
    );
    let image = pfm_size(&dir.join("out.pfm"));
    assert_eq!(image.0, 1200);
    assert!(image.1 < 1200, "only the rows reached, not {}", image.1);
    // The views lie over the image: the same rows, not the full height.
    assert_eq!(pfm_size(&dir.join("density.pfm")), image, "{seen}");
    // The cost view is a picture with a legend beside and a caption below its map, which
    // a full-height map alone would make taller than the image.
    let (_, cost_height) = image::image_dimensions(dir.join("cost.png")).unwrap();
    assert!(
        cost_height < 1200,
        "the cost view's map has every row: {cost_height}"
    );
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn an_interrupted_corners_pass_writes_only_the_rows_reached() {
    // Both lattice samplers trace every pixel corner first, from the top; a Ctrl-C in
    // that pass leaves the rows below the corners reached black, so they are not written.
    for sampler in ["corners", "adaptive"] {
        let (dir, seen) = interrupted_sphereflake(
            &format!("corners-{sampler}"),
            2400,
            &["--sampler", sampler, "-o", "out.pfm"],
        );
        let at = seen.find("writing the ").expect(&seen);
        assert!(seen[at..].contains("rows of 2400"), "{sampler}: {seen}");
        let (width, height) = pfm_size(&dir.join("out.pfm"));
        assert_eq!(width, 2400);
        assert!(height > 0 && height < 2400, "{sampler}: {height} rows");
        // Every row written holds the render's work: the sphereflake's background is
        // not black, so a row of zeros would be one no corner reached.
        let bytes = fs::read(dir.join("out.pfm")).unwrap();
        let floats: Vec<f32> = bytes[bytes.len() - (width * height * 12) as usize..]
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect();
        for (y, row) in floats.chunks_exact(width as usize * 3).enumerate() {
            assert!(
                row.iter().any(|&v| v > 0.0),
                "{sampler}: row {y} of {height} black"
            );
        }
        let _ = fs::remove_dir_all(&dir);
    }
}

/// `prism serve` started as a script starts it, in the background of a shell without job
/// control (which starts it with SIGINT ignored), ends on SIGINT and on SIGTERM, saying so.
#[test]
fn serve_started_in_the_background_stops_on_sigint_and_sigterm() {
    for (signal, code, said) in [
        ("INT", 130, "prism: interrupted: stopping the viewer"),
        (
            "TERM",
            143,
            "prism: terminated (SIGTERM): stopping the viewer",
        ),
    ] {
        let dir = common::work_dir("signals", &format!("serve-{signal}"));
        // The shell prints the server's process id, waits for it and prints its exit code.
        let script = "\"$0\" serve -b cornell --port 0 -W 64 -H 36 2>err.txt & \
                      echo \"pid $!\"; wait $!; echo \"exit $?\"";
        let mut shell = Command::new("sh")
            .args(["-c", script])
            .arg(common::bin())
            .current_dir(&dir)
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdout = BufReader::new(shell.stdout.take().unwrap());
        let mut lines = Vec::new();
        // Wait for the pid, then for the address the server prints once it listens.
        while !lines
            .iter()
            .any(|l: &String| l.starts_with("prism: viewing"))
        {
            let mut line = String::new();
            assert!(stdout.read_line(&mut line).unwrap() > 0, "{lines:?}");
            lines.push(line);
        }
        let pid = lines
            .iter()
            .find_map(|l| l.strip_prefix("pid "))
            .unwrap()
            .trim()
            .to_string();
        let ok = Command::new("kill")
            .args([&format!("-{signal}"), &pid])
            .status()
            .unwrap()
            .success();
        assert!(ok, "kill -{signal} {pid}");
        let mut rest = String::new();
        stdout.read_to_string(&mut rest).unwrap();
        shell.wait().unwrap();
        assert_eq!(rest.trim(), format!("exit {code}"), "{lines:?}");
        let err = fs::read_to_string(dir.join("err.txt")).unwrap();
        assert!(err.contains(said), "{err}");
        let _ = fs::remove_dir_all(&dir);
    }
}
