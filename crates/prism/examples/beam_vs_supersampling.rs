//! Beam tracing against jittered supersampling (docs/beam-tracing.md): for each scene the
//! beam tracer's exact box-filtered image and its time, fragments and beam-tree size, then
//! jittered 4×4, 8×8 and 16×16 samples per pixel with their times and RMSE against it.
//! Writes a Markdown table to stdout and an SVG plot (error against time) to the path given
//! (default docs/images/beam-vs-supersampling.svg). Run by bench/beam.sh.
//!
//! Scenes: the checkerboard (beam tolerance 1e-3 at 160 × 90: its horizon holds unboundedly
//! many squares), the built-in mirror-room (flat walls and a mirror, as tests/beam.rs uses
//! it), and SPD tetra (../shared/scenes/spd/tetra.nff, skipped when absent).

use prism::options::{IntegratorKind, RenderOptions};
use prism::render::{render, render_beam};
use prism::sampling::SamplerKind;
use prism::scene::{builtin, Scene};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

struct Row {
    scene: String,
    method: String,
    seconds: f64,
    rmse: Option<f64>,
    note: String,
}

fn main() {
    let svg = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "docs/images/beam-vs-supersampling.svg".into());
    let mut scenes: Vec<(String, Scene, u32, u32, f64)> = vec![
        (
            "checkerboard".into(),
            builtin::find("checkerboard").unwrap(),
            160,
            90,
            1e-3,
        ),
        (
            "mirror-room".into(),
            builtin::find("mirror-room").unwrap(),
            256,
            256,
            1e-4,
        ),
    ];
    let tetra = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/scenes/spd/tetra.nff");
    if tetra.exists() {
        // prism-io is a dev-dependency of the engine: its loader reads the NFF.
        scenes.push((
            "SPD tetra".into(),
            prism_io::scene::load(&tetra).unwrap(),
            256,
            256,
            1e-4,
        ));
    } else {
        eprintln!("skipped: {} is absent", tetra.display());
    }
    let mut rows = Vec::new();
    for (name, scene, w, h, tol) in &scenes {
        let prepared = scene.prepare(&scene.options.accel);
        let base = RenderOptions {
            width: *w,
            height: *h,
            ..scene.options.clone()
        };
        let beam_options = RenderOptions {
            integrator: IntegratorKind::Beam,
            ..base.clone()
        };
        let start = Instant::now();
        let beam = render_beam(
            &prepared,
            &beam_options,
            *tol,
            &|_| {},
            &AtomicBool::new(false),
        )
        .unwrap();
        rows.push(Row {
            scene: name.clone(),
            method: "beam (exact)".into(),
            seconds: start.elapsed().as_secs_f64(),
            rmse: None,
            note: format!(
                "{} beams, {} fragments, {} pixel pieces, depth {}, bound {:.0e}",
                beam.stats.beams,
                beam.stats.beam_fragments,
                beam.stats.beam_pieces,
                beam.deepest,
                beam.error_bound()
            ),
        });
        for n in [4, 8, 16] {
            let options = RenderOptions {
                sampler: SamplerKind::Jittered,
                samples: n,
                ..base.clone()
            };
            let start = Instant::now();
            let r = render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap();
            let seconds = start.elapsed().as_secs_f64();
            let rmse = prism_lab::metrics::rmse(&r.film, &beam.film, None).unwrap();
            rows.push(Row {
                scene: name.clone(),
                method: format!("jittered {n}×{n} ({} spp)", n * n),
                seconds,
                rmse: Some(rmse),
                note: format!("{} rays", r.stats.total_rays()),
            });
        }
    }
    println!("| scene | method | time (s) | RMSE against the beam image | work |");
    println!("|---|---|---|---|---|");
    for r in &rows {
        let e = r
            .rmse
            .map_or("0 (the reference)".into(), |e| format!("{e:.5}"));
        println!(
            "| {} | {} | {:.3} | {} | {} |",
            r.scene, r.method, r.seconds, e, r.note
        );
    }
    std::fs::write(&svg, plot(&rows)).unwrap();
    eprintln!("wrote {svg}");
}

