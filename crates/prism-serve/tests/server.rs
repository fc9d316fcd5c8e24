//! The viewer's server as a client meets it: the page and nothing else over HTTP, frames
//! over the WebSocket, errors (never a crash or a hang) for hostile messages, the camera
//! and the controls changing what the next frame shows, several tabs on one render, and no
//! rendering while no tab is open.

mod common;

use common::{difference, http, server, Client, Received, PATIENCE};
use prism_serve::Server;
use std::time::{Duration, Instant};
use tungstenite::client::IntoClientRequest;
use tungstenite::Message;

#[test]
fn the_page_its_script_and_style_sheet_are_served() {
    let s = server(64, 36);
    let (status, page) = http(&s, "GET", "/");
    assert_eq!(status, 200, "{page}");
    assert!(page.contains("text/html") && page.contains("/viewer.js") && page.contains("<canvas"));
    assert!(page
        .to_ascii_lowercase()
        .contains("content-security-policy"));
    let (status, script) = http(&s, "GET", "/viewer.js");
    assert_eq!(status, 200);
    assert!(script.contains("text/javascript") && script.contains("WebSocket"));
    let (status, css) = http(&s, "GET", "/viewer.css");
    assert_eq!(status, 200);
    assert!(css.contains("text/css"));
}

#[test]
fn every_other_path_is_a_404_and_no_file_is_ever_read() {
    let s = server(64, 36);
    // Files a path traversal would reach from the server's working folder (the crate's,
    // under cargo test) and from the root.
    let secrets = ["[package]", "[workspace]", "root:x:0", "#![", "fn main"];
    for target in [
        "/index.html",
        "/Cargo.toml",
        "/../Cargo.toml",
        "/../../Cargo.toml",
        "/%2e%2e/Cargo.toml",
        "/%2e%2e%2fCargo.toml",
        "/..%2f..%2fCargo.toml",
        "/.%2e/.%2e/etc/passwd",
        "/%2e%2e/%2e%2e/%2e%2e/%2e%2e/etc/passwd",
        "//etc/passwd",
        "/etc/passwd",
        "/viewer.js/../../Cargo.toml",
        "/ws/../Cargo.toml",
        "/assets/viewer.js",
        "/src/lib.rs",
        "/tests/server.rs",
        "/%00",
        "/viewer.js%00.txt",
        "/./viewer.css/.",
        "http://127.0.0.1/../../etc/passwd",
        "file:///etc/passwd",
        "*",
    ] {
        let (status, body) = http(&s, "GET", target);
        assert!(status == 404 || status == 400, "{target}: {status}\n{body}");
        for secret in secrets {
            assert!(!body.contains(secret), "{target} leaked {secret}:\n{body}");
        }
    }
    for method in ["POST", "PUT", "DELETE"] {
        let (status, _) = http(&s, method, "/");
        assert_eq!(status, 404, "{method} /");
    }
    // The server still answers.
    assert_eq!(http(&s, "GET", "/").0, 200);
}

#[test]
fn the_websocket_says_hello_and_sends_refining_frames() {
    let s = server(96, 54);
    let mut c = Client::connect(&s);
    let hello = c.text("hello");
    assert_eq!(hello["scene"], "builtin:whitted");
    let names: Vec<&str> = (hello["controls"].as_array().unwrap().iter())
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    for name in [
        "integrator",
        "accel",
        "sampler",
        "depth",
        "min_weight",
        "shadows",
        "view",
        "resolution",
    ] {
        assert!(names.contains(&name), "{name} in {names:?}");
    }
    let (first, pixels) = c.frame();
    assert_eq!((first.width, first.height), (96, 54));
    assert_eq!(pixels.len(), 96 * 54 * 4);
    assert!(first.rays_per_s > 0.0 && first.frame_ms > 0.0);
    let (later, _) = c.frame_where(|h| h.spp >= first.spp + 3);
    assert_eq!(later.generation, first.generation);
    assert!(
        pixels.chunks(4).any(|p| p[..3] != [0, 0, 0]),
        "the picture is not black"
    );
}

