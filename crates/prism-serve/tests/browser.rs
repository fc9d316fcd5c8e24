//! The viewer in a real browser: headless Chromium driven through chromedriver (WebDriver).
//! The page loads and draws frames, the image refines (consecutive frames differ less and
//! less), a mouse drag moves the view, a control changes the picture, and a screenshot is
//! kept in target/viewer-screenshot.png; a key zooms, **Save PNG** hands the browser a
//! PNG file to download, the picture scales with the window, and the page asks for no
//! favicon. Where Chromium or chromedriver is not installed
//! (Debian: `apt-get install chromium chromium-driver`) the test prints why it skips;
//! under CI, whose script installs them, it fails instead.

mod common;

use fantoccini::actions::{InputSource, MouseActions, PointerAction, MOUSE_BUTTON_LEFT};
use fantoccini::{Client, ClientBuilder, Locator};
use serde_json::{json, Value};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Generous: a loaded two-core machine may take seconds to start a browser.
const PATIENCE: Duration = Duration::from_secs(120);

/// The first of `names` found on the PATH.
fn find_program(names: &[&str]) -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .flat_map(|dir| names.iter().map(move |n| dir.join(n)))
        .find(|p| p.is_file())
}

/// chromedriver on a free port, ended when dropped.
struct Driver {
    child: Child,
    port: u16,
}

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn start_driver(program: &Path) -> Driver {
    let port = TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .expect("a free port")
        .port();
    let child = Command::new(program)
        .arg(format!("--port={port}"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("chromedriver starts");
    let driver = Driver { child, port };
    let deadline = Instant::now() + PATIENCE;
    while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(Instant::now() < deadline, "chromedriver never listened");
        std::thread::sleep(Duration::from_millis(100));
    }
    driver
}

/// Runs `script` (which returns a value, or null while not ready) until it returns
/// something other than null or false.
async fn poll(client: &Client, what: &str, script: &str) -> Value {
    let deadline = Instant::now() + PATIENCE;
    loop {
        let v = client
            .execute(script, vec![])
            .await
            .expect("the script runs");
        if !v.is_null() && v != json!(false) {
            return v;
        }
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        tokio::time::sleep(Duration::from_millis(50)).await;
    }
}

/// Waits for the next frame the page draws and returns its spp, generation and pixels
/// (every channel but alpha of every fourth pixel).
const NEXT_FRAME: &str = r#"
    const done = arguments[arguments.length - 1];
    const v = window.prismViewer;
    const start = v.frames;
    const timer = setInterval(() => {
        if (v.frames === start) return;
        clearInterval(timer);
        const c = document.getElementById("view");
        const data = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
        const pixels = [];
        for (let i = 0; i < data.length; i += 16) pixels.push(data[i], data[i + 1], data[i + 2]);
        done({ spp: v.header.spp, generation: v.header.generation, view: v.header.view, pixels });
    }, 2);
"#;

struct Frame {
    spp: u64,
    generation: u64,
    view: String,
    pixels: Vec<u8>,
}

async fn next_frame(client: &Client) -> Frame {
    let v = client
        .execute_async(NEXT_FRAME, vec![])
        .await
        .expect("a frame is drawn");
    Frame {
        spp: v["spp"].as_u64().unwrap(),
        generation: v["generation"].as_u64().unwrap(),
        view: v["view"].as_str().unwrap().to_string(),
        pixels: (v["pixels"].as_array().unwrap().iter())
            .map(|p| p.as_u64().unwrap() as u8)
            .collect(),
    }
}

/// The next frame for which `accept` holds.
async fn frame_where(client: &Client, what: &str, accept: impl Fn(&Frame) -> bool) -> Frame {
    let deadline = Instant::now() + PATIENCE;
    loop {
        let f = next_frame(client).await;
        if accept(&f) {
            return f;
        }
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
    }
}

fn difference(a: &Frame, b: &Frame) -> f64 {
    common::difference(&a.pixels, &b.pixels)
}

/// Where the picture is on screen: its scale (screen pixels per picture pixel, the same
/// across and down, as `object-fit: contain` draws it) and whether it lies inside the window.
#[derive(Debug)]
struct OnScreen {
    scale: f64,
    fits: bool,
}

async fn picture_on_screen(client: &Client) -> OnScreen {
    let v = client
        .execute(
            r#"const c = document.getElementById("view");
               const r = c.getBoundingClientRect();
               const scale = Math.min(r.width / c.width, r.height / c.height);
               const [w, h] = [c.width * scale, c.height * scale];
               const [left, top] = [r.left + (r.width - w) / 2, r.top + (r.height - h) / 2];
               return { scale, fits: left >= 0 && top >= 0 &&
                        left + w <= innerWidth + 0.5 && top + h <= innerHeight + 0.5 };"#,
            vec![],
        )
        .await
        .expect("the canvas's place");
    OnScreen {
        scale: v["scale"].as_f64().unwrap(),
        fits: v["fits"].as_bool().unwrap(),
    }
}

#[tokio::test(flavor = "current_thread")]
async fn the_page_refines_follows_the_mouse_and_the_controls() {
    let browser = find_program(&["chromium", "chromium-browser", "google-chrome"]);
    let driver = find_program(&["chromedriver"]);
    let (Some(browser), Some(driver)) = (browser, driver) else {
        let reason = "browser test skipped: chromium and chromedriver are not both on the \
                      PATH (Debian: apt-get install chromium chromium-driver)";
        assert!(
            std::env::var("CI").is_err(),
            "{reason}; CI's script installs them"
        );
        println!("{reason}");
        return;
    };
    let server = common::server(320, 180);
    let driver = start_driver(&driver);
    let capabilities = json!({
        "goog:chromeOptions": {
            "binary": browser,
            "args": ["--headless=new", "--no-sandbox", "--disable-gpu",
                     "--disable-dev-shm-usage", "--window-size=1000,520"],
        },
        "timeouts": { "script": PATIENCE.as_millis() as u64 },
    });
    let serde_json::Value::Object(capabilities) = capabilities else {
        unreachable!()
    };
    let connector = hyper_util::client::legacy::connect::HttpConnector::new();
    let client = ClientBuilder::new(connector)
        .capabilities(capabilities)
        .connect(&format!("http://127.0.0.1:{}", driver.port))
        .await
        .expect("a browser session");

    client.goto(&server.url()).await.expect("the page loads");
    poll(
        &client,
        "the first frame",
        "return window.prismViewer && window.prismViewer.frames > 0",
    )
    .await;
    let title = client.title().await.unwrap();
    assert_eq!(title, "prism viewer");

    // Refinement: two consecutive frames early on differ much more than two late ones.
    let a = next_frame(&client).await;
    let b = next_frame(&client).await;
    let early = difference(&a, &b);
    // Eight times the samples at least: the difference of two frames falls as 1/spp.
    let target = (8 * b.spp).max(32);
    let c = frame_where(&client, "8 times the samples", |f| f.spp >= target).await;
    let d = next_frame(&client).await;
    let late = difference(&c, &d);
    assert!(
        late < early * 0.5 && d.spp > c.spp,
        "frames {}→{} differ by {early:.3}, frames {}→{} by {late:.3}",
        a.spp,
        b.spp,
        c.spp,
        d.spp
    );

    // The screenshot: the refined picture in its page.
    let png = client.screenshot().await.expect("a screenshot");
    let target = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target");
    std::fs::create_dir_all(&target).unwrap();
    std::fs::write(target.join("viewer-screenshot.png"), png).unwrap();

    // A drag across the picture orbits the camera: a new generation, another picture.
    let canvas = client.find(Locator::Id("view")).await.unwrap();
    let before = next_frame(&client).await;
    let eye_before = client
        .execute("return window.prismViewer.state.camera.eye", vec![])
        .await
        .unwrap();
    let mut drag = MouseActions::new("mouse".to_string())
        .then(PointerAction::MoveToElement {
            element: canvas.clone(),
            duration: None,
            x: 0.0,
            y: 0.0,
        })
        .then(PointerAction::Down {
            button: MOUSE_BUTTON_LEFT,
        });
    for _ in 0..8 {
        drag = drag.then(PointerAction::MoveBy {
            duration: Some(Duration::from_millis(20)),
            x: 12.0,
            y: 2.0,
        });
    }
    drag = drag.then(PointerAction::Up {
        button: MOUSE_BUTTON_LEFT,
    });
    client.perform_actions(drag).await.expect("the drag");
    let after = frame_where(&client, "a frame after the drag", |f| {
        f.generation > before.generation && f.spp >= 2
    })
    .await;
    let moved = difference(&before, &after);
    assert!(
        moved > 3.0,
        "the drag changed the picture by only {moved:.3}"
    );
    let eye_after = client
        .execute("return window.prismViewer.state.camera.eye", vec![])
        .await
        .unwrap();
    assert_ne!(eye_before, eye_after, "the camera did not move");

    // A control: the cost view replaces the picture with a heat map.
    let view = client
        .find(Locator::Css("select[name=view]"))
        .await
        .unwrap();
    view.select_by_value("cost")
        .await
        .expect("the view control");
    let cost = frame_where(&client, "the cost view", |f| f.view == "cost").await;
    let changed = difference(&after, &cost);
    assert!(changed > 10.0, "the cost view differs by only {changed:.3}");
    // A key: `+` zooms in, a new generation.
    let before_key = next_frame(&client).await;
    let canvas = client.find(Locator::Id("view")).await.unwrap();
    canvas.send_keys("+").await.expect("a key press");
    frame_where(&client, "a frame after the key", |f| {
        f.generation > before_key.generation
    })
    .await;

    // Save: the page turns the server's PNG into a download. The blob and the anchor's
    // click are recorded instead of followed: the file's name and first bytes.
    client
        .execute(
            r#"const make = URL.createObjectURL;
               URL.createObjectURL = (blob) => { window.savedBlob = blob; return make(blob); };
               HTMLAnchorElement.prototype.click = function () {
                   const name = this.download;
                   window.savedBlob.arrayBuffer().then((b) => {
                       window.saved = { name, head: Array.from(new Uint8Array(b, 0, 8)) };
                   });
               };"#,
            vec![],
        )
        .await
        .unwrap();
    frame_where(&client, "a full frame to save", |f| f.spp >= 1).await;
    client
        .find(Locator::Id("save"))
        .await
        .unwrap()
        .click()
        .await
        .unwrap();
    let saved = poll(&client, "the saved image", "return window.saved || null").await;
    assert!(saved["name"].as_str().unwrap().ends_with(".png"), "{saved}");
    assert_eq!(
        saved["head"],
        json!([137, 80, 78, 71, 13, 10, 26, 10]),
        "a PNG signature"
    );

    // The picture fills the window whatever its pixel size, keeping its aspect ratio, and
    // follows the window when it shrinks. Before this, a 320 × 180 picture stayed 320 ×
    // 180 on screen.
    let wide = picture_on_screen(&client).await;
    assert!(wide.scale > 1.5, "the picture is not scaled up: {wide:?}");
    assert!(wide.fits, "the picture runs past the window: {wide:?}");
    client
        .set_window_size(640, 900)
        .await
        .expect("a smaller window");
    let narrow = poll(
        &client,
        "the layout of the smaller window",
        "return innerWidth < 700 ? true : null",
    )
    .await;
    assert_eq!(narrow, json!(true));
    let narrow = picture_on_screen(&client).await;
    assert!(
        narrow.scale < wide.scale && narrow.fits,
        "the picture does not follow the window: {wide:?}, then {narrow:?}"
    );
    // The page names its icon, so the browser asks the server for no /favicon.ico (a 404).
    let icon = client
        .execute(
            r#"const l = document.querySelector('link[rel~="icon"]');
               return l ? l.getAttribute("href") : null"#,
            vec![],
        )
        .await
        .unwrap();
    assert!(
        icon.as_str().is_some_and(|h| h.starts_with("data:")),
        "the page's icon: {icon}"
    );

    let errors = client
        .execute("return window.prismViewer.errors", vec![])
        .await
        .unwrap();
    assert_eq!(errors, json!([]), "the page was told of errors");

    client.close().await.unwrap();
}
