//! `prism bench --chart`: grouped bars of primary-ray throughput, one group per scene and
//! one bar per method, on a log axis (the methods differ by orders of magnitude); the
//! fastest bar of each scene carries a triangle, skipped methods a cross.

use super::results::SceneResult;
use crate::plot::{axis, escape, log_grid, GridStyle, PALETTE};
use std::fmt::Write;

const BAR: f64 = 12.0;
const GAP: f64 = 18.0;
const LEFT: f64 = 70.0;
const TOP: f64 = 50.0;
const PLOT_HEIGHT: f64 = 320.0;
const LABELS: f64 = 110.0;

pub(super) fn svg(scenes: &[SceneResult], methods: &[String], title: &str) -> String {
    let values: Vec<f64> = scenes
        .iter()
        .flat_map(|s| s.rows.iter().filter_map(|r| r.measured()))
        .map(|m| m.primary.mrays_per_s)
        .filter(|&v| v > 0.0 && v.is_finite())
        .collect();
    let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = values.iter().copied().fold(0.0, f64::max);
    let (ya, yb, ticks) = if values.is_empty() {
        axis(1.0, 10.0)
    } else {
        axis(lo, hi)
    };
    let group = methods.len().max(1) as f64 * BAR + GAP;
    let plot_w = (scenes.len().max(1) as f64 * group).max(200.0);
    let legend_w = 40.0 + 7.5 * methods.iter().map(|m| m.chars().count()).max().unwrap_or(0) as f64;
    let width = (LEFT + plot_w + legend_w).max(LEFT + 8.5 * title.chars().count() as f64);
    let height = TOP + PLOT_HEIGHT + LABELS;
    let py = |v: f64| TOP + (1.0 - (v.log10() - ya) / (yb - ya)) * PLOT_HEIGHT;
    let base = TOP + PLOT_HEIGHT;

    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="Helvetica, Arial, sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{LEFT}" y="22" font-size="15" font-weight="bold">{}</text>"#,
        escape(title)
    );
    let _ = writeln!(
        s,
        r##"<text x="{LEFT}" y="38" fill="#555">▲ fastest for primary rays · × skipped</text>"##
    );
    log_grid(
        &mut s,
        [LEFT, TOP, plot_w, PLOT_HEIGHT],
        [],
        ticks.iter().map(|&t| (t, py(t))),
        &GridStyle {
            stroke: "#ddd",
            x_label_below: 0.0,
            y_label_left: 6.0,
            edge_decimals: 0,
        },
    );
    let _ = writeln!(
        s,
        r#"<text transform="translate(18 {:.1}) rotate(-90)" text-anchor="middle">primary rays, Mrays/s (log)</text>"#,
        TOP + PLOT_HEIGHT / 2.0
    );
    for (g, scene) in scenes.iter().enumerate() {
        let x0 = LEFT + GAP / 2.0 + g as f64 * group;
        let fastest = scene.fastest();
        for (i, row) in scene.rows.iter().enumerate() {
            let k = methods.iter().position(|m| *m == row.method).unwrap_or(i);
            let x = x0 + k as f64 * BAR;
            let colour = PALETTE[k % PALETTE.len()];
            match row.measured().map(|m| m.primary.mrays_per_s) {
                Some(v) if v > 0.0 && v.is_finite() => {
                    let y = py(v).min(base);
                    let _ = writeln!(
                        s,
                        r#"<rect x="{x:.1}" y="{y:.1}" width="{:.1}" height="{:.1}" fill="{colour}"><title>{}, {}: {v:.3} Mrays/s</title></rect>"#,
                        BAR - 1.0,
                        base - y,
                        escape(&scene.name),
                        escape(&row.method)
                    );
                    if fastest == Some(i) {
                        let _ = writeln!(
                            s,
                            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle" font-size="10">▲</text>"#,
                            x + BAR / 2.0,
                            y - 3.0
                        );
                    }
                }
                _ => {
                    let _ = writeln!(
                        s,
                        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle" fill="{colour}">×</text>"#,
                        x + BAR / 2.0,
                        base - 4.0
                    );
                }
            }
        }
        let cx = x0 + methods.len() as f64 * BAR / 2.0;
        let _ = writeln!(
            s,
            r#"<text transform="translate({cx:.1} {:.1}) rotate(-40)" text-anchor="end">{}</text>"#,
            base + 14.0,
            escape(&scene.name)
        );
    }
    let _ = writeln!(
        s,
        r##"<line x1="{LEFT}" y1="{base}" x2="{:.1}" y2="{base}" stroke="#333"/><line x1="{LEFT}" y1="{TOP}" x2="{LEFT}" y2="{base}" stroke="#333"/>"##,
        LEFT + plot_w
    );
    for (k, m) in methods.iter().enumerate() {
        let (lx, ly) = (LEFT + plot_w + 14.0, TOP + 8.0 + k as f64 * 18.0);
        let _ = writeln!(
            s,
            r#"<rect x="{lx:.1}" y="{:.1}" width="12" height="12" fill="{}"/><text x="{:.1}" y="{:.1}">{}</text>"#,
            ly - 10.0,
            PALETTE[k % PALETTE.len()],
            lx + 18.0,
            ly,
            escape(m)
        );
    }
    s.push_str("</svg>\n");
    s
}
