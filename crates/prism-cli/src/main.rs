//! `prism`: the command-line front end. Parses arguments, loads or builds a scene, renders
//! it with a progress bar, writes the image and reports statistics. Exit codes: 0 success,
//! 1 bad input or failed output, 2 bad usage (from clap), 130 interrupted by Ctrl-C and 143
//! by SIGTERM (the image still written: the rows its finished tiles reached).

mod args;
mod bench;
mod cli;
mod compare;
mod cost;
mod density;
mod flags;
mod huge_pages;
mod info;
mod memory;
mod outputs;
mod patterns;
mod plot;
mod progress;
mod reference;
mod report;
mod scene_args;
mod serve;
mod signals;
mod sweep;
mod warnings;

use anyhow::{Context, Result};
use args::RenderArgs;
use clap::Parser;
use cli::{Cli, Command};
use prism::scene::builtin;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[global_allocator]
static ALLOCATOR: huge_pages::HugePages = huge_pages::HugePages;

fn main() -> ExitCode {
    huge_pages::enable_if_asked();
    signals::restore_unix_defaults();
    // No command means `render`, with the arguments given without its name.
    let command = Cli::parse().into_command().unwrap_or_else(|e| e.exit());
    let result = match command {
        Command::Render(args) => render(&args),
        Command::Info(args) => info(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Reference(args) => reference::run(&args),
        Command::Sweep(args) => sweep::run(&args),
        Command::Patterns(args) => patterns::run(&args),
        Command::Serve(args) => serve::run(&args),
        Command::List => {
            list();
            Ok(ExitCode::SUCCESS)
        }
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("prism: error: {e:#}");
            ExitCode::from(1)
        }
    }
}

fn info(args: &cli::InfoArgs) -> Result<ExitCode> {
    // clap requires a scene or --builtin, so the default is never taken.
    let (scene, name) = args.scene().load("whitted")?;
    // The tree the scene's own integrator would render with (`rays=auto` settled by it).
    let options = prism::RenderOptions {
        accel: args.accel.clone().unwrap_or(scene.options.accel.clone()),
        ..scene.options.clone()
    };
    info::print(&scene, &name, &options.accel_to_build())?;
    Ok(ExitCode::SUCCESS)
}

fn list() {
    println!("Built-in scenes (prism render --builtin NAME):");
    for b in builtin::BUILTINS {
        println!("  {:<14} {}", b.name, b.description);
    }
    println!("  {:<14} sphereflake of level N, 0 to 6", "sphereflake:N");
}

