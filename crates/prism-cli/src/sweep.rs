//! `prism sweep`: renders one scene with each sampling pattern at several sample counts
//! (adaptive: at several depths and thresholds), measures every image against a reference
//! and plots error against rays per pixel. The reference is exact for the checkerboard
//! (prism_lab::reference), else a file or a jittered render with many samples. Writes a CSV
//! table, SVG plots and a summary of the comparisons the sampling goals ask for.

use crate::flags::{per_axis, whole};
use crate::plot::{LogLogPlot, Series, PALETTE};
use crate::scene_args::{SceneArgs, SizeArgs};
use anyhow::{bail, Context, Result};
use clap::Args;
use prism::render::{render, Film, FilterKind};
use prism::sampling::{AdaptiveRule, SamplerKind};
use prism::RenderOptions;
use prism_lab::metrics::{compare, flip::DEFAULT_PPD, Comparison};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

#[derive(Args, Debug)]
pub(crate) struct SweepArgs {
    #[command(flatten)]
    pub scene: SceneArgs,

    /// Directory for the table, plots and (with --keep-images) images.
    #[arg(short, long, value_name = "DIR", default_value = "sweep")]
    pub out: PathBuf,

    #[command(flatten)]
    pub size: SizeArgs,

    /// Patterns to render, comma-separated.
    #[arg(
        long,
        value_name = "LIST",
        value_delimiter = ',',
        default_value = "centre,grid,corners,random,jittered,relaxed,adaptive"
    )]
    pub samplers: Vec<SamplerKind>,

    /// Samples per pixel for the patterns that take a count (squares), comma-separated.
    #[arg(
        long,
        value_name = "LIST",
        value_delimiter = ',',
        default_value = "1,4,9,16,36,64",
        allow_negative_numbers = true,
        value_parser = whole::<u32>("spp")
    )]
    pub spp: Vec<u32>,

    /// Adaptive depths to render, comma-separated.
    #[arg(
        long,
        value_name = "LIST",
        value_delimiter = ',',
        default_value = "1,2,3,4",
        allow_negative_numbers = true,
        value_parser = whole::<u32>("adaptive_depth")
    )]
    pub adaptive_depths: Vec<u32>,

    /// Adaptive thresholds to render, comma-separated.
    #[arg(
        long,
        value_name = "LIST",
        value_delimiter = ',',
        default_value = "0.05,0.1,0.2"
    )]
    pub adaptive_thresholds: Vec<f32>,

    /// Adaptive variants to render, comma-separated RULE:JITTER[:TEXTURE_SPP], e.g.
    /// `neighbourhood:1,corners:0` (the default adaptive sampler and POV-Ray's +AM2);
    /// TEXTURE_SPP is the stratified pass's samples (0: subdivide textured pixels too;
    /// left out: the default sampler's).
    #[arg(
        long,
        value_name = "LIST",
        value_delimiter = ',',
        default_value = "neighbourhood:1"
    )]
    pub adaptive_variants: Vec<Variant>,

    /// Reconstruction filter of every render, the reference's included.
    #[arg(long, value_name = "NAME", default_value = "box")]
    pub filter: FilterKind,

    /// Reference image to measure against, instead of the exact or rendered one.
    #[arg(long, value_name = "FILE")]
    pub reference: Option<PathBuf>,

    /// Samples per pixel of the rendered (jittered) reference, for scenes without an
    /// exact one.
    #[arg(long, value_name = "N", default_value_t = 1024, allow_negative_numbers = true, value_parser = whole::<u32>("spp"))]
    pub reference_spp: u32,

    /// Also write every image (PNG) into the output directory.
    #[arg(long)]
    pub keep_images: bool,

    /// Worker threads; 0 uses every core.
    #[arg(short, long, value_name = "N", default_value_t = 0, allow_negative_numbers = true, value_parser = whole::<usize>("threads"))]
    pub threads: usize,

    /// Seed for the random patterns.
    #[arg(long, value_name = "N", default_value_t = 0, allow_negative_numbers = true, value_parser = whole::<u64>("seed"))]
    pub seed: u64,

    /// No progress lines.
    #[arg(short, long)]
    pub quiet: bool,
}

