//! The statistics report: a table for people (`--stats`), JSON for scripts (`--stats-json`).

use anyhow::{Context, Result};
use prism::geometry::ShapeKind;
use prism::render::RenderResult;
use prism::scene::PreparedScene;
use prism::stats::StageTimes;
use prism::{RenderOptions, Stats};
use serde_json::json;
use std::path::Path;
use std::time::Duration;

pub(crate) struct Report {
    json: serde_json::Value,
    /// The shadow rays' lines of the table.
    shadows: Vec<String>,
    stats: Stats,
    accel: String,
    times: [(&'static str, Duration); 3],
    pixels: u64,
    sampling: String,
}

impl Report {
    pub(crate) fn new(
        scene: &str,
        prepared: &PreparedScene,
        options: &RenderOptions,
        result: &RenderResult,
        load: Duration,
        output: &Path,
    ) -> Self {
        let s = result.stats;
        let pixels = options.width as u64 * options.height as u64;
        let render_s = result.render_time.as_secs_f64();
        let accel = prepared.intersector.accel.describe();
        let json = json!({
            "scene": scene,
            "output": output.display().to_string(),
            "complete": result.complete,
            "options": options,
            "accelerator": accel,
            "primitives": prepared.scene.geometry.primitives.len(),
            "lights": prepared.scene.lights.len(),
            "times_ms": {
                "load": load.as_secs_f64() * 1e3,
                "build": prepared.build_time.as_secs_f64() * 1e3,
                "render": render_s * 1e3,
            },
            "rays": {
                "primary": s.primary_rays,
                "primary_hits": s.primary_hits,
                "shadow": s.shadow_rays,
                "shadow_continuations": s.shadow_continuations,
                "reflected": s.reflected_rays,
                "refracted": s.refracted_rays,
                "pruned_by_min_weight": s.pruned_rays,
                "shadow_pruned_by_min_weight": s.pruned_shadow_rays,
                "total": s.total_rays(),
                "camera_per_pixel": s.primary_rays as f64 / pixels.max(1) as f64,
                "per_pixel": s.total_rays() as f64 / pixels.max(1) as f64,
                "per_second": s.total_rays() as f64 / render_s.max(1e-9),
            },
            "sampling": options.sampling_summary(),
            "adaptive_splits": s.adaptive_splits,
            "adaptive_stratified_pixels": s.adaptive_stratified,
            "total_internal_reflections": s.total_internal_reflections,
            "primitive_tests": s.primitive_tests,
            "primitive_tests_by_kind": ShapeKind::ALL
                .iter()
                .map(|k| (k.name(), s.tests_by_kind[*k as usize]))
                .filter(|(_, n)| *n > 0)
                .map(|(k, n)| (k.to_string(), json!(n)))
                .collect::<serde_json::Map<_, _>>(),
            "node_visits": s.node_visits,
            "wavefront_stage_ns_per_path": StageTimes::NAMES
                .iter()
                .zip(s.stages.ns)
                .map(|(k, ns)| (k.to_string(), json!(ns as f64 / s.primary_rays.max(1) as f64)))
                .collect::<serde_json::Map<_, _>>(),
            "shadows": {
                "method": options.shadows.to_string(),
                "rays": s.shadow_rays,
                "primitive_tests": s.shadow_tests,
                "node_visits": s.shadow_node_visits,
                "tests_per_ray": s.shadow_tests as f64 / s.shadow_rays.max(1) as f64,
                "cache_hits": s.shadow_cache_hits,
                "light_buffer_queries": s.light_buffer_queries,
                "light_buffers": result.light_buffers.iter().map(|b| b.map(|b| json!({
                    "resolution": b.resolution,
                    "orthographic": b.orthographic,
                    "cells": b.cells,
                    "entry_nodes": b.entry_nodes,
                    "mean_subtrees": b.mean_subtrees,
                    "leaf_share": b.leaf_share,
                    "memory_bytes": b.memory_bytes,
                    "build_ms": b.build_time.as_secs_f64() * 1e3,
                }))).collect::<Vec<_>>(),
                "without_buffer": result.light_buffer_notes,
            },
        });
        let shadows = shadow_lines(options, result);
        Report {
            json,
            shadows,
            stats: s,
            accel,
            times: [
                ("load", load),
                ("build", prepared.build_time),
                ("render", result.render_time),
            ],
            pixels,
            sampling: options.sampling_summary(),
        }
    }

    pub(crate) fn print_table(&self) {
        let s = &self.stats;
        let total = s.total_rays().max(1) as f64;
        println!("accelerator        {}", self.accel);
        println!("sampling           {}", self.sampling);
        println!("{:<18} {:>14} {:>8}", "rays", "count", "share");
        for (name, n) in [
            ("primary", s.primary_rays),
            ("  that hit", s.primary_hits),
            ("shadow", s.shadow_rays),
            ("shadow (through)", s.shadow_continuations),
            ("reflected", s.reflected_rays),
            ("refracted", s.refracted_rays),
        ] {
            println!("{name:<18} {n:>14} {:>7.1}%", 100.0 * n as f64 / total);
        }
        println!("{:<18} {:>14}", "total", s.total_rays());
        let px = self.pixels.max(1) as f64;
        println!(
            "{:<18} {:>14.3} {:>8}",
            "per pixel",
            s.total_rays() as f64 / px,
            format!("({:.3} camera)", s.primary_rays as f64 / px)
        );
        println!(
            "{:<18} {:>14}   (reflected/refracted rays below min_weight, each with its subtree)",
            "pruned", s.pruned_rays
        );
        println!(
            "{:<18} {:>14}   (shadow rays not cast: the light could add less than min_weight)",
            "pruned shadow", s.pruned_shadow_rays
        );
        if s.adaptive_splits > 0 {
            println!("{:<18} {:>14}", "adaptive splits", s.adaptive_splits);
        }
        if s.adaptive_stratified > 0 {
            println!(
                "{:<18} {:>14}   (textured pixels given the stratified pass)",
                "stratified pixels", s.adaptive_stratified
            );
        }
        println!("{:<18} {:>14}", "TIR events", s.total_internal_reflections);
        println!(
            "{:<18} {:>14} {:>8.2} per ray",
            "primitive tests",
            s.primitive_tests,
            s.primitive_tests as f64 / total
        );
        for kind in ShapeKind::ALL {
            let n = s.tests_by_kind[kind as usize];
            if n > 0 {
                println!("{:<18} {n:>14}", format!("  {}", kind.name()));
            }
        }
        println!(
            "{:<18} {:>14} {:>8.2} per ray",
            "node visits",
            s.node_visits,
            s.node_visits as f64 / total
        );
        for line in &self.shadows {
            println!("{line}");
        }
        if s.stages.total() > 0 {
            println!(
                "{:<18} {:>14} {:>8}",
                "wavefront stages", "ns per path", "share"
            );
            let total = s.stages.total() as f64;
            for (name, ns) in StageTimes::NAMES.iter().zip(s.stages.ns) {
                println!(
                    "{:<18} {:>14.1} {:>7.1}%",
                    format!("  {name}"),
                    ns as f64 / s.primary_rays.max(1) as f64,
                    100.0 * ns as f64 / total
                );
            }
        }
        for (name, t) in self.times {
            println!(
                "{:<18} {:>11.1} ms",
                format!("time: {name}"),
                t.as_secs_f64() * 1e3
            );
        }
        let secs = self.times[2].1.as_secs_f64().max(1e-9);
        println!(
            "{:<18} {:>14.3} Mrays/s ({:.3} Mpixels/s)",
            "throughput",
            s.total_rays() as f64 / secs / 1e6,
            self.pixels as f64 / secs / 1e6
        );
    }

    pub(crate) fn write_json(&self, path: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(&self.json).expect("the report serialises");
        if path == Path::new("-") {
            println!("{text}");
            return Ok(());
        }
        prism_io::output::write_atomic(path, (text + "\n").as_bytes())
            .with_context(|| format!("cannot write statistics to {}", path.display()))
    }
}

/// The shadow rays' share of the work, and what their method built.
fn shadow_lines(options: &RenderOptions, result: &RenderResult) -> Vec<String> {
    let s = &result.stats;
    let rays = s.shadow_rays.max(1) as f64;
    let mut lines = vec![
        format!("shadows            {}", options.shadows),
        format!(
            "{:<18} {:>14} {:>8.2} per shadow ray",
            "  tests",
            s.shadow_tests,
            s.shadow_tests as f64 / rays
        ),
        format!(
            "{:<18} {:>14} {:>8.2} per shadow ray",
            "  node visits",
            s.shadow_node_visits,
            s.shadow_node_visits as f64 / rays
        ),
    ];
    if s.shadow_cache_hits > 0 {
        lines.push(format!(
            "{:<18} {:>14} {:>7.1}% of shadow rays",
            "  cache hits",
            s.shadow_cache_hits,
            100.0 * s.shadow_cache_hits as f64 / rays
        ));
    }
    if s.light_buffer_queries > 0 {
        lines.push(format!(
            "{:<18} {:>14} {:>8.2} per shadow ray (segments through glass ask again)",
            "  buffer queries",
            s.light_buffer_queries,
            s.light_buffer_queries as f64 / rays
        ));
        lines.push(format!(
            "{:<18} {:>14} {:>7.1}% of shadow rays",
            "  to the accel",
            s.light_buffer_fallbacks,
            100.0 * s.light_buffer_fallbacks as f64 / rays
        ));
    }
    for (i, b) in result.light_buffers.iter().enumerate() {
        if let Some(b) = b {
            let layout = if b.orthographic {
                "across its direction"
            } else {
                "a face"
            };
            lines.push(format!(
                "  light {i} buffer   {} cells ({}² {layout}), {} entry nodes (mean {:.1} \
                 subtrees a cell, {:.0} % leaves), {:.1} MiB, built in {:.1} ms",
                b.cells,
                b.resolution,
                b.entry_nodes,
                b.mean_subtrees,
                100.0 * b.leaf_share,
                b.memory_bytes as f64 / (1 << 20) as f64,
                b.build_time.as_secs_f64() * 1e3
            ));
        }
    }
    for (i, note) in result.light_buffer_notes.iter().enumerate() {
        if let Some(note) = note {
            lines.push(format!("  light {i}: no buffer, {note}"));
        }
    }
    lines
}
