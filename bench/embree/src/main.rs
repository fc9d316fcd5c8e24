//! prism against Embree 3, side by side in one process: the same triangles, the same rays,
//! methods timed in turns. `run.sh` runs every mesh and writes bench/results/embree.*;
//! this binary does one mesh per run (`run`) and turns the CSV into tables (`report`).

mod embree;
mod measure;
mod meshes;
mod report;
mod workload;

use measure::{median, time, Answers, Method, Sample};
use prism::accel::{AccelSpec, SceneIntersector};
use prism::geometry::{Geometry, TriangleMesh};
use std::io::Write;
use std::path::PathBuf;

const USAGE: &str = "usage:
  embree-bench run --mesh NAME [--meshes DIR] [--repeats N] [--builds N] [--threads 1,2] [--csv FILE]
                   [--ray-file FILE] [--builders NAME,...] [--rays primary,incoherent,shadow]
      DIR: where the bunny (stanford-bunny.obj) is read from; default ../shared/meshes,
      beside the repository when run from its root (as run.sh does)
      NAME: bunny, blob, sphereflake or soup, or cornell (prism's cornell-light as it is, seen
      by its camera, lit at its light; prism's tree for rays from inside); CSV rows are appended
      to FILE; --ray-file: trace FILE's rays (six little-endian f32s each: origin, direction;
      nearest hit) instead of the generated sets; --builders: prism's other BVH builders
      (`bvh:build=NAME`, e.g. sbvh,ploc,phr; NAME:KEY=V:... adds bvh keys, e.g.
      sbvh:overlap=0), built and traced (single rays) beside its default
      (binned) tree and Embree MEDIUM and HIGH; --rays: only these ray sets (primary, incoherent,
      shadow)
  embree-bench builds --mesh NAME [--builds N] [--prism-only 1] [--builders NAME,...]
      builds alone: prism's default BVH and Embree MEDIUM in turns, medians of wall and process CPU ms
      (--prism-only 1: prism alone, for a profiler; --builders: prism's trees by these builders
      too, and Embree HIGH)
  embree-bench report FILE.csv    markdown tables of a CSV
  embree-bench diff --mesh NAME    primary rays on which prism and Embree disagree
  embree-bench profile --mesh NAME [--repeats N] [--rays primary|incoherent|shadow] [--packets N]
      prism alone (in packets of N rays with --packets), 1 thread: each ray set traced N times through `measure::run`, for a
      profiler (valgrind --tool=callgrind --collect-atstart=no --toggle-collect=embree_bench::measure::run)";

struct Options {
    mesh: String,
    meshes_dir: PathBuf,
    repeats: usize,
    builds: usize,
    threads: Vec<usize>,
    csv: Option<PathBuf>,
    /// `profile`: trace just this ray set; `run`: these ray sets (comma-separated).
    rays: Option<String>,
    /// `run` and `builds`: prism's other builders, beside its default tree.
    builders: Vec<String>,
    /// `profile` only: trace in packets of this many rays.
    packets: Option<usize>,
    /// `builds` only: time prism's build alone.
    prism_only: bool,
    /// `run` only: trace these rays instead of the three generated sets.
    ray_file: Option<PathBuf>,
}

// The allocator `prism` itself runs with (large blocks advised as huge pages when
// PRISM_HUGE_PAGES=1 asks for it), so the build is timed as the command line runs it.
#[path = "../../../crates/prism-cli/src/huge_pages.rs"]
mod huge_pages;
#[global_allocator]
static ALLOCATOR: huge_pages::HugePages = huge_pages::HugePages;

