//! The render thread: it owns the scene, its accelerator, the settings and the
//! [`Frames`], applies the commands the pages send, and publishes every frame to all
//! of them. It renders only while at least one page is connected and the image has not
//! converged; otherwise it sleeps on its command channel and uses no CPU.
//!
//! A camera move or a setting sets `cancel`, so the frame in flight stops after its bands
//! in flight and the next frame starts from the new state. The flag is cleared before the
//! commands are read, so a command is never lost; at worst a move that lands between the
//! two cancels one frame that already shows it.

use crate::controls::{self, Setting, View};
use crate::limits::{MAX_MESSAGE_BYTES, MAX_PIXELS, MAX_SAMPLES, MAX_SIDE};
use crate::picture::{self, Encoder};
use crate::protocol::{self, CameraInfo, FrameHeader, LimitsInfo, SaveHeader, ServerMessage};
use crate::source::{Advance, Frames};
use crate::steer::{self, Motion};
use axum::body::Bytes;
use prism::accel::SceneIntersector;
use prism::camera::Camera;
use prism::render::RenderError;
use prism::sampling::SamplerKind;
use prism::scene::PreparedScene;
use prism::{RenderOptions, Scene};
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::{broadcast, oneshot, watch};

/// What a page asks the render thread for.
pub(crate) enum Command {
    /// A page connected.
    Join,
    /// A page left.
    Leave,
    /// Camera motion, checked when applied (the result must render).
    Move(Motion),
    /// A whole camera, already checked.
    Camera(Camera),
    /// Back to the scene's camera.
    ResetCamera,
    /// A checked setting.
    Set(Setting),
    /// The current image as a binary save message (header and PNG), or why not.
    Save(oneshot::Sender<Result<Bytes, String>>),
}

/// Counters and flags the render thread shares with the pages and the server's handle.
#[derive(Default)]
pub(crate) struct Shared {
    /// Stops the frame in flight.
    pub(crate) cancel: AtomicBool,
    /// Frames published since the start.
    pub(crate) frames: AtomicU64,
    /// Pages connected now.
    pub(crate) clients: std::sync::atomic::AtomicUsize,
}

/// The render thread as the pages see it: where to send commands, and where frames, state
/// and events appear.
#[derive(Clone)]
pub(crate) struct Link {
    pub(crate) commands: mpsc::Sender<Command>,
    /// The latest frame (a binary message), None before the first.
    pub(crate) frames: watch::Receiver<Option<Bytes>>,
    /// The latest state message (JSON).
    pub(crate) state: watch::Receiver<String>,
    /// Messages for every page (errors of the render thread).
    pub(crate) events: broadcast::Sender<String>,
    /// The hello message (JSON).
    pub(crate) hello: Arc<str>,
    pub(crate) shared: Arc<Shared>,
}

/// Starts the render thread for `scene` with `options`; `name` is the scene's name for the
/// page. The thread ends when every `Link` (and so every command sender) is gone.
pub(crate) fn start(
    scene: Scene,
    name: &str,
    options: RenderOptions,
) -> std::io::Result<(Link, std::thread::JoinHandle<()>)> {
    let (commands, rx) = mpsc::channel();
    let (frames_tx, frames) = watch::channel(None);
    let shared = Arc::new(Shared::default());
    let hello = ServerMessage::Hello {
        scene: name.to_string(),
        controls: controls::controls(),
        limits: LimitsInfo {
            message_bytes: MAX_MESSAGE_BYTES,
            side: MAX_SIDE,
            pixels: MAX_PIXELS,
            samples: MAX_SAMPLES,
        },
    }
    .to_json();
    let (events, _) = broadcast::channel(16);
    let mut engine = Engine::new(
        scene,
        name,
        options,
        frames_tx,
        events.clone(),
        shared.clone(),
    );
    let (state_tx, state) = watch::channel(engine.state());
    engine.state_tx = Some(state_tx);
    let thread = std::thread::Builder::new()
        .name("prism-serve render".into())
        .spawn(move || engine.run(rx))?;
    let link = Link {
        commands,
        frames,
        state,
        events,
        hello: hello.into(),
        shared,
    };
    Ok((link, thread))
}

/// The scene and its accelerator. The accelerator is lent to a `PreparedScene` for each
/// frame, so that a camera move (a change of `scene`) needs no rebuild.
struct Stage {
    scene: Scene,
    intersector: Option<SceneIntersector>,
    has_transmissive: bool,
}

