//! The terminal table of `prism bench`: one block per scene, one line per method; "P" is
//! primary rays (nearest hit), "S" shadow rays (any hit), "I" incoherent rays (nearest
//! hit).

use super::results::SceneResult;
use prism_lab::bench::RayKindResult;
use std::fmt::Write;

/// Nodes and tests per ray and Mrays/s, or dashes when a scene has no rays of the kind
/// (no lights, so no shadow rays).
fn kind_cells(r: &RayKindResult) -> String {
    if r.rays == 0 {
        return format!("{:>8} {:>8} {:>8}", "-", "-", "-");
    }
    format!(
        "{:>8.1} {:>8.1} {:>8}",
        r.node_visits_per_ray,
        r.primitive_tests_per_ray,
        rate(r.mrays_per_s)
    )
}

/// Mrays/s with three significant digits down to 0.001, so that a collapsed method does
/// not read as zero.
fn rate(v: f64) -> String {
    match v {
        v if v >= 100.0 => format!("{v:.0}"),
        v if v >= 10.0 => format!("{v:.1}"),
        v if v >= 1.0 => format!("{v:.2}"),
        v if v >= 0.1 => format!("{v:.3}"),
        v => format!("{v:.4}"),
    }
}

pub(super) fn header() -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<16} {:>8} {:<22} {:>9} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} \
         {:>8}",
        "scene",
        "prims",
        "method",
        "build ms",
        "MiB",
        "P nodes",
        "P tests",
        "P Mray/s",
        "S nodes",
        "S tests",
        "S Mray/s",
        "I nodes",
        "I tests",
        "I Mray/s",
        "vs best"
    );
    let _ = write!(s, "{}", "-".repeat(16 + 9 + 23 + 10 + 9 * 11));
    s
}

/// One scene's lines; the fastest method for primary rays is marked with `*`.
pub(super) fn scene_block(scene: &SceneResult) -> String {
    let mut s = String::new();
    let fastest = scene.fastest();
    for (i, row) in scene.rows.iter().enumerate() {
        let name = if i == 0 { scene.name.as_str() } else { "" };
        let prims = if i == 0 {
            scene.primitives.to_string()
        } else {
            String::new()
        };
        let method = if fastest == Some(i) {
            format!("{}*", row.method)
        } else {
            row.method.clone()
        };
        let _ = write!(s, "{name:<16} {prims:>8} {method:<22}");
        match row.measured() {
            Some(m) => {
                let vs = scene
                    .vs_best(i)
                    .map_or(String::from("-"), |v| format!("{:.2}", v));
                let _ = write!(
                    s,
                    " {:>9.1} {:>8.2} {} {} {} {:>8}",
                    m.build_ms,
                    m.accel.memory_bytes as f64 / (1024.0 * 1024.0),
                    kind_cells(&m.primary),
                    kind_cells(&m.shadow),
                    kind_cells(&m.incoherent),
                    vs
                );
                if row.mismatch {
                    let _ = write!(s, "  (hits differ from the reference!)");
                }
            }
            None => {
                let _ = write!(s, " {}", row.status());
            }
        }
        s.push('\n');
    }
    s
}

/// The shadow methods' lines of a scene (none unless `--shadows` asked for them): build
/// time, memory, work per shadow ray, the share of rays blocked, answered by the cache and
/// handed by a buffer to the accelerator, and throughput against the first method's.
pub(super) fn shadow_block(s: &SceneResult) -> String {
    let Some(first) = s.shadow_methods.first() else {
        return String::new();
    };
    let mut out = format!(
        "  {:<26} {:>9} {:>9} {:>9} {:>9} {:>7} {:>7} {:>7} {:>9} {:>8}\n",
        "shadow method",
        "build ms",
        "MiB",
        "tests/S",
        "nodes/S",
        "blocked",
        "cache",
        "accel",
        "MS/s",
        "vs first"
    );
    for m in &s.shadow_methods {
        out += &format!(
            "  {:<26} {:>9.1} {:>9.2} {:>9.2} {:>9.2} {:>6.1}% {:>6.1}% {:>6.1}% {:>9.2} \
             {:>7.0}%{}\n",
            m.method,
            m.build_ms,
            m.memory_bytes as f64 / (1 << 20) as f64,
            m.tests_per_ray,
            m.node_visits_per_ray,
            100.0 * m.blocked as f64 / m.rays.max(1) as f64,
            100.0 * m.cache_hit_rate,
            100.0 * m.fallback_rate,
            m.mrays_per_s,
            100.0 * m.mrays_per_s / first.mrays_per_s.max(1e-12),
            if m.mismatch { "  MISMATCH" } else { "" }
        );
        for note in &m.notes {
            out += &format!("    {note}\n");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::rate;

    #[test]
    fn rates_keep_three_digits_down_to_a_thousandth() {
        assert_eq!(rate(115.04), "115");
        assert_eq!(rate(23.96), "24.0");
        assert_eq!(rate(1.594), "1.59");
        assert_eq!(rate(0.2345), "0.234");
        assert_eq!(rate(0.00123), "0.0012");
    }
}
