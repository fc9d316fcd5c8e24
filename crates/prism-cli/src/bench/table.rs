//! The terminal table of `prism bench`: one block per scene, one line per method; "P" is
//! primary rays (nearest hit), "S" shadow rays (any hit).

use super::results::SceneResult;
use std::fmt::Write;

pub fn header() -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<16} {:>8} {:<22} {:>9} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8}",
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
        "vs best"
    );
    let _ = write!(s, "{}", "-".repeat(16 + 9 + 23 + 10 + 9 * 8));
    s
}

/// One scene's lines; the fastest method for primary rays is marked with `*`.
pub fn scene_block(scene: &SceneResult) -> String {
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
                    " {:>9.1} {:>8.2} {:>8.1} {:>8.1} {:>8.2} {:>8.1} {:>8.1} {:>8.2} {:>8}",
                    m.build_ms,
                    m.accel.memory_bytes as f64 / (1024.0 * 1024.0),
                    m.primary.node_visits_per_ray,
                    m.primary.primitive_tests_per_ray,
                    m.primary.mrays_per_s,
                    m.shadow.node_visits_per_ray,
                    m.shadow.primitive_tests_per_ray,
                    m.shadow.mrays_per_s,
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
