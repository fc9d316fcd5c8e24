//! `prism patterns`: a picture of every sampling pattern's points over a few pixels (SVG),
//! drawn with the library's own patterns. The adaptive panels refine the edge of a disk
//! (white inside, black outside) and a checker finer than the pixels (which takes the
//! stratified pass) with the library's refinement rule.

use crate::flags::per_axis;
use crate::plot::escape;
use anyhow::Result;
use clap::Args;
use prism::math::{Color, Vec2};
use prism::sampling::adaptive::{Refinement, Square, Visit};
use prism::sampling::{PixelPattern, RelaxedTile, Sampler, SamplerKind};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Args, Debug)]
pub(crate) struct PatternsArgs {
    /// Output picture (SVG).
    #[arg(short, long, value_name = "FILE", default_value = "patterns.svg")]
    pub output: PathBuf,

    /// Samples per pixel of the patterns that take a count (a square).
    #[arg(
        long,
        value_name = "N",
        default_value_t = 16,
        allow_negative_numbers = true
    )]
    pub spp: i64,

    /// Seed of the random patterns.
    #[arg(long, value_name = "N", default_value_t = 0, allow_negative_numbers = true, value_parser = crate::flags::whole::<u64>("seed"))]
    pub seed: u64,

    /// No closing message naming the file written (errors still show).
    #[arg(short, long)]
    pub quiet: bool,
}

/// Pixels per panel side, and drawing units per pixel.
const PIXELS: u32 = 3;
const UNIT: f64 = 72.0;
const PANEL: f64 = PIXELS as f64 * UNIT;
const GAP: f64 = 36.0;
const TITLE: f64 = 34.0;

/// What one panel shows.
struct Panel {
    title: String,
    /// Pixels across the panel.
    pixels: u32,
    /// Lines inside pixels (strata, quadtree squares): from, to, in pixel units.
    lines: Vec<(Vec2, Vec2)>,
    /// Points in pixel units, and whether they are shared with neighbouring pixels.
    points: Vec<(Vec2, bool)>,
    /// A circle to outline (centre, radius), for the adaptive panel.
    circle: Option<(Vec2, f32)>,
    /// Checker squares to shade (side in pixels), for the textured adaptive panel.
    checker: Option<f32>,
}

