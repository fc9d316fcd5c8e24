//! `prism bench` and the cost view from the command line: the files the benchmark writes
//! and what their numbers must satisfy, refusals that leave nothing behind, and a cost
//! view that does not depend on the thread count.

use crate::common;

use common::{run, words};
use std::fs;
use std::path::PathBuf;

fn work_dir(test: &str) -> PathBuf {
    common::work_dir("bench", test)
}

const QUICK: [&str; 12] = [
    "bench",
    "--quick",
    "-q",
    "--scenes",
    "cornell,sphereflake:1",
    "--methods",
    "bvh;brute-force",
    "--csv",
    "out.csv",
    "--json",
    "out.json",
    "--chart",
];

#[test]
fn bench_writes_the_same_results_as_csv_json_and_chart() {
    let dir = work_dir("files");
    let mut args = QUICK.to_vec();
    args.push("out.svg");
    let (table, _) = run(&dir, &args, 0);
    assert!(table.contains("1 thread"), "{table}");
    assert!(table.contains("within 10 %"), "{table}");

    let csv = fs::read_to_string(dir.join("out.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|&h| h == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 4, "two scenes × two methods:\n{csv}");
    for row in &rows {
        assert_eq!(row.len(), header.len(), "{row:?}");
        assert_eq!(row[col("status")], "ok", "{row:?}");
    }
    let num = |row: &[&str], name: &str| row[col(name)].parse::<f64>().unwrap();
    for pair in rows.chunks(2) {
        let (bvh, brute) = (&pair[0], &pair[1]);
        assert_eq!(
            (bvh[col("method")], brute[col("method")]),
            ("bvh", "brute-force")
        );
        // Brute force tests every primitive on every ray; the BVH must test fewer.
        let prims = num(brute, "primitives");
        assert_eq!(num(brute, "primary_tests_per_ray"), prims);
        assert_eq!(num(brute, "primary_nodes_per_ray"), 0.0);
        assert!(num(bvh, "primary_tests_per_ray") < prims, "{bvh:?}");
        assert!(num(bvh, "primary_nodes_per_ray") > 0.0);
        // The same rays and the same answers for both.
        for c in [
            "primary_rays",
            "primary_hits",
            "shadow_rays",
            "shadow_hits",
            "incoherent_rays",
            "incoherent_hits",
        ] {
            assert_eq!(bvh[col(c)], brute[col(c)], "{c}");
        }
        assert!(num(bvh, "primary_rays") == num(bvh, "width") * num(bvh, "height"));
        assert!(num(bvh, "shadow_rays") > 0.0);
        // One diffuse bounce from every camera ray's hit; inside the closed Cornell box
        // and off the sphereflake's floor many of them hit something again.
        assert_eq!(num(bvh, "incoherent_rays"), num(bvh, "primary_hits"));
        assert!(num(bvh, "incoherent_hits") > 0.0);
        assert_eq!(num(brute, "incoherent_tests_per_ray"), prims);
        assert!(num(bvh, "incoherent_mrays_per_s") > 0.0);
        let best = pair.iter().filter(|r| r[col("fastest")] == "true").count();
        assert_eq!(best, 1);
        for r in pair {
            let vs = num(r, "vs_best");
            assert!(vs > 0.0 && vs <= 1.0);
            assert_eq!(vs == 1.0, r[col("fastest")] == "true");
            assert!(num(r, "primary_mrays_per_s") > 0.0);
        }
    }

    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("out.json")).unwrap()).unwrap();
    assert_eq!(json["threads"], 1);
    assert_eq!(json["default_method"], "bvh");
    let scenes = json["scenes"].as_array().unwrap();
    assert_eq!(scenes.len(), 2);
    assert_eq!(scenes[0]["name"], "cornell");
    assert_eq!(scenes[1]["name"], "sphereflake:1");
    for (s, pair) in scenes.iter().zip(rows.chunks(2)) {
        let methods = s["methods"].as_array().unwrap();
        assert_eq!(methods.len(), 2);
        for (m, row) in methods.iter().zip(pair) {
            let measured = &m["measured"];
            assert_eq!(
                measured["primary"]["hits"].as_u64().unwrap(),
                num(row, "primary_hits") as u64
            );
            assert_eq!(
                measured["accel"]["memory_bytes"].as_u64().unwrap(),
                num(row, "memory_bytes") as u64
            );
        }
    }

    let svg = fs::read_to_string(dir.join("out.svg")).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert_eq!(svg.matches("Mrays/s</title>").count(), 4, "one bar per row");
    for name in ["cornell", "sphereflake:1", "bvh", "brute-force", "▲"] {
        assert!(svg.contains(name), "{name}");
    }
}

