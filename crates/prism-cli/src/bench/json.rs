//! `prism bench --json`: the run's settings and, per scene, every method's full
//! measurement (what was built, per ray kind the work and throughput).

use super::results::{SceneResult, DEFAULT_TOLERANCE};
use prism::accel::AccelSpec;
use serde_json::{json, Value};

pub(super) struct RunSettings {
    pub threads: usize,
    /// What the times were read from.
    pub clock: &'static str,
    pub size: u32,
    pub repeat: usize,
}

pub(super) fn json(scenes: &[SceneResult], settings: &RunSettings) -> Value {
    let scenes: Vec<Value> = scenes
        .iter()
        .map(|s| {
            let rows: Vec<Value> = s
                .rows
                .iter()
                .enumerate()
                .map(|(i, r)| {
                    json!({
                        "method": r.method,
                        "spec": r.spec.to_string(),
                        "status": r.status(),
                        "measured": r.measured().map(|m| serde_json::to_value(m).unwrap_or(Value::Null)),
                        "vs_best": s.vs_best(i),
                    })
                })
                .collect();
            json!({
                "name": s.name,
                "primitives": s.primitives,
                "width": s.width,
                "height": s.height,
                "primary_rays": s.rays.primary,
                "primary_hits": s.primary_hits,
                "shadow_rays": s.rays.shadow,
                "incoherent_rays": s.rays.incoherent,
                "fastest": s.fastest().map(|i| s.rows[i].method.clone()),
                "default_vs_best": s.default_row().and_then(|i| s.vs_best(i)),
                "methods": rows,
            })
        })
        .collect();
    json!({
        "threads": settings.threads,
        "clock": settings.clock,
        "size": settings.size,
        "repeat": settings.repeat,
        "default_method": AccelSpec::default().to_string(),
        "default_tolerance": DEFAULT_TOLERANCE,
        "scenes": scenes,
    })
}