fn main() {
    // As `prism` does: huge pages only with PRISM_HUGE_PAGES=1.
    huge_pages::enable_if_asked();
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("run") => parse(&args[1..]).and_then(|o| run(&o)),
        Some("profile") => parse(&args[1..]).and_then(|o| profile(&o)),
        Some("diff") => parse(&args[1..]).and_then(|o| diff(&o)),
        Some("builds") => parse(&args[1..]).and_then(|o| builds(&o)),
        Some("report") if args.len() == 2 => {
            report::markdown(&PathBuf::from(&args[1])).map(|t| print!("{t}"))
        }
        _ => Err(USAGE.to_string()),
    };
    if let Err(e) = result {
        eprintln!("embree-bench: {e}");
        std::process::exit(2);
    }
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        mesh: String::new(),
        // Beside the repository: `run.sh` runs this binary from the repository's root.
        meshes_dir: PathBuf::from("../shared/meshes"),
        repeats: 5,
        builds: 3,
        threads: vec![1, 2],
        csv: None,
        rays: None,
        builders: Vec::new(),
        packets: None,
        prism_only: false,
        ray_file: None,
    };
    let mut it = args.iter();
    while let Some(flag) = it.next() {
        let value = it.next().ok_or(format!("{flag} needs a value\n{USAGE}"))?;
        let number = || {
            value
                .parse::<usize>()
                .map_err(|e| format!("{flag} {value}: {e}"))
        };
        match flag.as_str() {
            "--mesh" => o.mesh = value.clone(),
            "--meshes" => o.meshes_dir = PathBuf::from(value),
            "--repeats" => o.repeats = number()?.max(1),
            "--builds" => o.builds = number()?.max(1),
            "--threads" => {
                o.threads = value
                    .split(',')
                    .map(|t| t.parse().map_err(|e| format!("--threads {value}: {e}")))
                    .collect::<Result<_, _>>()?
            }
            "--csv" => o.csv = Some(PathBuf::from(value)),
            "--rays" => o.rays = Some(value.clone()),
            "--builders" => {
                o.builders = value
                    .split(',')
                    .filter(|b| !b.is_empty() && *b != "none")
                    .map(String::from)
                    .collect()
            }
            "--ray-file" => o.ray_file = Some(PathBuf::from(value)),
            "--prism-only" => o.prism_only = number()? != 0,
            "--packets" => o.packets = Some(number()?.clamp(1, prism::accel::PACKET_MAX)),
            _ => return Err(format!("unknown option {flag}\n{USAGE}")),
        }
    }
    if o.mesh.is_empty() {
        return Err(format!("--mesh is required\n{USAGE}"));
    }
    Ok(o)
}

/// Which packet widths this CPU runs (Embree's 8-wide kernels need AVX, 16-wide AVX-512).
fn packet_widths(device: &embree::Device) -> Vec<embree::Width> {
    let mut widths = vec![embree::Width::One];
    if std::arch::is_x86_feature_detected!("avx2") && device.native_packets(8) {
        widths.push(embree::Width::Eight);
    }
    if std::arch::is_x86_feature_detected!("avx512f") && device.native_packets(16) {
        widths.push(embree::Width::Sixteen);
    }
    widths
}

