//! The wavefront's diffuse bounces in SIMD lanes: the leave stage gathers the vertices
//! that draw their next direction from a BSDF's diffuse lobe (a BSDF without a glossy lobe,
//! `Bsdf::diffuse_only`, whose lobe number chose it) into blocks of structure-of-arrays
//! state, and draws their directions, densities and weights eight lanes at a time with
//! AVX2 (four with SSE elsewhere), where `Bsdf::sample` would draw them one by one.
//!
//! The kernel is the scalar code's operations in its order over `FloatLanes`: the
//! direction is `warp::cosine_direction`, which `Bsdf::sample` itself calls with one lane
//! (its sine and cosine `lanes::sincos`), the density and weight `Bsdf::pdf`'s and
//! `Bsdf::eval`'s arithmetic for a lobe without gloss. So every sample is the scalar one
//! bit for bit, and the wavefront's image stays the one-path tracer's (`tests/wavefront.rs`).

// `#[target_feature]` functions can only be called in unsafe blocks, and only after
// `is_x86_feature_detected!` said yes (`DiffuseBlock::run`); nothing else here is unsafe.
// The workspace's `unsafe_code = "deny"` lists this module as an exception.
#![allow(unsafe_code)]

use crate::math::lanes::FloatLanes;
use crate::math::warp::cosine_direction;
use crate::math::Vec3;
use crate::shading::{BsdfSample, DiffuseLobe};
use glam::Vec4;
use std::f32::consts::FRAC_1_PI;

/// Vertices a block holds: a multiple of every width's lanes.
const BLOCK: usize = 64;

/// Up to `BLOCK` diffuse bounces, by component: what each reads, then what it answers.
pub(super) struct DiffuseBlock {
    len: usize,
    /// Each bounce's place in the queue.
    index: [u32; BLOCK],
    ns: [[f32; BLOCK]; 3],
    ng: [[f32; BLOCK]; 3],
    diffuse: [[f32; BLOCK]; 3],
    p_diffuse: [f32; BLOCK],
    u1: [f32; BLOCK],
    u2: [f32; BLOCK],
    wi: [[f32; BLOCK]; 3],
    weight: [[f32; BLOCK]; 3],
    pdf: [f32; BLOCK],
    /// Bit k: bounce k's density is not at most zero, so it goes on (`Bsdf::sample`'s
    /// `Some`).
    valid: u64,
}

impl Default for DiffuseBlock {
    fn default() -> Self {
        DiffuseBlock {
            len: 0,
            index: [0; BLOCK],
            ns: [[0.0; BLOCK]; 3],
            ng: [[0.0; BLOCK]; 3],
            diffuse: [[0.0; BLOCK]; 3],
            p_diffuse: [0.0; BLOCK],
            u1: [0.5; BLOCK],
            u2: [0.5; BLOCK],
            wi: [[0.0; BLOCK]; 3],
            weight: [[0.0; BLOCK]; 3],
            pdf: [0.0; BLOCK],
            valid: 0,
        }
    }
}

impl DiffuseBlock {
    /// Adds the bounce of queue place `index` from `lobe` with direction numbers `u1`,
    /// `u2`; true when the block is full (then `run` it).
    #[inline]
    pub(super) fn push(&mut self, index: usize, lobe: &DiffuseLobe, u1: f32, u2: f32) -> bool {
        let k = self.len;
        self.index[k] = index as u32;
        for (axis, (ns, ng)) in [
            (lobe.ns.x, lobe.ng.x),
            (lobe.ns.y, lobe.ng.y),
            (lobe.ns.z, lobe.ng.z),
        ]
        .into_iter()
        .enumerate()
        {
            self.ns[axis][k] = ns;
            self.ng[axis][k] = ng;
        }
        self.diffuse[0][k] = lobe.diffuse.x;
        self.diffuse[1][k] = lobe.diffuse.y;
        self.diffuse[2][k] = lobe.diffuse.z;
        self.p_diffuse[k] = lobe.p_diffuse;
        self.u1[k] = u1;
        self.u2[k] = u2;
        self.len += 1;
        self.len == BLOCK
    }

    /// Draws every bounce of the block into `samples` at its queue place (what
    /// `Bsdf::sample` gives), and empties the block.
    pub(super) fn run(&mut self, samples: &mut [Option<BsdfSample>]) {
        if self.len == 0 {
            return;
        }
        #[cfg(target_arch = "x86_64")]
        {
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the CPU has AVX2 (just asked).
                unsafe { sample_avx2(self) };
            } else {
                sample_lanes::<Vec4>(self);
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        sample_lanes::<Vec4>(self);
        for k in 0..self.len {
            samples[self.index[k] as usize] = (self.valid >> k & 1 == 1).then(|| BsdfSample {
                wi: Vec3::new(self.wi[0][k], self.wi[1][k], self.wi[2][k]),
                weight: Vec3::new(self.weight[0][k], self.weight[1][k], self.weight[2][k]),
                pdf: self.pdf[k],
                delta: false,
                transmitted: false,
            });
        }
        self.len = 0;
    }
}

/// `sample_lanes` with eight lanes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sample_avx2(block: &mut DiffuseBlock) {
    sample_lanes::<crate::math::lanes::F32x8>(block);
}

/// `Bsdf::sample`'s diffuse branch for a BSDF without gloss, `L::LANES` bounces at a time.
#[inline(always)]
fn sample_lanes<L: FloatLanes>(b: &mut DiffuseBlock) {
    let zero = L::splat(0.0);
    let mut valid = 0u64;
    let mut at = 0;
    while at < b.len {
        let ns = [
            L::load(&b.ns[0], at),
            L::load(&b.ns[1], at),
            L::load(&b.ns[2], at),
        ];
        let ng = [
            L::load(&b.ng[0], at),
            L::load(&b.ng[1], at),
            L::load(&b.ng[2], at),
        ];
        let wi = cosine_direction(ns, L::load(&b.u1, at), L::load(&b.u2, at));
        // Bsdf::pdf: zero below either normal, else p_diffuse · cosine_hemisphere_pdf.
        let cos_i = wi[0] * ns[0] + wi[1] * ns[1] + wi[2] * ns[2];
        let cos_g = wi[0] * ng[0] + wi[1] * ng[1] + wi[2] * ng[2];
        let below = cos_i.le(zero) | cos_g.le(zero);
        let pdf = L::select(
            below,
            zero,
            L::load(&b.p_diffuse, at) * (cos_i.max(zero) * L::splat(FRAC_1_PI)),
        );
        // Bsdf::eval above both normals (the only case with pdf > 0), times cos / pdf.
        let ratio = cos_i / pdf;
        let lanes = L::all_lanes() & !L::bits(pdf.le(zero));
        valid |= u64::from(lanes) << at;
        store(&mut b.pdf, at, pdf);
        for (axis, &w) in wi.iter().enumerate() {
            store(&mut b.wi[axis], at, w);
            let f = L::load(&b.diffuse[axis], at) * L::splat(FRAC_1_PI);
            store(&mut b.weight[axis], at, f * ratio);
        }
        at += L::LANES;
    }
    b.valid = valid;
}

/// Lanes `at ..` of `row` set to `value`'s.
#[inline(always)]
fn store<L: FloatLanes>(row: &mut [f32; BLOCK], at: usize, value: L) {
    let lanes = value.to_array();
    for k in 0..L::LANES {
        row[at + k] = lanes[k];
    }
}
