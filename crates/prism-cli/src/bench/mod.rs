//! `prism bench`: a matrix of scenes × acceleration methods on a fixed workload (one camera
//! ray per pixel and the shadow rays of their hits, the same for every method), printed as
//! a table and written as CSV, JSON and an SVG chart from the same results.

mod chart;
mod csv;
mod frontier;
mod json;
mod results;
mod scenes;
mod table;

use anyhow::{Context, Result};
use clap::Args;
use prism::accel::{AccelKind, AccelSpec, BvhBuilder};
use prism_lab::bench::{measure_all_expecting, Clock, MeasureOptions, RaySet};
use results::{Outcome, Row, SceneResult};
use scenes::SceneSource;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

/// The methods measured when none are given. Any spec `--accel` takes may be added.
pub(crate) const DEFAULT_METHODS: &[&str] = &["bvh", "grid", "kdtree", "octree", "brute-force"];

/// Brute force is skipped when primitives × rays exceeds this (about ten seconds a pass).
const BRUTE_FORCE_BUDGET: u64 = 1_000_000_000;

#[derive(Args, Debug)]
pub(crate) struct BenchArgs {
    /// Scenes, comma separated: built-in names (see `prism list`), sphereflake:N, or scene
    /// files [default: every built-in, the bad cases included].
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub scenes: Vec<String>,

    /// Methods as `--accel` specs, separated by ';' (a ',' separates a spec's parameters),
    /// e.g. "bvh;bvh:leaf=1;grid:lambda=2" [default: bvh;grid;kdtree;octree;brute-force].
    #[arg(long, value_name = "LIST")]
    pub methods: Option<String>,

    /// One method as an `--accel` spec; may be repeated, and adds to --methods.
    #[arg(long = "method", value_name = "SPEC")]
    pub method: Vec<String>,

    /// Also run every .nff file in DIR (e.g. a folder of Haines' SPD scenes).
    #[arg(long, value_name = "DIR")]
    pub spd: Option<PathBuf>,

    /// Longer image side in pixels; the scene's aspect ratio is kept. One camera ray per
    /// pixel [default: 256, or 32 with --quick].
    #[arg(long, value_name = "PIXELS", allow_negative_numbers = true, value_parser = crate::flags::whole::<u32>("size"))]
    pub size: Option<u32>,

    /// Timed samples per method and ray kind, each as many passes over the rays as last
    /// 30 ms; the median counts. Sampling stops early after 3 s [default: 5, or 1 with
    /// --quick].
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = crate::flags::whole::<usize>("repeat"))]
    pub repeat: Option<usize>,

    /// Worker threads for building and tracing; 0 uses every core. One keeps the noise
    /// down.
    #[arg(long, value_name = "N", default_value_t = 1, allow_negative_numbers = true, value_parser = crate::flags::whole::<usize>("threads"))]
    pub threads: usize,

    /// Small images and a single pass and build: for tests and a first look.
    #[arg(long)]
    pub quick: bool,

    /// Write the results as CSV.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,

    /// Write the results as JSON.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,

    /// Write a bar chart of primary-ray throughput (SVG).
    #[arg(long, value_name = "FILE")]
    pub chart: Option<PathBuf>,

    /// Write a chart of build time against trace time per scene, the Pareto front of the
    /// methods marked (SVG); e.g. with every BVH builder as the methods.
    #[arg(long, value_name = "FILE")]
    pub frontier: Option<PathBuf>,

    /// Also time shadow methods (as `render --shadows` takes them, separated by ';') on
    /// each scene's shadow rays with the default BVH, in turns, e.g.
    /// "any-hit;cache;light-buffer;both;auto".
    #[arg(long, value_name = "LIST")]
    pub shadows: Option<String>,

    /// Measure each `build=auto` method once per pass count in LIST (comma separated), as
    /// the row METHOD@N built for N passes over the camera and shadow rays, the render
    /// bench/bvh-auto-check.py weighs [default: one row, built for one pass over the
    /// camera, shadow and incoherent rays].
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = crate::flags::whole::<u32>("auto-passes"))]
    pub auto_passes: Vec<u32>,

    /// No progress lines on standard error.
    #[arg(short, long)]
    pub quiet: bool,
}