/// An adaptive rule with a jitter amount and a stratified pass.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Variant {
    rule: AdaptiveRule,
    jitter: f32,
    texture_spp: u32,
}

impl std::str::FromStr for Variant {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let mut parts = s.split(':');
        let (Some(rule), Some(jitter)) = (parts.next(), parts.next()) else {
            return Err(format!(
                "expected RULE:JITTER[:TEXTURE_SPP] such as corners:0, got '{s}'"
            ));
        };
        let jitter: f32 = jitter
            .parse()
            .ok()
            .filter(|j| (0.0..=1.0).contains(j))
            .ok_or_else(|| format!("the jitter in '{s}' must be a number from 0 to 1"))?;
        let texture_spp = match parts.next() {
            None => prism::options::DEFAULT_ADAPTIVE_TEXTURE_SPP,
            Some(t) => t
                .parse()
                .ok()
                .filter(|&n: &u32| {
                    let r = prism::sampling::floor_sqrt(n);
                    r * r == n && r <= prism::sampling::adaptive::MAX_TEXTURE_N
                })
                .ok_or_else(|| {
                    format!("the texture spp in '{s}' must be 0 or a square number up to 1024")
                })?,
        };
        if parts.next().is_some() {
            return Err(format!("expected at most three parts, got '{s}'"));
        }
        Ok(Variant {
            rule: rule.parse()?,
            jitter,
            texture_spp,
        })
    }
}

/// One render of the sweep.
#[derive(Clone, Debug)]
struct Run {
    sampler: SamplerKind,
    /// Samples per pixel asked for (patterns with a count), else 0.
    spp: u32,
    threshold: f32,
    depth: u32,
    rule: AdaptiveRule,
    jitter: f32,
    texture_spp: u32,
    /// Name the rule and jitter in labels (several were asked for).
    variant: bool,
}

impl Run {
    /// The adaptive variant, when the sweep has several.
    fn variant(&self) -> String {
        if self.variant {
            format!(" {} j{} s{}", self.rule, self.jitter, self.texture_spp)
        } else {
            String::new()
        }
    }

    fn label(&self) -> String {
        match self.sampler {
            SamplerKind::Adaptive => format!(
                "adaptive t={} d={}{}",
                self.threshold,
                self.depth,
                self.variant()
            ),
            k if k.uses_sample_count() => format!("{k} {}", self.spp),
            k => k.to_string(),
        }
    }

    fn file_name(&self) -> String {
        self.label().replace([' ', '='], "-") + ".png"
    }
}

struct Measured {
    run: Run,
    camera_per_pixel: f64,
    rays_per_pixel: f64,
    /// Rays per pixel in the far field.
    far_rays_per_pixel: Option<f64>,
    all: Comparison,
    far: Option<Comparison>,
    seconds: f64,
}

