//! Markdown tables from the CSV that `run` appends to, for docs/performance.md: ray
//! throughput on 1 thread (process CPU time) with prism/Embree ratios, 2-thread scaling
//! (wall time), build times, and how far the answers agree.

use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

/// One CSV row, by column name.
struct Row(BTreeMap<String, String>);

impl Row {
    fn get(&self, key: &str) -> &str {
        self.0.get(key).map_or("", String::as_str)
    }

    fn num(&self, key: &str) -> f64 {
        self.get(key).parse().unwrap_or(f64::NAN)
    }
}

struct Table {
    rows: Vec<Row>,
    /// Meshes in the order they were run.
    meshes: Vec<(String, String)>,
}

impl Table {
    fn find(
        &self,
        kind: &str,
        mesh: &str,
        rays: &str,
        method: &str,
        threads: &str,
    ) -> Option<&Row> {
        self.rows.iter().find(|r| {
            r.get("kind") == kind
                && r.get("mesh") == mesh
                && r.get("rays_kind") == rays
                && r.get("method") == method
                && r.get("threads") == threads
        })
    }

    /// `column` of every matching row: one per process run (run.sh runs each mesh in
    /// several processes).
    fn values(
        &self,
        kind: &str,
        mesh: &str,
        rays: &str,
        method: &str,
        threads: &str,
        column: &str,
    ) -> Vec<f64> {
        let mut v: Vec<f64> = self
            .rows
            .iter()
            .filter(|r| {
                r.get("kind") == kind
                    && r.get("mesh") == mesh
                    && r.get("rays_kind") == rays
                    && r.get("method") == method
                    && r.get("threads") == threads
            })
            .map(|r| r.num(column))
            .filter(|x| x.is_finite())
            .collect();
        v.sort_by(f64::total_cmp);
        v
    }

    /// A method's throughput (Mrays/s) on `clock` ("mrays_cpu" or "mrays_wall"): the
    /// median over processes of each process's median.
    fn rate(
        &self,
        mesh: &str,
        rays: &str,
        method: &str,
        threads: &str,
        clock: &str,
    ) -> Option<f64> {
        median(&self.values("trace", mesh, rays, method, threads, clock))
    }

    /// A build time (`column` "wall_ms" or "cpu_ms"), the median over processes.
    fn build(&self, mesh: &str, method: &str, column: &str) -> Option<f64> {
        median(&self.values("build", mesh, "", method, "", column))
    }
}

/// The middle value (the upper of the two middle ones for an even count) of sorted values.
fn median(sorted: &[f64]) -> Option<f64> {
    sorted.get(sorted.len() / 2).copied()
}

