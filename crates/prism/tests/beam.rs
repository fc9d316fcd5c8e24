//! The beam tracer (issue 15).

use prism::options::{IntegratorKind, RenderOptions};
use prism::render::render_beam;
use prism::scene::builtin;
use std::sync::atomic::AtomicBool;

#[test]
fn debug_checker() {
    let scene = builtin::find("checkerboard").unwrap();
    let prepared = scene.prepare(&Default::default());
    for (w, h, tol) in [(32, 18, 1e-2), (64, 36, 1e-3), (160, 90, 1e-4)] {
        let options = RenderOptions {
            width: w,
            height: h,
            integrator: IntegratorKind::Beam,
            ..scene.options.clone()
        };
        let t = std::time::Instant::now();
        let r = render_beam(&prepared, &options, tol, &|_| {}, &AtomicBool::new(false)).unwrap();
        eprintln!("{w}x{h} tol {tol}: {:?} {:?} bound {}", t.elapsed(), r.stats, r.error_bound());
    }
}