impl Stage {
    /// One frame of `source` with `options`.
    fn advance(
        &mut self,
        source: &mut Frames,
        options: &RenderOptions,
        cancel: &AtomicBool,
    ) -> Result<Option<Advance>, RenderError> {
        let prepared = PreparedScene {
            scene: &self.scene,
            intersector: (self.intersector.take()).expect("the accelerator is home between frames"),
            build_time: Duration::ZERO,
            has_transmissive: self.has_transmissive,
        };
        let result = source.advance(&prepared, options, cancel);
        self.intersector = Some(prepared.intersector);
        result
    }
}

struct Engine {
    stage: Stage,
    name: String,
    /// The scene's own camera, for reset and the zoom range.
    home: Camera,
    options: RenderOptions,
    view: View,
    source: Frames,
    encoder: Encoder,
    generation: u64,
    clients: usize,
    /// The last frame's figures: render time and rays per second.
    last: (Duration, f64),
    /// Render time per pixel of the last full-resolution frame, which sizes the previews
    /// (per pixel, so that a change of resolution scales it).
    last_full_per_pixel: f64,
    /// The next frame is the first after a change: a preview if full frames are slow.
    preview_due: bool,
    /// The render failed with these settings; wait for a change.
    failed: bool,
    frames_tx: watch::Sender<Option<Bytes>>,
    state_tx: Option<watch::Sender<String>>,
    events: broadcast::Sender<String>,
    shared: Arc<Shared>,
}

impl Engine {
    fn new(
        scene: Scene,
        name: &str,
        mut options: RenderOptions,
        frames_tx: watch::Sender<Option<Bytes>>,
        events: broadcast::Sender<String>,
        shared: Arc<Shared>,
    ) -> Self {
        // The viewer traces camera rays: an integrator it does not offer (the beam tracer,
        // which renders whole beams) would give its camera rays to Whitted's tracer, so
        // that is what the page shows and renders.
        if !controls::INTEGRATORS.contains(&options.integrator.name()) {
            options.integrator = prism::options::IntegratorKind::Whitted;
        }
        let mut engine = Engine {
            home: scene.camera,
            stage: Stage {
                scene,
                intersector: None,
                has_transmissive: false,
            },
            name: name.to_string(),
            view: View::Image,
            source: Frames::new(),
            encoder: Encoder::new(options.transfer),
            options,
            generation: 0,
            clients: 0,
            last: (Duration::ZERO, 0.0),
            last_full_per_pixel: 0.0,
            preview_due: false,
            failed: false,
            frames_tx,
            state_tx: None,
            events,
            shared,
        };
        engine.rebuild();
        engine
    }

    /// Builds the accelerator the options name, for their integrator.
    fn rebuild(&mut self) {
        let stage = &mut self.stage;
        stage.intersector = None;
        let prepared = stage.scene.prepare_for(&self.options);
        stage.has_transmissive = prepared.has_transmissive;
        stage.intersector = Some(prepared.intersector);
    }

    fn run(mut self, rx: Receiver<Command>) {
        loop {
            let idle = self.clients == 0 || self.failed || self.converged();
            if idle {
                // Nothing to do until a page says something: sleep on the channel.
                match rx.recv() {
                    Ok(command) => self.apply(command),
                    Err(_) => return,
                }
            }
            self.shared.cancel.store(false, Ordering::SeqCst);
            loop {
                match rx.try_recv() {
                    Ok(command) => self.apply(command),
                    Err(TryRecvError::Empty) => break,
                    Err(TryRecvError::Disconnected) => return,
                }
            }
            if self.clients == 0 || self.failed || self.converged() {
                continue;
            }
            self.frame();
        }
    }

    /// Whether more frames would not change the image: the sample limit, or one frame of
    /// the centre sampler, whose every frame traces the same rays.
    fn converged(&self) -> bool {
        let limit = match self.options.sampler {
            SamplerKind::Centre => 1,
            _ => MAX_SAMPLES,
        };
        self.source.samples() >= limit
    }

    /// Renders one frame and publishes it: a preview after a change when full frames are
    /// slow, otherwise one more sample per pixel.
    fn frame(&mut self) {
        if std::mem::take(&mut self.preview_due) {
            let pixels = self.options.width as f64 * self.options.height as f64;
            let expected = Duration::from_secs_f64(self.last_full_per_pixel * pixels);
            if let Some(scale) = preview_scale(expected) {
                self.preview(scale);
                return;
            }
        }
        let result = (self.stage).advance(&mut self.source, &self.options, &self.shared.cancel);
        if let Some(advance) = self.settle(result) {
            let pixels = self.options.width as f64 * self.options.height as f64;
            self.last_full_per_pixel = advance.time.as_secs_f64() / pixels;
            let image = self.source.image().expect("a frame was just added");
            let (width, height, rgba) = picture::rgba(image, self.view, &mut self.encoder);
            self.publish(advance, width, height, &rgba, false);
        }
    }

