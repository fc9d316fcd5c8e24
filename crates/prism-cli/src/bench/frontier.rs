//! `prism bench --frontier`: build time against trace time, one panel per scene and one
//! point per method, both axes logarithmic; the methods that no other beats on both (the
//! Pareto front) are filled and joined by a line, the others hollow. Trace time is one
//! pass over the scene's camera, shadow and incoherent rays.

use super::results::SceneResult;
use crate::plot::{axis, escape, log_grid, GridStyle, PALETTE};
use std::fmt::Write;

const PANEL_W: f64 = 250.0;
const PANEL_H: f64 = 190.0;
const MARGIN_L: f64 = 56.0;
const MARGIN_B: f64 = 40.0;
const PAD_T: f64 = 26.0;
const COLUMNS: usize = 4;
const TOP: f64 = 50.0;

/// Build and trace time of one method on one scene, in ms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Cost {
    pub build_ms: f64,
    pub trace_ms: f64,
}

/// Each measured method's cost on `scene`, by row (`None` where it was skipped or took
/// no measurable time).
pub(super) fn costs(scene: &SceneResult) -> Vec<Option<Cost>> {
    (scene.rows.iter())
        .map(|r| {
            let m = r.measured()?;
            let cost = Cost {
                // A build under the clock's resolution still costs something: keep it on
                // the log axis at a microsecond.
                build_ms: m.build_ms.max(1e-3),
                trace_ms: 1e3 * (m.primary.seconds + m.shadow.seconds + m.incoherent.seconds),
            };
            (cost.trace_ms > 0.0 && cost.trace_ms.is_finite()).then_some(cost)
        })
        .collect()
}

/// The indices of the points no other point beats on both build and trace time (ties
/// count as beaten only by an earlier point), in order of build time.
pub(super) fn pareto_front(points: &[Option<Cost>]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).filter(|&i| points[i].is_some()).collect();
    let cost = |i: usize| points[i].expect("measured");
    order.sort_by(|&a, &b| {
        (cost(a).build_ms.total_cmp(&cost(b).build_ms))
            .then(cost(a).trace_ms.total_cmp(&cost(b).trace_ms))
            .then(a.cmp(&b))
    });
    let mut front = Vec::new();
    let mut best_trace = f64::INFINITY;
    for i in order {
        if cost(i).trace_ms < best_trace {
            best_trace = cost(i).trace_ms;
            front.push(i);
        }
    }
    front
}

pub(super) fn svg(scenes: &[SceneResult], methods: &[String], title: &str) -> String {
    let columns = scenes.len().clamp(1, COLUMNS);
    let rows = scenes.len().div_ceil(COLUMNS).max(1);
    let cell_w = MARGIN_L + PANEL_W + 20.0;
    let cell_h = PAD_T + PANEL_H + MARGIN_B;
    let legend_h = 18.0 * methods.len() as f64 + 20.0;
    let width = (columns as f64 * cell_w + 20.0).max(8.5 * title.chars().count() as f64);
    let height = TOP + rows as f64 * cell_h + legend_h;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="Helvetica, Arial, sans-serif" font-size="11">"#
    );
    let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="20" y="22" font-size="15" font-weight="bold">{}</text>"#,
        escape(title)
    );
    let _ = writeln!(
        s,
        r##"<text x="20" y="38" fill="#555">x: build ms, y: ms per pass over the camera and shadow rays (both log); filled and joined: the Pareto front</text>"##
    );
    for (k, scene) in scenes.iter().enumerate() {
        let x0 = 20.0 + (k % COLUMNS) as f64 * cell_w + MARGIN_L;
        let y0 = TOP + (k / COLUMNS) as f64 * cell_h + PAD_T;
        panel(&mut s, scene, methods, x0, y0);
    }
    let legend_y = TOP + rows as f64 * cell_h;
    for (k, m) in methods.iter().enumerate() {
        let y = legend_y + 14.0 + 18.0 * k as f64;
        let _ = writeln!(
            s,
            r#"<circle cx="26" cy="{:.1}" r="5" fill="{}"/><text x="38" y="{y:.1}">{}</text>"#,
            y - 4.0,
            PALETTE[k % PALETTE.len()],
            escape(m)
        );
    }
    s.push_str("</svg>\n");
    s
}