/// Error against time, log–log, one line of jittered points per scene and the beam
/// tracer's time as a vertical mark on it.
fn plot(rows: &[Row]) -> String {
    let (w, h, m) = (640.0, 400.0, 60.0);
    let times: Vec<f64> = rows.iter().map(|r| r.seconds.max(1e-4)).collect();
    let errs: Vec<f64> = rows
        .iter()
        .filter_map(|r| r.rmse)
        .map(|e| e.max(1e-5))
        .collect();
    let (t0, t1) = (
        times
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min)
            .log10()
            .floor(),
        times.iter().cloned().fold(0.0, f64::max).log10().ceil(),
    );
    let (e0, e1) = (
        errs.iter()
            .cloned()
            .fold(f64::INFINITY, f64::min)
            .log10()
            .floor(),
        errs.iter().cloned().fold(0.0, f64::max).log10().ceil(),
    );
    let x = |t: f64| m + (t.max(1e-4).log10() - t0) / (t1 - t0).max(1.0) * (w - 2.0 * m);
    let y = |e: f64| h - m - (e.max(1e-5).log10() - e0) / (e1 - e0).max(1.0) * (h - 2.0 * m);
    let colours = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd"];
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" \
         fill=\"white\"/>\n<text x=\"{}\" y=\"20\" text-anchor=\"middle\">RMSE of jittered \
         supersampling against the exact beam image, by time; dashed: the beam tracer's \
         time</text>\n<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">seconds (log)</text>\n\
         <text x=\"14\" y=\"{}\" transform=\"rotate(-90 14 {})\" text-anchor=\"middle\">RMSE \
         (log)</text>\n",
        w / 2.0,
        w / 2.0,
        h - 15.0,
        h / 2.0,
        h / 2.0
    );
    s += &format!(
        "<rect x=\"{m}\" y=\"{m}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888\"/>\n",
        w - 2.0 * m,
        h - 2.0 * m
    );
    for d in (t0 as i32)..=(t1 as i32) {
        s += &format!(
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">1e{d}</text>\n",
            x(10f64.powi(d)),
            h - m + 15.0
        );
    }
    for d in (e0 as i32)..=(e1 as i32) {
        s += &format!(
            "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">1e{d}</text>\n",
            m - 4.0,
            y(10f64.powi(d)) + 4.0
        );
    }
    let mut names: Vec<&str> = rows.iter().map(|r| r.scene.as_str()).collect();
    names.dedup();
    for (k, name) in names.iter().enumerate() {
        let c = colours[k % colours.len()];
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.scene == *name)
            .filter_map(|r| r.rmse.map(|e| (x(r.seconds), y(e))))
            .collect();
        let path: Vec<String> = pts.iter().map(|(a, b)| format!("{a:.1},{b:.1}")).collect();
        s += &format!(
            "<polyline points=\"{}\" fill=\"none\" stroke=\"{c}\" stroke-width=\"2\"/>\n",
            path.join(" ")
        );
        for (a, b) in &pts {
            s += &format!("<circle cx=\"{a:.1}\" cy=\"{b:.1}\" r=\"3\" fill=\"{c}\"/>\n");
        }
        if let Some(r) = rows.iter().find(|r| r.scene == *name && r.rmse.is_none()) {
            let bx = x(r.seconds);
            s += &format!(
                "<line x1=\"{bx:.1}\" y1=\"{m}\" x2=\"{bx:.1}\" y2=\"{}\" stroke=\"{c}\" \
                 stroke-dasharray=\"5,4\"/>\n",
                h - m
            );
        }
        s += &format!(
            "<text x=\"{}\" y=\"{}\" fill=\"{c}\">{name}</text>\n",
            w - m - 150.0,
            m + 16.0 + 16.0 * k as f64
        );
    }
    s + "</svg>\n"
}
