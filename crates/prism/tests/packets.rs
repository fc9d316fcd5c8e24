//! Ray packets (`Accel::query_packet`): every ray of a packet gets exactly the answer its
//! own query gives (the same hit, bit for bit, for nearest-hit packets; the same
//! occluded/visible answer for any-hit packets), for coherent camera and shadow packets
//! that take the packet walk and for incoherent ones that fall back to single rays, with
//! both node widths and both packet kernels (AVX2, AVX-512), at 1e-3 and 1e3 scale; and
//! coherent packets do visit fewer nodes.

use crate::common;

use common::oracle::{random_triangles, TestScene};
use common::{film_bits, icosphere, Rng};
use prism::accel::{
    Accel, Avx512, Bvh, BvhOptions, Hit, NodeWidth, PacketQuery, QueryMode, RayQuery, PACKET_MAX,
};
use prism::geometry::{AaBox, Cone, Shape, Sphere};
use prism::math::{Ray, TraceRay, Vec3};
use prism::Stats;

/// Icospheres (closed meshes, packed leaves), loose triangles, spheres, boxes, cylinders and
/// cones (leaves of other shapes) in `[-2, 2]³ · scale + offset`.
fn scene(seed: u64, scale: f32, offset: Vec3) -> TestScene {
    let mut rng = Rng::new(seed);
    let mut s = TestScene::new();
    let p = |rng: &mut Rng| offset + scale * rng.point_in(Vec3::splat(-2.0), Vec3::splat(2.0));
    for _ in 0..6 {
        let c = p(&mut rng);
        s.add_mesh(icosphere(c, scale * rng.range(0.2, 0.7), 3));
    }
    let tris = random_triangles(&mut rng, 200, p, |rng| scale * rng.range(0.02, 0.5));
    s.add_triangles(&tris);
    for _ in 0..30 {
        let c = p(&mut rng);
        let r = scale * rng.range(0.05, 0.3);
        s.geometry.add(Shape::from(Sphere::new(c, r)), 0);
        s.features.push(c + Vec3::new(r, 0.0, 0.0));
    }
    for _ in 0..10 {
        let a = p(&mut rng);
        let b = a + scale * rng.point_in(Vec3::splat(0.05), Vec3::splat(0.6));
        s.add_box(AaBox::new(a, b));
    }
    // Cylinders (most of them open, as NFF's) and cones, some in small groups as SPD's
    // lattice and rings join theirs, so that leaves hold several.
    for k in 0..24 {
        let base = p(&mut rng);
        let axis = rng.unit_vector();
        let r = scale * rng.range(0.03, 0.2);
        let apex_radius = if k % 3 == 0 {
            r * rng.range(0.0, 0.9)
        } else {
            r
        };
        let length = scale * rng.range(0.3, 1.5);
        for j in 0..1 + k % 3 {
            let start = base + axis * length * j as f32;
            let cone = Cone::new(start, r, start + axis * length, apex_radius, k % 4 == 1);
            if let Some(cone) = cone {
                s.geometry.add(Shape::from(cone), 0);
                s.features.push(start + axis.any_orthonormal_vector() * r);
            }
        }
    }
    s
}

