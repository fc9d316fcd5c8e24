//! Sampling patterns on their own: points inside the pixel, one per stratum, the relaxed
//! pattern's blue-noise spacing, and that every pattern is a pure function of its inputs.

use prism::math::Vec2;
use prism::sampling::{PixelPattern, RelaxedTile, Sampler, SamplerKind};
use prism::RenderOptions;

fn offsets(pattern: &PixelPattern, x: u32, y: u32) -> Vec<Vec2> {
    let mut out = Vec::new();
    pattern.offsets(x, y, &mut out);
    out
}

fn pattern(kind: SamplerKind, n: u32, seed: u64) -> PixelPattern {
    let options = RenderOptions {
        sampler: kind,
        samples: n,
        seed,
        ..Default::default()
    };
    match Sampler::new(&options) {
        Sampler::Pixel(p) => p,
        other => panic!("{kind} is not a per-pixel pattern: {other:?}"),
    }
}

const PER_PIXEL: [SamplerKind; 5] = [
    SamplerKind::Centre,
    SamplerKind::Grid,
    SamplerKind::Random,
    SamplerKind::Jittered,
    SamplerKind::Relaxed,
];

#[test]
fn every_point_lies_strictly_inside_its_pixel() {
    for kind in PER_PIXEL {
        for n in [1, 2, 3, 5, 8] {
            let p = pattern(kind, n, 7);
            let expected = if kind == SamplerKind::Centre {
                1
            } else {
                n * n
            };
            assert_eq!(p.count(), expected, "{kind} {n}");
            for (x, y) in [(0, 0), (1, 0), (17, 3), (640, 480), (65535, 65535)] {
                let pts = offsets(&p, x, y);
                assert_eq!(pts.len() as u32, expected, "{kind} {n} at ({x}, {y})");
                for o in pts {
                    assert!(
                        o.x > 0.0 && o.x < 1.0 && o.y > 0.0 && o.y < 1.0,
                        "{kind} {n} at ({x}, {y}): {o}"
                    );
                }
            }
        }
    }
}

#[test]
fn jittered_puts_one_point_in_every_stratum() {
    for n in [1, 2, 4, 7, 16] {
        let p = pattern(SamplerKind::Jittered, n, 3);
        for (x, y) in [(0, 0), (5, 9), (1000, 2)] {
            let mut seen = vec![0u32; (n * n) as usize];
            for o in offsets(&p, x, y) {
                let stratum = |v: f32| {
                    (0..n)
                        .find(|&i| v >= i as f32 / n as f32 && v < (i + 1) as f32 / n as f32)
                        .expect("inside the pixel")
                };
                seen[(stratum(o.y) * n + stratum(o.x)) as usize] += 1;
            }
            assert!(seen.iter().all(|&c| c == 1), "n {n}: strata {seen:?}");
        }
    }
}

#[test]
fn grid_points_are_the_subpixel_centres() {
    let p = pattern(SamplerKind::Grid, 4, 0);
    let pts = offsets(&p, 3, 3);
    for (k, o) in pts.iter().enumerate() {
        let (i, j) = (k % 4, k / 4);
        assert_eq!(
            *o,
            Vec2::new((i as f32 + 0.5) / 4.0, (j as f32 + 0.5) / 4.0)
        );
    }
}

#[test]
fn random_patterns_differ_between_pixels_and_seeds_but_repeat_exactly() {
    for kind in [
        SamplerKind::Random,
        SamplerKind::Jittered,
        SamplerKind::Relaxed,
    ] {
        let a = pattern(kind, 3, 1);
        let b = pattern(kind, 3, 1);
        let c = pattern(kind, 3, 2);
        assert_eq!(
            offsets(&a, 10, 20),
            offsets(&b, 10, 20),
            "{kind}: repeatable"
        );
        assert_ne!(
            offsets(&a, 10, 20),
            offsets(&a, 11, 20),
            "{kind}: per pixel"
        );
        assert_ne!(offsets(&a, 10, 20), offsets(&c, 10, 20), "{kind}: per seed");
    }
}