    /// The first frame after a change, at `scale` of the resolution each way: a fraction of
    /// a full frame's rays, so the page shows the new view at once; the browser scales it
    /// up. Its samples are not kept: the accumulation starts with the next full frame.
    fn preview(&mut self, scale: f64) {
        let side = |n: u32| ((n as f64 * scale).round() as u32).clamp(8, n);
        let options = RenderOptions {
            width: side(self.options.width),
            height: side(self.options.height),
            ..self.options.clone()
        };
        let mut small = Frames::new();
        let result = self
            .stage
            .advance(&mut small, &options, &self.shared.cancel);
        if let Some(advance) = self.settle(result) {
            let image = small.image().expect("a frame was just added");
            let (width, height, rgba) = picture::rgba(image, self.view, &mut self.encoder);
            self.publish(advance, width, height, &rgba, true);
        }
    }

    /// The frame a render made; None when it was cancelled or failed (the pages are told
    /// of a failure, and rendering waits for a change).
    fn settle(&mut self, result: Result<Option<Advance>, RenderError>) -> Option<Advance> {
        result.unwrap_or_else(|e| {
            self.failed = true;
            self.event(format!(
                "the render failed: {e}; change a setting to try again"
            ));
            None
        })
    }

    /// Sends a frame to every page; `advance` is what its render did.
    fn publish(&mut self, advance: Advance, width: u32, height: u32, rgba: &[u8], preview: bool) {
        let seconds = advance.time.as_secs_f64().max(1e-9);
        self.last = (advance.time, advance.rays as f64 / seconds);
        let header = FrameHeader {
            kind: "frame".into(),
            width,
            height,
            display: [self.options.width, self.options.height],
            preview,
            spp: if preview { 0 } else { self.source.samples() },
            generation: self.generation,
            frame_ms: self.last.0.as_secs_f64() * 1e3,
            rays_per_s: self.last.1,
            view: self.view.name().into(),
            converged: self.converged(),
        };
        // Counted before it is sent: a page that has the frame must find it counted (the
        // other order let a test's client see the frame while the count still lagged).
        self.shared.frames.fetch_add(1, Ordering::SeqCst);
        self.frames_tx
            .send_replace(Some(protocol::binary(&header, rgba).into()));
    }

    /// The current accumulation again, as it is (after a change of view).
    fn republish(&mut self) {
        let Some(image) = self.source.image() else {
            return;
        };
        let (width, height, rgba) = picture::rgba(image, self.view, &mut self.encoder);
        let advance = Advance {
            rays: (self.last.1 * self.last.0.as_secs_f64()) as u64,
            time: self.last.0,
        };
        self.publish(advance, width, height, &rgba, false);
    }

    fn event(&self, message: String) {
        // No receivers means no pages: nobody to tell.
        let _ = self.events.send(ServerMessage::Error { message }.to_json());
    }

    fn apply(&mut self, command: Command) {
        match command {
            Command::Join => self.clients += 1,
            Command::Leave => self.clients = self.clients.saturating_sub(1),
            Command::Move(motion) => {
                match steer::apply(&self.stage.scene.camera, &self.home, &motion) {
                    Ok(camera) => self.set_camera(camera),
                    Err(e) => self.event(format!("camera not moved: {e}")),
                }
            }
            Command::Camera(camera) => self.set_camera(camera),
            Command::ResetCamera => self.set_camera(self.home),
            Command::Set(setting) => self.set(setting),
            Command::Save(reply) => {
                let Some(image) = self.source.image() else {
                    let why = "no full frame since the last change yet; try again in a moment";
                    let _ = reply.send(Err(why.to_string()));
                    return;
                };
                let message = picture::png(image, self.view).map(|png| {
                    let header = SaveHeader {
                        kind: "png".into(),
                        name: format!(
                            "prism-{}-{}spp.png",
                            file_stem(&self.name),
                            self.source.samples()
                        ),
                    };
                    Bytes::from(protocol::binary(&header, &png))
                });
                // The page may have gone meanwhile.
                let _ = reply.send(message);
            }
        }
    }

    fn set_camera(&mut self, camera: Camera) {
        self.stage.scene.camera = camera;
        self.changed(true);
    }

