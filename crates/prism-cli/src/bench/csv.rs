//! `prism bench --csv`: one line per (scene, method), the same figures as the table and
//! JSON, empty cells where a method was skipped.

use super::results::SceneResult;

pub(super) const COLUMNS: [&str; 27] = [
    "scene",
    "primitives",
    "width",
    "height",
    "method",
    "status",
    "build_ms",
    "memory_bytes",
    "nodes",
    "leaves",
    "depth",
    "sah_cost",
    "primary_rays",
    "primary_hits",
    "primary_nodes_per_ray",
    "primary_tests_per_ray",
    "primary_mrays_per_s",
    "shadow_rays",
    "shadow_hits",
    "shadow_nodes_per_ray",
    "shadow_tests_per_ray",
    "shadow_mrays_per_s",
    "incoherent_rays",
    "incoherent_hits",
    "incoherent_nodes_per_ray",
    "incoherent_tests_per_ray",
    "incoherent_mrays_per_s",
];

/// The last two columns: primary throughput over the scene's fastest, and whether this is
/// the fastest.
pub(super) const COMPARISON: [&str; 2] = ["vs_best", "fastest"];

/// Quotes a field holding a comma, quote or line break (RFC 4180).
fn field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

pub(super) fn csv(scenes: &[SceneResult]) -> String {
    let mut out = COLUMNS
        .iter()
        .chain(&COMPARISON)
        .copied()
        .collect::<Vec<_>>()
        .join(",");
    out.push('\n');
    for s in scenes {
        let fastest = s.fastest();
        for (i, row) in s.rows.iter().enumerate() {
            let mut cells = vec![
                field(&s.name),
                s.primitives.to_string(),
                s.width.to_string(),
                s.height.to_string(),
                field(&row.method),
                field(&row.status()),
            ];
            match row.measured() {
                Some(m) => {
                    let kind = |r: &prism_lab::bench::RayKindResult| {
                        [
                            r.rays.to_string(),
                            r.hits.to_string(),
                            format!("{:.4}", r.node_visits_per_ray),
                            format!("{:.4}", r.primitive_tests_per_ray),
                            format!("{:.4}", r.mrays_per_s),
                        ]
                    };
                    cells.extend([
                        format!("{:.3}", m.build_ms),
                        m.accel.memory_bytes.to_string(),
                        m.accel.nodes.to_string(),
                        m.accel.leaves.to_string(),
                        m.accel.depth.to_string(),
                        m.accel
                            .sah_cost
                            .map_or(String::new(), |c| format!("{c:.3}")),
                    ]);
                    for r in [&m.primary, &m.shadow, &m.incoherent] {
                        cells.extend(kind(r));
                    }
                }
                None => cells.extend(std::iter::repeat_n(String::new(), COLUMNS.len() - 6)),
            }
            cells.push(s.vs_best(i).map_or(String::new(), |v| format!("{v:.4}")));
            cells.push((fastest == Some(i)).to_string());
            out += &cells.join(",");
            out.push('\n');
        }
    }
    out
}
