//! `prism`: the command-line front end. Parses arguments, loads or builds a scene, renders
//! it with a progress bar, writes the image and reports statistics. Exit codes: 0 success,
//! 1 bad input or failed output, 2 bad usage (from clap), 130 interrupted (image still
//! written with the finished tiles).

mod args;
mod bench;
mod compare;
mod cost;
mod density;
mod info;
mod patterns;
mod plot;
mod progress;
mod reference;
mod report;
mod sweep;

use anyhow::{Context, Result};
use args::{Cli, Command, RenderArgs};
use clap::Parser;
use prism::scene::builtin;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli
        .command
        .unwrap_or(Command::Render(RenderArgs::default()))
    {
        Command::Render(args) => render(&args),
        Command::Info(args) => info(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Reference(args) => reference::run(&args),
        Command::Sweep(args) => sweep::run(&args),
        Command::Patterns(args) => patterns::run(&args),
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

fn info(args: &args::InfoArgs) -> Result<ExitCode> {
    let scene = match args.scene.strip_prefix("builtin:") {
        Some(name) => args::find_builtin(name)?,
        None => prism::scene::load(std::path::Path::new(&args.scene))?,
    };
    let accel = args.accel.as_ref().unwrap_or(&scene.options.accel);
    info::print(&scene, &args.scene, accel)?;
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
    let load_start = Instant::now();
    let (mut scene, scene_name) = args.load_scene()?;
    let load_time = load_start.elapsed();
    scene.validate().context("the scene is not valid")?;
    let mut options = args.options(&scene.options)?;
    if args.preset == Some(args::Preset::Spd) {
        prism::preset::apply_spd(&mut scene, &mut options);
    }
    options
        .validate()
        .map_err(|e| anyhow::anyhow!("invalid option: {e}"))?;
    // Fail on an unwritable format before spending time on the render.
    let format = match prism::output::ImageFormat::from_path(&args.output)? {
        prism::output::ImageFormat::Exr { .. } => {
            prism::output::ImageFormat::Exr { half: args.half }
        }
        other => other,
    };

    if let Some(path) = &args.density {
        density::check(path)?;
    }
    if let Some(path) = &args.cost {
        cost::check(path)?;
    }
    let prepared = scene.prepare(&options.accel);

    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        // If a handler cannot be installed, Ctrl-C simply kills the process as usual.
        let _ = ctrlc::set_handler(move || {
            if cancel.swap(true, Ordering::SeqCst) {
                // A second Ctrl-C: the user does not want to wait for the tiles in flight.
                std::process::exit(130);
            }
        });
    }
    let bar = progress::RenderProgress::new(&options, args.quiet);
    let result = prism::render::render(&prepared, &options, &|t| bar.tile_done(t), &cancel)?;
    bar.finish(result.complete);

    prism::output::write_image_as(&args.output, &result.film, format)?;
    if let Some(path) = &args.density {
        density::write(path, &result.rays, args.density_rays)?;
    }
    if let Some(path) = &args.cost {
        let accel = options.accel.to_string();
        cost::write(path, &result.rays, args.cost_metric, &accel)?;
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
    if let Some(path) = &args.stats_json {
        report.write_json(path)?;
    }
    if !result.complete {
        eprintln!(
            "prism: interrupted; wrote the finished tiles to {}",
            args.output.display()
        );
        return Ok(ExitCode::from(130));
    }
    if !args.quiet {
        eprintln!(
            "prism: wrote {} ({}×{}, {:.2} s)",
            args.output.display(),
            options.width,
            options.height,
            result.render_time.as_secs_f64()
        );
    }
    Ok(ExitCode::SUCCESS)
}
