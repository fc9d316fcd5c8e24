//! A render is a pure function of (scene, options, seed): the image must be bit-identical
//! and the statistics equal for any thread count and any tile size.

use crate::common::film_bits;
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
    let bits = |r: &RenderResult| film_bits(&r.film);
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

/// The image of `options` assembled from `render_region` pieces cut `edge` pixels square.
fn assembled(
    prepared: &prism::scene::PreparedScene,
    options: &RenderOptions,
    edge: u32,
) -> Vec<u32> {
    use prism::render::{render_region, Tile};
    let (w, h) = (options.width, options.height);
    let mut bits = vec![0u32; (w * h * 3) as usize];
    for y0 in (0..h).step_by(edge as usize) {
        for x0 in (0..w).step_by(edge as usize) {
            let region = Tile {
                x0,
                y0,
                x1: (x0 + edge).min(w),
                y1: (y0 + edge).min(h),
            };
            let r =
                render_region(prepared, options, region, &|_| {}, &AtomicBool::new(false)).unwrap();
            assert_eq!(
                (r.film.width, r.film.height),
                (region.width(), region.height())
            );
            assert_eq!(r.rays.camera.len(), region.pixel_count() as usize);
            for y in region.y0..region.y1 {
                for x in region.x0..region.x1 {
                    let c = r.film.get(x - x0, y - y0);
                    let i = ((y * w + x) * 3) as usize;
                    bits[i..i + 3].copy_from_slice(&[c.x.to_bits(), c.y.to_bits(), c.z.to_bits()]);
                }
            }
        }
    }
    bits
}

/// Regions of an image (how prism's Python package cuts a render for Dask) hold exactly
/// the whole render's pixels, with the one-pixel box filter and with filters whose reach
/// crosses the regions' edges, with and without packets, for both integrators.
#[test]
fn regions_assemble_into_the_whole_image() {
    use prism::render::FilterKind;
    let cases = [
        ("whitted", FilterKind::Box, None, true),
        ("whitted", FilterKind::Mitchell, None, true),
        ("whitted", FilterKind::Gaussian, None, false),
        ("whitted", FilterKind::Box, Some(1.0), true),
        ("cornell-light", FilterKind::Tent, None, false),
    ];
    for (name, filter, radius, packets) in cases {
        let scene = builtin::find(name).unwrap();
        let options = RenderOptions {
            width: 45,
            height: 31,
            samples: 2,
            filter,
            filter_radius: radius,
            packets,
            threads: 2,
            ..scene.options.clone()
        };
        let prepared = scene.prepare(&options.accel);
        let whole = render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap();
        let expected = film_bits(&whole.film);
        for edge in [1, 7, 16, 45] {
            assert!(
                assembled(&prepared, &options, edge) == expected,
                "{name}, {filter} filter, packets {packets}: {edge}-pixel regions differ"
            );
        }
    }
}

/// A region outside the image, or a part of it for the samplers that share samples
/// across the whole image, is refused with a message rather than rendered wrong.
#[test]
fn regions_that_cannot_be_rendered_are_refused() {
    use prism::render::{render_region, Tile};
    use prism::sampling::SamplerKind;
    let scene = builtin::find("whitted").unwrap();
    let options = RenderOptions {
        width: 20,
        height: 10,
        ..scene.options.clone()
    };
    let prepared = scene.prepare(&options.accel);
    let cancel = AtomicBool::new(false);
    let outside = Tile {
        x0: 10,
        y0: 0,
        x1: 21,
        y1: 10,
    };
    let e = render_region(&prepared, &options, outside, &|_| {}, &cancel)
        .err()
        .unwrap();
    assert!(e.to_string().contains("outside the 20×10 image"), "{e}");
    let empty = Tile {
        x0: 5,
        y0: 5,
        x1: 5,
        y1: 8,
    };
    assert!(render_region(&prepared, &options, empty, &|_| {}, &cancel).is_err());
    let adaptive = RenderOptions {
        sampler: SamplerKind::Adaptive,
        ..options.clone()
    };
    let part = Tile {
        x0: 0,
        y0: 0,
        x1: 10,
        y1: 10,
    };
    let e = render_region(&prepared, &adaptive, part, &|_| {}, &cancel)
        .err()
        .unwrap();
    assert!(e.to_string().contains("adaptive sampler"), "{e}");
    let all = Tile::full(20, 10);
    assert!(render_region(&prepared, &adaptive, all, &|_| {}, &cancel).is_ok());
}

/// Without per-pixel ray counts (`RenderOptions::per_pixel_rays` off, as `prism render`
/// runs without `--density` or `--cost`) a render gives the same image and statistics and
/// keeps no counts; with them, the counts add up to the statistics' rays. For the per-pixel
/// samplers (a box and a wider filter), the lattice samplers and the path tracer.
#[test]
fn ray_counts_are_optional_and_change_nothing_else() {
    let scene = builtin::find("whitted").unwrap();
    let base = RenderOptions {
        width: 67,
        height: 43,
        threads: 2,
        ..scene.options.clone()
    };
    let variants = [
        base.clone(),
        RenderOptions {
            filter: prism::render::FilterKind::Tent,
            ..base.clone()
        },
        RenderOptions {
            sampler: prism::sampling::SamplerKind::Corners,
            ..base.clone()
        },
        RenderOptions {
            sampler: prism::sampling::SamplerKind::Adaptive,
            ..base.clone()
        },
        RenderOptions {
            integrator: prism::options::IntegratorKind::Path,
            samples: 2,
            ..base.clone()
        },
    ];
    for (k, options) in variants.into_iter().enumerate() {
        let prepared = scene.prepare_for(&options);
        let run = |per_pixel_rays: bool| {
            let o = RenderOptions {
                per_pixel_rays,
                ..options.clone()
            };
            render(&prepared, &o, &|_| {}, &AtomicBool::new(false)).unwrap()
        };
        let (with, without) = (run(true), run(false));
        assert_eq!(with.film.pixels, without.film.pixels, "variant {k}");
        assert_eq!(with.stats, without.stats, "variant {k}");
        assert!(
            with.rays.is_recorded() && !without.rays.is_recorded(),
            "variant {k}"
        );
        assert!(without.rays.total.is_empty(), "variant {k}");
        let counted: u64 = with.rays.total.iter().map(|&t| u64::from(t)).sum();
        assert_eq!(counted, with.stats.total_rays(), "variant {k}");
    }
}
