//! Figures as hand-written SVG: a log–log line plot (error against rays per pixel) and
//! the drawing helpers the pattern pictures use. No plotting library: the few elements
//! needed are simpler to write than to configure.

use std::fmt::Write;

/// Okabe and Ito's colour-blind-safe palette without its yellow (too pale on white),
/// then three of Paul Tol's muted colours and a grey.
pub(crate) const PALETTE: [&str; 10] = [
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000", "#882255",
    "#999933", "#777777",
];

pub(crate) struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub colour: &'static str,
    pub dashed: bool,
}

pub(crate) struct LogLogPlot {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

const PLOT_WIDTH: f64 = 560.0;
const HEIGHT: f64 = 480.0;
const LEFT: f64 = 80.0;
const TOP: f64 = 44.0;
const BOTTOM: f64 = 60.0;

/// Escapes text for SVG.
pub(crate) fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A log axis from `lo` to `hi` (positive): the range with a little room on both sides,
/// as powers of ten, and its labelled ticks (1, 2, 5 or 1, 3 times powers of ten).
pub(crate) fn axis(lo: f64, hi: f64) -> (f64, f64, Vec<f64>) {
    let (mut a, mut b) = (lo.log10(), hi.log10());
    if b - a < 0.5 {
        let mid = 0.5 * (a + b);
        a = mid - 0.25;
        b = mid + 0.25;
    }
    let pad = 0.06 * (b - a);
    let (a, b) = (a - pad, b + pad);
    let mults: &[f64] = if b - a <= 2.5 {
        &[1.0, 2.0, 5.0]
    } else if b - a <= 4.0 {
        &[1.0, 3.0]
    } else {
        &[1.0]
    };
    let mut ticks = Vec::new();
    for e in a.floor() as i32..=b.ceil() as i32 {
        for m in mults {
            let v = m * 10f64.powi(e);
            if (a..=b).contains(&v.log10()) {
                ticks.push(v);
            }
        }
    }
    (a, b, ticks)
}

/// A tick label: 0.001, 0.02, 1, 30, 1000, 1e5.
pub(crate) fn tick_label(v: f64) -> String {
    if (1e-4..1e5).contains(&v) {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.0e}")
    }
}

/// How `log_grid` draws a plot area's grid: the gridlines' colour, how far below the area
/// the x labels' baseline sits, how far left of it the y labels end, and the decimals of
/// the area's edges in the SVG (each figure keeps the text it has always written).
pub(crate) struct GridStyle {
    pub stroke: &'static str,
    pub x_label_below: f64,
    pub y_label_left: f64,
    pub edge_decimals: usize,
}

/// Gridlines across the plot area `[left, top, width, height]` at the ticks of its log
/// axes, each labelled with its value: `xs` and `ys` are the ticks' values and positions.
pub(crate) fn log_grid(
    s: &mut String,
    [left, top, width, height]: [f64; 4],
    xs: impl IntoIterator<Item = (f64, f64)>,
    ys: impl IntoIterator<Item = (f64, f64)>,
    style: &GridStyle,
) {
    let (stroke, d) = (style.stroke, style.edge_decimals);
    for (t, x) in xs {
        let _ = writeln!(
            s,
            r#"<line x1="{x:.1}" y1="{top:.d$}" x2="{x:.1}" y2="{:.1}" stroke="{stroke}"/><text x="{x:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            top + height,
            top + height + style.x_label_below,
            tick_label(t)
        );
    }
    for (t, y) in ys {
        let _ = writeln!(
            s,
            r#"<line x1="{left:.d$}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="{stroke}"/><text x="{:.1}" y="{:.1}" text-anchor="end">{}</text>"#,
            left + width,
            left - style.y_label_left,
            y + 4.0,
            tick_label(t)
        );
    }
}

