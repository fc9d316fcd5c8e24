//! The exact integral of a checker texture over a convex piece of film. A facet's uv
//! coordinates are projective functions of film position, u = U(x, y)/W(x, y) with U, W
//! affine (`ProjectiveUv`), so every square's border u = k is a straight line on the film and
//! the squares a piece covers are convex polygons, cut out exactly and summed.
//!
//! Towards the horizon of an endless plane a pixel covers unboundedly many squares. There
//! the piece takes the mean colour (a + b)/2 where that is provably close: in each strip of
//! squares the colours alternate, and for the unimodal run of cell areas along a strip the
//! alternating sum is at most the largest cell's area, so the white area differs from half
//! the piece by at most (strips) × (largest square's area on the film), the area being
//! size²·|W|³/|det M| for the 3 × 3 matrix M of (U, V, W). Pieces whose bound is too large
//! are cut in two along a square border and tried again. Within `delta` pixels of the
//! horizon line (W = 0) no square is resolved at all: the mean's error there is at most
//! half the sliver's area. The bounds are returned, so callers know how exact a pixel is.

use super::convex::{Affine2, Convex};
use crate::math::Color;
use crate::shading::Checker;
use glam::DVec3;

/// uv in units of squares as projective functions of film position: u = nu/den, v = nv/den.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ProjectiveUv {
    /// Numerator of u.
    pub(crate) nu: Affine2,
    /// Numerator of v.
    pub(crate) nv: Affine2,
    /// Common denominator (never zero on the facet's visible part).
    pub(crate) den: Affine2,
}

impl ProjectiveUv {
    fn at(&self, p: glam::DVec2) -> (f64, f64) {
        let w = self.den.at(p);
        (self.nu.at(p) / w, self.nv.at(p) / w)
    }
}

/// Squares a piece may be cut into directly; more are first split in two.
const EXACT_SQUARES: f64 = 256.0;
/// Splits of one pixel's piece before the pieces left take the mean with the bounds they
/// have (reported, so never silently).
const MAX_SPLITS: usize = 20_000;

/// The integral of a checker's colour over a piece, and a bound on its error.
pub(crate) struct CheckerIntegral {
    /// ∫ colour dA (colour × square pixels).
    pub(crate) sum: DVec3,
    /// Bound on the error of `sum` (per channel).
    pub(crate) bound: f64,
}

/// Integrates `checker` (whose uv in squares `uv` gives) over `piece`, to within
/// `tolerance` × the piece's area away from the horizon, and half the area within `delta`
/// pixels of it. Pieces too full of squares to cut out wait in a queue by their bound; the
/// worst is split in two along a square border until the bounds left add up to the budget,
/// so the squares are cut out only where they are large enough to matter.
pub(crate) fn integrate(
    piece: &Convex,
    uv: &ProjectiveUv,
    checker: &Checker,
    tolerance: f64,
    delta: f64,
) -> CheckerIntegral {
    let job = Job {
        uv,
        checker,
        delta,
        a: to_d(checker.a),
        b: to_d(checker.b),
        diff: (to_d(checker.a) - to_d(checker.b)).abs().max_element(),
    };
    let mut out = CheckerIntegral {
        sum: DVec3::ZERO,
        bound: 0.0,
    };
    let mut fresh = Vec::new();
    job.piece(piece.clone(), false, &mut out, &mut fresh);
    let budget = tolerance * piece.area();
    let mut queue = std::collections::BinaryHeap::new();
    let mut pending = 0.0;
    let mut splits = 0;
    loop {
        for p in fresh.drain(..) {
            pending += p.bound;
            queue.push(p);
        }
        if pending <= budget || splits >= MAX_SPLITS {
            break;
        }
        // The piece with the largest bound.
        let Some(p) = queue.pop() else {
            break;
        };
        pending -= p.bound;
        splits += 1;
        job.piece(p.piece.clip(&p.cut), p.beyond, &mut out, &mut fresh);
        job.piece(
            p.piece.clip(&p.cut.flipped()),
            p.beyond,
            &mut out,
            &mut fresh,
        );
    }
    for p in queue {
        job.mean(&p.piece, p.bound, &mut out);
    }
    out
}

fn to_d(c: Color) -> DVec3 {
    DVec3::new(c.x as f64, c.y as f64, c.z as f64)
}

struct Job<'a> {
    uv: &'a ProjectiveUv,
    checker: &'a Checker,
    delta: f64,
    a: DVec3,
    b: DVec3,
    diff: f64,
}

/// A piece that would take the mean colour with error at most `bound`, unless split along
/// `cut`.
struct Pending {
    piece: Convex,
    bound: f64,
    cut: Affine2,
    beyond: bool,
}

impl PartialEq for Pending {
    fn eq(&self, o: &Self) -> bool {
        self.bound.total_cmp(&o.bound).is_eq()
    }
}
impl Eq for Pending {}
impl PartialOrd for Pending {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Pending {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.bound.total_cmp(&o.bound)
    }
}

