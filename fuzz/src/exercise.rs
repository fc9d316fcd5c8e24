//! What every target does with a parser's result: an error must say where it is; a scene
//! must be valid and must survive what rendering does with it (accelerator build, camera
//! setup, a few traced rays), since a loaded scene is handed to the renderer as it is.

use prism::accel::AccelSpec;
use prism::integrator::Whitted;
use prism::{Scene, Stats};
use prism_io::scene::LoadError;

/// The traced image is this many pixels on each side: enough to reach every shape kind's
/// intersection and shading code, few enough to keep executions fast.
const PIXELS: u32 = 3;
/// Ray-tree depth for the traced pixels. A scene may ask for up to 256 with every hit
/// spawning two rays (SPD rules), a cost that is the scene's, not a parser's, finding.
const MAX_DEPTH: u32 = 3;

/// What a target made of its input, for the replayer to print.
#[derive(Debug)]
pub enum Outcome {
    /// The scene, by its number of primitives (meshes count one per triangle) and lights.
    Parsed { primitives: usize, lights: usize },
    /// A material library's number of materials.
    Materials(usize),
    /// The parser's error message.
    Rejected(String),
}

/// Checks a parser's result; `text` is the input when it is text, to bound line numbers.
pub fn outcome(result: Result<Scene, LoadError>, text: Option<&str>) -> Outcome {
    match result {
        Ok(scene) => {
            render(&scene);
            Outcome::Parsed {
                primitives: scene.geometry.primitives.len(),
                lights: scene.lights.len(),
            }
        }
        Err(e) => {
            error(&e, text);
            Outcome::Rejected(e.to_string())
        }
    }
}

fn error(e: &LoadError, text: Option<&str>) {
    let message = e.to_string();
    assert!(!message.is_empty());
    if let LoadError::Syntax { line, column, .. } = *e {
        assert!(
            line >= 1 && column >= 1,
            "{message}: lines and columns count from 1"
        );
        if let Some(text) = text {
            // A file ending in a line break may be blamed at the start of the line after it.
            let lines = text.lines().count().max(1) + 1;
            assert!(line <= lines, "{message}: the text has {lines} lines");
        }
    }
}

fn render(scene: &Scene) {
    if let Err(e) = scene.validate() {
        panic!("a parser returned an invalid scene: {e}");
    }
    let mut options = scene.options.clone();
    options.width = PIXELS;
    options.height = PIXELS;
    options.samples = 1;
    options.threads = 1;
    options.max_depth = options.max_depth.min(MAX_DEPTH);
    let prepared = scene.prepare(&AccelSpec::default());
    let camera = match scene.camera.setup(options.width, options.height) {
        Ok(camera) => camera,
        Err(e) => panic!("a parser returned a scene whose camera cannot be set up: {e}"),
    };
    let whitted = Whitted::new(&prepared, &options);
    let mut stats = Stats::default();
    for y in 0..PIXELS {
        for x in 0..PIXELS {
            let ray = camera.ray(x as f32 + 0.5, y as f32 + 0.5);
            whitted.trace_camera_ray(&ray, &mut stats);
        }
    }
}