pub(crate) fn run(args: &SweepArgs) -> Result<ExitCode> {
    let (scene, name) = args.scene.load("checkerboard")?;
    scene.validate().context("the scene is not valid")?;
    let base = RenderOptions {
        width: args.size.width.unwrap_or(scene.options.width),
        height: args.size.height.unwrap_or(scene.options.height),
        threads: args.threads,
        seed: args.seed,
        filter: args.filter,
        filter_radius: None,
        ..scene.options.clone()
    };
    base.validate()
        .map_err(|e| anyhow::anyhow!("invalid option: {e}"))?;
    for &spp in &args.spp {
        per_axis(spp.into())?;
    }
    let runs = plan(args)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    // Learn now, not after the renders, that the folder cannot take the files.
    crate::outputs::check_writable(&output(&args.out, "summary.txt"))?;
    let prepared = scene.prepare_for(&base);
    let say = |msg: String| {
        if !args.quiet {
            eprintln!("{msg}");
        }
    };

    // The reference, and the far-field mask where the reference is exact.
    let (reference, far, reference_note) = if let Some(path) = &args.reference {
        let film = prism_io::output::read_image(path)?;
        (film, None, format!("the image {}", path.display()))
    } else {
        match prism_lab::reference::checkerboard(
            &scene,
            base.width,
            base.height,
            prism_lab::reference::DEFAULT_TOLERANCE,
        ) {
            Ok(r) if args.filter == FilterKind::Box => {
                let far = r.far_field();
                let note = format!(
                    "exact box-filtered pixel integrals (each within {:.0e})",
                    r.error_bound
                );
                (r.film, Some(far), note)
            }
            _ => {
                let n = per_axis(args.reference_spp.into())?;
                say(format!(
                    "sweep: rendering the reference, jittered {} spp…",
                    args.reference_spp
                ));
                let options = RenderOptions {
                    sampler: SamplerKind::Jittered,
                    samples: n,
                    seed: args.seed ^ 0x5EED_5EED,
                    ..base.clone()
                };
                let film = render_film(&prepared, &options)?.0;
                let note = format!("a jittered render with {} spp", args.reference_spp);
                (film, None, note)
            }
        }
    };
    let far = far.filter(|m| m.iter().any(|&b| b));

    let mut results = Vec::new();
    for run in runs {
        let options = RenderOptions {
            sampler: run.sampler,
            samples: if run.spp > 0 {
                per_axis(run.spp.into())?
            } else {
                1
            },
            adaptive: prism::sampling::AdaptiveSpec {
                threshold: run.threshold,
                depth: run.depth,
                rule: run.rule,
                jitter: run.jitter,
                texture_spp: run.texture_spp,
            },
            ..base.clone()
        };
        let start = Instant::now();
        let (film, stats, rays) = render_film(&prepared, &options)?;
        let far_rays = far.as_ref().map(|mask| {
            let (sum, n) = rays
                .total
                .iter()
                .zip(mask)
                .filter(|(_, &m)| m)
                .fold((0u64, 0u64), |(s, n), (&r, _)| (s + r as u64, n + 1));
            sum as f64 / n.max(1) as f64
        });
        let seconds = start.elapsed().as_secs_f64();
        let pixels = (base.width as u64 * base.height as u64) as f64;
        let all = compare(&reference, &film, None, DEFAULT_PPD)?;
        let far_c = match &far {
            Some(mask) => Some(compare(&reference, &film, Some(mask), DEFAULT_PPD)?),
            None => None,
        };
        if args.keep_images {
            prism_io::output::write_image(&output(&args.out, run.file_name()), &film)?;
        }
        let m = Measured {
            camera_per_pixel: stats.primary_rays as f64 / pixels,
            rays_per_pixel: stats.total_rays() as f64 / pixels,
            far_rays_per_pixel: far_rays,
            all,
            far: far_c,
            seconds,
            run,
        };
        say(format!(
            "sweep: {:<26} {:>8.2} rays/px  RMSE {:.5}  FLIP {:.4}{}",
            m.run.label(),
            m.rays_per_pixel,
            m.all.rmse,
            m.all.flip,
            m.far
                .map(|f| format!(
                    "  far RMSE {:.5} at {:.1} rays/px",
                    f.rmse,
                    m.far_rays_per_pixel.unwrap_or(0.0)
                ))
                .unwrap_or_default()
        ));
        results.push(m);
    }

    write_csv(&output(&args.out, "sweep.csv"), &name, &results)?;
    let title = format!("{name}, {}×{}", base.width, base.height);
    write_plot(
        &output(&args.out, "sweep-rmse.svg"),
        &format!("RMSE against the reference: {title}"),
        "RMSE (linear)",
        &results,
        |m| m.all.rmse,
    )?;
    write_plot(
        &output(&args.out, "sweep-flip.svg"),
        &format!("Mean FLIP against the reference: {title}"),
        "mean FLIP",
        &results,
        |m| m.all.flip,
    )?;
    if far.is_some() {
        write_plot(
            &output(&args.out, "sweep-far-rmse.svg"),
            &format!("RMSE in the far field (squares < ½ pixel): {title}"),
            "far-field RMSE (linear)",
            &results,
            |m| m.far.map_or(f64::NAN, |f| f.rmse),
        )?;
    }
    let summary = summary(&name, &base, &reference_note, &results);
    prism_io::output::write_atomic(&output(&args.out, "summary.txt"), summary.as_bytes())
        .with_context(|| {
            format!(
                "cannot write {}",
                output(&args.out, "summary.txt").display()
            )
        })?;
    print!("{summary}");
    Ok(ExitCode::SUCCESS)
}