/// Each message gets an error reply; a good message after them still works.
#[test]
fn hostile_messages_get_errors_and_the_connection_goes_on() {
    let s = server(64, 36);
    let mut c = Client::connect(&s);
    c.text("state");
    let nested = format!("{}{}", "[".repeat(5000), "]".repeat(5000));
    let long = format!(
        r#"{{"type":"set","control":"accel","value":"{}"}}"#,
        "x".repeat(20_000)
    );
    let hostile: Vec<String> = [
        "",
        "{",
        "not json",
        "null",
        "42",
        r#"{"type":"move"}x"#,
        r#"{"type":"teleport"}"#,
        r#"{"type":"move","orbit":[1,2],"warp":9}"#,
        r#"{"type":"move","orbit":[1e308,0]}"#,
        r#"{"type":"move","zoom":1e400}"#,
        r#"{"type":"move","zoom":NaN}"#,
        r#"{"type":"move","pan":["a",0]}"#,
        r#"{"type":"move","orbit":[1,2,3]}"#,
        r#"{"type":"camera","eye":[NaN,0,0],"look_at":[0,0,0],"up":[0,1,0],"fov":40}"#,
        r#"{"type":"camera","eye":[1e39,0,0],"look_at":[0,0,0],"up":[0,1,0],"fov":40}"#,
        r#"{"type":"camera","eye":[1,1,1],"look_at":[1,1,1],"up":[0,1,0],"fov":40}"#,
        r#"{"type":"camera","eye":[0,0,5],"look_at":[0,0,0],"up":[0,0,1],"fov":40}"#,
        r#"{"type":"camera","eye":[0,0,5],"look_at":[0,0,0],"up":[0,1,0],"fov":180}"#,
        r#"{"type":"camera","eye":[0,0,5],"look_at":[0,0,0],"up":[0,1,0]}"#,
        r#"{"type":"set","control":"resolution","value":"100000x100000"}"#,
        r#"{"type":"set","control":"resolution","value":"3840x3840"}"#,
        r#"{"type":"set","control":"resolution","value":"0x0"}"#,
        r#"{"type":"set","control":"depth","value":"4294967296"}"#,
        r#"{"type":"set","control":"depth","value":"-1"}"#,
        r#"{"type":"set","control":"min_weight","value":"-1"}"#,
        r#"{"type":"set","control":"min_weight","value":"1/0"}"#,
        r#"{"type":"set","control":"min_weight","value":"NaN"}"#,
        r#"{"type":"set","control":"accel","value":"bvh:leaf=999999999999"}"#,
        r#"{"type":"set","control":"accel","value":"../../etc/passwd"}"#,
        r#"{"type":"set","control":"shadows","value":"telepathy"}"#,
        r#"{"type":"set","control":"sampler","value":"adaptive"}"#,
        r#"{"type":"set","control":"threads","value":"1000"}"#,
        r#"{"type":"set","control":"view","value":5}"#,
    ]
    .iter()
    .map(|s| s.to_string())
    .chain([nested, long])
    .collect();
    for text in &hostile {
        c.send(text);
        let error = c.text("error");
        let message = error["message"].as_str().unwrap();
        assert!(!message.is_empty(), "{text}");
    }
    c.ws.send(Message::Binary(vec![0u8; 100].into())).unwrap();
    assert!(c.text("error")["message"]
        .as_str()
        .unwrap()
        .contains("binary"));
    // Still served: a good message changes the state.
    c.send(r#"{"type":"set","control":"depth","value":"3"}"#);
    let state = c.text("state");
    assert_eq!(state["values"]["depth"], "3");
    assert_eq!(state["values"]["min_weight"], "1/255");
    c.send(r#"{"type":"set","control":"min_weight","value":"0"}"#);
    assert_eq!(c.text("state")["values"]["min_weight"], "0");
    c.frame();
}

#[test]
fn a_message_too_big_to_read_closes_only_its_own_connection() {
    let s = server(64, 36);
    let mut other = Client::connect(&s);
    let mut c = Client::connect(&s);
    c.text("state");
    let huge = format!(r#"{{"type":"save","x":"{}"}}"#, "y".repeat(2 << 20));
    let _ = c.ws.send(Message::Text(huge.into()));
    let deadline = Instant::now() + PATIENCE;
    loop {
        match c.receive() {
            Received::Closed => break,
            _ => assert!(Instant::now() < deadline, "the connection stays open"),
        }
    }
    // The other tab and new tabs go on.
    other.frame();
    let mut again = Client::connect(&s);
    again.frame();
    assert_eq!(http(&s, "GET", "/").0, 200);
}

#[test]
fn a_camera_move_restarts_the_accumulation_and_changes_the_picture() {
    let s = server(96, 54);
    let mut c = Client::connect(&s);
    let (before, old) = c.frame_where(|h| h.spp >= 16);
    let rendered = s.frames_rendered();
    c.send(r#"{"type":"move","orbit":[40,10]}"#);
    let state = c.text("state");
    assert!(state["generation"].as_u64().unwrap() > before.generation);
    let (after, new) = c.frame_where(|h| h.generation > before.generation && !h.preview);
    // Restarted: the new image holds only frames rendered since the move (a slow reader
    // may see a later one than the first), never the old ones too.
    let since = s.frames_rendered() - rendered;
    assert!(
        after.spp as u64 <= since,
        "{} samples after the move, only {since} frames rendered since; {} before",
        after.spp,
        before.spp
    );
    let d = difference(&old, &new);
    assert!(d > 5.0, "the view moved, the picture differs by only {d}");
    // Back home: the picture is the old one again (frame k has seed k: equal at equal spp,
    // close at any two counts).
    c.send(r#"{"type":"reset_camera"}"#);
    let (_, home) = c.frame_where(|h| h.generation > after.generation && h.spp >= 16);
    let d = difference(&old, &home);
    assert!(d < 2.0, "reset differs by {d}");
}

/// Full frames of 960×540 on one thread take far longer than a preview's 25 ms budget on
/// any machine this runs on, so the first frame after a move is a smaller preview.
#[test]
fn after_a_move_a_slow_render_shows_a_preview_first() {
    let s = common::server_with_threads(960, 540, 1);
    let mut c = Client::connect(&s);
    let (full, _) = c.frame();
    assert!(!full.preview && full.width == 960);
    c.send(r#"{"type":"move","zoom":0.5}"#);
    let (preview, pixels) = c.frame_where(|h| h.generation > full.generation);
    assert!(preview.preview, "{preview:?}");
    assert_eq!(preview.display, [960, 540]);
    assert!(preview.width < 960 && preview.height < 540 && preview.width >= 8);
    assert_eq!(pixels.len(), (preview.width * preview.height * 4) as usize);
    assert_eq!(preview.spp, 0);
    let (next, _) = c.frame_where(|h| h.generation == preview.generation && !h.preview);
    assert_eq!((next.width, next.spp), (960, 1));
}

#[test]
fn controls_change_the_picture_and_save_sends_a_png() {
    let s = server(96, 54);
    let mut c = Client::connect(&s);
    let (image, pixels) = c.frame_where(|h| h.spp >= 2);
    c.send(r#"{"type":"set","control":"view","value":"cost"}"#);
    let (cost, heat) = c.frame_where(|h| h.view == "cost" && !h.preview);
    assert!(cost.generation > image.generation);
    assert!(difference(&pixels, &heat) > 10.0);
    c.send(r#"{"type":"set","control":"resolution","value":"80x40"}"#);
    let (small, p) = c.frame_where(|h| h.width == 80 && !h.preview);
    assert_eq!((small.height, p.len()), (40, 80 * 40 * 4));
    c.send(r#"{"type":"set","control":"accel","value":"kdtree"}"#);
    let state = c.text("state");
    assert_eq!(state["values"]["accel"], "kdtree");
    let generation = state["generation"].as_u64().unwrap();
    // Saving needs a full frame since the change; until then the answer is an error.
    c.frame_where(|h| h.generation == generation && !h.preview);
    c.send(r#"{"type":"save"}"#);
    let deadline = Instant::now() + PATIENCE;
    loop {
        assert!(Instant::now() < deadline, "no saved image");
        match c.receive() {
            Received::Text(v) if v["type"] == "error" => panic!("save refused: {v}"),
            Received::Binary(header, png) => {
                assert_eq!(header["kind"], "png");
                assert!(header["name"]
                    .as_str()
                    .unwrap()
                    .starts_with("prism-whitted-"));
                assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
                break;
            }
            _ => {}
        }
    }
    // Right after a change there is nothing to save yet.
    c.send(r#"{"type":"set","control":"depth","value":"4"}"#);
    c.send(r#"{"type":"save"}"#);
    loop {
        assert!(Instant::now() < deadline, "no answer to the early save");
        match c.receive() {
            Received::Text(v) if v["type"] == "error" => {
                assert!(
                    v["message"].as_str().unwrap().contains("no full frame"),
                    "{v}"
                );
                break;
            }
            // The frame may have finished before the save arrived: then it is saved.
            Received::Binary(header, _) if header["kind"] == "png" => break,
            _ => {}
        }
    }
}

/// The centre sampler traces the same rays every frame: one frame, then nothing more.
#[test]
fn the_centre_sampler_converges_after_one_frame() {
    let s = server(64, 36);
    let mut c = Client::connect(&s);
    c.frame();
    c.send(r#"{"type":"set","control":"sampler","value":"centre"}"#);
    let (done, _) = c.frame_where(|h| h.converged);
    assert_eq!(done.spp, 1);
    let count = s.frames_rendered();
    std::thread::sleep(Duration::from_millis(1000));
    assert_eq!(s.frames_rendered(), count, "rendered past convergence");
    c.send(r#"{"type":"set","control":"sampler","value":"jittered"}"#);
    c.frame_where(|h| !h.converged && h.spp >= 2);
}

#[test]
fn several_tabs_watch_one_render_and_steer_it_together() {
    let s = server(64, 36);
    let mut a = Client::connect(&s);
    let mut b = Client::connect(&s);
    let (fa, _) = a.frame();
    b.frame();
    b.send(r#"{"type":"set","control":"depth","value":"2"}"#);
    let state = a.text("state");
    assert_eq!(state["values"]["depth"], "2");
    let (fa2, _) = a.frame_where(|h| h.generation > fa.generation);
    assert!(fa2.generation > fa.generation);
}

/// The page's controls show the settings the server started with (the scene's, or
/// `prism serve --integrator path`'s): a path-traced scene shows `path`, not the first
/// integrator of the list. The beam tracer, which the viewer does not offer, is shown as
/// what the viewer renders in its place, Whitted's tracer.
#[test]
fn the_page_shows_the_settings_the_server_started_with() {
    use prism::options::IntegratorKind;
    for (scene, integrator, shown) in [
        ("cornell-light", None, "path"),
        ("whitted", Some(IntegratorKind::Path), "path"),
        ("whitted", Some(IntegratorKind::Beam), "whitted"),
    ] {
        let scene = prism::scene::builtin::find(scene).unwrap();
        let mut options = prism::RenderOptions {
            width: 64,
            height: 36,
            samples: 1,
            sampler: prism::sampling::SamplerKind::Random,
            max_depth: 3,
            ..scene.options.clone()
        };
        if let Some(kind) = integrator {
            options.integrator = kind;
        }
        let config = prism_serve::ServerConfig {
            bind: std::net::Ipv4Addr::LOCALHOST.into(),
            port: 0,
        };
        let s = prism_serve::Server::start(scene, "test", options, &config).unwrap();
        let mut c = Client::connect(&s);
        let state = c.text("state");
        assert_eq!(state["values"]["integrator"], shown, "{state}");
        assert_eq!(state["values"]["depth"], "3", "{state}");
        assert_eq!(state["values"]["sampler"], "random", "{state}");
        c.frame();
    }
}

/// A site whose name was made to resolve to 127.0.0.1 (DNS rebinding) sends its own name
/// as Host: refused, for the page and the WebSocket alike.
#[test]
fn requests_for_another_host_name_are_refused() {
    let s = server(32, 18);
    // The reply to a request for the page that names `host`.
    let page_for = |host: &str| {
        let mut stream = std::net::TcpStream::connect(s.addr()).unwrap();
        use std::io::{Read, Write};
        write!(
            stream,
            "GET / HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"
        )
        .unwrap();
        let mut reply = String::new();
        let _ = stream.read_to_string(&mut reply);
        reply
    };
    for host in [
        "evil.example",
        "evil.example:8000",
        "127.0.0.1.evil.example",
        "",
        "[::2]:80",
    ] {
        let reply = page_for(host);
        assert!(
            reply.starts_with("HTTP/1.1 403") || reply.starts_with("HTTP/1.1 400"),
            "{host}: {reply}"
        );
        assert!(!reply.contains("<canvas"), "{host}");
    }
    for host in [
        "localhost",
        "LOCALHOST:1234",
        "127.0.0.1",
        "127.0.0.2:80",
        "[::1]:8000",
    ] {
        let reply = page_for(host);
        assert!(reply.starts_with("HTTP/1.1 200"), "{host}: {reply}");
    }
    let evil = [("Host", "evil.example"), ("Origin", "http://evil.example")];
    assert!(!websocket_opens(&s, &evil));
}

/// Whether the viewer's WebSocket opens for a request with `headers` (beside the client's
/// own).
fn websocket_opens(s: &Server, headers: &[(&'static str, &str)]) -> bool {
    let mut request = format!("ws://{}/ws", s.addr())
        .into_client_request()
        .unwrap();
    for &(name, value) in headers {
        request.headers_mut().insert(name, value.parse().unwrap());
    }
    tungstenite::connect(request).is_ok()
}

#[test]
fn a_page_of_another_site_cannot_open_the_websocket() {
    let s = server(64, 36);
    assert!(
        !websocket_opens(&s, &[("Origin", "http://evil.example")]),
        "a foreign origin was let in"
    );
    let own = format!("http://{}", s.addr());
    assert!(websocket_opens(&s, &[("Origin", &own)]));
}

#[test]
fn rendering_stops_while_no_tab_is_open() {
    let s = server(160, 90);
    assert_eq!(s.frames_rendered(), 0, "nothing renders before a tab opens");
    let mut a = Client::connect(&s);
    let mut b = Client::connect(&s);
    a.frame();
    b.frame_where(|h| h.spp >= 2);
    a.ws.close(None).unwrap();
    b.ws.close(None).unwrap();
    drop((a, b));
    // The frame in flight may still finish; after that the count stands still.
    let settle = Instant::now() + PATIENCE;
    let mut count = s.frames_rendered();
    loop {
        std::thread::sleep(Duration::from_millis(1000));
        let now = s.frames_rendered();
        if now == count {
            break;
        }
        count = now;
        assert!(Instant::now() < settle, "still rendering with no tab open");
    }
    std::thread::sleep(Duration::from_millis(1500));
    assert_eq!(s.frames_rendered(), count, "rendered with no tab open");
    // A new tab sees the last frame at once, and starts the render again.
    let mut c = Client::connect(&s);
    let (last, _) = c.frame();
    c.frame_where(|h| h.spp > last.spp);
    assert!(s.frames_rendered() > count);
}

#[test]
fn pages_past_the_limit_are_told_and_turned_away() {
    let s = server(32, 18);
    let mut pages: Vec<Client> = (0..prism_serve::limits::MAX_CLIENTS)
        .map(|_| Client::connect(&s))
        .collect();
    for p in &mut pages {
        p.text("hello");
    }
    let mut extra = Client::connect(&s);
    let error = extra.text("error");
    assert!(error["message"].as_str().unwrap().contains("too many"));
    assert!(matches!(extra.receive(), Received::Closed));
    // A place comes free when a page closes.
    pages.pop().unwrap().ws.close(None).unwrap();
    let deadline = Instant::now() + PATIENCE;
    loop {
        let mut again = Client::connect(&s);
        match again.receive() {
            Received::Text(v) if v["type"] == "hello" => break,
            _ => assert!(Instant::now() < deadline, "no place came free"),
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}
