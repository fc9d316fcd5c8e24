//! Four triangles stored by axis, and a 4-wide first pass of the watertight test that
//! rejects the ones a ray cannot hit.
//!
//! Most triangle tests a traversal makes are misses. The first pass computes, for four
//! triangles in SIMD lanes, exactly the edge functions, determinant and scaled distance of
//! `intersect_triangle` (the same operations in the same order, so the same values), and
//! rejects a lane only on a comparison the scalar test would reject on too. A lane it keeps
//! is handed to `intersect_triangle` itself, which decides it; so the answers are the
//! scalar test's bit for bit, while a miss costs a quarter of a SIMD pass instead of three
//! vertex gathers through the mesh's index list and a scalar test.
//!
//! Lanes whose edge functions contain an exact zero are always kept: the scalar test
//! re-evaluates those in f64, and only it can decide them.

use super::triangle::{intersect_triangle, TriangleHit};
use super::triangle_lanes::{LaneHits, Sheared};
use crate::math::{TraceRay, Vec3};
use glam::Vec4;

/// Four triangles' vertices: `v[i][axis]` holds vertex `i`'s coordinate on `axis` for the
/// four triangles in lanes 0..4. Unused lanes repeat a used lane's triangle and are masked
/// off by `lanes`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(16))]
pub struct TrianglePack {
    v: [[Vec4; 3]; 3],
    /// The triangles' ids (whatever the owner numbers them by), lane by lane.
    pub ids: [u32; 4],
    /// How many lanes hold a triangle (1..=4).
    lanes: u32,
}

impl TrianglePack {
    /// A pack of one to four triangles (vertices and ids), in lane order.
    pub fn new(triangles: &[([Vec3; 3], u32)]) -> TrianglePack {
        assert!(
            (1..=4).contains(&triangles.len()),
            "a pack holds one to four triangles"
        );
        let mut pack = TrianglePack {
            v: [[Vec4::ZERO; 3]; 3],
            ids: [0; 4],
            lanes: triangles.len() as u32,
        };
        for lane in 0..4 {
            // Padding lanes repeat the last triangle: real numbers, never tested.
            let (vertices, id) = triangles[lane.min(triangles.len() - 1)];
            for (i, v) in vertices.iter().enumerate() {
                for axis in 0..3 {
                    pack.v[i][axis][lane] = v[axis];
                }
            }
            pack.ids[lane] = id;
        }
        pack
    }

    /// How many lanes hold a triangle.
    #[inline(always)]
    pub fn len(&self) -> usize {
        self.lanes as usize
    }

    /// Packs always hold at least one triangle.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// Vertex coordinates by vertex, axis and lane: `[i][axis][lane]`, for first passes
    /// that test one triangle against several rays.
    #[inline(always)]
    pub fn lanes_by_vertex(&self) -> &[[Vec4; 3]; 3] {
        &self.v
    }

    /// Triangle `lane`'s vertices.
    #[inline(always)]
    pub fn vertices(&self, lane: usize) -> [Vec3; 3] {
        self.v
            .map(|axes| Vec3::new(axes[0][lane], axes[1][lane], axes[2][lane]))
    }

    /// The four lanes' edge functions, determinant and scaled distance, as
    /// `intersect_triangle` computes them.
    #[inline(always)]
    fn sheared(&self, ray: &PackRay) -> Sheared<Vec4> {
        let (kx, ky, kz) = (ray.kx, ray.ky, ray.kz);
        // As in `intersect_triangle`: vertices relative to the origin, permuted and sheared.
        let rel = |v: &[Vec4; 3]| {
            [
                v[kx] - ray.origin[0],
                v[ky] - ray.origin[1],
                v[kz] - ray.origin[2],
            ]
        };
        Sheared::new(
            [rel(&self.v[0]), rel(&self.v[1]), rel(&self.v[2])],
            ray.shear,
        )
    }

    /// The lanes (bit k for lane k) that `intersect_triangle(ray, …, t_max)` might report a
    /// hit for; every other lane it certainly rejects.
    #[inline(always)]
    pub fn candidates(&self, ray: &PackRay, t_max: f32) -> u32 {
        let (rejected, exact_zero) = self.sheared(ray).rejected(Vec4::splat(t_max));
        // Lanes with an exact zero edge function are left to the scalar test, since it
        // re-evaluates those in f64 first.
        !(rejected & !exact_zero) & self.lane_mask()
    }

    /// The whole watertight test in four lanes at bound `t_max`: each lane's hit is the one
    /// `intersect_triangle(ray, …, t_max)` reports, bit for bit (the same operations in the
    /// same order, the division included), except the lanes in `PackHits::undecided`,
    /// which the scalar test must decide (an exact zero edge function, which it
    /// re-evaluates in f64, or a value that is not finite).
    #[inline(always)]
    pub(crate) fn hits(&self, ray: &PackRay, t_max: f32) -> PackHits {
        self.sheared(ray).hits(Vec4::splat(t_max), self.lane_mask())
    }