pub(crate) fn run(args: &PatternsArgs) -> Result<ExitCode> {
    let n = per_axis(args.spp)?;
    crate::outputs::check_writable(&args.output)?;
    let mut panels = Vec::new();
    for kind in SamplerKind::ALL {
        panels.push(panel(kind, n, args.seed));
    }
    // Relaxation works across pixel borders: show more pixels at fewer samples.
    let tile = RelaxedTile::new(2, args.seed);
    let mut wide = pixel_panel(
        "relaxed: 4 per pixel, 8×8 pixels".to_string(),
        8,
        &PixelPattern::Relaxed(tile),
    );
    wide.lines.clear();
    let options = prism::RenderOptions {
        sampler: SamplerKind::Adaptive,
        seed: args.seed,
        ..Default::default()
    };
    if let Sampler::Adaptive(rule) = Sampler::new(&options) {
        panels.push(adaptive_panel(rule, Motif::Checker(CHECKER)));
    }
    panels.push(wide);

    let cols = 4;
    let rows = panels.len().div_ceil(cols);
    let width = cols as f64 * (PANEL + GAP) + GAP;
    let height = rows as f64 * (PANEL + GAP + TITLE) + GAP;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="Helvetica, Arial, sans-serif" font-size="13">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    for (i, p) in panels.iter().enumerate() {
        let x0 = GAP + (i % cols) as f64 * (PANEL + GAP);
        let y0 = GAP + (i / cols) as f64 * (PANEL + GAP + TITLE) + TITLE;
        draw(&mut s, p, x0, y0);
    }
    s.push_str("</svg>\n");
    let output = crate::outputs::through_links(&args.output);
    prism_io::output::write_atomic(&output, s.as_bytes())?;
    if !args.quiet {
        eprintln!(
            "prism: wrote {} ({} panels)",
            args.output.display(),
            panels.len()
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn panel(kind: SamplerKind, n: u32, seed: u64) -> Panel {
    let options = prism::RenderOptions {
        sampler: kind,
        samples: n,
        seed,
        ..Default::default()
    };
    match Sampler::new(&options) {
        Sampler::Pixel(pattern) => {
            let count = pattern.count();
            let mut p = pixel_panel(format!("{kind}: {count} per pixel"), PIXELS, &pattern);
            if kind != SamplerKind::Jittered {
                p.lines.clear();
            }
            p
        }
        Sampler::Corners => {
            let mut points = Vec::new();
            for y in 0..=PIXELS {
                for x in 0..=PIXELS {
                    points.push((Vec2::new(x as f32, y as f32), true));
                }
            }
            for y in 0..PIXELS {
                for x in 0..PIXELS {
                    points.push((Vec2::new(x as f32 + 0.5, y as f32 + 0.5), false));
                }
            }
            Panel {
                title: "corners: ≈ 2 per pixel (shared)".into(),
                pixels: PIXELS,
                lines: Vec::new(),
                points,
                circle: None,
                checker: None,
            }
        }
        Sampler::Adaptive(rule) => adaptive_panel(rule, Motif::Disk(DISK.0, DISK.1)),
    }
}

/// The samples at `offsets` in pixel (`px`, `py`), as unmarked points of a panel.
fn pixel_samples(px: u32, py: u32, offsets: &[Vec2]) -> impl Iterator<Item = (Vec2, bool)> + '_ {
    (offsets.iter()).map(move |o| (Vec2::new(px as f32 + o.x, py as f32 + o.y), false))
}

fn pixel_panel(title: String, pixels: u32, pattern: &PixelPattern) -> Panel {
    let mut points = Vec::new();
    let mut offsets = Vec::new();
    for py in 0..pixels {
        for px in 0..pixels {
            offsets.clear();
            pattern.offsets(px, py, &mut offsets);
            points.extend(pixel_samples(px, py, &offsets));
        }
    }
    // Strata lines, for the jittered panel.
    let n = (pattern.count() as f32).sqrt().round() as u32;
    let mut lines = Vec::new();
    for k in 1..pixels * n {
        if k % n == 0 {
            continue;
        }
        let t = k as f32 / n as f32;
        let end = pixels as f32;
        lines.push((Vec2::new(t, 0.0), Vec2::new(t, end)));
        lines.push((Vec2::new(0.0, t), Vec2::new(end, t)));
    }
    Panel {
        title,
        pixels,
        lines,
        points,
        circle: None,
        checker: None,
    }
}

/// The disk of the adaptive panel (centre, radius) and the side of the textured panel's
/// checker squares, in pixels.
const DISK: (Vec2, f32) = (Vec2::new(-0.4, 3.3), 2.9);
const CHECKER: f32 = 0.3;

/// What the adaptive panels refine: white inside, black outside.
#[derive(Clone, Copy)]
enum Motif {
    Disk(Vec2, f32),
    Checker(f32),
}

impl Motif {
    fn white(self, p: Vec2) -> bool {
        match self {
            Motif::Disk(centre, radius) => p.distance(centre) < radius,
            Motif::Checker(side) => {
                let q = p / side;
                (q.x.floor() + q.y.floor()).rem_euclid(2.0) < 1.0
            }
        }
    }
}

/// Adaptive refinement of a motif: the points traced (each once), the squares, and the
/// stratified pass's points in textured pixels.
fn adaptive_panel(rule: Refinement, motif: Motif) -> Panel {
    let steps = rule.steps();
    let lookup = |x: u32, y: u32| {
        let (fx, fy) = rule.position(x, y);
        let p = Vec2::new(fx, fy) / steps as f32;
        Some(if motif.white(p) {
            Color::ONE
        } else {
            Color::ZERO
        })
    };
    let mut keys = std::collections::BTreeSet::new();
    let mut stratified = Vec::new();
    let mut offsets = Vec::new();
    let mut lines = Vec::new();
    for py in 0..PIXELS {
        for px in 0..PIXELS {
            rule.walk(
                Square::pixel(px, py, steps),
                rule.depth,
                &lookup,
                &mut |sq, v| {
                    for c in sq.corners() {
                        keys.insert(c);
                    }
                    if matches!(v, Visit::Stratified(_)) {
                        offsets.clear();
                        rule.texture_offsets(px, py, &mut offsets);
                        stratified.extend(pixel_samples(px, py, &offsets));
                    }
                    if matches!(v, Visit::Split) {
                        let s = steps as f32;
                        let (x, y, h) = (sq.x as f32 / s, sq.y as f32 / s, sq.size as f32 / s);
                        lines.push((Vec2::new(x + h / 2.0, y), Vec2::new(x + h / 2.0, y + h)));
                        lines.push((Vec2::new(x, y + h / 2.0), Vec2::new(x + h, y + h / 2.0)));
                    }
                },
            );
        }
    }
    let mut points: Vec<(Vec2, bool)> = keys
        .iter()
        .map(|&(x, y)| {
            let on_border = x % steps == 0 || y % steps == 0;
            let (fx, fy) = rule.position(x, y);
            (Vec2::new(fx, fy) / steps as f32, on_border)
        })
        .collect();
    points.extend(stratified);
    let (title, circle, checker) = match motif {
        Motif::Disk(c, r) => (
            format!("adaptive: {} rays, depth {}", points.len(), rule.depth),
            Some((c, r)),
            None,
        ),
        Motif::Checker(side) => (
            format!(
                "adaptive, texture: {} per pixel",
                rule.texture_n * rule.texture_n
            ),
            None,
            Some(side),
        ),
    };
    Panel {
        title,
        pixels: PIXELS,
        lines,
        points,
        circle,
        checker,
    }
}

fn draw(s: &mut String, p: &Panel, x0: f64, y0: f64) {
    let unit = PANEL / p.pixels as f64;
    let at = |v: Vec2| (x0 + v.x as f64 * unit, y0 + v.y as f64 * unit);
    let _ = writeln!(
        s,
        r#"<text x="{x0}" y="{}" font-weight="bold">{}</text>"#,
        y0 - 10.0,
        escape(&p.title)
    );
    let _ = writeln!(s, r##"<g clip-path="none">"##);
    if let Some((c, r)) = p.circle {
        let (cx, cy) = at(c);
        let _ = writeln!(
            s,
            r##"<clipPath id="clip{x0}{y0}"><rect x="{x0}" y="{y0}" width="{PANEL}" height="{PANEL}"/></clipPath><circle cx="{cx:.1}" cy="{cy:.1}" r="{:.1}" fill="#fde9c8" stroke="#e69f00" clip-path="url(#clip{x0}{y0})"/>"##,
            r as f64 * unit
        );
    }
    if let Some(side) = p.checker {
        // The white squares of the motif, cut at the panel's edge.
        let end = p.pixels as f32;
        let squares = (end / side).ceil() as u32;
        for j in 0..squares {
            for i in 0..squares {
                if (i + j) % 2 == 1 {
                    continue;
                }
                let lo = Vec2::new(i as f32, j as f32) * side;
                let hi = (lo + side).min(Vec2::splat(end));
                let (x, y) = at(lo);
                let (w, h) = ((hi - lo).as_dvec2() * unit).into();
                let _ = writeln!(
                    s,
                    r##"<rect x="{x:.1}" y="{y:.1}" width="{w:.2}" height="{h:.2}" fill="#fde9c8"/>"##
                );
            }
        }
    }
    for &(a, b) in &p.lines {
        let ((xa, ya), (xb, yb)) = (at(a), at(b));
        let _ = writeln!(
            s,
            r##"<line x1="{xa:.1}" y1="{ya:.1}" x2="{xb:.1}" y2="{yb:.1}" stroke="#bbb" stroke-width="0.8"/>"##
        );
    }
    for k in 0..=p.pixels {
        let t = k as f64 * unit;
        let _ = writeln!(
            s,
            r##"<line x1="{:.1}" y1="{y0}" x2="{:.1}" y2="{:.1}" stroke="#333" stroke-width="1.2"/><line x1="{x0}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="#333" stroke-width="1.2"/>"##,
            x0 + t,
            x0 + t,
            y0 + PANEL,
            y0 + t,
            x0 + PANEL,
            y0 + t
        );
    }
    let r = if p.pixels > PIXELS { 2.0 } else { 3.0 };
    let inside =
        |v: Vec2| (0.0..=p.pixels as f32).contains(&v.x) && (0.0..=p.pixels as f32).contains(&v.y);
    for &(v, shared) in p.points.iter().filter(|(v, _)| inside(*v)) {
        let (x, y) = at(v);
        let fill = if shared { "#D55E00" } else { "#0072B2" };
        let _ = writeln!(
            s,
            r#"<circle cx="{x:.1}" cy="{y:.1}" r="{r}" fill="{fill}"/>"#
        );
    }
    s.push_str("</g>\n");
}
