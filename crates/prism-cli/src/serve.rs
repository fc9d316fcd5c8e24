//! `prism serve`: the live viewer (crate prism-serve). Loads the scene as `render` does,
//! starts the server, prints the page's address and serves until Ctrl-C or SIGTERM (also
//! when a script started it in the background), then says so and stops the server.

use crate::args::RenderArgs;
use crate::scene_args::{SceneArgs, SizeArgs};
use anyhow::{Context, Result};
use clap::Args;
use prism::sampling::SamplerKind;
use std::net::IpAddr;
use std::process::ExitCode;

#[derive(Args, Debug)]
pub(crate) struct ServeArgs {
    #[command(flatten)]
    pub scene: SceneArgs,

    /// Address to listen on. The default answers this machine only; 0.0.0.0 opens the
    /// viewer (and the CPU it steers) to the network.
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1")]
    pub bind: IpAddr,

    /// Port to listen on; 0 lets the system choose a free one (the address is printed).
    #[arg(long, value_name = "N", default_value_t = 8000)]
    pub port: u16,

    /// Image width in pixels at the start (the page can change it).
    #[arg(short = 'W', long, value_name = "PIXELS", default_value_t = 640)]
    pub width: u32,

    /// Image height in pixels at the start.
    #[arg(short = 'H', long, value_name = "PIXELS", default_value_t = 360)]
    pub height: u32,

    /// Acceleration structure at the start, as `render --accel` takes it [default: the
    /// scene's].
    #[arg(long, value_name = "SPEC")]
    pub accel: Option<prism::accel::AccelSpec>,

    /// Shadow-ray method at the start, as `render --shadows` takes it [default: the
    /// scene's].
    #[arg(long, value_name = "SPEC")]
    pub shadows: Option<prism::integrator::ShadowSpec>,

    /// Maximum ray-tree depth at the start [default: the scene's].
    #[arg(short, long, value_name = "N")]
    pub depth: Option<u32>,

    /// Adaptive depth control and adaptive shadow testing at the start, as `render
    /// --min-weight` takes it (0 to 1 here, as the page's control) [default: the scene's].
    #[arg(long, value_name = "W", allow_negative_numbers = true)]
    pub min_weight: Option<f32>,

    /// Where each frame's one sample per pixel goes: jittered, random or centre.
    #[arg(long, value_name = "NAME", default_value = "jittered")]
    pub sampler: SamplerKind,

    /// Worker threads; 0 uses every core.
    #[arg(short, long, value_name = "N", default_value_t = 0)]
    pub threads: usize,
}

pub(crate) fn run(args: &ServeArgs) -> Result<ExitCode> {
    let render = RenderArgs {
        scene: args.scene.clone(),
        size: SizeArgs {
            width: Some(args.width),
            height: Some(args.height),
        },
        accel: args.accel.clone(),
        shadows: args.shadows,
        depth: args.depth,
        min_weight: args.min_weight,
        threads: Some(args.threads),
        ..RenderArgs::default()
    };
    let (mut scene, name) = render.load_scene()?;
    for warning in std::mem::take(&mut scene.warnings) {
        eprintln!("prism: warning: {warning}");
    }
    scene.validate().context("the scene is not valid")?;
    let options = render.options(&scene.options)?;
    // The page's controls take the same values; checking here names the option.
    let resolution = format!("{}x{}", options.width, options.height);
    for (flag, control, value) in [
        ("sampler", "sampler", args.sampler.to_string()),
        ("width and --height", "resolution", resolution),
        ("min-weight", "min_weight", options.min_weight.to_string()),
    ] {
        prism_serve::controls::parse(control, &value)
            .map_err(|e| anyhow::anyhow!("--{flag}: {e}"))?;
    }
    let options = prism::RenderOptions {
        sampler: args.sampler,
        samples: 1,
        ..options
    };
    // Checked here too, so that a refused option names its flag (`--depth`).
    options
        .validate()
        .map_err(|e| anyhow::anyhow!("invalid option: {}", crate::flags::in_flags(&e)))?;
    let config = prism_serve::ServerConfig {
        bind: args.bind,
        port: args.port,
    };
    let stop = crate::signals::StopSignals::listen();
    let server = prism_serve::Server::start(scene, &name, options, &config)?;
    // The one line a script waits for (the port is the system's choice with --port 0).
    println!("prism: viewing {name} at {}", server.url());
    if !args.bind.is_loopback() {
        eprintln!(
            "prism: note: listening on {}: anyone who can reach this address can steer the \
             render",
            args.bind
        );
    }
    use std::io::Write;
    std::io::stdout().flush()?;
    let Some(code) = stop.wait() else {
        server.wait();
        return Ok(ExitCode::SUCCESS);
    };
    let cause = if code == 143 {
        "terminated (SIGTERM)"
    } else {
        "interrupted"
    };
    eprintln!("prism: {cause}: stopping the viewer");
    server.stop();
    Ok(ExitCode::from(code))
}