/// One scene's panel with its top left corner (of the plot area) at (`x0`, `y0`).
fn panel(s: &mut String, scene: &SceneResult, methods: &[String], x0: f64, y0: f64) {
    let points = costs(scene);
    let measured: Vec<Cost> = points.iter().flatten().copied().collect();
    let _ = writeln!(
        s,
        r#"<text x="{x0:.1}" y="{:.1}" font-weight="bold">{}</text>"#,
        y0 - 8.0,
        escape(&scene.name)
    );
    let _ = writeln!(
        s,
        r##"<rect x="{x0:.1}" y="{y0:.1}" width="{PANEL_W}" height="{PANEL_H}" fill="none" stroke="#333"/>"##
    );
    if measured.is_empty() {
        return;
    }
    let range = |f: fn(&Cost) -> f64| {
        let lo = measured.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = measured.iter().map(f).fold(0.0, f64::max);
        axis(lo, hi)
    };
    let (xa, xb, xticks) = range(|c| c.build_ms);
    let (ya, yb, yticks) = range(|c| c.trace_ms);
    let px = |v: f64| x0 + (v.log10() - xa) / (xb - xa) * PANEL_W;
    let py = |v: f64| y0 + (1.0 - (v.log10() - ya) / (yb - ya)) * PANEL_H;
    log_grid(
        s,
        [x0, y0, PANEL_W, PANEL_H],
        xticks.iter().map(|&t| (t, px(t))),
        yticks.iter().map(|&t| (t, py(t))),
        &GridStyle {
            stroke: "#eee",
            x_label_below: 14.0,
            y_label_left: 4.0,
            edge_decimals: 1,
        },
    );
    let _ = writeln!(
        s,
        r##"<text x="{:.1}" y="{:.1}" text-anchor="middle" fill="#555">build ms</text>"##,
        x0 + PANEL_W / 2.0,
        y0 + PANEL_H + 30.0
    );
    let front = pareto_front(&points);
    let line: Vec<String> = (front.iter())
        .map(|&i| {
            let c = points[i].expect("on the front");
            format!("{:.1},{:.1}", px(c.build_ms), py(c.trace_ms))
        })
        .collect();
    let _ = writeln!(
        s,
        r##"<polyline points="{}" fill="none" stroke="#999" stroke-dasharray="4 3"/>"##,
        line.join(" ")
    );
    for (i, (row, point)) in scene.rows.iter().zip(&points).enumerate() {
        let Some(c) = point else {
            continue;
        };
        let k = methods.iter().position(|m| *m == row.method).unwrap_or(i);
        let colour = PALETTE[k % PALETTE.len()];
        let fill = if front.contains(&i) { colour } else { "white" };
        let _ = writeln!(
            s,
            r#"<circle cx="{:.1}" cy="{:.1}" r="4.5" fill="{fill}" stroke="{colour}" stroke-width="1.5"><title>{}: build {:.3} ms, trace {:.3} ms</title></circle>"#,
            px(c.build_ms),
            py(c.trace_ms),
            escape(&row.method),
            c.build_ms,
            c.trace_ms
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cost(build_ms: f64, trace_ms: f64) -> Option<Cost> {
        Some(Cost { build_ms, trace_ms })
    }

    #[test]
    fn the_front_keeps_the_points_nothing_beats_on_both() {
        let points = [
            cost(10.0, 5.0),  // front: fastest trace
            cost(1.0, 9.0),   // front: fastest build
            cost(5.0, 9.5),   // beaten by 1 on both
            None,             // skipped
            cost(4.0, 6.0),   // front
            cost(4.0, 6.0),   // a tie with 4: beaten by the earlier one
            cost(20.0, 5.0),  // beaten by 0 (same trace, slower build)
            cost(0.5, 100.0), // front
        ];
        assert_eq!(pareto_front(&points), vec![7, 1, 4, 0]);
        assert!(pareto_front(&[None, None]).is_empty());
    }
}
