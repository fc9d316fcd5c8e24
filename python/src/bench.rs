//! `prism.bench`: the acceleration benchmark of `prism bench` (prism-lab's workload: one
//! camera ray per pixel and the shadow rays of their hits, every method timed in turns on
//! the same rays), returned as one record per scene and method instead of a table.

use crate::errors::{bad_argument, scene_error};
use prism::accel::AccelSpec;
use prism_lab::bench::{measure_all, Clock, MeasureOptions, RaySet};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::time::Duration;

/// A scene by name: a built-in (also sphereflake:N) or a scene file.
fn scene(name: &str) -> PyResult<prism::Scene> {
    match prism::scene::builtin::find(name) {
        Some(s) => Ok(s),
        None if std::path::Path::new(name).is_file() => {
            prism_io::scene::load(std::path::Path::new(name)).map_err(scene_error)
        }
        None => Err(bad_argument(format!(
            "'{name}' is neither a built-in scene ({}) nor a file",
            prism::scene::builtin::names().join(", ")
        ))),
    }
}

/// The image size with `size` pixels along the longer side, keeping the scene's aspect.
fn bench_size(options: &prism::RenderOptions, size: u32) -> (u32, u32) {
    let (w, h) = (options.width.max(1) as u64, options.height.max(1) as u64);
    let s = size as u64;
    if w >= h {
        (size, ((s * h + w / 2) / w).max(1) as u32)
    } else {
        (((s * w + h / 2) / h).max(1) as u32, size)
    }
}

/// Measures every method on every scene; records of scene, method, build time, structure
/// size, work per ray, throughput, and whether its hits match the reference BVH's.
#[pyfunction]
#[pyo3(signature = (scenes, methods=vec!["bvh".into(), "grid".into(), "kdtree".into(), "octree".into()],
    size=32, repeat=1, threads=1))]
pub(crate) fn bench<'py>(
    py: Python<'py>,
    scenes: Vec<String>,
    methods: Vec<String>,
    size: u32,
    repeat: usize,
    threads: usize,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let specs: Vec<AccelSpec> = (methods.iter())
        .map(|m| {
            m.parse()
                .map_err(|e: String| bad_argument(format!("method {m:?}: {e}")))
        })
        .collect::<PyResult<_>>()?;
    if size == 0 || repeat == 0 {
        return Err(bad_argument("size and repeat must be at least 1"));
    }
    let options = MeasureOptions {
        repeat,
        max_builds: 1,
        trace_budget: Duration::from_secs(3),
        min_sample: Duration::from_millis(10),
        clock: if threads == 1 {
            Clock::ProcessCpu
        } else {
            Clock::Wall
        },
        ..MeasureOptions::default()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| crate::errors::RenderError::new_err(e.to_string()))?;
    let mut records = Vec::new();
    for name in &scenes {
        let scene = scene(name)?;
        scene
            .validate()
            .map_err(|e| scene_error(format!("{name}: {e}")))?;
        let (width, height) = bench_size(&scene.options, size);
        let measured = py.allow_threads(|| {
            pool.install(|| {
                let reference = scene.prepare(&AccelSpec::default());
                let rays = RaySet::generate(&reference, width, height)?;
                drop(reference);
                let measured = measure_all(&scene, &specs, &rays, &options, |_| {});
                Ok::<_, prism::camera::CameraError>((rays, measured))
            })
        });
        let (rays, measured) =
            measured.map_err(|e| scene_error(format!("{name}: the camera: {e}")))?;
        for (method, m) in methods.iter().zip(measured) {
            let d = PyDict::new(py);
            d.set_item("scene", name)?;
            d.set_item("method", method)?;
            d.set_item("primitives", scene.geometry.primitives.len())?;
            d.set_item("width", width)?;
            d.set_item("height", height)?;
            d.set_item("build_ms", m.build_ms)?;
            d.set_item("nodes", m.accel.nodes)?;
            d.set_item("memory_bytes", m.accel.memory_bytes)?;
            d.set_item("primary_rays", m.primary.rays)?;
            d.set_item("primary_mrays_per_s", m.primary.mrays_per_s)?;
            d.set_item("primary_nodes_per_ray", m.primary.node_visits_per_ray)?;
            d.set_item("primary_tests_per_ray", m.primary.primitive_tests_per_ray)?;
            d.set_item("shadow_rays", m.shadow.rays)?;
            d.set_item("shadow_mrays_per_s", m.shadow.mrays_per_s)?;
            d.set_item("shadow_nodes_per_ray", m.shadow.node_visits_per_ray)?;
            d.set_item("shadow_tests_per_ray", m.shadow.primitive_tests_per_ray)?;
            d.set_item(
                "matches_reference",
                m.primary_digest == rays.primary_digest && m.shadow_digest == rays.shadow_digest,
            )?;
            records.push(d);
        }
    }
    Ok(records)
}