/// `--auto-passes` measures `build=auto` once per pass count, each row's tree built for
/// that many passes over the camera and shadow rays (the render the auto check weighs).
#[test]
fn auto_rows_are_built_for_their_passes() {
    let dir = work_dir("auto-passes");
    let args = [
        "bench",
        "--quick",
        "-q",
        "--scenes",
        "shards",
        "--methods",
        "bvh;bvh:build=auto",
        "--auto-passes",
        "1,500",
        "--csv",
        "out.csv",
        "--json",
        "out.json",
    ];
    run(&dir, &args, 0);
    let csv = fs::read_to_string(dir.join("out.csv")).unwrap();
    let methods: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(4).unwrap())
        .collect();
    assert_eq!(methods, ["bvh", "bvh:build=auto@1", "bvh:build=auto@500"]);
    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("out.json")).unwrap()).unwrap();
    let scene = &json["scenes"][0];
    let per_pass = scene["primary_rays"].as_u64().unwrap() + scene["shadow_rays"].as_u64().unwrap();
    for (row, passes) in scene["methods"].as_array().unwrap()[1..]
        .iter()
        .zip([1, 500])
    {
        let built = row["measured"]["accel"]["method"].as_str().unwrap();
        let told = format!("and {} expected rays", passes * per_pass);
        assert!(built.contains(&told), "{built}: {told}");
    }
}

#[test]
fn bad_bench_input_fails_at_once_and_writes_nothing() {
    let dir = work_dir("bad");
    let mut cases: Vec<(&[&str], &str)> = vec![
        (&["--scenes", "cornell,nope"], "unknown scene 'nope'"),
        (&["--methods", "bvh;bvh:leaf=0"], "bad method 'bvh:leaf=0'"),
        (&["--method", "quadtree"], "bad method 'quadtree'"),
        (&["--methods", ";;"], "no method given"),
        (&["--csv", "missing/out.csv"], "does not exist"),
        (&["--chart", "out.png"], "expected a .svg file name"),
    ];
    // A folder that exists but takes no files (even for root): found before any work.
    if std::path::Path::new("/proc/self").is_dir() {
        cases.push((&["--csv", "/proc/prism-bench.csv"], "is not writable"));
    }
    for (extra, message) in cases {
        let mut args = vec!["bench", "--quick", "-q", "--json", "out.json"];
        if !extra.contains(&"--scenes") {
            args.extend(["--scenes", "cornell"]);
        }
        args.extend(extra);
        let (_, err) = run(&dir, &args, 1);
        assert!(err.contains(message), "{args:?}: {err}");
        let left: Vec<_> = fs::read_dir(&dir).unwrap().collect();
        assert!(left.is_empty(), "{args:?} left files behind: {left:?}");
    }
}