impl BenchArgs {
    /// The methods, each as written and parsed; a `build=auto` one once per `--auto-passes`.
    fn methods(&self) -> Result<Vec<Method>> {
        let mut texts: Vec<String> = self
            .methods
            .iter()
            .flat_map(|m| m.split(';'))
            .chain(self.method.iter().map(String::as_str))
            .map(|m| m.trim().to_string())
            .filter(|m| !m.is_empty())
            .collect();
        if texts.is_empty() {
            if self.methods.is_some() || !self.method.is_empty() {
                anyhow::bail!("no method given: --methods takes specs separated by ';'");
            }
            texts = DEFAULT_METHODS.iter().map(|m| m.to_string()).collect();
        }
        let mut methods = Vec::new();
        for t in texts {
            let spec = t
                .parse::<AccelSpec>()
                .map_err(|e| anyhow::anyhow!("bad method '{t}': {e}"))?;
            let auto = matches!(&spec, AccelSpec::Bvh(o) if o.builder == BvhBuilder::Auto);
            if auto && !self.auto_passes.is_empty() {
                methods.extend(self.auto_passes.iter().map(|&n| Method {
                    name: format!("{t}@{n}"),
                    spec: spec.clone(),
                    auto_passes: Some(n),
                }));
            } else {
                methods.push(Method {
                    name: t,
                    spec,
                    auto_passes: None,
                });
            }
        }
        Ok(methods)
    }

    fn sources(&self) -> Result<Vec<SceneSource>> {
        let mut sources: Vec<SceneSource> = if self.scenes.is_empty() {
            prism::scene::builtin::names()
                .into_iter()
                .map(|n| SceneSource::Builtin(n.to_string()))
                .collect()
        } else {
            self.scenes
                .iter()
                .map(|s| SceneSource::resolve(s))
                .collect::<Result<_>>()?
        };
        if let Some(dir) = &self.spd {
            sources.extend(scenes::spd_files(dir)?);
        }
        Ok(sources)
    }
}

/// A method to measure: its name in the results, its spec, and for a `build=auto` row of
/// `--auto-passes`, the passes over the camera and shadow rays it is built for.
struct Method {
    name: String,
    spec: AccelSpec,
    auto_passes: Option<u32>,
}