    #[inline(always)]
    fn lane_mask(&self) -> u32 {
        (1u32 << self.lanes) - 1
    }

    /// The scalar test of lane `lane`: the answer, bit for bit, of `intersect_triangle` on
    /// that triangle.
    #[inline(always)]
    pub fn intersect(&self, lane: usize, ray: &TraceRay, t_max: f32) -> Option<TriangleHit> {
        let [v0, v1, v2] = self.vertices(lane);
        intersect_triangle(ray, v0, v1, v2, t_max)
    }
}

/// A ray's constants for `TrianglePack::candidates`: the origin in the ray's axis
/// permutation and the shear, each splatted across four lanes.
#[derive(Clone, Copy, Debug)]
pub struct PackRay {
    origin: [Vec4; 3],
    shear: [Vec4; 3],
    kx: usize,
    ky: usize,
    kz: usize,
}

/// What `TrianglePack::hits` found, lane by lane.
pub(crate) type PackHits = LaneHits<Vec4>;

/// One lane's hit, decided by a SIMD pass of the watertight test at some bound: the
/// values the scalar test would compute, from which the hit at a tighter bound follows.
#[derive(Clone, Copy, Debug)]
pub struct DecidedHit {
    /// The determinant (sum of the edge functions).
    pub det: f32,
    /// The distance times the determinant, before the division.
    pub t_scaled: f32,
    /// The distance.
    pub t: f32,
    /// The barycentric coordinate of the second vertex.
    pub b1: f32,
    /// The barycentric coordinate of the third vertex.
    pub b2: f32,
}

impl DecidedHit {
    /// The hit if it also holds at the tighter bound `t_max`: what `intersect_triangle(ray,
    /// …, t_max)` reports, for the comparisons of the bound are made again on the lane's
    /// own values.
    #[inline(always)]
    pub fn within(&self, t_max: f32) -> Option<TriangleHit> {
        let beyond = if self.det < 0.0 {
            self.t_scaled < t_max * self.det
        } else {
            self.t_scaled > t_max * self.det
        };
        (!beyond && self.t < t_max).then_some(TriangleHit {
            t: self.t,
            b1: self.b1,
            b2: self.b2,
        })
    }
}

impl PackRay {
    /// The constants of `ray`.
    #[inline(always)]
    pub fn new(ray: &TraceRay) -> PackRay {
        let o = ray.ray.origin;
        let (kx, ky, kz) = (ray.kx % 3, ray.ky % 3, ray.kz % 3);
        PackRay {
            origin: [o[kx], o[ky], o[kz]].map(Vec4::splat),
            shear: [ray.shear.x, ray.shear.y, ray.shear.z].map(Vec4::splat),
            kx,
            ky,
            kz,
        }
    }

    /// The origin's coordinates in the ray's axis permutation, for first passes of other
    /// widths (`accel/bvh/simd8/pair.rs`), which broadcast them themselves.
    #[inline(always)]
    pub(crate) fn origin(&self) -> [f32; 3] {
        self.origin.map(|o| o.x)
    }

    /// The shear constants, as `origin`.
    #[inline(always)]
    pub(crate) fn shear(&self) -> [f32; 3] {
        self.shear.map(|s| s.x)
    }