/// The runs the arguments ask for, in a fixed order.
fn plan(args: &SweepArgs) -> Result<Vec<Run>> {
    let variant = args.adaptive_variants.len() > 1;
    let mut runs = Vec::new();
    for &sampler in &args.samplers {
        let run = |spp, threshold, depth, v: Variant| Run {
            sampler,
            spp,
            threshold,
            depth,
            rule: v.rule,
            jitter: v.jitter,
            texture_spp: v.texture_spp,
            variant,
        };
        let none = Variant {
            rule: AdaptiveRule::default(),
            jitter: 0.0,
            texture_spp: 0,
        };
        match sampler {
            SamplerKind::Adaptive => {
                for v in &args.adaptive_variants {
                    for &t in &args.adaptive_thresholds {
                        for &d in &args.adaptive_depths {
                            runs.push(run(0, t, d, *v));
                        }
                    }
                }
            }
            k if k.uses_sample_count() => {
                for &spp in &args.spp {
                    runs.push(run(spp, 0.0, 0, none));
                }
            }
            _ => runs.push(run(0, 0.0, 0, none)),
        }
    }
    if runs.is_empty() {
        bail!("nothing to sweep: give at least one sampler and sample count");
    }
    Ok(runs)
}

fn render_film(
    prepared: &prism::scene::PreparedScene,
    options: &RenderOptions,
) -> Result<(Film, prism::Stats, prism::render::RayCounts)> {
    let r = render(prepared, options, &|_| {}, &AtomicBool::new(false))?;
    Ok((r.film, r.stats, r.rays))
}

/// The file `name` of the output folder; one that is a symbolic link is written where the
/// link points.
fn output(folder: &Path, name: impl AsRef<Path>) -> PathBuf {
    crate::outputs::through_links(&folder.join(name))
}

fn write_csv(path: &Path, scene: &str, results: &[Measured]) -> Result<()> {
    let mut s = String::from(
        "scene,sampler,label,spp,threshold,depth,rule,jitter,texture_spp,camera_rays_per_pixel,rays_per_pixel,\
         rmse,psnr,ssim,flip,far_rays_per_pixel,far_rmse,far_ssim,far_flip,seconds\n",
    );
    for m in results {
        let far = |f: fn(&Comparison) -> f64| {
            m.far
                .as_ref()
                .map(f)
                .map_or(String::new(), |v| format!("{v:.6}"))
        };
        let _ = writeln!(
            s,
            "{scene},{},{},{},{},{},{},{},{},{:.4},{:.4},{:.6},{:.3},{:.5},{:.5},{},{},{},{},{:.3}",
            m.run.sampler,
            m.run.label(),
            m.run.spp,
            m.run.threshold,
            m.run.depth,
            m.run.rule,
            m.run.jitter,
            m.run.texture_spp,
            m.camera_per_pixel,
            m.rays_per_pixel,
            m.all.rmse,
            m.all.psnr,
            m.all.ssim,
            m.all.flip,
            m.far_rays_per_pixel
                .map_or(String::new(), |r| format!("{r:.3}")),
            far(|c| c.rmse),
            far(|c| c.ssim),
            far(|c| c.flip),
            m.seconds
        );
    }
    prism_io::output::write_atomic(path, s.as_bytes())?;
    Ok(())
}