/// prism's builders beside Embree's two qualities, when the run had `--builders`: build
/// time and single-ray throughput of each tree, prism's relative to its default (binned
/// SAH) tree and Embree HIGH's relative to MEDIUM, so the two steps up in quality can be
/// set side by side.
fn builders(t: &Table, w: &mut String) {
    let mut trees: Vec<&str> = Vec::new();
    for r in &t.rows {
        let m = r.get("method");
        if r.get("kind") == "build" && m.starts_with("prism-") && !trees.contains(&m) {
            trees.push(m);
        }
    }
    if trees.is_empty() {
        return;
    }
    let _ = writeln!(w, "\nprism's builders beside Embree MEDIUM and HIGH: builds on both cores where the builder is parallel, ms of process CPU time (wall in brackets); single rays on 1 thread, Mrays/s by process CPU time; medians; `vs` is prism's tree against its binned SAH tree (`prism`), Embree HIGH against MEDIUM: build time ratio (above 1: slower), ray speed ratios (above 1: faster).\n");
    let _ = writeln!(w, "| mesh | tree | build ms | SAH cost | primary | incoherent | build vs | primary vs | incoherent vs |");
    let _ = writeln!(w, "|---|---|---:|---:|---:|---:|---:|---:|---:|");
    for (mesh, _) in &t.meshes {
        if t.build(mesh, "prism", "cpu_ms").is_none() {
            continue;
        }
        // (label, build row's method, trace row's method, reference's build and trace)
        let mut rows = vec![("binned (default)", "prism", "prism", "prism", "prism")];
        for m in &trees {
            rows.push((&m["prism-".len()..], m, m, "prism", "prism"));
        }
        rows.push((
            "Embree MEDIUM",
            "embree-M",
            "embree-M1",
            "embree-M",
            "embree-M1",
        ));
        rows.push((
            "Embree HIGH",
            "embree-H",
            "embree-H1",
            "embree-M",
            "embree-M1",
        ));
        for (label, build, trace, ref_build, ref_trace) in rows {
            let rate = |m: &str, rays: &str| t.rate(mesh, rays, m, "1", "mrays_cpu");
            let (cpu, wall) = (
                t.build(mesh, build, "cpu_ms"),
                t.build(mesh, build, "wall_ms"),
            );
            let built = match (cpu, wall) {
                (Some(cpu), Some(wall)) => format!("{cpu:.0} ({wall:.0})"),
                _ => "–".into(),
            };
            let sah = t
                .find("build", mesh, "", build, "")
                .map_or(f64::NAN, |r| r.num("sah_cost"));
            let sah = if sah.is_finite() {
                format!("{sah:.1}")
            } else {
                "–".into()
            };
            let _ = writeln!(
                w,
                "| {mesh} | {label} | {built} | {sah} | {} | {} | {} | {} | {} |",
                f(rate(trace, "primary")),
                f(rate(trace, "incoherent")),
                ratio(cpu, t.build(mesh, ref_build, "cpu_ms")),
                ratio(rate(trace, "primary"), rate(ref_trace, "primary")),
                ratio(rate(trace, "incoherent"), rate(ref_trace, "incoherent")),
            );
        }
    }
}

fn read(path: &Path) -> Result<Table, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().ok_or("empty CSV")?.split(',').collect();
    let mut table = Table {
        rows: Vec::new(),
        meshes: Vec::new(),
    };
    for line in lines.filter(|l| !l.trim().is_empty()) {
        let row = Row(header
            .iter()
            .zip(line.split(','))
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect());
        let mesh = (
            row.get("mesh").to_string(),
            row.get("triangles").to_string(),
        );
        if !table.meshes.contains(&mesh) {
            table.meshes.push(mesh);
        }
        table.rows.push(row);
    }
    Ok(table)
}

fn f(x: Option<f64>) -> String {
    match x {
        Some(x) if x.is_finite() => format!("{x:.2}"),
        _ => "–".into(),
    }
}

fn ratio(a: Option<f64>, b: Option<f64>) -> String {
    match (a, b) {
        (Some(a), Some(b)) if a.is_finite() && b > 0.0 => format!("{:.2}×", a / b),
        _ => "–".into(),
    }
}

/// Thousands separated by commas, as the docs write counts.
fn count(s: &str) -> String {
    let digits: Vec<char> = s.chars().collect();
    let mut out = String::new();
    for (i, c) in digits.iter().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(*c);
    }
    out
}

const RAYS: [&str; 3] = ["primary", "incoherent", "shadow"];