fn ms(d: std::time::Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

/// prism's tree for a mesh: the default one, and for `cornell` the one its path tracer
/// builds (`rays=auto` settles on rays from inside for the path integrator).
fn spec_for(mesh: &str) -> AccelSpec {
    if mesh == meshes::CORNELL {
        "bvh:rays=inside".parse().expect("a valid accelerator spec")
    } else {
        AccelSpec::default()
    }
}

/// prism's tree by another builder: `spec_for`'s with `build=NAME`; `NAME:KEY=V:...`
/// adds those `bvh` keys (a comma separates builders on the command line).
fn builder_spec(mesh: &str, builder: &str) -> Result<AccelSpec, String> {
    let builder = builder.replace(':', ",");
    let spec = if mesh == meshes::CORNELL {
        format!("bvh:rays=inside,build={builder}")
    } else {
        format!("bvh:build={builder}")
    };
    spec.parse()
        .map_err(|e| format!("--builders {builder}: {e}"))
}

/// prism's geometry for a mesh (one `TriangleMesh`, so primitive = triangle index).
fn prism_geometry(mesh: &meshes::Mesh) -> Result<Geometry, String> {
    let mut geometry = Geometry::default();
    let prism_mesh = TriangleMesh::new(mesh.positions.clone(), mesh.indices.clone(), None, None)
        .map_err(|e| e.to_string())?;
    geometry.add_mesh(prism_mesh, 0);
    Ok(geometry)
}

/// The primary rays on which prism and Embree (MEDIUM, single rays) disagree, with both
/// answers: what the agreement table counts, one by one.
fn diff(o: &Options) -> Result<(), String> {
    let mesh = meshes::make(&o.mesh, &o.meshes_dir)?;
    let geometry = prism_geometry(&mesh)?;
    let intersector = SceneIntersector::build(&geometry, &spec_for(mesh.name));
    let positions: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.to_array()).collect();
    let device = embree::Device::new();
    let scene = embree::Scene::new(&device, &positions, &mesh.indices, embree::Quality::Medium);
    scene.commit();
    let sets = workload::generate(
        &geometry,
        &intersector,
        &workload::View::of(mesh.name, &geometry),
    );
    let set = &sets[0];
    let (mut ours, mut theirs) = (Answers::for_set(set), Answers::for_set(set));
    measure::run(&Method::Prism(&intersector, &geometry), set, &mut ours, 1);
    let method = Method::Embree(&scene, embree::Quality::Medium, embree::Width::One);
    measure::run(&method, set, &mut theirs, 1);
    // Whether two triangles share vertices (adjacent in the mesh).
    let shared = |a: u32, b: u32| {
        let (a, b) = (mesh.indices[a as usize], mesh.indices[b as usize]);
        a.iter().filter(|i| b.contains(i)).count()
    };
    println!("ray: prism t, triangle / Embree t, triangle / shared vertices");
    for i in 0..set.len() {
        let (a, b) = (ours.t[i], theirs.t[i]);
        if a.is_finite() != b.is_finite() || (a - b).abs() > 1e-4 * a.abs().max(1.0) {
            let (pa, pb) = (ours.prim[i], theirs.prim[i]);
            // prism's own triangle test on Embree's triangle, and prism's brute force.
            let ray = prism::math::TraceRay::new(set.rays[i]);
            let own = geometry.intersect(pb, &ray, f32::INFINITY).map(|h| h.t);
            let brute = (0..mesh.indices.len() as u32)
                .filter_map(|p| geometry.intersect(p, &ray, f32::INFINITY).map(|h| (h.t, p)))
                .min_by(|x, y| x.0.total_cmp(&y.0));
            println!(
                "{i}: {a} {pa} / {b} {pb} / {} / prism's test on Embree's triangle {own:?}, prism brute force {brute:?}",
                shared(pa, pb)
            );
        }
    }
    Ok(())
}

/// Builds alone, prism's and Embree MEDIUM's in turns (or prism's alone, for a profiler);
/// with `--builders`, also prism's trees by those builders and Embree HIGH, all in turns.
fn builds(o: &Options) -> Result<(), String> {
    let mesh = meshes::make(&o.mesh, &o.meshes_dir)?;
    let geometry = prism_geometry(&mesh)?;
    let positions: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.to_array()).collect();
    let device = embree::Device::new();
    let mut specs = vec![("prism".to_string(), spec_for(mesh.name))];
    for b in &o.builders {
        specs.push((format!("prism-{b}"), builder_spec(mesh.name, b)?));
    }
    let qualities: &[(&str, embree::Quality)] = match (o.prism_only, o.builders.is_empty()) {
        (true, _) => &[],
        (false, true) => &[("embree-M", embree::Quality::Medium)],
        (false, false) => &[
            ("embree-M", embree::Quality::Medium),
            ("embree-H", embree::Quality::High),
        ],
    };
    let methods = specs.len() + qualities.len();
    let mut samples: Vec<Vec<Sample>> = vec![Vec::new(); methods];
    // Page faults of each build (fresh memory: the first builds of a process fault in
    // every page they write, later ones reuse what the allocator kept).
    let mut faults: Vec<Vec<i64>> = vec![Vec::new(); methods];
    let mut sahs = vec![f64::NAN; specs.len()];
    for _ in 0..o.builds {
        for (k, (_, spec)) in specs.iter().enumerate() {
            let mut built = None;
            let before = minor_faults();
            samples[k].push(time(|| {
                built = Some(SceneIntersector::build(&geometry, spec))
            }));
            faults[k].push(minor_faults() - before);
            sahs[k] = built
                .and_then(|b| b.accel.info().sah_cost)
                .unwrap_or(f64::NAN);
        }
        for (k, &(_, q)) in qualities.iter().enumerate() {
            let scene = embree::Scene::new(&device, &positions, &mesh.indices, q);
            let before = minor_faults();
            samples[specs.len() + k].push(time(|| scene.commit()));
            faults[specs.len() + k].push(minor_faults() - before);
        }
    }
    println!(
        "{}: {} triangles, median of {} builds, wall ms / process CPU ms, page faults (first, median):",
        mesh.name,
        mesh.indices.len(),
        o.builds
    );
    let names = specs
        .iter()
        .map(|(name, _)| name.as_str())
        .chain(qualities.iter().map(|(name, _)| *name));
    let medians: Vec<Sample> = samples.iter().map(|s| median(s)).collect();
    for (k, name) in names.enumerate() {
        let m = medians[k];
        let f = &mut faults[k];
        let first = f[0];
        f.sort_unstable();
        let sah = sahs
            .get(k)
            .map_or(String::new(), |s| format!(", SAH {s:.2}"));
        let against = if qualities.is_empty() {
            String::new()
        } else {
            // The same process's last Embree build: HIGH where it was built, else MEDIUM.
            let theirs = medians[methods - 1];
            format!(
                ", CPU {:.2}x {}'s",
                ms(m.cpu) / ms(theirs.cpu),
                qualities[qualities.len() - 1].0
            )
        };
        println!(
            "  {name:<12} {:8.1} / {:8.1}, faults {first} / {}{sah}{against}",
            ms(m.wall),
            ms(m.cpu),
            f[f.len() / 2]
        );
    }
    Ok(())
}