/// Camera rays of one `w` × `h` block of pixels of an image of `res` × `res` pixels seen
/// from `eye` toward `target`, block at pixel (x0, y0).
fn camera_block(
    eye: Vec3,
    target: Vec3,
    res: u32,
    (x0, y0, w, h): (u32, u32, u32, u32),
) -> Vec<TraceRay> {
    let forward = (target - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let half = (0.4f32).tan();
    let mut rays = Vec::new();
    for y in y0..y0 + h {
        for x in x0..x0 + w {
            let u = (2.0 * (x as f32 + 0.5) / res as f32 - 1.0) * half;
            let v = (1.0 - 2.0 * (y as f32 + 0.5) / res as f32) * half;
            let dir = (forward + u * right + v * up).normalize();
            rays.push(TraceRay::new(Ray::new(eye, dir)));
        }
    }
    rays
}

/// The rays themselves, as `query_packet` takes them (it prepares them in its own way).
fn plain(rays: &[TraceRay]) -> Vec<Ray> {
    rays.iter().map(|r| r.ray).collect()
}

/// Holds `accel`'s packet answers to its single-ray answers; returns the node visits of
/// the packet queries and of the single ones.
fn check_packet(
    what: &str,
    accel: &dyn Accel,
    s: &TestScene,
    rays: &[TraceRay],
    t_max: &[f32],
    mode: QueryMode,
) -> (u64, u64) {
    let g = &s.geometry;
    let mut answers = vec![None; rays.len()];
    let mut packet_stats = Stats::default();
    let plain_rays = plain(rays);
    let packet = PacketQuery::new(g, &plain_rays, t_max, mode);
    accel.query_packet(&packet, &mut answers, &mut packet_stats);
    let mut single_stats = Stats::default();
    for (i, (ray, &t)) in rays.iter().zip(t_max).enumerate() {
        let query = RayQuery::new(g, ray, t, mode);
        let single: Option<Hit> = accel.query(&query, &mut single_stats);
        match mode {
            QueryMode::Nearest => assert_eq!(
                answers[i],
                single,
                "{what}: ray {i} of {}: {:?}, t_max {t}",
                rays.len(),
                ray.ray
            ),
            // Any hit may stop at a different blocker; whether there is one is the answer.
            QueryMode::Any => assert_eq!(
                answers[i].is_some(),
                single.is_some(),
                "{what}: any-hit ray {i} of {}: {:?}, t_max {t}",
                rays.len(),
                ray.ray
            ),
        }
    }
    (packet_stats.node_visits, single_stats.node_visits)
}

fn settings() -> Vec<(&'static str, BvhOptions)> {
    vec![
        ("8-wide where the CPU allows", BvhOptions::default()),
        (
            "8-wide, AVX2 packet kernels even where AVX-512 is available",
            BvhOptions {
                avx512: Avx512::Off,
                ..BvhOptions::default()
            },
        ),
        (
            "4-wide",
            BvhOptions {
                width: NodeWidth::Four,
                ..BvhOptions::default()
            },
        ),
        (
            "one primitive per leaf",
            BvhOptions {
                max_leaf_size: 1,
                ..BvhOptions::default()
            },
        ),
        (
            "progressive hierarchical refinement",
            BvhOptions {
                builder: prism::accel::BvhBuilder::Phr,
                ..BvhOptions::default()
            },
        ),
    ]
}

fn check_scene(name: &str, scale: f32, offset: Vec3, seed: u64) {
    let s = scene(seed, scale, offset);
    let g = &s.geometry;
    let prims: Vec<u32> = (0..g.primitives.len() as u32).collect();
    let centre = offset;
    let mut rng = Rng::new(seed ^ 0x5eed);
    for (setting, options) in settings() {
        let bvh = Bvh::build(g, prims.clone(), &options);
        let what = |kind: &str| format!("{name}/{setting}/{kind}");
        let (mut packet_visits, mut single_visits) = (0, 0);
        // Camera blocks from outside the scene and from inside it, of every size up to the
        // largest packet, including odd shapes, over the whole image.
        let eyes = [
            centre + scale * Vec3::new(5.0, 2.5, 6.0),
            centre + scale * Vec3::new(-0.3, 0.2, 0.1),
        ];
        for eye in eyes {
            for (w, h) in [(8, 8), (4, 4), (2, 1), (5, 3), (1, 1)] {
                let res = 48;
                for y0 in (0..res - h + 1).step_by(h as usize * 3) {
                    for x0 in (0..res - w + 1).step_by(w as usize * 2) {
                        let rays = camera_block(eye, centre, res, (x0, y0, w, h));
                        assert!(rays.len() <= PACKET_MAX);
                        let inf = vec![f32::INFINITY; rays.len()];
                        let (p, s1) = check_packet(
                            &what("camera"),
                            &bvh,
                            &s,
                            &rays,
                            &inf,
                            QueryMode::Nearest,
                        );
                        packet_visits += p;
                        single_visits += s1;
                        // Bounded queries: each ray's own bound, some before its nearest
                        // hit, some exactly at it, some beyond.
                        let mut answers = vec![None; rays.len()];
                        let mut stats = Stats::default();
                        let plain_rays = plain(&rays);
                        let packet = PacketQuery::new(g, &plain_rays, &inf, QueryMode::Nearest);
                        bvh.query_packet(&packet, &mut answers, &mut stats);
                        let bounds: Vec<f32> = answers
                            .iter()
                            .map(|a| match (a, rng.below(3)) {
                                (Some(h), 0) => h.t,
                                (Some(h), 1) => h.t * rng.range(0.5, 1.5),
                                _ => scale * rng.range(0.0, 10.0),
                            })
                            .collect();
                        check_packet(
                            &what("bounded"),
                            &bvh,
                            &s,
                            &rays,
                            &bounds,
                            QueryMode::Nearest,
                        );
                        check_packet(&what("any-hit"), &bvh, &s, &rays, &bounds, QueryMode::Any);
                        // Shadow packets: from this block's hits to one light.
                        let light = centre + scale * Vec3::new(rng.range(-3.0, 3.0), 4.0, 1.0);
                        let (shadow, dist): (Vec<TraceRay>, Vec<f32>) = rays
                            .iter()
                            .zip(&answers)
                            .filter_map(|(r, a)| {
                                let p = r.ray.at(a.as_ref()?.t * 0.999);
                                let to = light - p;
                                let d = to.length();
                                Some((TraceRay::new(Ray::new(p, to / d)), d))
                            })
                            .unzip();
                        if !shadow.is_empty() {
                            check_packet(&what("shadow"), &bvh, &s, &shadow, &dist, QueryMode::Any);
                        }
                    }
                }
            }
        }
        // The packet walk must be the one taken: one visit per packet, not per ray.
        assert!(
            packet_visits * 2 < single_visits,
            "{name}/{setting}: packets visited {packet_visits} nodes, single rays {single_visits}"
        );
        // A camera packet across two axis planes of the view (the block at the image's
        // centre, looking down an axis): its rays run in four octants, sixteen in each,
        // and each octant's rays walk as a packet of their own.
        let eye = centre + scale * Vec3::new(0.0, 0.0, 6.0);
        let rays = camera_block(eye, centre, 48, (20, 20, 8, 8));
        let octants: std::collections::HashSet<[bool; 3]> = rays
            .iter()
            .map(|r| r.ray.dir.to_array().map(|d| d < 0.0))
            .collect();
        assert_eq!(
            octants.len(),
            4,
            "{name}/{setting}: the block spans four octants"
        );
        let inf = vec![f32::INFINITY; rays.len()];
        let (packet, single) = check_packet(
            &what("across axis planes"),
            &bvh,
            &s,
            &rays,
            &inf,
            QueryMode::Nearest,
        );
        assert!(
            packet * 2 < single,
            "{name}/{setting}: a packet across axis planes visited {packet} nodes, its rays \
             one by one {single}: its octants did not walk as packets"
        );
        check_packet(
            &what("across axis planes, any-hit"),
            &bvh,
            &s,
            &rays,
            &inf,
            QueryMode::Any,
        );
        // Camera packets across the diagonal plane where the dominant axis, and with it
        // the watertight test's axis permutation, changes (|x| = |z|): a leaf's triangles
        // are tested in lanes for each permutation's rays in turn.
        let eye = centre + scale * Vec3::new(-5.0, 0.3, 5.0);
        let mut across = 0;
        for x0 in [16, 20, 24] {
            let rays = camera_block(eye, centre, 48, (x0, 20, 8, 8));
            let kinds: std::collections::HashSet<usize> = rays.iter().map(|r| r.kz).collect();
            across += usize::from(kinds.len() > 1);
            for mode in [QueryMode::Nearest, QueryMode::Any] {
                check_packet(&what("across a diagonal"), &bvh, &s, &rays, &inf, mode);
            }
        }
        assert!(across > 0, "{name}: no block spans two dominant axes");
        // Incoherent packets (random origins and directions, axis-parallel rays with zero
        // components, a ray repeated) answer one ray at a time, still correctly.
        let bounds = g.world_bounds();
        for n in [2, 7, 16, 64] {
            let rays: Vec<TraceRay> = (0..n)
                .map(|k| {
                    let o = rng.point_in(bounds.min, bounds.max);
                    let d = match k % 3 {
                        0 => rng.unit_vector(),
                        1 => rng.axis_direction(),
                        _ => (s.features[rng.below(s.features.len())] - o).normalize(),
                    };
                    TraceRay::new(Ray::new(o, d))
                })
                .collect();
            let inf = vec![f32::INFINITY; n];
            check_packet(
                &what("incoherent"),
                &bvh,
                &s,
                &rays,
                &inf,
                QueryMode::Nearest,
            );
            check_packet(
                &what("incoherent any"),
                &bvh,
                &s,
                &rays,
                &inf,
                QueryMode::Any,
            );
            // Nearly parallel rays aimed at surface features: a coherent packet whose rays
            // graze edges and vertices.
            let eye = centre + scale * Vec3::new(4.0, -3.0, 5.0);
            let f = s.features[rng.below(s.features.len())];
            let rays: Vec<TraceRay> = (0..n)
                .map(|_| {
                    let jitter = scale * 1e-4 * rng.unit_vector();
                    TraceRay::new(Ray::new(eye, (f + jitter - eye).normalize()))
                })
                .collect();
            check_packet(&what("grazing"), &bvh, &s, &rays, &inf, QueryMode::Nearest);
        }
    }
}

#[test]
fn packets_answer_as_single_rays_do() {
    check_scene("unit", 1.0, Vec3::ZERO, 1);
}

#[test]
fn packets_answer_as_single_rays_do_at_small_scale() {
    check_scene("1e-3", 1e-3, Vec3::splat(2e-3), 2);
}

#[test]
fn packets_answer_as_single_rays_do_at_large_scale() {
    check_scene("1e3", 1e3, Vec3::new(4e3, -2e3, 1e3), 3);
}

/// Renders built-in `name` at a small size with packets on or off.
fn render_builtin(
    name: &str,
    packets: bool,
    tweak: impl Fn(&mut prism::RenderOptions),
) -> prism::render::RenderResult {
    let scene = prism::scene::builtin::find(name).unwrap();
    let mut options = prism::RenderOptions {
        width: 83,
        height: 45,
        threads: 2,
        packets,
        ..scene.options.clone()
    };
    tweak(&mut options);
    let prepared = scene.prepare(&options.accel);
    prism::render::render(
        &prepared,
        &options,
        &|_| {},
        &std::sync::atomic::AtomicBool::new(false),
    )
    .unwrap()
}

/// Every built-in renders bit-identically with and without packets at one sample per pixel
/// and traces the same rays (only the traversal work differs); the long tier adds several
/// samples per pixel, the corners and adaptive samplers, a wide filter and the 4-wide nodes.
#[test]
fn renders_are_identical_with_and_without_packets() {
    compare_renders_with_and_without_packets(1);
}

/// The built-ins rendered with and without packets under the first `count` variants of
/// sampler, filter and tree layout.
fn compare_renders_with_and_without_packets(count: usize) {
    use prism::render::FilterKind;
    use prism::sampling::SamplerKind;
    type Tweak = Box<dyn Fn(&mut prism::RenderOptions)>;
    let variants: Vec<(&str, Tweak)> = vec![
        ("1 spp", Box::new(|_| {})),
        (
            "jittered 3×3, Gaussian",
            Box::new(|o| {
                o.samples = 3;
                o.sampler = SamplerKind::Jittered;
                o.filter = FilterKind::Gaussian;
            }),
        ),
        ("corners", Box::new(|o| o.sampler = SamplerKind::Corners)),
        ("adaptive", Box::new(|o| o.sampler = SamplerKind::Adaptive)),
        (
            "AVX2 packet kernels only",
            Box::new(|o| o.accel = "bvh:avx512=off".parse().unwrap()),
        ),
        (
            "4-wide, tiles of 5",
            Box::new(|o| {
                o.accel = "bvh:width=4".parse().unwrap();
                o.tile_size = 5;
            }),
        ),
    ];
    for name in prism::scene::builtin::names() {
        for (label, tweak) in variants.iter().take(count) {
            let single = render_builtin(name, false, tweak);
            let packed = render_builtin(name, true, tweak);
            assert!(
                film_bits(&single.film) == film_bits(&packed.film),
                "{name} ({label}): packets change the image"
            );
            let (a, b) = (&single.stats, &packed.stats);
            assert_eq!(a.primary_rays, b.primary_rays, "{name} ({label})");
            assert_eq!(a.total_rays(), b.total_rays(), "{name} ({label})");
            assert_eq!(single.rays.camera, packed.rays.camera, "{name} ({label})");
            assert_eq!(single.rays.total, packed.rays.total, "{name} ({label})");
        }
    }
}

/// Minutes of CPU time between them, so the README's test command leaves them out:
/// `cargo test --release -- --ignored long_tier` runs them (.ci/run does).
mod long_tier {
    #[test]
    #[ignore = "long tier: every sampler, filter and layout variant"]
    fn renders_are_identical_with_and_without_packets_in_every_variant() {
        super::compare_renders_with_and_without_packets(usize::MAX);
    }
}