impl LogLogPlot {
    pub(crate) fn svg(&self) -> String {
        let all: Vec<(f64, f64)> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|&(x, y)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite())
            .collect();
        let fold = |f: fn(f64, f64) -> f64, init: f64, pick: fn(&(f64, f64)) -> f64| {
            all.iter().map(pick).fold(init, f)
        };
        let (x_lo, x_hi) = (
            fold(f64::min, f64::INFINITY, |p| p.0),
            fold(f64::max, 0.0, |p| p.0),
        );
        let (y_lo, y_hi) = (
            fold(f64::min, f64::INFINITY, |p| p.1),
            fold(f64::max, 0.0, |p| p.1),
        );
        let (xa, xb, xt) = if all.is_empty() {
            axis(1.0, 10.0)
        } else {
            axis(x_lo, x_hi)
        };
        let (ya, yb, yt) = if all.is_empty() {
            axis(1.0, 10.0)
        } else {
            axis(y_lo, y_hi)
        };
        let longest = self
            .series
            .iter()
            .map(|s| s.label.chars().count())
            .max()
            .unwrap_or(0);
        let right = 60.0 + 7.5 * longest as f64;
        let width = LEFT + PLOT_WIDTH + right;
        let pw = PLOT_WIDTH;
        let ph = HEIGHT - TOP - BOTTOM;
        let px = |x: f64| LEFT + (x.log10() - xa) / (xb - xa) * pw;
        let py = |y: f64| TOP + (1.0 - (y.log10() - ya) / (yb - ya)) * ph;

        let mut s = String::new();
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{HEIGHT}" viewBox="0 0 {width} {HEIGHT}" font-family="Helvetica, Arial, sans-serif" font-size="13">"#
        );
        let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
        let _ = writeln!(
            s,
            r#"<text x="{}" y="24" font-size="15" font-weight="bold">{}</text>"#,
            LEFT,
            escape(&self.title)
        );
        log_grid(
            &mut s,
            [LEFT, TOP, pw, ph],
            xt.iter().map(|&t| (t, px(t))),
            yt.iter().map(|&t| (t, py(t))),
            &GridStyle {
                stroke: "#ddd",
                x_label_below: 18.0,
                y_label_left: 6.0,
                edge_decimals: 0,
            },
        );
        let _ = writeln!(
            s,
            r##"<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="none" stroke="#333"/>"##
        );
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            LEFT + pw / 2.0,
            HEIGHT - 16.0,
            escape(&self.x_label)
        );
        let _ = writeln!(
            s,
            r#"<text transform="translate(20 {:.1}) rotate(-90)" text-anchor="middle">{}</text>"#,
            TOP + ph / 2.0,
            escape(&self.y_label)
        );
        // Series and legend.
        for (i, series) in self.series.iter().enumerate() {
            let pts: Vec<(f64, f64)> = series
                .points
                .iter()
                .copied()
                .filter(|&(x, y)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite())
                .collect();
            let dash = if series.dashed {
                r#" stroke-dasharray="6 4""#
            } else {
                ""
            };
            if pts.len() > 1 {
                let path: Vec<String> = pts
                    .iter()
                    .map(|&(x, y)| format!("{:.1},{:.1}", px(x), py(y)))
                    .collect();
                let _ = writeln!(
                    s,
                    r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="2"{dash}/>"#,
                    path.join(" "),
                    series.colour
                );
            }
            for &(x, y) in &pts {
                let _ = writeln!(
                    s,
                    r#"<circle cx="{:.1}" cy="{:.1}" r="3.5" fill="{}"/>"#,
                    px(x),
                    py(y),
                    series.colour
                );
            }
            let ly = TOP + 10.0 + i as f64 * 20.0;
            let lx = LEFT + pw + 16.0;
            let _ = writeln!(
                s,
                r#"<line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="{}" stroke-width="2"{dash}/><circle cx="{}" cy="{ly}" r="3.5" fill="{}"/><text x="{}" y="{}">{}</text>"#,
                lx + 24.0,
                series.colour,
                lx + 12.0,
                series.colour,
                lx + 30.0,
                ly + 4.0,
                escape(&series.label)
            );
        }
        s.push_str("</svg>\n");
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_cover_the_data_with_round_ticks() {
        let (a, b, ticks) = axis(1.0, 64.0);
        assert!(a <= 0.0 && b >= 64f64.log10());
        assert!(ticks.contains(&1.0) && ticks.contains(&10.0) && ticks.contains(&50.0));
        assert!(
            !ticks.contains(&0.5) && !ticks.contains(&100.0),
            "{ticks:?}"
        );
        assert_eq!(tick_label(0.02), "0.02");
        assert_eq!(tick_label(1000.0), "1000");
    }

    #[test]
    fn a_plot_is_one_svg_document_with_every_series() {
        let plot = LogLogPlot {
            title: "a < b".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            series: vec![Series {
                label: "jittered".into(),
                points: vec![(1.0, 0.1), (4.0, 0.05), (16.0, 0.02)],
                colour: PALETTE[0],
                dashed: false,
            }],
        };
        let svg = plot.svg();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("a &lt; b") && svg.contains("jittered"));
        assert_eq!(svg.matches("<circle").count(), 4);
    }
}