    /// The axis permutation `[kx, ky, kz]`.
    #[inline(always)]
    pub(crate) fn axes(&self) -> [usize; 3] {
        [self.kx, self.ky, self.kz]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::hash::uniform;
    use crate::math::robust::{next_down, next_up};
    use crate::math::Ray;

    fn point(seed: u64, scale: f32) -> Vec3 {
        let c = |k| (uniform(seed as u32, 0, 0, k, 7) * 2.0 - 1.0) * scale;
        Vec3::new(c(0), c(1), c(2))
    }

    /// The first pass never rejects a lane the scalar test hits (so the pack's answers are
    /// the scalar test's), and rejects most lanes the scalar test misses, on random rays
    /// against random triangles, fans around shared vertices (exact zeros), and
    /// axis-parallel rays, at three scales.
    #[test]
    fn the_first_pass_keeps_every_hit() {
        let (mut hits, mut misses, mut kept_misses) = (0, 0, 0);
        for scale in [1e-3f32, 1.0, 1e3] {
            for case in 0..4000u64 {
                let mut tris: Vec<([Vec3; 3], u32)> = (0..4)
                    .map(|k| {
                        let s = case * 16 + k * 4;
                        (
                            [point(s, scale), point(s + 1, scale), point(s + 2, scale)],
                            k as u32,
                        )
                    })
                    .collect();
                if case % 4 == 1 {
                    // A fan sharing vertex 0 and edges: rays through the shared vertex
                    // produce exact zeros.
                    let hub = point(case * 16 + 99, scale);
                    for t in tris.iter_mut() {
                        t.0[0] = hub;
                    }
                }
                let lanes = 1 + (case % 4) as usize;
                let pack = TrianglePack::new(&tris[..lanes]);
                let origin = point(case * 16 + 50, 2.0 * scale);
                let target = if case % 4 == 1 {
                    tris[0].0[0]
                } else {
                    let [a, b, c] = tris[(case % 4) as usize % lanes].0;
                    (a + b + c) / 3.0 + point(case * 16 + 51, 0.3 * scale)
                };
                let mut dir = target - origin;
                if case % 8 == 3 {
                    // Axis-parallel: keep the dominant component only.
                    let k = dir.abs().max_position();
                    let mut d = Vec3::ZERO;
                    d[k] = dir[k];
                    dir = d;
                }
                if dir == Vec3::ZERO {
                    continue;
                }
                let ray = TraceRay::new(Ray::new(origin, dir));
                let pack_ray = PackRay::new(&ray);
                for t_max in [f32::INFINITY, 0.9, 1.0, 1.1] {
                    let kept = pack.candidates(&pack_ray, t_max);
                    assert_eq!(kept >> lanes, 0, "a padding lane is kept");
                    for (lane, &(v, _)) in tris[..lanes].iter().enumerate() {
                        let scalar = intersect_triangle(&ray, v[0], v[1], v[2], t_max);
                        assert_eq!(pack.intersect(lane, &ray, t_max), scalar);
                        if scalar.is_some() {
                            hits += 1;
                            assert!(
                                kept & (1 << lane) != 0,
                                "case {case} lane {lane}: a hit rejected"
                            );
                        } else {
                            misses += 1;
                            kept_misses += (kept >> lane) & 1;
                        }
                    }
                }
            }
        }
        assert!(
            hits > 2000,
            "the cases hit too rarely to show anything ({hits})"
        );
        assert!(
            kept_misses * 10 < misses,
            "the first pass keeps {kept_misses} of {misses} misses"
        );
    }

    /// The 4-wide test reports each lane's hit exactly as the scalar test does, bit for
    /// bit, at its own bound and at every tighter one (`within`), on the cases of
    /// `the_first_pass_keeps_every_hit`; only lanes it marks undecided are left out.
    #[test]
    fn the_four_wide_test_is_the_scalar_test() {
        let (mut decided, mut undecided, mut hit) = (0, 0, 0);
        for scale in [1e-3f32, 1.0, 1e3] {
            for case in 0..3000u64 {
                let tris: Vec<([Vec3; 3], u32)> = (0..4)
                    .map(|k| {
                        let s = case * 16 + k * 4;
                        let hub = point(case * 16 + 99, scale);
                        let first = if case % 4 == 1 { hub } else { point(s, scale) };
                        ([first, point(s + 1, scale), point(s + 2, scale)], k as u32)
                    })
                    .collect();
                let lanes = 1 + (case % 4) as usize;
                let pack = TrianglePack::new(&tris[..lanes]);
                let origin = point(case * 16 + 50, 2.0 * scale);
                let [a, b, c] = tris[(case % 4) as usize % lanes].0;
                let target = (a + b + c) / 3.0 + point(case * 16 + 51, 0.3 * scale);
                let dir = target - origin;
                if dir == Vec3::ZERO {
                    continue;
                }
                let ray = TraceRay::new(Ray::new(origin, dir));
                let pack_ray = PackRay::new(&ray);
                for t_max in [f32::INFINITY, 1.1, 1.0, 0.9] {
                    let hits = pack.hits(&pack_ray, t_max);
                    assert_eq!((hits.hit | hits.undecided) >> lanes, 0, "a padding lane");
                    for (lane, &(v, _)) in tris[..lanes].iter().enumerate() {
                        if hits.undecided & (1 << lane) != 0 {
                            undecided += 1;
                            continue;
                        }
                        decided += 1;
                        let scalar = |bound| intersect_triangle(&ray, v[0], v[1], v[2], bound);
                        let found = (hits.hit & (1 << lane) != 0)
                            .then(|| hits.decided(lane).within(t_max))
                            .flatten();
                        assert_eq!(found, scalar(t_max), "case {case} lane {lane} at {t_max}");
                        let Some(h) = found else { continue };
                        hit += 1;
                        // Tighter bounds: around the hit itself, where rounding decides.
                        for bound in [next_up(h.t), h.t, next_down(h.t), 0.5 * h.t] {
                            assert_eq!(
                                hits.decided(lane).within(bound),
                                scalar(bound),
                                "case {case}"
                            );
                        }
                    }
                }
            }
        }
        assert!(
            decided > 10 * undecided,
            "{undecided} of {decided} undecided"
        );
        assert!(
            hit > 2000,
            "the cases hit too rarely to show anything ({hit})"
        );
    }

    #[test]
    fn lanes_and_vertices_round_trip() {
        let t = |k: f32| {
            (
                [Vec3::splat(k), Vec3::new(k, 1.0, 2.0), Vec3::Z * k],
                k as u32,
            )
        };
        let pack = TrianglePack::new(&[t(1.0), t(2.0), t(3.0)]);
        assert_eq!(pack.len(), 3);
        assert_eq!(pack.vertices(1), t(2.0).0);
        assert_eq!(pack.ids[..3], [1, 2, 3]);
    }
}