/// Smallest distance between two points on a torus of side `period`.
fn min_distance(points: &[Vec2], period: f32) -> f32 {
    let mut m = f32::INFINITY;
    for i in 0..points.len() {
        for j in 0..i {
            let mut d = points[i] - points[j];
            d -= (d / period).round() * period;
            m = m.min(d.length());
        }
    }
    m
}

#[test]
fn relaxed_points_keep_a_blue_noise_distance_across_pixels_and_the_tile_edge() {
    // A hexagonal packing of N points per unit area has spacing 1.07/√N; relaxation gets
    // about half of that everywhere in its tile, pixel borders and wrap-around included,
    // where jittering leaves pairs almost touching.
    for n in [2, 4, 6] {
        let tile = RelaxedTile::new(n, 11);
        let k = tile.side() as f32;
        let relaxed = tile.tile_points();
        let spacing = min_distance(&relaxed, k) * n as f32;
        assert!(spacing > 0.4, "relaxed {n}×{n}: min distance {spacing}/√N");

        let jittered = pattern(SamplerKind::Jittered, n, 11);
        let mut points = Vec::new();
        for y in 0..tile.side() {
            for x in 0..tile.side() {
                points.extend(
                    offsets(&jittered, x, y)
                        .into_iter()
                        .map(|o| Vec2::new(x as f32, y as f32) + o),
                );
            }
        }
        let jitter_spacing = min_distance(&points, k) * n as f32;
        assert!(
            jitter_spacing < 0.2,
            "jittered {n}×{n} spacing {jitter_spacing}: the bound would not tell them apart"
        );
    }
}

#[test]
fn relaxed_blocks_show_the_tile_shifted_mirrored_or_transposed() {
    let tile = RelaxedTile::new(3, 5);
    let p = PixelPattern::Relaxed(tile.clone());
    let k = tile.side();
    // The eight symmetries of the square, as maps of a tile offset.
    let symmetries: [fn(Vec2) -> Vec2; 8] = [
        |o| o,
        |o| Vec2::new(1.0 - o.x, o.y),
        |o| Vec2::new(o.x, 1.0 - o.y),
        |o| Vec2::new(1.0 - o.x, 1.0 - o.y),
        |o| Vec2::new(o.y, o.x),
        |o| Vec2::new(1.0 - o.y, o.x),
        |o| Vec2::new(o.y, 1.0 - o.x),
        |o| Vec2::new(1.0 - o.y, 1.0 - o.x),
    ];
    let same = |a: &[Vec2], b: &[Vec2]| {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(u, v)| (*u - *v).abs().max_element() < 1e-5)
    };
    for (bx, by) in [(0, 0), (3, 2)] {
        let mut sources = Vec::new();
        for (x, y) in [
            (0, 0),
            (1, 0),
            (k - 1, 2),
            (5, 7),
            (2, k - 1),
            (k / 2, k / 2),
        ] {
            let (x, y) = (bx * k + x, by * k + y);
            let shown = offsets(&p, x, y);
            assert_eq!(shown.len(), 9, "3×3 points in pixel ({x}, {y})");
            let found = (0..k * k).find_map(|t| {
                let src = tile.tile_pixel(t % k, t / k);
                symmetries.iter().find_map(|f| {
                    let mapped: Vec<Vec2> = src.iter().map(|&o| f(o)).collect();
                    same(&mapped, &shown).then_some(t)
                })
            });
            let t = found.unwrap_or_else(|| panic!("pixel ({x}, {y}) shows no tile pixel"));
            sources.push(t);
        }
        sources.sort_unstable();
        sources.dedup();
        assert_eq!(
            sources.len(),
            6,
            "distinct pixels show distinct tile pixels"
        );
    }
    // Neighbouring blocks are arranged differently.
    assert_ne!(offsets(&p, 0, 0), offsets(&p, k, 0));
}