/// The process's minor page faults so far.
#[allow(unsafe_code)]
fn minor_faults() -> i64 {
    // SAFETY: getrusage writes one `rusage` into the zeroed struct it is given.
    unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        libc::getrusage(libc::RUSAGE_SELF, &mut usage);
        usage.ru_minflt
    }
}

/// Only prism's tracing, for a profiler: no Embree, no timing in turns.
fn profile(o: &Options) -> Result<(), String> {
    let mesh = meshes::make(&o.mesh, &o.meshes_dir)?;
    let geometry = prism_geometry(&mesh)?;
    let intersector = SceneIntersector::build(&geometry, &spec_for(mesh.name));
    let method = match o.packets {
        Some(n) => Method::PrismPackets(&intersector, &geometry, n),
        None => Method::Prism(&intersector, &geometry),
    };
    let sets = workload::generate(
        &geometry,
        &intersector,
        &workload::View::of(mesh.name, &geometry),
    );
    for set in sets
        .iter()
        .filter(|s| o.rays.as_deref().is_none_or(|r| r == s.name))
    {
        let mut answers = Answers::for_set(set);
        let s = time(|| {
            for _ in 0..o.repeats {
                measure::run(&method, set, &mut answers, 1)
            }
        });
        let rate = (set.len() * o.repeats) as f64 / s.cpu.as_secs_f64() / 1e6;
        println!(
            "{} rays: {} × {}, {rate:.2} Mrays/s",
            set.name,
            set.len(),
            o.repeats
        );
    }
    Ok(())
}

