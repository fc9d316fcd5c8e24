//! The settings as the scene file's `[render]` table writes them: one flat table, the
//! adaptive sampler's keys spelt `adaptive_threshold`, `adaptive_depth`, … . Serde reads
//! and writes `RenderOptions` through this, so the file format stays flat while the
//! options group each choice's settings.

use super::RenderOptions;
use crate::accel::AccelSpec;
use crate::choices::{
    AdaptiveRule, AdaptiveSpec, FilterKind, IntegratorKind, SamplerKind, ShadowSpec, Transfer,
};
use serde::{Deserialize, Serialize};

/// `RenderOptions` without the settings a file does not set (`path_strategy`,
/// `per_pixel_rays`), flat.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub(super) struct RenderTable {
    width: u32,
    height: u32,
    samples: u32,
    sampler: SamplerKind,
    filter: FilterKind,
    filter_radius: Option<f32>,
    adaptive_threshold: f32,
    adaptive_depth: u32,
    adaptive_rule: AdaptiveRule,
    adaptive_jitter: f32,
    adaptive_texture_spp: u32,
    transfer: Transfer,
    max_depth: u32,
    min_weight: f32,
    area_samples: u32,
    spd_rules: bool,
    threads: usize,
    seed: u64,
    accel: AccelSpec,
    shadows: ShadowSpec,
    tile_size: u32,
    packets: bool,
    wavefront: bool,
    integrator: IntegratorKind,
}

impl Default for RenderTable {
    fn default() -> Self {
        RenderOptions::default().into()
    }
}

impl From<RenderOptions> for RenderTable {
    fn from(o: RenderOptions) -> Self {
        RenderTable {
            width: o.width,
            height: o.height,
            samples: o.samples,
            sampler: o.sampler,
            filter: o.filter,
            filter_radius: o.filter_radius,
            adaptive_threshold: o.adaptive.threshold,
            adaptive_depth: o.adaptive.depth,
            adaptive_rule: o.adaptive.rule,
            adaptive_jitter: o.adaptive.jitter,
            adaptive_texture_spp: o.adaptive.texture_spp,
            transfer: o.transfer,
            max_depth: o.max_depth,
            min_weight: o.min_weight,
            area_samples: o.area_samples,
            spd_rules: o.spd_rules,
            threads: o.threads,
            seed: o.seed,
            accel: o.accel,
            shadows: o.shadows,
            tile_size: o.tile_size,
            packets: o.packets,
            wavefront: o.wavefront,
            integrator: o.integrator,
        }
    }
}

impl From<RenderTable> for RenderOptions {
    fn from(t: RenderTable) -> Self {
        RenderOptions {
            width: t.width,
            height: t.height,
            samples: t.samples,
            sampler: t.sampler,
            filter: t.filter,
            filter_radius: t.filter_radius,
            adaptive: AdaptiveSpec {
                threshold: t.adaptive_threshold,
                depth: t.adaptive_depth,
                rule: t.adaptive_rule,
                jitter: t.adaptive_jitter,
                texture_spp: t.adaptive_texture_spp,
            },
            transfer: t.transfer,
            max_depth: t.max_depth,
            min_weight: t.min_weight,
            area_samples: t.area_samples,
            spd_rules: t.spd_rules,
            threads: t.threads,
            seed: t.seed,
            accel: t.accel,
            shadows: t.shadows,
            tile_size: t.tile_size,
            packets: t.packets,
            wavefront: t.wavefront,
            integrator: t.integrator,
            ..RenderOptions::default()
        }
    }
}
