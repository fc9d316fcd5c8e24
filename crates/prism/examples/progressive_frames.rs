//! Frames of the live viewer without the viewer: `Progressive::advance` of one sample per
//! pixel on a built-in scene, timed per frame in wall-clock and process CPU time, so the
//! engine's part of the viewer's frame rate can be measured (and compared between builds)
//! on its own. `bench/serve.sh` measures the whole viewer.
//!
//! cargo run --release -p prism --example progressive_frames -- [SCENE] [WIDTHxHEIGHT] [FRAMES] [THREADS]

use prism::render::Progressive;
use prism_lab::bench::Clock;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let name = args.first().map_or("whitted", String::as_str);
    let (width, height) = args
        .get(1)
        .and_then(|r| r.split_once('x'))
        .map_or((640, 360), |(w, h)| {
            (w.parse().unwrap(), h.parse().unwrap())
        });
    let frames: usize = args.get(2).map_or(40, |s| s.parse().unwrap());
    let threads: usize = args.get(3).map_or(0, |s| s.parse().unwrap());
    let scene = prism::scene::builtin::find(name).expect("a built-in scene");
    let options = prism::RenderOptions {
        width,
        height,
        threads,
        sampler: prism::sampling::SamplerKind::Jittered,
        ..scene.options.clone()
    };
    let prepared = scene.prepare_for(&options);
    let mut p = Progressive::new(width, height).unwrap();
    let cancel = AtomicBool::new(false);
    let (mut walls, mut cpus) = (Vec::new(), Vec::new());
    let mut rays = 0;
    for _ in 0..frames {
        let (w0, cpu) = (Instant::now(), Clock::ProcessCpu.start());
        rays = p
            .advance(&prepared, &options, 1, &cancel)
            .unwrap()
            .total_rays();
        walls.push(w0.elapsed().as_secs_f64());
        cpus.push(cpu.elapsed().as_secs_f64());
    }
    let (wall, cpu) = (median(walls), cpus.iter().sum::<f64>() / frames as f64);
    println!(
        "{name} {width}x{height}, {frames} frames, threads {threads}: wall {:.1} ms a frame (median), CPU {:.1} ms a frame (mean), {:.1} frames/s, {rays} rays a frame, {:.2} Mrays per CPU-s",
        wall * 1e3,
        cpu * 1e3,
        1.0 / wall,
        rays as f64 / cpu / 1e6
    );
}
