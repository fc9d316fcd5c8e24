//! Running a method over a ray set on 1 or more threads, timing it, and comparing answers.

use crate::embree;
use crate::workload::RaySet;
use prism::accel::SceneIntersector;
use prism::geometry::Geometry;
use prism::Stats;
use prism_lab::bench::Clock;
use std::sync::Mutex;
use std::time::Duration;

/// Rays handed to a thread at a time: a multiple of 256, so a chunk holds whole tiles
/// and packets never straddle two chunks; small enough that two threads finish together.
const CHUNK: usize = 4096;

/// What traces the rays.
pub enum Method<'a> {
    /// prism's default BVH through its public single-ray API.
    Prism(&'a SceneIntersector, &'a Geometry),
    /// Another of prism's BVH builders (`bvh:build=NAME`), single rays as `Prism`.
    PrismBuilder(&'a SceneIntersector, &'a Geometry, &'a str),
    /// The same through its packet API (`intersect_packet`, `occluded_packet`), this many
    /// consecutive rays to a packet.
    PrismPackets(&'a SceneIntersector, &'a Geometry, usize),
    Embree(&'a embree::Scene<'a>, embree::Quality, embree::Width),
}

impl Method<'_> {
    pub fn label(&self) -> String {
        match self {
            Method::Prism(..) => "prism".into(),
            Method::PrismBuilder(_, _, name) => format!("prism-{name}"),
            Method::PrismPackets(_, _, n) => format!("prism-p{n}"),
            Method::Embree(_, q, w) => {
                let q = match q {
                    embree::Quality::Medium => "M",
                    embree::Quality::High => "H",
                };
                format!("embree-{q}{}", w.lanes())
            }
        }
    }

    /// Traces `set`'s rays `start..start + len` into the matching slice of the answers.
    fn trace(&self, set: &RaySet, job: Job<'_>) {
        let range = job.start..job.start + job.len();
        match *self {
            Method::Prism(intersector, geometry)
            | Method::PrismBuilder(intersector, geometry, _) => {
                let mut stats = Stats::default();
                for (k, i) in range.enumerate() {
                    let (ray, t_max) = (&set.rays[i], set.t_max[i]);
                    if set.any_hit {
                        job.hit[k] = intersector.occluded(geometry, ray, t_max, &mut stats) as u8;
                    } else {
                        let hit = intersector.intersect(geometry, ray, t_max, &mut stats);
                        job.t[k] = hit.map_or(f32::INFINITY, |h| h.t);
                        job.prim[k] = hit.map_or(u32::MAX, |h| h.prim);
                    }
                }
            }
            Method::PrismPackets(intersector, geometry, lanes) => {
                let mut stats = Stats::default();
                let mut start = 0;
                while start < range.len() {
                    let end = (start + lanes).min(range.len());
                    let i = range.start + start..range.start + end;
                    let rays = &set.rays[i.clone()];
                    if set.any_hit {
                        let mut blocked = [false; prism::accel::PACKET_MAX];
                        let n = rays.len();
                        intersector.occluded_packet(
                            geometry,
                            rays,
                            &set.t_max[i],
                            &mut blocked[..n],
                            &mut stats,
                        );
                        for (k, b) in blocked[..n].iter().enumerate() {
                            job.hit[start + k] = *b as u8;
                        }
                    } else {
                        let mut hits = [None; prism::accel::PACKET_MAX];
                        let n = rays.len();
                        // Every ray of a set shares one bound in nearest-hit sets.
                        let t_max = set.t_max[i.start];
                        intersector.intersect_packet(
                            geometry,
                            rays,
                            t_max,
                            &mut hits[..n],
                            &mut stats,
                        );
                        for (k, hit) in hits[..n].iter().enumerate() {
                            job.t[start + k] = hit.map_or(f32::INFINITY, |h| h.t);
                            job.prim[start + k] = hit.map_or(u32::MAX, |h| h.prim);
                        }
                    }
                    start = end;
                }
            }
            Method::Embree(scene, _, width) => {
                let rays = &set.embree[range];
                if set.any_hit {
                    scene.occluded(width, set.coherent, rays, job.hit);
                } else {
                    scene.intersect(width, set.coherent, rays, job.t, job.prim);
                }
            }
        }
    }
}