fn run(o: &Options) -> Result<(), String> {
    // Read first, so that a bad file stops the run before the builds.
    let file_rays = o.ray_file.as_deref().map(workload::from_file).transpose()?;
    let mesh = match meshes::make(&o.mesh, &o.meshes_dir) {
        Ok(mesh) => mesh,
        Err(meshes::MeshError::Absent(reason)) => {
            println!("## {}: skipped: {reason}\n", o.mesh);
            return Ok(());
        }
        Err(unknown) => return Err(unknown.into()),
    };
    let triangles = mesh.indices.len();
    let positions: Vec<[f32; 3]> = mesh.positions.iter().map(|p| p.to_array()).collect();
    let geometry = prism_geometry(&mesh)?;
    let mut csv = CsvOut::open(o.csv.as_ref())?;
    let load = Load::start();
    println!(
        "## {} ({triangles} triangles, {} vertices)\n",
        mesh.name,
        positions.len()
    );

    // Builds, in turns: prism's default BVH (SceneIntersector::build, as Scene::prepare
    // does), its other builders (`--builders`) and Embree's rtcCommitScene at both
    // qualities (the copy into Embree's buffers is not timed). All use every core where
    // they are parallel: prism through rayon, Embree through TBB.
    let device = embree::Device::new();
    // prism's trees: the default first, then one per builder.
    let mut specs = vec![("prism".to_string(), spec_for(mesh.name))];
    for b in &o.builders {
        specs.push((format!("prism-{b}"), builder_spec(mesh.name, b)?));
    }
    let qualities = [embree::Quality::Medium, embree::Quality::High];
    let mut build_samples: Vec<Vec<Sample>> = vec![Vec::new(); specs.len() + qualities.len()];
    let mut intersectors: Vec<SceneIntersector> = Vec::new();
    let mut scenes = Vec::new();
    for _ in 0..o.builds {
        // Drop the previous round's structures first, so no build runs next to their memory.
        intersectors.clear();
        scenes.clear();
        for (k, (_, spec)) in specs.iter().enumerate() {
            let mut built = None;
            build_samples[k].push(time(|| {
                built = Some(SceneIntersector::build(&geometry, spec))
            }));
            intersectors.extend(built);
        }
        for (k, &q) in qualities.iter().enumerate() {
            let scene = embree::Scene::new(&device, &positions, &mesh.indices, q);
            build_samples[specs.len() + k].push(time(|| scene.commit()));
            scenes.push(scene);
        }
    }
    let intersector = &intersectors[0];
    let sahs: Vec<f64> = intersectors
        .iter()
        .map(|i| i.accel.info().sah_cost.unwrap_or(f64::NAN))
        .collect();
    println!("build, median of {} (wall ms / process CPU ms):", o.builds);
    let build_names: Vec<&str> = specs
        .iter()
        .map(|(name, _)| name.as_str())
        .chain(["embree-M", "embree-H"])
        .collect();
    for (k, (name, samples)) in build_names.iter().zip(&build_samples).enumerate() {
        let m = median(samples);
        println!("  {name:<12} {:8.1} / {:8.1}", ms(m.wall), ms(m.cpu));
        csv.row(&[
            "build",
            mesh.name,
            &triangles.to_string(),
            "",
            name,
            "",
            "",
            "",
            "",
            "",
            &format!("{:.3}", ms(m.cpu)),
            &format!("{:.3}", ms(m.wall)),
            "",
            "",
            &samples.len().to_string(),
            &sahs.get(k).map_or(String::new(), |sah| format!("{sah:.3}")),
            "",
        ])?;
    }
    for ((name, _), i) in specs.iter().zip(&intersectors) {
        println!("  {name}: {}", i.accel.info());
    }
    println!();

    let widths = packet_widths(&device);
    let mut methods = vec![
        Method::Prism(intersector, &geometry),
        Method::PrismPackets(intersector, &geometry, 16),
        Method::PrismPackets(intersector, &geometry, 64),
    ];
    for (b, i) in o.builders.iter().zip(&intersectors[1..]) {
        methods.push(Method::PrismBuilder(i, &geometry, b));
    }
    for (scene, &q) in scenes.iter().zip(&qualities) {
        for &w in &widths {
            methods.push(Method::Embree(scene, q, w));
        }
    }

    let sets = match file_rays {
        Some(set) => vec![set],
        None => {
            let view = workload::View::of(mesh.name, &geometry);
            workload::generate(&geometry, intersector, &view).into()
        }
    };
    let wanted = |set: &&workload::RaySet| {
        o.rays
            .as_deref()
            .is_none_or(|r| r.split(',').any(|name| name == set.name))
    };
    for set in sets.iter().filter(wanted) {
        let n = set.len();
        // An untimed run of each method: it warms the caches and gives the answers that
        // are compared with prism's.
        let mut answers: Vec<Answers> = methods.iter().map(|_| Answers::for_set(set)).collect();
        for (m, a) in methods.iter().zip(&mut answers) {
            measure::run(m, set, a, 1);
        }
        println!(
            "{} rays: {n}; answers (hits, distance checksum, rays that differ from prism):",
            set.name
        );
        for (m, a) in methods.iter().zip(&answers) {
            println!(
                "  {:<12} {:8} {:16.3} {:6}",
                m.label(),
                a.hits(),
                a.checksum(),
                a.differ(&answers[0])
            );
        }
        for &threads in &o.threads {
            // Sample r of every method before sample r + 1 of any, so that load from other
            // processes falls on all methods alike.
            let mut samples: Vec<Vec<Sample>> = vec![Vec::new(); methods.len()];
            for _ in 0..o.repeats {
                for (k, m) in methods.iter().enumerate() {
                    let a = &mut answers[k];
                    samples[k].push(time(|| measure::run(m, set, a, threads)));
                }
            }
            println!(
                "  {threads} thread(s), median of {}: Mrays/s by process CPU time / by wall time (CPU ms, wall ms)",
                o.repeats
            );
            for (k, m) in methods.iter().enumerate() {
                let s = median(&samples[k]);
                let rate = |d: std::time::Duration| n as f64 / d.as_secs_f64() / 1e6;
                println!(
                    "  {:<12} {:7.2} / {:7.2}   ({:7.1}, {:7.1})",
                    m.label(),
                    rate(s.cpu),
                    rate(s.wall),
                    ms(s.cpu),
                    ms(s.wall)
                );
                let a = &answers[k];
                csv.row(&[
                    "trace",
                    mesh.name,
                    &triangles.to_string(),
                    set.name,
                    &m.label(),
                    &threads.to_string(),
                    &n.to_string(),
                    &a.hits().to_string(),
                    &format!("{:.3}", a.checksum()),
                    &a.differ(&answers[0]).to_string(),
                    &format!("{:.3}", ms(s.cpu)),
                    &format!("{:.3}", ms(s.wall)),
                    &format!("{:.4}", rate(s.cpu)),
                    &format!("{:.4}", rate(s.wall)),
                    &o.repeats.to_string(),
                    "",
                    "",
                ])?;
            }
        }
        println!();
    }
    let (own, wall, other) = load.finish();
    println!(
        "this run: {own:.1} s of process CPU time in {wall:.1} s; other processes used {other:.2} cores on average\n"
    );
    csv.row(&[
        "load",
        mesh.name,
        &triangles.to_string(),
        "",
        "",
        "",
        "",
        "",
        "",
        "",
        &format!("{:.3}", own * 1e3),
        &format!("{:.3}", wall * 1e3),
        "",
        "",
        "",
        "",
        &format!("{other:.3}"),
    ])?;
    Ok(())
}

