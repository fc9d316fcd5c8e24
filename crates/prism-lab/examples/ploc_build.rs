//! PLOC's build against binned SAH's on embree-bench's million-triangle meshes (the
//! sphereflake and the soup, from `prism_lab::meshes` as embree-bench makes them) and the
//! Stanford bunny where its file is found: process CPU time of each `Bvh::build` on all
//! threads, the two builders in turns, medians; SAH costs and their ratio. Run with
//! `cargo run --release -p prism-lab --example ploc_build [-- [--builds N] [--meshes DIR]
//! [MESH...]]`; it needs no Embree.

use prism::accel::{Bvh, BvhBuilder, BvhOptions};
use prism::cpu_time::{cpu_time, CpuClock};
use prism::geometry::Geometry;
use prism::geometry::TriangleMesh;
use prism_lab::meshes::{self, Triangles};
use std::path::PathBuf;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// The Stanford bunny, all parts of its file in one mesh, where the file is found.
fn bunny(dir: &std::path::Path) -> Option<Triangles> {
    let path = dir.join("stanford-bunny.obj");
    let file =
        prism_io::scene::load_mesh_file(&path, prism_io::scene::mesh_file::Materials::Ignore)
            .ok()?;
    let mut mesh = Triangles::default();
    for part in &file.parts {
        mesh.append(part.mesh.positions(), part.mesh.indices());
    }
    Some(mesh)
}

fn measure(name: &str, mut mesh: Triangles, builds: usize, radius: usize) {
    // As embree-bench normalises them: the same triangles as its tables.
    meshes::normalise(&mut mesh.positions);
    let mut geometry = Geometry::default();
    let mesh = TriangleMesh::new(mesh.positions, mesh.indices, None, None).expect("a valid mesh");
    geometry.add_mesh(mesh, 0);
    let prims: Vec<u32> = (0..geometry.primitives.len() as u32).collect();
    let builders = [BvhBuilder::Binned, BvhBuilder::Ploc];
    let mut cpu = vec![Vec::new(); builders.len()];
    let mut wall = vec![Vec::new(); builders.len()];
    let mut sah = vec![0.0; builders.len()];
    for _ in 0..builds {
        for (k, &builder) in builders.iter().enumerate() {
            let options = BvhOptions {
                builder,
                radius,
                ..BvhOptions::default()
            };
            let prims = prims.clone();
            let (c0, w0) = (cpu_time(CpuClock::Process), Instant::now());
            let bvh = Bvh::build(&geometry, prims, &options);
            let (c1, w1) = (cpu_time(CpuClock::Process), w0.elapsed());
            cpu[k].push((c1.unwrap() - c0.unwrap()).as_secs_f64() * 1e3);
            wall[k].push(w1.as_secs_f64() * 1e3);
            sah[k] = bvh.info().sah_cost.unwrap_or(f64::NAN);
        }
    }
    let (b, p) = (median(cpu[0].clone()), median(cpu[1].clone()));
    println!(
        "{name:<12} {:>9} tris  binned {b:7.1} ms ({:6.1} wall) SAH {:8.2} | ploc {p:7.1} ms ({:6.1} wall) SAH {:8.2} | ploc/binned time {:.3} SAH {:.3}",
        prims.len(),
        median(wall[0].clone()),
        sah[0],
        median(wall[1].clone()),
        sah[1],
        p / b,
        sah[1] / sah[0],
    );
}

fn main() {
    let mut builds = 5;
    let mut radius = BvhOptions::default().radius;
    let mut meshes = PathBuf::from("../shared/meshes");
    let mut names = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--builds" => {
                builds = args
                    .next()
                    .and_then(|v| v.parse().ok())
                    .expect("--builds N")
            }
            "--radius" => {
                radius = args
                    .next()
                    .and_then(|v| v.parse().ok())
                    .expect("--radius N")
            }
            "--meshes" => meshes = PathBuf::from(args.next().expect("--meshes DIR")),
            _ => names.push(a),
        }
    }
    if names.is_empty() {
        names = vec!["bunny".into(), "sphereflake".into(), "soup".into()];
    }
    println!("{} threads", rayon::current_num_threads());
    for name in names {
        let mesh = match name.as_str() {
            "bunny" => bunny(&meshes),
            "sphereflake" => Some(meshes::sphereflake(4, 12, 7)),
            "sphereflake3" => Some(meshes::sphereflake(3, 12, 7)),
            "soup" => Some(meshes::soup(1_000_000, 0x5eed)),
            "soup100k" => Some(meshes::soup(100_000, 0x5eed)),
            _ => None,
        };
        match mesh {
            Some(mesh) => measure(&name, mesh, builds, radius),
            None => eprintln!("no mesh '{name}' (the bunny needs --meshes DIR)"),
        }
    }
}