impl Job<'_> {
    fn mean(&self, piece: &Convex, bound: f64, out: &mut CheckerIntegral) {
        out.sum += (self.a + self.b) * 0.5 * piece.area();
        out.bound += bound;
    }

    /// Integrates `piece` exactly when it holds few squares or lies in the horizon's
    /// sliver; otherwise queues it with its bound. `beyond`: known to be clear of the
    /// sliver.
    fn piece(
        &self,
        piece: Convex,
        beyond: bool,
        out: &mut CheckerIntegral,
        queue: &mut Vec<Pending>,
    ) {
        let area = piece.area();
        if area <= 0.0 {
            return;
        }
        if self.diff == 0.0 {
            out.sum += self.a * area;
            return;
        }
        let den = &self.uv.den;
        let sign = if den.at(piece.centroid()) < 0.0 {
            -1.0
        } else {
            1.0
        };
        // Distance in pixels from the horizon line den = 0.
        let grad = den.a.hypot(den.b);
        if grad > 0.0 && !beyond {
            let (near, far) = piece
                .points
                .iter()
                .map(|&p| sign * den.at(p) / grad)
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
                    (lo.min(d), hi.max(d))
                });
            if near < self.delta {
                if far <= self.delta {
                    return self.mean(&piece, 0.5 * area * self.diff, out);
                }
                // sign·den − delta·grad ≥ 0: the part beyond the sliver.
                let line = Affine2 {
                    a: sign * den.a,
                    b: sign * den.b,
                    c: sign * den.c - self.delta * grad,
                };
                let sliver = piece.clip(&line.flipped());
                self.mean(&sliver, 0.5 * sliver.area() * self.diff, out);
                return self.piece(piece.clip(&line), true, out, queue);
            }
        }
        let (mut u_lo, mut u_hi, mut v_lo, mut v_hi) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for &p in &piece.points {
            let (u, v) = self.uv.at(p);
            u_lo = u_lo.min(u);
            u_hi = u_hi.max(u);
            v_lo = v_lo.min(v);
            v_hi = v_hi.max(v);
        }
        if !(u_lo.is_finite() && u_hi.is_finite() && v_lo.is_finite() && v_hi.is_finite()) {
            return self.mean(&piece, 0.5 * area * self.diff, out);
        }
        let n_u = u_hi.floor() - u_lo.floor() + 1.0;
        let n_v = v_hi.floor() - v_lo.floor() + 1.0;
        if n_u * n_v <= EXACT_SQUARES {
            return self.exact(&piece, sign, (u_lo, u_hi), (v_lo, v_hi), out);
        }
        // The largest square on the film within the piece: |den|³ is largest at a vertex.
        let m = glam::DMat3::from_cols(
            DVec3::new(self.uv.nu.a, self.uv.nv.a, den.a),
            DVec3::new(self.uv.nu.b, self.uv.nv.b, den.b),
            DVec3::new(self.uv.nu.c, self.uv.nv.c, den.c),
        );
        let det = m.determinant().abs();
        let w3 = piece
            .points
            .iter()
            .map(|&p| den.at(p).abs().powi(3))
            .fold(0.0, f64::max);
        let square = w3 / det;
        let bound = (n_u.min(n_v) * square * self.diff).min(0.5 * area * self.diff);
        // Cut along the square border in the middle of the longer run.
        let (num, k) = if n_u >= n_v {
            (
                &self.uv.nu,
                (0.5 * (u_lo + u_hi)).floor().max(u_lo.floor() + 1.0),
            )
        } else {
            (
                &self.uv.nv,
                (0.5 * (v_lo + v_hi)).floor().max(v_lo.floor() + 1.0),
            )
        };
        queue.push(Pending {
            cut: border(num, den, k, sign),
            piece,
            bound: if bound.is_finite() {
                bound
            } else {
                0.5 * area * self.diff
            },
            beyond,
        });
    }

    /// Cuts the piece into its squares and sums their colours.
    fn exact(
        &self,
        piece: &Convex,
        sign: f64,
        u: (f64, f64),
        v: (f64, f64),
        out: &mut CheckerIntegral,
    ) {
        let den = &self.uv.den;
        let (i0, i1) = (u.0.floor() as i64, u.1.floor() as i64);
        let (j0, j1) = (v.0.floor() as i64, v.1.floor() as i64);
        for i in i0..=i1 {
            let strip = band(piece, &self.uv.nu, den, sign, i, (i0, i1));
            if strip.is_empty() {
                continue;
            }
            for j in j0..=j1 {
                let cell = band(&strip, &self.uv.nv, den, sign, j, (j0, j1));
                let area = cell.area();
                if area > 0.0 {
                    // The square's own colour, by the texture's parity rule.
                    let size = self.checker.size;
                    let uv = glam::Vec2::new(
                        ((i as f64 + 0.5) * size as f64) as f32,
                        ((j as f64 + 0.5) * size as f64) as f32,
                    );
                    out.sum += to_d(self.checker.eval(uv, glam::Vec3::ZERO)) * area;
                }
            }
        }
    }
}

/// The part of `piece` in band `k` (k ≤ num/den < k + 1) of the bands `first..=last` it
/// spans: clipped at the band's lower border unless it is the first, at its upper one
/// unless it is the last.
fn band(
    piece: &Convex,
    num: &Affine2,
    den: &Affine2,
    sign: f64,
    k: i64,
    (first, last): (i64, i64),
) -> Convex {
    let mut part = piece.clone();
    if k > first {
        part = part.clip(&border(num, den, k as f64, sign));
    }
    if k < last {
        part = part.clip(&border(num, den, (k + 1) as f64, sign).flipped());
    }
    part
}

/// The half-plane (num/den ≥ k) as an affine function, given den's sign on the piece.
fn border(num: &Affine2, den: &Affine2, k: f64, sign: f64) -> Affine2 {
    let f = num.minus_scaled(k, den);
    if sign < 0.0 {
        f.flipped()
    } else {
        f
    }
}
