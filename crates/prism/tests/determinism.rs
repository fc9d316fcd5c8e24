//! A render is a pure function of (scene, options, seed): the image must be bit-identical
//! and the statistics equal for any thread count and any tile size.

use prism::render::{render, RenderResult};
use prism::scene::builtin;
use prism::RenderOptions;
use std::sync::atomic::AtomicBool;

fn render_with(name: &str, threads: usize, tile_size: u32) -> RenderResult {
    let scene = builtin::find(name).unwrap();
    let options = RenderOptions {
        width: 97,
        height: 61,
        samples: 2,
        threads,
        tile_size,
        ..scene.options.clone()
    };
    let prepared = scene.prepare(&options.accel);
    render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap()
}

fn check(name: &str) {
    let reference = render_with(name, 1, 16);
    assert!(reference.complete);
    assert!(reference.stats.total_rays() > 0);
    let bits = |r: &RenderResult| -> Vec<u32> {
        r.film
            .pixels
            .iter()
            .flat_map(|c| [c.x.to_bits(), c.y.to_bits(), c.z.to_bits()])
            .collect()
    };
    let expected = bits(&reference);
    // Odd and prime tile sizes cut the image unevenly; 1 makes every pixel its own tile.
    for (threads, tile) in [(2, 16), (2, 7), (1, 64), (2, 1), (2, 200)] {
        let r = render_with(name, threads, tile);
        assert!(
            bits(&r) == expected,
            "{name}: image differs with {threads} threads and {tile}-pixel tiles"
        );
        assert_eq!(
            r.stats, reference.stats,
            "{name}: statistics differ with {threads} threads and {tile}-pixel tiles"
        );
    }
}

#[test]
fn whitted_is_deterministic() {
    check("whitted");
}

#[test]
fn sphereflake_is_deterministic() {
    check("sphereflake:2");
}