#[test]
fn the_cost_view_is_the_same_for_any_thread_count() {
    let dir = work_dir("cost");
    let render = |threads: &str, metric: &str, sampler: &str, out: &str| {
        let line = format!(
            "render -b sphereflake:2 -q -W 24 -H 18 -o img.png -t {threads} --cost {out} \
             --cost-metric {metric} --sampler {sampler}"
        );
        run(&dir, &words(&line), 0);
        fs::read(dir.join(out)).unwrap()
    };
    // Per-pixel tiles (grid) and row passes over a shared lattice (adaptive).
    for (metric, sampler) in [("nodes", "grid"), ("prims", "grid"), ("nodes", "adaptive")] {
        let one = render("1", metric, sampler, "one.png");
        let two = render("2", metric, sampler, "two.png");
        assert!(
            one == two,
            "{metric}, {sampler}: the view depends on the thread count"
        );
        let image = image::load_from_memory(&one).unwrap();
        // The heat map enlarges small renders by a whole factor and adds a colour bar to the
        // right and a caption below.
        let zoom = 240 / 18;
        assert!(image.width() > 24 * zoom && image.height() > 18 * zoom);
        let rgb = image.to_rgb8();
        let colours: std::collections::HashSet<_> = (0..24 * zoom)
            .flat_map(|x| (0..18 * zoom).map(move |y| (x, y)))
            .map(|(x, y)| rgb.get_pixel(x, y).0)
            .collect();
        assert!(
            colours.len() > 4,
            "{metric}, {sampler}: the view is nearly flat"
        );
    }
    let (_, err) = run(
        &dir,
        &[
            "render", "-b", "cornell", "-q", "-W", "8", "-H", "8", "-o", "a.png", "--cost", "c.exr",
        ],
        1,
    );
    assert!(err.contains("cost view is written as PNG"), "{err}");
}

#[test]
fn the_bad_case_scenes_render_and_describe_themselves() {
    let dir = work_dir("bad-cases");
    let (list, _) = run(&dir, &["list"], 0);
    for (name, what) in [
        ("stadium", "bad for the grid"),
        ("slivers", "bad for bounding boxes"),
        ("shards", "bad for the kd-tree"),
        ("pearls", "bad for the octree"),
    ] {
        let line = list.lines().find(|l| l.trim_start().starts_with(name));
        assert!(line.is_some_and(|l| l.contains(what)), "{name}: {list}");
        run(
            &dir,
            &[
                "render", "-b", name, "-q", "-W", "32", "-H", "24", "-o", "img.png",
            ],
            0,
        );
        let image = image::open(dir.join("img.png")).unwrap().to_rgb8();
        let first = *image.get_pixel(0, 0);
        assert!(
            image.pixels().any(|p| *p != first),
            "{name}: the render is one flat colour"
        );
        let builtin = format!("builtin:{name}");
        let (info, _) = run(&dir, &["info", &builtin], 0);
        assert!(info.contains("accelerator"), "{info}");
    }
}

#[test]
fn the_shadow_cost_view_shows_the_shadow_rays_work_only() {
    let dir = work_dir("cost-shadow");
    let render = |rays: &str, shadows: &str, threads: &str, out: &str| {
        let line = format!(
            "render -b whitted -q -W 24 -H 18 -o img.png --cost-metric prims --cost {out} \
             --cost-rays {rays} --shadows {shadows} -t {threads}"
        );
        run(&dir, &words(&line), 0);
        fs::read(dir.join(out)).unwrap()
    };
    let all = render("all", "light-buffer", "1", "all.png");
    let shadow = render("shadow", "light-buffer", "1", "shadow.png");
    assert!(
        all != shadow,
        "the shadow view differs from the whole work's"
    );
    assert!(
        shadow == render("shadow", "light-buffer", "2", "shadow2.png"),
        "the shadow view is the same for any thread count"
    );
    assert!(
        shadow != render("shadow", "any-hit", "1", "bvh.png"),
        "the light buffer and the BVH do different work"
    );
}

/// The cost view shows each pixel's own work: its rays are traced alone, so it is the same
/// with and without `--no-packets` (with packets on, a packet's work would be shared evenly
/// among its 8 × 8 pixels and paint blocks).
#[test]
fn the_cost_view_shows_each_pixels_own_work() {
    let dir = work_dir("cost-own-work");
    let render = |extra: &[&str], out: &str| {
        let line = format!("render -b sphereflake:2 -q -W 24 -H 16 -o img.png --cost {out}");
        let mut args = words(&line);
        args.extend(extra);
        run(&dir, &args, 0);
        fs::read(dir.join(out)).unwrap()
    };
    let default = render(&[], "default.png");
    let alone = render(&["--no-packets"], "alone.png");
    assert!(default == alone, "the cost view depends on packets");
}