/// How busy the rest of the machine was during a run: the whole machine's busy CPU time
/// (from /proc/stat) minus this process's own.
struct Load {
    busy: Option<f64>,
    own: prism_lab::bench::Stopwatch,
    wall: prism_lab::bench::Stopwatch,
}

impl Load {
    fn start() -> Self {
        Load {
            busy: machine_busy_seconds(),
            own: prism_lab::bench::Clock::ProcessCpu.start(),
            wall: prism_lab::bench::Clock::Wall.start(),
        }
    }

    /// (own CPU seconds, wall seconds, other processes' mean number of busy cores).
    fn finish(&self) -> (f64, f64, f64) {
        let (own, wall) = (
            self.own.elapsed().as_secs_f64(),
            self.wall.elapsed().as_secs_f64(),
        );
        let other = match (self.busy, machine_busy_seconds()) {
            (Some(a), Some(b)) => ((b - a - own) / wall).max(0.0),
            _ => f64::NAN,
        };
        (own, wall, other)
    }
}

/// CPU seconds all cores have spent busy since boot (user, nice, system, irq, softirq,
/// steal), from the first line of /proc/stat.
fn machine_busy_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/stat").ok()?;
    let ticks: Vec<f64> = stat
        .lines()
        .next()?
        .split_whitespace()
        .skip(1)
        .filter_map(|t| t.parse().ok())
        .collect();
    // SAFETY: sysconf has no preconditions.
    let hz = unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64;
    let busy = [0, 1, 2, 5, 6, 7]
        .iter()
        .filter_map(|&i| ticks.get(i))
        .sum::<f64>();
    Some(busy / hz)
}

/// CSV rows appended to a file (with the header when the file is new).
struct CsvOut(Option<std::fs::File>);

pub const CSV_HEADER: &str = "kind,mesh,triangles,rays_kind,method,threads,rays,hits,checksum,differ,cpu_ms,wall_ms,mrays_cpu,mrays_wall,samples,sah_cost,other_cores";

impl CsvOut {
    fn open(path: Option<&PathBuf>) -> Result<Self, String> {
        let Some(path) = path else {
            return Ok(CsvOut(None));
        };
        let new = !path.exists();
        let mut file = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(path)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        if new {
            writeln!(file, "{CSV_HEADER}").map_err(|e| e.to_string())?;
        }
        Ok(CsvOut(Some(file)))
    }

    fn row(&mut self, fields: &[&str]) -> Result<(), String> {
        match &mut self.0 {
            Some(f) => writeln!(f, "{}", fields.join(",")).map_err(|e| e.to_string()),
            None => Ok(()),
        }
    }
}