    fn set(&mut self, setting: Setting) {
        let restart = !matches!(setting, Setting::View(_));
        if let Setting::View(view) = setting {
            self.view = view;
        }
        // A new accelerator, or a BVH left at rays=auto under another integrator, whose
        // rays it is built for, is built anew.
        let built = self.options.accel_to_build();
        setting.apply(&mut self.options);
        if self.options.accel_to_build() != built {
            self.rebuild();
        }
        self.changed(restart);
        if !restart && self.source.samples() > 0 {
            // Same samples, another picture of them: show it now, even when converged.
            self.republish();
        }
    }

    /// After any change: a new generation, every page told, and (unless only the view
    /// changed) the accumulation restarted.
    fn changed(&mut self, restart: bool) {
        self.generation += 1;
        self.failed = false;
        if restart {
            self.source.reset();
            self.preview_due = true;
        }
        let state = self.state();
        if let Some(tx) = &self.state_tx {
            tx.send_replace(state);
        }
    }

    /// The state message: every control's value and the camera.
    fn state(&self) -> String {
        let o = &self.options;
        let values: BTreeMap<String, String> = [
            ("integrator", o.integrator.to_string()),
            ("accel", o.accel.to_string()),
            ("sampler", o.sampler.to_string()),
            ("depth", o.max_depth.to_string()),
            ("min_weight", crate::controls::weight_text(o.min_weight)),
            ("shadows", o.shadows.to_string()),
            ("view", self.view.name().to_string()),
            ("resolution", format!("{}x{}", o.width, o.height)),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect();
        let c = &self.stage.scene.camera;
        ServerMessage::State {
            values,
            camera: CameraInfo {
                eye: c.eye.to_array(),
                look_at: c.look_at.to_array(),
                up: c.up.to_array(),
                fov: c.fov_degrees,
            },
            generation: self.generation,
        }
        .to_json()
    }
}

/// How long a preview may take: a frame within it shows a move at once, at 60 Hz of
/// mouse events.
const PREVIEW_TIME: Duration = Duration::from_millis(25);

/// The slowest full frame that follows a change without a preview. A full frame reaches
/// the page a band in flight, the encoding and the message after its render, up to a
/// fifth more, and its time swings by as much on a shared machine: frames of 41 ms put the
/// first frame after a move at 46 ms (median) and 52 ms (90th percentile), over the 50 ms
/// a move should take to show.
const FULL_FRAME_FAST_ENOUGH: Duration = Duration::from_millis(30);

/// The scale of a preview after a change, each way, from the last full frame's render
/// time: rays are in proportion to pixels, so √(PREVIEW_TIME / last) renders in about
/// PREVIEW_TIME; between 1/8 (fewer pixels show nothing) and 1/2 (more saves too little to
/// be worth a frame that is thrown away). None when full frames are fast enough already
/// (and before the first, when nothing is known).
fn preview_scale(last_full: Duration) -> Option<f64> {
    if last_full <= FULL_FRAME_FAST_ENOUGH {
        return None;
    }
    let ratio = PREVIEW_TIME.as_secs_f64() / last_full.as_secs_f64();
    Some(ratio.sqrt().clamp(0.125, 0.5))
}

/// A scene name as a safe file name part: `builtin:whitted` → `whitted`, a path → its stem.
fn file_stem(name: &str) -> String {
    let last = name.rsplit(['/', '\\', ':']).next().unwrap_or(name);
    let stem = last.split('.').next().unwrap_or(last);
    let safe: String = stem
        .chars()
        .filter(|c| c.is_ascii_alphanumeric() || *c == '-' || *c == '_')
        .take(40)
        .collect();
    if safe.is_empty() {
        "scene".into()
    } else {
        safe
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn previews_come_only_for_slow_frames_and_take_about_their_budget() {
        assert_eq!(preview_scale(Duration::from_millis(20)), None);
        assert_eq!(preview_scale(Duration::from_millis(30)), None);
        // Frames a little slower than that would land near the 50 ms a move may take.
        assert_eq!(preview_scale(Duration::from_millis(31)), Some(0.5));
        assert_eq!(preview_scale(Duration::from_millis(41)), Some(0.5));
        assert_eq!(preview_scale(Duration::from_millis(60)), Some(0.5));
        let s = preview_scale(Duration::from_millis(400)).unwrap();
        assert!((s - 0.25).abs() < 1e-9, "{s}");
        assert_eq!(preview_scale(Duration::from_secs(100)), Some(0.125));
        // Before the first full frame nothing is known: no preview.
        assert_eq!(preview_scale(Duration::ZERO), None);
    }
}
