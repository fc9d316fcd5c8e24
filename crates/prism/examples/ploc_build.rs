//! PLOC's build against binned SAH's on embree-bench's million-triangle meshes (the
//! sphereflake and the soup, made here the same way) and the Stanford bunny where its file
//! is found: process CPU time of each `Bvh::build` on all threads, the two builders in
//! turns, medians; SAH costs and their ratio. Run with
//! `cargo run --release --example ploc_build [-- [--builds N] [--meshes DIR] [MESH...]]`.

use prism::accel::{Bvh, BvhBuilder, BvhOptions};
use prism::cpu_time::{cpu_time, CpuClock};
use prism::geometry::Geometry;
use prism::geometry::TriangleMesh;
use prism::math::Vec3;
use std::f32::consts::{PI, TAU};
use std::path::PathBuf;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// `count` random triangles: centres uniform in a cube of side 100, vertices within ±1.
fn soup(count: u32, seed: u64) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut state = seed;
    let mut uniform = move || {
        let mut z = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut positions = Vec::with_capacity(3 * count as usize);
    for _ in 0..count {
        let c = Vec3::new(uniform(), uniform(), uniform()) * 100.0 - 50.0;
        for _ in 0..3 {
            positions.push(c + Vec3::new(uniform(), uniform(), uniform()) * 2.0 - 1.0);
        }
    }
    let indices = (0..count).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    (positions, indices)
}

/// Haines's sphereflake of UV spheres (12 segments, 7 rings): 1,062,864 triangles at level 4.
fn sphereflake(level: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut mesh = (Vec::new(), Vec::new());
    flake(&mut mesh, Vec3::ZERO, 1.0, Vec3::Y, level);
    mesh
}

fn flake(mesh: &mut (Vec<Vec3>, Vec<[u32; 3]>), centre: Vec3, radius: f32, axis: Vec3, level: u32) {
    let (nu, rings) = (12, 7);
    let (positions, indices) = mesh;
    let base = positions.len() as u32;
    positions.push(centre + radius * Vec3::Y);
    for j in 1..rings {
        let theta = PI * j as f32 / rings as f32;
        for i in 0..nu {
            let phi = TAU * i as f32 / nu as f32;
            let d = Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            );
            positions.push(centre + radius * d);
        }
    }
    positions.push(centre - radius * Vec3::Y);
    let south = positions.len() as u32 - 1;
    let ring = |j: u32, i: u32| base + 1 + (j - 1) * nu + i % nu;
    for i in 0..nu {
        indices.push([base, ring(1, i + 1), ring(1, i)]);
        for j in 1..rings - 1 {
            let (a, b) = (ring(j, i), ring(j, i + 1));
            let (c, d) = (ring(j + 1, i + 1), ring(j + 1, i));
            indices.push([a, b, c]);
            indices.push([a, c, d]);
        }
        indices.push([ring(rings - 1, i), ring(rings - 1, i + 1), south]);
    }
    if level == 0 {
        return;
    }
    let frame = prism::math::Frame::from_z(axis);
    let child = radius / 3.0;
    for k in 0..9 {
        let (elevation, phi) = if k < 6 {
            (0.0f32, k as f32 * TAU / 6.0)
        } else {
            (60f32.to_radians(), (k - 6) as f32 * TAU / 3.0 + TAU / 12.0)
        };
        let local = Vec3::new(
            elevation.cos() * phi.cos(),
            elevation.cos() * phi.sin(),
            elevation.sin(),
        );
        let dir = frame.to_world(local).normalize();
        flake(mesh, centre + (radius + child) * dir, child, dir, level - 1);
    }
}

fn bunny(dir: &std::path::Path) -> Option<(Vec<Vec3>, Vec<[u32; 3]>)> {
    let path = dir.join("stanford-bunny.obj");
    let file =
        prism_io::scene::load_mesh_file(&path, prism_io::scene::mesh_file::Materials::Ignore)
            .ok()?;
    let (mut positions, mut indices) = (Vec::new(), Vec::new());
    for part in &file.parts {
        let base = positions.len() as u32;
        positions.extend_from_slice(part.mesh.positions());
        indices.extend(part.mesh.indices().iter().map(|t| t.map(|i| i + base)));
    }
    Some((positions, indices))
}

fn measure(name: &str, positions: Vec<Vec3>, indices: Vec<[u32; 3]>, builds: usize, radius: usize) {
    let mut geometry = Geometry::default();
    let mesh = TriangleMesh::new(positions, indices, None, None).expect("a valid mesh");
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
            "sphereflake" => Some(sphereflake(4)),
            "sphereflake3" => Some(sphereflake(3)),
            "soup" => Some(soup(1_000_000, 0x5eed)),
            "soup100k" => Some(soup(100_000, 0x5eed)),
            _ => None,
        };
        match mesh {
            Some((positions, indices)) => measure(&name, positions, indices, builds, radius),
            None => eprintln!("no mesh '{name}' (the bunny needs --meshes DIR)"),
        }
    }
}