/// Every ray's answer: `t` and `prim` for nearest-hit sets, `hit` for any-hit sets.
#[derive(Clone, Default)]
pub struct Answers {
    pub t: Vec<f32>,
    pub prim: Vec<u32>,
    pub hit: Vec<u8>,
}

impl Answers {
    pub fn for_set(set: &RaySet) -> Self {
        let n = set.len();
        if set.any_hit {
            Answers {
                hit: vec![0; n],
                ..Answers::default()
            }
        } else {
            Answers {
                t: vec![0.0; n],
                prim: vec![0; n],
                hit: Vec::new(),
            }
        }
    }

    pub fn hits(&self) -> usize {
        self.t.iter().filter(|t| t.is_finite()).count()
            + self.hit.iter().filter(|&&h| h != 0).count()
    }

    /// Sum of hit distances (any-hit sets have none: 0).
    pub fn checksum(&self) -> f64 {
        self.t
            .iter()
            .filter(|t| t.is_finite())
            .map(|&t| t as f64)
            .sum()
    }

    /// Rays whose answers differ from `other`'s: one hits and the other misses, or both
    /// hit at distances more than 10⁻⁴ apart (relative).
    pub fn differ(&self, other: &Answers) -> usize {
        let t = self.t.iter().zip(&other.t).filter(|(&a, &b)| {
            a.is_finite() != b.is_finite()
                || (a.is_finite() && (a - b).abs() > 1e-4 * a.abs().max(1.0))
        });
        let hit = self.hit.iter().zip(&other.hit).filter(|(a, b)| a != b);
        t.count() + hit.count()
    }
}

/// A disjoint piece of the answers, for one thread.
struct Job<'o> {
    start: usize,
    t: &'o mut [f32],
    prim: &'o mut [u32],
    hit: &'o mut [u8],
}

impl Job<'_> {
    fn len(&self) -> usize {
        self.t.len().max(self.hit.len())
    }
}

/// Traces every ray of `set` with `method` on `threads` threads (the calling thread and
/// `threads − 1` others), which take chunks from one queue until it is empty.
pub fn run(method: &Method, set: &RaySet, answers: &mut Answers, threads: usize) {
    let mut jobs = Vec::new();
    if set.any_hit {
        for (k, hit) in answers.hit.chunks_mut(CHUNK).enumerate() {
            jobs.push(Job {
                start: k * CHUNK,
                t: &mut [],
                prim: &mut [],
                hit,
            });
        }
    } else {
        let pieces = answers
            .t
            .chunks_mut(CHUNK)
            .zip(answers.prim.chunks_mut(CHUNK));
        for (k, (t, prim)) in pieces.enumerate() {
            jobs.push(Job {
                start: k * CHUNK,
                t,
                prim,
                hit: &mut [],
            });
        }
    }
    let queue = Mutex::new(jobs.into_iter());
    let worker = || loop {
        let job = queue.lock().unwrap().next();
        match job {
            Some(job) => method.trace(set, job),
            None => break,
        }
    };
    if threads <= 1 {
        worker();
    } else {
        std::thread::scope(|s| {
            for _ in 1..threads {
                s.spawn(worker);
            }
            worker();
        });
    }
}

/// Process CPU time and wall time of one run.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    pub cpu: Duration,
    pub wall: Duration,
}

/// Times `f` on both clocks.
pub fn time(f: impl FnOnce()) -> Sample {
    let (cpu, wall) = (Clock::ProcessCpu.start(), Clock::Wall.start());
    f();
    Sample {
        cpu: cpu.elapsed(),
        wall: wall.elapsed(),
    }
}

/// Medians of each clock separately.
pub fn median(samples: &[Sample]) -> Sample {
    let mid = |mut v: Vec<Duration>| {
        v.sort();
        v[v.len() / 2]
    };
    Sample {
        cpu: mid(samples.iter().map(|s| s.cpu).collect()),
        wall: mid(samples.iter().map(|s| s.wall).collect()),
    }
}