pub(crate) fn run(args: &BenchArgs) -> Result<ExitCode> {
    let methods = args.methods()?;
    let shadow_specs: Vec<prism::integrator::ShadowSpec> = match &args.shadows {
        None => Vec::new(),
        Some(list) => list
            .split(';')
            .map(|s| {
                s.trim()
                    .parse()
                    .map_err(|e: String| anyhow::anyhow!("--shadows: {e}"))
            })
            .collect::<Result<_>>()?,
    };
    let sources = args.sources()?;
    let mut outputs = crate::outputs::Outputs::default();
    for (path, ext) in [
        (&args.csv, &[][..]),
        (&args.json, &[][..]),
        (&args.chart, &["svg"][..]),
        (&args.frontier, &["svg"][..]),
    ] {
        if let Some(p) = path {
            outputs.add(p, ext)?;
        }
    }
    let size = args
        .size
        .unwrap_or(if args.quick { 32 } else { 256 })
        .max(1);
    let repeat = args.repeat.unwrap_or(if args.quick { 1 } else { 5 }).max(1);
    let mut options = MeasureOptions {
        repeat,
        max_builds: if args.quick { 1 } else { 5 },
        trace_budget: Duration::from_secs(3),
        min_sample: if args.quick {
            Duration::ZERO
        } else {
            Duration::from_millis(30)
        },
        ..MeasureOptions::default()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads)
        .build()
        .context("cannot start the worker threads")?;
    let threads = pool.current_num_threads();
    // One thread: CPU time, which other processes on the machine do not inflate. Several:
    // CPU time would sum them, so wall time.
    options.clock = if threads == 1 {
        Clock::ProcessCpu
    } else {
        Clock::Wall
    };
    println!(
        "prism bench: {size} px (longer side), 1 camera ray per pixel plus shadow rays to each \
         light and a diffuse bounce from each hit; {threads} thread{}, median of {repeat} sample{} timed by {}",
        if threads == 1 { "" } else { "s" },
        if repeat == 1 { "" } else { "s" },
        options.clock.describe()
    );
    println!(
        "P = primary rays (nearest hit), S = shadow rays (any hit), I = incoherent rays \
         (nearest hit); nodes and tests per ray; * = fastest for P"
    );
    println!("{}", table::header());

    let mut results = Vec::new();
    for source in &sources {
        let scene = source.load()?;
        scene
            .validate()
            .with_context(|| format!("{}: the scene is not valid", source.name()))?;
        let result = pool.install(|| {
            bench_scene(
                &scene,
                source.name(),
                (&methods, &shadow_specs),
                size,
                &options,
                args.quiet,
            )
        })?;
        print!("{}", table::scene_block(&result));
        print!("{}", table::shadow_block(&result));
        results.push(result);
    }
    println!();
    for line in results::summary(&results) {
        println!("{line}");
    }

    let method_names: Vec<String> = methods.iter().map(|m| m.name.clone()).collect();
    let settings = json::RunSettings {
        threads,
        clock: options.clock.describe(),
        size,
        repeat,
    };
    let mut outputs: Vec<(&PathBuf, Vec<u8>)> = Vec::new();
    if let Some(p) = &args.csv {
        outputs.push((p, csv::csv(&results).into_bytes()));
    }
    if let Some(p) = &args.json {
        let text = serde_json::to_string_pretty(&json::json(&results, &settings))?;
        outputs.push((p, (text + "\n").into_bytes()));
    }
    if let Some(p) = &args.chart {
        let title = format!(
            "Primary rays per second by scene and method ({size} px, {threads} thread{})",
            if threads == 1 { "" } else { "s" }
        );
        outputs.push((p, chart::svg(&results, &method_names, &title).into_bytes()));
    }
    if let Some(p) = &args.frontier {
        let title = format!(
            "Build time against trace time by scene and method ({size} px, {threads} thread{})",
            if threads == 1 { "" } else { "s" }
        );
        outputs.push((
            p,
            frontier::svg(&results, &method_names, &title).into_bytes(),
        ));
    }
    for (path, bytes) in outputs {
        prism_io::output::write_atomic(path, &bytes)?;
    }
    let wrong: Vec<String> = results
        .iter()
        .flat_map(|s| {
            let accels = s
                .rows
                .iter()
                .filter(|r| r.mismatch)
                .map(move |r| format!("{} on {}", r.method, s.name));
            let shadows = s
                .shadow_methods
                .iter()
                .filter(|m| m.mismatch)
                .map(move |m| format!("shadows {} on {}", m.method, s.name));
            accels.chain(shadows)
        })
        .collect();
    if !wrong.is_empty() {
        anyhow::bail!(
            "hits differ from the reference BVH's: {} (the results are written, marked)",
            wrong.join(", ")
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn bench_scene(
    scene: &prism::Scene,
    name: String,
    (methods, shadow_specs): (&[Method], &[prism::integrator::ShadowSpec]),
    size: u32,
    options: &MeasureOptions,
    quiet: bool,
) -> Result<SceneResult> {
    let (w, h) = (scene.options.width.max(1), scene.options.height.max(1));
    let (width, height) = if w >= h {
        (
            size,
            ((size as u64 * h as u64 + w as u64 / 2) / w as u64).max(1) as u32,
        )
    } else {
        (
            ((size as u64 * w as u64 + h as u64 / 2) / h as u64).max(1) as u32,
            size,
        )
    };
    if !quiet {
        eprintln!("bench: {name}: tracing the reference rays");
    }
    let reference = scene.prepare(&AccelSpec::default());
    let rays = RaySet::generate(&reference, width, height)
        .with_context(|| format!("{name}: cannot set up the camera"))?;
    let shadow_methods = if shadow_specs.is_empty() {
        Vec::new()
    } else {
        if !quiet {
            eprintln!("bench: {name}: shadow methods");
        }
        prism_lab::bench::measure_shadow_methods(&reference, &rays, shadow_specs, options)
    };
    let bounded = (0..scene.geometry.primitives.len() as u32)
        .filter(|&i| scene.geometry.bounds(i).is_some())
        .count() as u64;
    drop(reference);
    let traced = rays.primary.len() + rays.shadow.len() + rays.incoherent.len();
    let work = bounded * traced as u64;
    let skipped =
        |spec: &AccelSpec| spec.kind() == AccelKind::BruteForce && work > BRUTE_FORCE_BUDGET;
    // The methods that run are built first and then timed in turns (`measure_all_expecting`).
    let running: Vec<&Method> = methods.iter().filter(|m| !skipped(&m.spec)).collect();
    let specs: Vec<AccelSpec> = running.iter().map(|m| m.spec.clone()).collect();
    let expected_rays: Vec<f64> = (running.iter())
        .map(|m| match m.auto_passes {
            Some(n) => n as f64 * (rays.primary.len() + rays.shadow.len()) as f64,
            None => traced as f64,
        })
        .collect();
    let mut measured = measure_all_expecting(scene, &specs, &expected_rays, &rays, options, |i| {
        if !quiet {
            eprintln!("bench: {name}: {}", running[i].name);
        }
    })
    .into_iter();
    let mut rows = Vec::new();
    for Method {
        name: method, spec, ..
    } in methods
    {
        let outcome = if skipped(spec) {
            Outcome::Skipped(format!("{bounded} primitives × {traced} rays is too slow"))
        } else {
            Outcome::Measured(Box::new(
                measured.next().expect("one measurement per running method"),
            ))
        };
        let mismatch = match &outcome {
            // Which primitive at which distance for every primary and incoherent ray,
            // which shadow rays are blocked: all as the reference BVH answered.
            Outcome::Measured(m) => {
                m.primary_digest != rays.primary_digest
                    || m.shadow_digest != rays.shadow_digest
                    || m.incoherent_digest != rays.incoherent_digest
            }
            Outcome::Skipped(_) => false,
        };
        rows.push(Row {
            method: method.clone(),
            spec: spec.clone(),
            outcome,
            mismatch,
        });
    }
    Ok(SceneResult {
        name,
        primitives: scene.geometry.primitives.len(),
        width,
        height,
        rays: rays.size(),
        primary_hits: rays.primary_hits,
        rows,
        shadow_methods,
    })
}
