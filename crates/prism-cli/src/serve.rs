//! `prism serve`: the live viewer (crate prism-serve). Loads the scene as `render` does,
//! starts the server, prints the page's address and serves until Ctrl-C or SIGTERM (also
//! when a script started it in the background), then says so and stops the server.

use crate::args::RenderArgs;
use crate::flags::{setting_help, whole};
use crate::scene_args::{SceneArgs, SizeArgs};
use anyhow::{Context, Result};
use clap::Args;
use prism::options::Setting;
use prism::sampling::SamplerKind;
use prism_serve::controls::{self, Control, ControlKind};
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

    /// Image width in pixels at the start (the page's resolution control can change it).
    #[arg(short = 'W', long, value_name = "PIXELS", allow_negative_numbers = true, value_parser = whole::<u32>("width"), default_value_t = 640)]
    pub width: u32,

    /// Image height in pixels at the start.
    #[arg(short = 'H', long, value_name = "PIXELS", allow_negative_numbers = true, value_parser = whole::<u32>("height"), default_value_t = 360)]
    pub height: u32,

    #[command(flatten)]
    pub controls: ControlFlags,

    #[arg(short, long, value_name = "N", allow_negative_numbers = true, value_parser = whole::<usize>("threads"), help = setting_help("threads"))]
    pub threads: Option<usize>,
}

/// The render settings the page's controls change, as flags: one for each control of
/// `prism_serve::controls` that sets a setting of the settings table
/// (`prism::options::SETTINGS`), under the table's flag with `render`'s short name and
/// value name, its help the table's sentence and what the page takes. A control added to
/// the page is a flag here without a line of its own; each value is checked as the page
/// checks it (`controls::parse`).
#[derive(Clone, Debug, Default)]
pub(crate) struct ControlFlags {
    /// (control, value as typed), in the page's order.
    pub given: Vec<(&'static str, String)>,
}

/// The page's controls that set a setting of the table, with that setting.
fn setting_controls() -> Vec<(Control, &'static Setting)> {
    controls::controls()
        .into_iter()
        .filter_map(|c| {
            let setting = prism::options::setting(controls::setting_key(c.name)?)?;
            setting.flag.is_some().then_some((c, setting))
        })
        .collect()
}

/// The sampler a frame uses unless `--sampler` says otherwise: the scene's usually takes
/// many samples per pixel at once, the viewer one a frame.
const SAMPLER: SamplerKind = SamplerKind::Jittered;

/// A control's flag help: the table's sentence, what the page takes and the default.
fn control_help(c: &Control, setting: &Setting) -> String {
    let takes = match c.kind {
        ControlKind::Choice => format!("one of {}", c.choices.join(", ")),
        ControlKind::Text => format!("e.g. {}", c.choices.join(", ")),
        ControlKind::Number => format!(
            "{} to {}",
            c.min.unwrap_or_default(),
            c.max.unwrap_or(u32::MAX)
        ),
    };
    let default = match setting.key {
        "sampler" => SAMPLER.name(),
        _ => "the scene's",
    };
    format!(
        "{}. At the start; the page's {} control takes {takes} [default: {default}]",
        setting.help.trim_end_matches('.'),
        c.label
    )
}

impl clap::FromArgMatches for ControlFlags {
    fn from_arg_matches(matches: &clap::ArgMatches) -> Result<Self, clap::Error> {
        let mut flags = ControlFlags::default();
        flags.update_from_arg_matches(matches)?;
        Ok(flags)
    }

    fn update_from_arg_matches(&mut self, matches: &clap::ArgMatches) -> Result<(), clap::Error> {
        self.given = setting_controls()
            .into_iter()
            .filter_map(|(c, _)| Some((c.name, matches.get_one::<String>(c.name)?.clone())))
            .collect();
        Ok(())
    }
}

impl Args for ControlFlags {
    fn augment_args(mut cmd: clap::Command) -> clap::Command {
        // `render`'s flag of the same setting, for its short name and value name.
        let render = RenderArgs::augment_args(clap::Command::new("render"));
        for (c, setting) in setting_controls() {
            let flag = setting.flag.expect("setting_controls keeps flags only");
            let mut arg = clap::Arg::new(c.name)
                .long(flag)
                .value_parser(clap::value_parser!(String))
                .allow_negative_numbers(true)
                .help(control_help(&c, setting));
            if let Some(twin) = render.get_arguments().find(|a| a.get_long() == Some(flag)) {
                if let Some(short) = twin.get_short() {
                    arg = arg.short(short);
                }
                if let Some(names) = twin.get_value_names() {
                    arg = arg.value_names(names.to_vec());
                }
            }
            cmd = cmd.arg(arg);
        }
        cmd
    }

    fn augment_args_for_update(cmd: clap::Command) -> clap::Command {
        Self::augment_args(cmd)
    }
}

impl ControlFlags {
    /// The flags given, checked as the page checks its controls, on top of `options`.
    fn apply(&self, options: &mut prism::RenderOptions) -> Result<()> {
        let settings = setting_controls();
        for (name, value) in &self.given {
            let flag = settings
                .iter()
                .find(|(c, _)| c.name == *name)
                .and_then(|(_, s)| s.flag)
                .unwrap_or(name);
            controls::parse(name, value)
                .map_err(|e| anyhow::anyhow!("--{flag}: {e}"))?
                .apply(options);
        }
        Ok(())
    }
}

pub(crate) fn run(args: &ServeArgs) -> Result<ExitCode> {
    let render = RenderArgs {
        scene: args.scene.clone(),
        size: SizeArgs {
            width: Some(args.width),
            height: Some(args.height),
        },
        threads: args.threads,
        ..RenderArgs::default()
    };
    let (mut scene, name) = render.load_scene()?;
    for warning in std::mem::take(&mut scene.warnings) {
        eprintln!("prism: warning: {warning}");
    }
    scene.validate().context("the scene is not valid")?;
    let mut options = prism::RenderOptions {
        sampler: SAMPLER,
        ..render.options(&scene.options)?
    };
    args.controls.apply(&mut options)?;
    // The page's resolution control takes the same sizes; checking here names the flags.
    let resolution = format!("{}x{}", options.width, options.height);
    controls::parse("resolution", &resolution)
        .map_err(|e| anyhow::anyhow!("--width and --height: {e}"))?;
    let options = prism::RenderOptions {
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