pub fn markdown(path: &Path) -> Result<String, String> {
    let t = read(path)?;
    let mut s = String::new();
    let w = &mut s;

    let _ = writeln!(w, "Ray throughput, 1 thread, Mrays/s by process CPU time (the median over process runs of each run's median); ratios are prism / Embree (above 1: prism faster).\n");
    let _ = writeln!(w, "| mesh (triangles) | rays | Embree MEDIUM 1 / 8 / 16 | Embree HIGH 1 / 8 / 16 | prism 1 / packets of 16 / 64 | prism / M1 | prism / M16 | prism 64 / M16 | prism / H1 |");
    let _ = writeln!(w, "|---|---|---:|---:|---:|---:|---:|---:|---:|");
    for (mesh, tris) in &t.meshes {
        for rays in RAYS {
            let r = |m: &str| t.rate(mesh, rays, m, "1", "mrays_cpu");
            if r("prism").is_none() {
                continue;
            }
            let group = |q: &str| {
                [1, 8, 16]
                    .map(|w| f(r(&format!("embree-{q}{w}"))))
                    .join(" / ")
            };
            let _ = writeln!(
                w,
                "| {mesh} ({}) | {rays} | {} | {} | {} | {} | {} | {} | {} |",
                count(tris),
                group("M"),
                group("H"),
                ["prism", "prism-p16", "prism-p64"]
                    .map(|m| f(r(m)))
                    .join(" / "),
                ratio(r("prism"), r("embree-M1")),
                ratio(r("prism"), r("embree-M16")),
                ratio(r("prism-p64"), r("embree-M16")),
                ratio(r("prism"), r("embree-H1")),
            );
        }
    }

    // The ranges over meshes, for the reading below the table.
    let _ = writeln!(
        w,
        "\nIn short, prism / Embree over the meshes (lowest to highest):\n"
    );
    for rays in RAYS {
        let range_of = |ours: &str, method: &str| {
            let ratios: Vec<f64> = t
                .meshes
                .iter()
                .filter_map(|(mesh, _)| {
                    Some(
                        t.rate(mesh, rays, ours, "1", "mrays_cpu")?
                            / t.rate(mesh, rays, method, "1", "mrays_cpu")?,
                    )
                })
                .collect();
            let lo = ratios.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = ratios.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            if ratios.is_empty() {
                "–".to_string()
            } else {
                format!("{lo:.2}–{hi:.2}×")
            }
        };
        let range = |method: &str| range_of("prism", method);
        let _ = writeln!(
            w,
            "- {rays} rays: {} of Embree's single rays (MEDIUM), {} of its 16-ray packets; prism's 64-ray packets {} of Embree's 16-ray packets",
            range("embree-M1"),
            range("embree-M16"),
            range_of("prism-p64", "embree-M16")
        );
    }

    let _ = writeln!(w, "\nTwo threads: Mrays/s by wall time (median), and the speed-up over 1 thread by wall time.\n");
    let _ = writeln!(
        w,
        "| mesh | rays | prism | Embree M1 | Embree M16 | prism / M1, 2 threads |"
    );
    let _ = writeln!(w, "|---|---|---:|---:|---:|---:|");
    for (mesh, _) in &t.meshes {
        for rays in RAYS {
            let cell = |m: &str| {
                let two = t.rate(mesh, rays, m, "2", "mrays_wall");
                let one = t.rate(mesh, rays, m, "1", "mrays_wall");
                format!("{} ({})", f(two), ratio(two, one))
            };
            if t.rate(mesh, rays, "prism", "2", "mrays_wall").is_none() {
                continue;
            }
            let _ = writeln!(
                w,
                "| {mesh} | {rays} | {} | {} | {} | {} |",
                cell("prism"),
                cell("embree-M1"),
                cell("embree-M16"),
                ratio(
                    t.rate(mesh, rays, "prism", "2", "mrays_wall"),
                    t.rate(mesh, rays, "embree-M1", "2", "mrays_wall")
                ),
            );
        }
    }

    let _ = writeln!(w, "\nBuilds on both cores, ms of wall time (process CPU time in brackets), median over processes of each one's median; prism's SAH cost as `prism info` reports it (Embree does not report one).\n");
    let _ = writeln!(
        w,
        "| mesh | prism | prism SAH cost | Embree MEDIUM | Embree HIGH | prism / MEDIUM, speed |"
    );
    let _ = writeln!(w, "|---|---:|---:|---:|---:|---:|");
    for (mesh, _) in &t.meshes {
        let cell = |m: &str| match (t.build(mesh, m, "wall_ms"), t.build(mesh, m, "cpu_ms")) {
            (Some(wall), Some(cpu)) => format!("{wall:.0} ({cpu:.0})"),
            _ => "–".into(),
        };
        let Some(prism) = t.build(mesh, "prism", "wall_ms") else {
            continue;
        };
        let sah = t
            .find("build", mesh, "", "prism", "")
            .map_or(f64::NAN, |r| r.num("sah_cost"));
        let _ = writeln!(
            w,
            "| {mesh} | {} | {sah:.1} | {} | {} | {} |",
            cell("prism"),
            cell("embree-M"),
            cell("embree-H"),
            // As a speed ratio like the other tables: above 1, prism builds faster.
            ratio(t.build(mesh, "embree-M", "wall_ms"), Some(prism)),
        );
    }

    builders(&t, w);

    // How much a process run moves the figures: each process's median, lowest to highest.
    let runs = t
        .values(
            "trace",
            t.meshes.first().map_or("", |(mesh, _)| mesh.as_str()),
            "primary",
            "prism",
            "1",
            "mrays_cpu",
        )
        .len();
    if runs > 1 {
        let _ = writeln!(w, "\nSpread over the {runs} process runs: each run's 1-thread median (Mrays/s, CPU time), lowest and highest.\n");
        let _ = writeln!(w, "| mesh | rays | prism | Embree M1 | Embree M16 |");
        let _ = writeln!(w, "|---|---|---:|---:|---:|");
        for (mesh, _) in &t.meshes {
            for rays in RAYS {
                let cell = |m: &str| {
                    let v = t.values("trace", mesh, rays, m, "1", "mrays_cpu");
                    match (v.first(), v.last()) {
                        (Some(lo), Some(hi)) => format!("{lo:.2}–{hi:.2}"),
                        _ => "–".into(),
                    }
                };
                let _ = writeln!(
                    w,
                    "| {mesh} | {rays} | {} | {} | {} |",
                    cell("prism"),
                    cell("embree-M1"),
                    cell("embree-M16")
                );
            }
        }
    }

    let _ = writeln!(w, "\nAgreement: hits, and rays whose answer differs from prism's (hit against miss, or distances more than 10⁻⁴ apart), the most over Embree's six modes; distance checksums (sums of hit distances) of prism and Embree MEDIUM 1-ray.\n");
    let _ = writeln!(w, "| mesh | rays | count | prism hits | Embree hits (M1) | differing rays, most | prism checksum | Embree checksum | relative difference |");
    let _ = writeln!(w, "|---|---|---:|---:|---:|---:|---:|---:|---:|");
    for (mesh, _) in &t.meshes {
        for rays in RAYS {
            let Some(p) = t.find("trace", mesh, rays, "prism", "1") else {
                continue;
            };
            let e = t.find("trace", mesh, rays, "embree-M1", "1");
            let differ = t
                .rows
                .iter()
                .filter(|r| {
                    r.get("kind") == "trace"
                        && r.get("mesh") == mesh
                        && r.get("rays_kind") == rays
                        && r.get("threads") == "1"
                })
                .map(|r| r.num("differ") as u64)
                .max()
                .unwrap_or(0);
            let (pc, ec) = (p.num("checksum"), e.map_or(f64::NAN, |r| r.num("checksum")));
            let rel = if rays == "shadow" {
                "–".into()
            } else {
                format!("{:.1e}", (ec - pc).abs() / pc.abs())
            };
            let checksum = |c: f64| {
                if rays == "shadow" {
                    "–".into()
                } else {
                    format!("{c:.1}")
                }
            };
            let n = p.num("rays");
            let _ = writeln!(
                w,
                "| {mesh} | {rays} | {} | {} | {} | {differ} ({:.4} %) | {} | {} | {rel} |",
                count(p.get("rays")),
                count(p.get("hits")),
                e.map_or("–".into(), |r| count(r.get("hits"))),
                100.0 * differ as f64 / n,
                checksum(pc),
                checksum(ec),
            );
        }
    }
    let loads: Vec<String> = t
        .rows
        .iter()
        .filter(|r| r.get("kind") == "load")
        .map(|r| format!("{} {:.2}", r.get("mesh"), r.num("other_cores")))
        .collect();
    // (one entry per process run, in the order they ran)
    if !loads.is_empty() {
        let _ = writeln!(
            w,
            "\nOther processes kept on average this many of the 2 cores busy during each mesh's run (from /proc/stat): {}.",
            loads.join(", ")
        );
    }
    Ok(s)
}