fn render(args: &RenderArgs) -> Result<ExitCode> {
    // Every output is checked before anything else, so a typo in a folder name costs
    // nothing and a bad extra output means nothing is written.
    // An output named by a symbolic link is written where the link points.
    let mut outputs = outputs::Outputs::default();
    let image_file = outputs::through_links(&args.output);
    outputs.add(&image_file, &[])?;
    let format = prism_io::output::ImageFormat::from_path(&args.output)?;
    let density_file = args.density.as_deref().map(outputs::through_links);
    if let Some(path) = &density_file {
        density::check(path)?;
        outputs.add(path, &[])?;
    }
    let cost_file = args.cost.as_deref().map(outputs::through_links);
    if let Some(path) = &cost_file {
        cost::check(path)?;
        outputs.add(path, &[])?;
    }
    let stats_file = (args.stats_json.as_deref()).map(|p| {
        if p == Path::new("-") {
            p.to_path_buf()
        } else {
            outputs::through_links(p)
        }
    });
    if let Some(path) = stats_file.as_ref().filter(|p| *p != Path::new("-")) {
        outputs.add(path, &[])?;
    }
    let mut warnings = warnings::Warnings::new(args.strict);
    let format = match format {
        prism_io::output::ImageFormat::Exr { .. } => {
            prism_io::output::ImageFormat::Exr { half: args.half }
        }
        other => {
            if args.half {
                warnings.add(format!(
                    "--half applies to EXR output only; {} is written at full precision",
                    args.output.display()
                ));
            }
            other
        }
    };

    let load_start = Instant::now();
    let (mut scene, scene_name) = args.load_scene()?;
    let load_time = load_start.elapsed();
    warnings.extend(std::mem::take(&mut scene.warnings));
    if scene.geometry.primitives.is_empty() {
        warnings.add(format!(
            "{scene_name} has no objects: the image will show only the background"
        ));
    }
    scene.validate().context("the scene is not valid")?;
    let mut options = args.options(&scene.options)?;
    if args.preset == Some(args::Preset::Spd) {
        prism::preset::apply_spd(&mut scene, &mut options);
    }
    // Per-pixel ray counts only for the views made of them.
    options.per_pixel_rays = args.density.is_some() || args.cost.is_some();
    // A packet's traversal is shared evenly among its pixels, which would paint the cost
    // view in 8 × 8 blocks: for it every ray is traced alone, so each pixel shows its own
    // work (the image is the same either way).
    if args.cost.is_some() {
        options.packets = false;
    }
    options
        .validate()
        .map_err(|e| anyhow::anyhow!("invalid option: {}", flags::in_flags(&e)))?;
    warnings.report()?;
    note_threads(&options);
    memory::check(&scene, &options, args)?;
    let prepared = scene.prepare_for(&options);

    let interrupt = signals::listen();
    let bar = progress::RenderProgress::new(&options, args.quiet);
    let mut result = prism::render::render(
        &prepared,
        &options,
        &|t| bar.tile_done(t),
        &interrupt.cancel,
    )?;
    bar.finish();

    // The image and the views made of its rays, in the order they are written.
    let mut targets = vec![args.output.clone()];
    targets.extend(args.density.iter().cloned());
    targets.extend(args.cost.iter().cloned());
    // An interrupted render writes only the rows its finished work reached (those below
    // are black, their counts zero): at once at any size, rather than encoding a mostly
    // black full image. Its views keep the same rows, so that they lie over it.
    let rows = result.rows_reached.unwrap_or(options.height);
    if !result.complete {
        let what = match rows {
            0 if targets.len() == 1 => "no tile was finished: the image is not written".into(),
            0 => "no tile was finished: the image and its views are not written".into(),
            n if n < options.height => format!(
                "writing the {n} rows of {} that finished tiles reached (an image {}×{n}) \
                 to {}",
                options.height,
                options.width,
                names(&targets)
            ),
            _ => format!("writing the finished tiles to {}", names(&targets)),
        };
        eprintln!(
            "prism: {} at {:.0} %; {what}",
            interrupt.cause(),
            bar.fraction_done() * 100.0
        );
    }
    let mut written = Vec::new();
    if rows > 0 {
        result.film.keep_top_rows(rows);
        result.rays.keep_top_rows(rows);
        prism_io::output::write_image_as(&image_file, &result.film, format)?;
        written.push(args.output.clone());
    }
    if let (Some(path), Some(name), true) = (&density_file, &args.density, rows > 0) {
        density::write(path, &result.rays, args.density_rays)?;
        written.push(name.clone());
    }
    if let (Some(path), Some(name), true) = (&cost_file, &args.cost, rows > 0) {
        let accel = options.accel_to_build();
        let method = match args.cost_rays {
            cost::CostRays::All => accel.to_string(),
            cost::CostRays::Shadow => format!("{}, {accel}", options.shadows),
        };
        cost::write(
            path,
            &result.rays,
            (args.cost_metric, args.cost_rays),
            &method,
        )?;
        written.push(name.clone());
    }
    let report = report::Report::new(
        &scene_name,
        &prepared,
        &options,
        &result,
        load_time,
        &args.output,
    );
    if args.stats {
        report.print_table();
    }
    if let (Some(path), Some(name)) = (&stats_file, &args.stats_json) {
        report.write_json(path)?;
        if path != Path::new("-") {
            written.push(name.clone());
        }
    }
    if !result.complete {
        if !written.is_empty() {
            eprintln!("prism: wrote {}", names(&written));
        }
        return Ok(ExitCode::from(interrupt.exit_code()));
    }
    if !args.quiet {
        eprintln!(
            "prism: wrote {} ({}×{}, {:.2} s)",
            names(&written),
            options.width,
            options.height,
            result.render_time.as_secs_f64()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// A note (not a warning: harmless, and machine-dependent) when more threads are asked for
/// than the machine has cores.
fn note_threads(options: &prism::RenderOptions) {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    if options.threads > cores {
        eprintln!(
            "prism: note: {} worker threads on {cores} cores; threads beyond the cores only \
             take turns",
            options.threads
        );
    }
}

/// "a.png", "a.png and b.png", "a.png, b.png and c.json".
fn names(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
    match names.split_last() {
        None => String::new(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
    }
}
