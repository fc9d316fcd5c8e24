//! Rays per pixel: how many camera rays and how many rays in all each pixel cost, for the
//! sample-density view, and the node visits and primitive tests those rays made, for the
//! cost view. Rays shared by several pixels count in the pixel that traced them.

use crate::stats::Stats;

/// Per-pixel ray and traversal counts of a render, for the density and cost views.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Camera rays per pixel, row-major.
    pub camera: Vec<u32>,
    /// Every ray (camera, shadow, reflected, refracted) per pixel.
    pub total: Vec<u32>,
    /// Acceleration-structure node visits of all of a pixel's rays.
    pub node_visits: Vec<u64>,
    /// Ray–primitive tests of all of a pixel's rays.
    pub primitive_tests: Vec<u64>,
    /// The part of `node_visits` made by the pixel's shadow rays.
    pub shadow_node_visits: Vec<u64>,
    /// The part of `primitive_tests` made by the pixel's shadow rays.
    pub shadow_tests: Vec<u64>,
}

impl RayCounts {
    /// Zero counts, or an out-of-memory error instead of an abort.
    pub fn try_new(width: u32, height: u32) -> Result<Self, super::RenderError> {
        use super::memory::try_zeroed;
        let n = width as usize * height as usize;
        Ok(RayCounts {
            width,
            height,
            camera: try_zeroed(n, "ray counts")?,
            total: try_zeroed(n, "ray counts")?,
            node_visits: try_zeroed(n, "ray counts")?,
            primitive_tests: try_zeroed(n, "ray counts")?,
            shadow_node_visits: try_zeroed(n, "ray counts")?,
            shadow_tests: try_zeroed(n, "ray counts")?,
        })
    }

    /// No counts, for a render that keeps none (`RenderOptions::per_pixel_rays` off):
    /// `add` leaves it empty.
    pub fn unrecorded(width: u32, height: u32) -> Self {
        RayCounts {
            width,
            height,
            ..RayCounts::default()
        }
    }

    /// Whether the counts were kept (else every vector is empty).
    pub fn is_recorded(&self) -> bool {
        self.camera.len() == self.width as usize * self.height as usize
    }

    /// Cuts the counts to their first `rows` rows, as `Film::keep_top_rows` the image.
    pub fn keep_top_rows(&mut self, rows: u32) {
        self.height = self.height.min(rows);
        let n = self.height as usize * self.width as usize;
        self.camera.truncate(n);
        self.total.truncate(n);
        self.node_visits.truncate(n);
        self.primitive_tests.truncate(n);
        self.shadow_node_visits.truncate(n);
        self.shadow_tests.truncate(n);
    }

    /// Adds rays to pixel (x, y) (nothing where counts are not kept).
    pub fn add(&mut self, x: u32, y: u32, rays: PixelRays) {
        if self.camera.is_empty() {
            return;
        }
        let i = y as usize * self.width as usize + x as usize;
        self.camera[i] = self.camera[i].saturating_add(rays.camera);
        self.total[i] = self.total[i].saturating_add(rays.total);
        self.node_visits[i] += rays.node_visits;
        self.primitive_tests[i] += rays.primitive_tests;
        self.shadow_node_visits[i] += rays.shadow_node_visits;
        self.shadow_tests[i] += rays.shadow_tests;
    }

    /// Mean camera rays per pixel.
    pub fn mean_camera(&self) -> f64 {
        self.camera.iter().map(|&c| c as f64).sum::<f64>() / self.camera.len().max(1) as f64
    }
}

/// Camera rays and all rays of one piece of work, and the traversal work they did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PixelRays {
    /// Camera rays.
    pub camera: u32,
    /// Every ray (camera, shadow, reflected, refracted).
    pub total: u32,
    /// Acceleration-structure node visits of all the rays.
    pub node_visits: u64,
    /// Ray–primitive tests of all the rays.
    pub primitive_tests: u64,
    /// The part of `node_visits` made by shadow rays.
    pub shadow_node_visits: u64,
    /// The part of `primitive_tests` made by shadow rays.
    pub shadow_tests: u64,
}

impl PixelRays {
    /// The rays counted between two snapshots of a worker's statistics.
    pub fn between(before: &Stats, after: &Stats) -> Self {
        let clamp = |n: u64| n.min(u32::MAX as u64) as u32;
        PixelRays {
            camera: clamp(after.primary_rays - before.primary_rays),
            total: clamp(after.total_rays() - before.total_rays()),
            node_visits: after.node_visits - before.node_visits,
            primitive_tests: after.primitive_tests - before.primitive_tests,
            shadow_node_visits: after.shadow_node_visits - before.shadow_node_visits,
            shadow_tests: after.shadow_tests - before.shadow_tests,
        }
    }
}

/// The statistics `PixelRays` reads, taken before a piece of work so that its rays can be
/// counted afterwards (`PixelRays::since`): six counters instead of a copy of all of
/// `Stats`, which samplers that attribute every ray to its pixel take once a ray.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RayMark([u64; 6]);

impl RayMark {
    #[inline]
    pub(crate) fn of(s: &Stats) -> Self {
        RayMark([
            s.primary_rays,
            s.total_rays(),
            s.node_visits,
            s.primitive_tests,
            s.shadow_node_visits,
            s.shadow_tests,
        ])
    }
}

impl PixelRays {
    /// The rays counted since `mark` was taken of `stats`: `between` (the same counts).
    #[inline]
    pub(crate) fn since(mark: RayMark, stats: &Stats) -> Self {
        let clamp = |n: u64| n.min(u32::MAX as u64) as u32;
        let [camera, total, nodes, tests, shadow_nodes, shadow_tests] = mark.0;
        PixelRays {
            camera: clamp(stats.primary_rays - camera),
            total: clamp(stats.total_rays() - total),
            node_visits: stats.node_visits - nodes,
            primitive_tests: stats.primitive_tests - tests,
            shadow_node_visits: stats.shadow_node_visits - shadow_nodes,
            shadow_tests: stats.shadow_tests - shadow_tests,
        }
    }
}

impl PixelRays {
    /// Ray `i`'s share when `n` rays split these counts evenly (the first ones take the
    /// remainders): how a packet's shared traversal is charged to its pixels.
    pub(crate) fn share(&self, i: usize, n: usize) -> PixelRays {
        let n64 = n as u64;
        let part = |v: u64| v / n64 + u64::from((i as u64) < v % n64);
        let part32 = |v: u32| part(u64::from(v)) as u32;
        PixelRays {
            camera: part32(self.camera),
            total: part32(self.total),
            node_visits: part(self.node_visits),
            primitive_tests: part(self.primitive_tests),
            shadow_node_visits: part(self.shadow_node_visits),
            shadow_tests: part(self.shadow_tests),
        }
    }
}

impl std::ops::AddAssign for PixelRays {
    fn add_assign(&mut self, o: PixelRays) {
        self.camera = self.camera.saturating_add(o.camera);
        self.total = self.total.saturating_add(o.total);
        self.node_visits += o.node_visits;
        self.primitive_tests += o.primitive_tests;
        self.shadow_node_visits += o.shadow_node_visits;
        self.shadow_tests += o.shadow_tests;
    }
}