fn write_plot(
    path: &Path,
    title: &str,
    y_label: &str,
    results: &[Measured],
    metric: fn(&Measured) -> f64,
) -> Result<()> {
    // One line per pattern; adaptive: one per threshold and variant, over its depths.
    let key_of = |m: &Measured| {
        (
            m.run.sampler,
            (m.run.sampler == SamplerKind::Adaptive)
                .then(|| format!("adaptive t={}{}", m.run.threshold, m.run.variant())),
        )
    };
    let mut keys: Vec<(SamplerKind, Option<String>)> = Vec::new();
    for m in results {
        let key = key_of(m);
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    let series = keys
        .iter()
        .enumerate()
        .map(|(i, key)| {
            let (sampler, name) = key;
            let points = results
                .iter()
                .filter(|m| key_of(m) == *key)
                .map(|m| (m.rays_per_pixel, metric(m)))
                .collect();
            let label = name.clone().unwrap_or_else(|| sampler.to_string());
            let sampler = *sampler;
            Series {
                label,
                points,
                colour: PALETTE[i % PALETTE.len()],
                dashed: sampler == SamplerKind::Adaptive,
            }
        })
        .collect();
    let plot = LogLogPlot {
        title: title.to_string(),
        x_label: "rays per pixel (all rays: camera, shadow, secondary)".into(),
        y_label: y_label.into(),
        series,
    };
    prism_io::output::write_atomic(path, plot.svg().as_bytes())?;
    Ok(())
}

/// The comparisons the sampling goals name, in words and numbers.
fn summary(scene: &str, base: &RenderOptions, reference: &str, results: &[Measured]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "sweep of {scene} at {}×{}, {} filter; reference: {reference}",
        base.width, base.height, base.filter
    );
    let _ = writeln!(
        s,
        "{:<26} {:>10} {:>10} {:>9} {:>8} {:>8} {:>10}",
        "run", "camera/px", "rays/px", "RMSE", "SSIM", "FLIP", "far RMSE"
    );
    for m in results {
        let _ = writeln!(
            s,
            "{:<26} {:>10.3} {:>10.3} {:>9.5} {:>8.4} {:>8.4} {:>10}",
            m.run.label(),
            m.camera_per_pixel,
            m.rays_per_pixel,
            m.all.rmse,
            m.all.ssim,
            m.all.flip,
            m.far.map_or("-".into(), |f| format!("{:.5}", f.rmse))
        );
    }
    let find = |k: SamplerKind, spp: u32| {
        results
            .iter()
            .find(|m| m.run.sampler == k && m.run.spp == spp)
    };
    if let Some(j16) = find(SamplerKind::Jittered, 16) {
        for (metric, get) in [
            ("RMSE", (|m: &Measured| m.all.rmse) as fn(&Measured) -> f64),
            ("FLIP", |m: &Measured| m.all.flip),
        ] {
            let target = get(j16);
            let best = results
                .iter()
                .filter(|m| m.run.sampler == SamplerKind::Adaptive && get(m) <= target)
                .min_by(|a, b| a.rays_per_pixel.total_cmp(&b.rays_per_pixel));
            match best {
                Some(a) => {
                    let _ = writeln!(
                        s,
                        "goal: adaptive reaches jittered-16's {metric} ({target:.5}) with {} \
                         ({:.5}) at {:.2} rays/px = {:.0}% of jittered-16's {:.2}; camera \
                         rays {:.2}/px = {:.0}% (goal ≤ 35%)",
                        a.run.label(),
                        get(a),
                        a.rays_per_pixel,
                        100.0 * a.rays_per_pixel / j16.rays_per_pixel,
                        j16.rays_per_pixel,
                        a.camera_per_pixel,
                        100.0 * a.camera_per_pixel / j16.camera_per_pixel,
                    );
                }
                None => {
                    let _ = writeln!(
                        s,
                        "goal: no adaptive run reaches jittered-16's {metric} ({target:.5})"
                    );
                }
            }
        }
    }
    for (a, b, what, far) in [
        (SamplerKind::Relaxed, SamplerKind::Jittered, "RMSE", false),
        (
            SamplerKind::Jittered,
            SamplerKind::Grid,
            "far-field RMSE",
            true,
        ),
    ] {
        let mut line = format!("goal: {a} vs {b}, {what} at equal spp:");
        let mut any = false;
        for spp in results.iter().map(|m| m.run.spp).filter(|&n| n > 0) {
            if line.contains(&format!(" {spp}: ")) {
                continue;
            }
            let (Some(x), Some(y)) = (find(a, spp), find(b, spp)) else {
                continue;
            };
            let pick = |m: &Measured| {
                if far {
                    m.far.map(|f| f.rmse)
                } else {
                    Some(m.all.rmse)
                }
            };
            if let (Some(ex), Some(ey)) = (pick(x), pick(y)) {
                any = true;
                let _ = write!(
                    line,
                    " {spp}: {ex:.5} vs {ey:.5} ({})",
                    if ex < ey { "better" } else { "not better" }
                );
            }
        }
        if any {
            let _ = writeln!(s, "{line}");
        }
    }
    s
}
