//! The viewer's goals, measured through the real WebSocket: frames per second at one
//! sample per pixel per frame, and the time from a camera move to the first frame that
//! shows it, for a scene at a resolution (default: the built-in Whitted scene at 640×360),
//! plus what each way of encoding a frame would cost. `bench/serve.sh` runs it; the figures
//! are in docs/viewer.md.
//!
//! cargo run --release -p prism-serve --example viewer_bench -- [SCENE] [WIDTHxHEIGHT] [SECONDS] [KEY=VALUE ...]

use prism_lab::bench::Clock;
use prism_serve::protocol::{split_binary, FrameHeader};
use prism_serve::{Server, ServerConfig};
use std::net::{Ipv4Addr, TcpStream};
use std::time::{Duration, Instant};
use tungstenite::stream::MaybeTlsStream;
use tungstenite::{Message, WebSocket};

type Socket = WebSocket<MaybeTlsStream<TcpStream>>;

/// The next frame's header and payload, skipping text messages.
fn frame(ws: &mut Socket) -> (FrameHeader, Vec<u8>) {
    loop {
        if let Message::Binary(b) = ws.read().expect("the server answers") {
            let (header, payload) = split_binary(&b).expect("a binary message");
            let value: serde_json::Value = serde_json::from_str(header).unwrap();
            if value["kind"] == "frame" {
                return (serde_json::from_value(value).unwrap(), payload.to_vec());
            }
        }
    }
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
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
    let seconds: f64 = args.get(2).map_or(10.0, |s| s.parse().unwrap());
    let scene = prism::scene::builtin::find(name).expect("a built-in scene");
    let mut options = prism::RenderOptions {
        width,
        height,
        samples: 1,
        sampler: prism::sampling::SamplerKind::Jittered,
        ..scene.options.clone()
    };
    // Settings after the seconds, as KEY=VALUE (the scene file's keys), e.g. wavefront=false.
    for setting in args.iter().skip(3) {
        let (key, value) = setting
            .split_once('=')
            .unwrap_or_else(|| panic!("'{setting}': expected KEY=VALUE"));
        options.set(key, value).unwrap_or_else(|e| panic!("{e}"));
    }
    let config = ServerConfig {
        bind: Ipv4Addr::LOCALHOST.into(),
        port: 0,
    };
    let server = Server::start(scene, name, options.clone(), &config).expect("the server starts");
    let (mut ws, _) = tungstenite::connect(format!("ws://{}/ws", server.addr())).unwrap();
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    println!(
        "viewer: builtin:{name} at {width}x{height}, 1 spp per frame, {cores} cores, {} integrator{}",
        options.integrator,
        if args.len() > 3 { format!(", {}", args[3..].join(" ")) } else { String::new() }
    );

    // Frames per second: frames rendered (the spp count) over a stretch of accumulation,
    // and frames received (a slow client skips frames; this one keeps up).
    let (first, _) = frame(&mut ws);
    // Process CPU time: the server's render and network threads and this client.
    let (start, cpu_watch) = (Instant::now(), Clock::ProcessCpu.start());
    let mut received = 0u32;
    let mut frame_ms = Vec::new();
    let mut rays = Vec::new();
    let mut last = first.clone();
    while start.elapsed().as_secs_f64() < seconds {
        let (h, _) = frame(&mut ws);
        received += 1;
        frame_ms.push(h.frame_ms);
        rays.push(h.rays_per_s);
        last = h;
    }
    let elapsed = start.elapsed().as_secs_f64();
    let cpu = cpu_watch.elapsed().as_secs_f64();
    let rendered = (last.spp - first.spp) as f64;
    frame_ms.sort_by(f64::total_cmp);
    rays.sort_by(f64::total_cmp);
    println!(
        "frames/s: {:.1} rendered, {:.1} received; render time per frame median {:.1} ms; \
         {:.2} Mrays/s median",
        rendered / elapsed,
        received as f64 / elapsed,
        percentile(&frame_ms, 0.5),
        percentile(&rays, 0.5) / 1e6
    );
    // CPU time a frame of the whole process (render, encoding, WebSocket, this client):
    // the frame rate two cores would reach if nothing else ran on them.
    let cpu_ms = 1e3 * cpu / rendered.max(1.0);
    println!(
        "CPU per frame (server and client): {cpu_ms:.1} ms; {:.1} frames/s on {cores} cores if they were this process's alone",
        cores as f64 * 1e3 / cpu_ms.max(1e-9)
    );

    // Time to the first frame after a camera move (a preview when full frames are slow)
    // and to the first full-resolution frame: a small orbit, twenty times, with a few
    // frames of accumulation between.
    let (mut first_any, mut first_full) = (Vec::new(), Vec::new());
    let mut generation = last.generation;
    let verbose = std::env::var_os("VIEWER_BENCH_VERBOSE").is_some();
    for i in 0..20 {
        let yaw = if i % 2 == 0 { 3.0 } else { -3.0 };
        let sent = Instant::now();
        let text = format!(r#"{{"type":"move","orbit":[{yaw},0]}}"#);
        ws.send(Message::Text(text.into())).unwrap();
        let mut seen = false;
        loop {
            let (h, _) = frame(&mut ws);
            if h.generation <= generation {
                continue;
            }
            let ms = sent.elapsed().as_secs_f64() * 1e3;
            if !seen {
                first_any.push(ms);
                seen = true;
            }
            if verbose {
                eprintln!(
                    "move {i}: {ms:.1} ms, {}x{}{}, rendered in {:.1} ms",
                    h.width,
                    h.height,
                    if h.preview { " preview" } else { "" },
                    h.frame_ms
                );
            }
            if !h.preview {
                first_full.push(ms);
                generation = h.generation;
                break;
            }
        }
        // Let the accumulation run a little, as between two real moves.
        for _ in 0..2 {
            frame(&mut ws);
        }
    }
    for (what, list) in [
        ("first frame after a camera move", &mut first_any),
        ("first full-resolution frame after it", &mut first_full),
    ] {
        list.sort_by(f64::total_cmp);
        println!(
            "{what}: median {:.1} ms, 90th percentile {:.1} ms, best {:.1} ms",
            percentile(list, 0.5),
            percentile(list, 0.9),
            list[0]
        );
    }
    drop(ws);

    // Frame encodings on one core: what the server would spend per frame, and the bytes.
    let film = {
        let scene = prism::scene::builtin::find(name).unwrap();
        let prepared = scene.prepare_for(&options);
        let o = prism::RenderOptions {
            samples: 4,
            ..options.clone()
        };
        let cancel = std::sync::atomic::AtomicBool::new(false);
        prism::render::render(&prepared, &o, &|_| {}, &cancel)
            .unwrap()
            .film
    };
    let time = |f: &mut dyn FnMut() -> usize| {
        let mut best = Duration::MAX;
        let mut size = 0;
        for _ in 0..5 {
            let t = Instant::now();
            size = f();
            best = best.min(t.elapsed());
        }
        (best.as_secs_f64() * 1e3, size)
    };
    let rgb = prism_io::output::to_rgb8(&film);
    let rgba: Vec<u8> = rgb
        .chunks(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    let rows: [(&str, (f64, usize)); 4] = [
        ("raw RGBA (sent as is)", time(&mut || rgba.clone().len())),
        (
            "film to 8-bit sRGB (powf)",
            time(&mut || prism_io::output::to_rgb8(&film).len()),
        ),
        (
            "PNG",
            time(&mut || {
                prism_io::output::png_rgb8_bytes(&rgb, width, height)
                    .unwrap()
                    .len()
            }),
        ),
        (
            "JPEG quality 85",
            time(&mut || {
                let mut out = Vec::new();
                image::codecs::jpeg::JpegEncoder::new_with_quality(&mut out, 85)
                    .encode(&rgb, width, height, image::ExtendedColorType::Rgb8)
                    .unwrap();
                out.len()
            }),
        ),
    ];
    for (what, (ms, bytes)) in rows {
        println!("encoding {what:<28} {ms:>7.2} ms {:>9} bytes", bytes);
    }
    server.stop();
}
