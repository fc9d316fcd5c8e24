//! Binned SAH splits (Wald 2007): centroids are sorted into a few bins per axis, and the
//! split between bins with the lowest surface-area cost wins, unless a leaf is cheaper.
//! One pass bins all three axes; the bins also give each side's bounds, so a child never
//! passes over its primitives just to bound them.

use super::inside_share;
use super::prim_ref::{PrimRef, SimdBox};
use super::topdown::{Split, SplitRule, PARALLEL_PASS};
use super::BuildPrims;
use crate::accel::bvh::BvhOptions;
use crate::math::{Aabb, Vec3};
use glam::{BVec3A, Mat3A, Vec3A, Vec4};
use rayon::prelude::*;

pub(super) struct BinnedSah {
    bins: usize,
    max_leaf_size: usize,
    traversal_cost: f32,
    /// Rays start inside the scene (`RayOrigins::Inside`): children weighted by
    /// `inside_share`, and small nodes split tentatively and collapsed by `topdown.rs`.
    inside: bool,
}

impl BinnedSah {
    pub(super) fn new(options: &BvhOptions) -> Self {
        BinnedSah {
            bins: options.bins.max(2),
            max_leaf_size: options.max_leaf_size.max(1),
            traversal_cost: options.node_cost(),
            inside: options.for_rays_from_inside(),
        }
    }
}

/// Scratch space of the SAH sweep: the bins of all three axes (axis-major), and the
/// right-to-left sweep's running areas, volumes and counts for one axis.
pub(super) struct Sweep {
    bins: Vec<Bin>,
    /// The two sets of bins `Binning::fill` counts in.
    counting: Vec<CountingBin>,
    right_area: Vec<f32>,
    right_volume: Vec<f32>,
    right_count: Vec<u32>,
    /// The lanes sweep's right sides: per bin, the three axes' areas, volumes (for rays
    /// from inside) and leaf costs.
    right_lanes: Vec<[Vec3A; 3]>,
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: SimdBox,
    count: u32,
}

impl Bin {
    const EMPTY: Bin = Bin {
        bounds: SimdBox::EMPTY,
        count: 0,
    };

    fn merge(&self, other: &Bin) -> Bin {
        Bin {
            bounds: self.bounds.union(&other.bounds),
            count: self.count + other.count,
        }
    }
}

/// A bin while `Binning::fill` fills it: its box, and its count in the fourth lane of the
/// maximum, so that one chain of operations a bin updates both. A separate count was a
/// read-modify-write of memory per bin, waiting on the last one to the same bin.
#[derive(Clone, Copy)]
struct CountingBin {
    min: Vec3A,
    max: Vec4,
}

impl CountingBin {
    const EMPTY: CountingBin = CountingBin {
        min: Vec3A::INFINITY,
        max: Vec4::new(f32::NEG_INFINITY, f32::NEG_INFINITY, f32::NEG_INFINITY, 0.0),
    };

    /// Adds a reference's box, its maximum with 0 in the fourth lane (`PrimRef::max4`).
    #[inline(always)]
    fn add(&mut self, min: Vec3A, max4: Vec4) {
        self.min = self.min.min(min);
        // `max` keeps the count (a reference's fourth lane is 0, counts are not
        // negative); subtracting +0 leaves every coordinate as it was, -0 too, and
        // subtracting -1 counts the reference.
        self.max = self.max.max(max4) - Vec4::new(0.0, 0.0, 0.0, -1.0);
    }

    fn merge(&self, other: &CountingBin) -> CountingBin {
        CountingBin {
            min: self.min.min(other.min),
            max: self.max.max(other.max).with_w(self.max.w + other.max.w),
        }
    }

    /// The bin as the sweep reads it. Counts in f32 are exact below 2²⁴, far above the
    /// references one `fill` counts.
    fn to_bin(self) -> Bin {
        Bin {
            bounds: SimdBox {
                min: self.min,
                max: Vec3A::from_vec4(self.max),
            },
            count: self.max.w as u32,
        }
    }
}

/// How centroids map to bins on the three axes: the one rule both binning and
/// partitioning follow, so each side of a split is exactly the union of its bins.
#[derive(Clone, Copy)]
struct Binning {
    lo: Vec3A,
    /// Bins per unit length; 0 on an axis whose centroids all coincide.
    scale: Vec3A,
    /// The last bin's number, as a float.
    last: Vec3A,
    bins: usize,
}

impl Binning {
    /// The bins of centroid `c` on the three axes. The clamp keeps the maximum in the last
    /// bin and sends NaN to bin 0 (`max` returns its argument when a lane is NaN).
    #[inline(always)]
    fn bins_of(&self, c: Vec3A) -> [usize; 3] {
        truncate_lanes(self.position(c).max(Vec3A::ZERO).min(self.last))
    }

    /// Where centroid `c` falls on the three axes, in bins from the first bin's start.
    #[inline(always)]
    fn position(&self, c: Vec3A) -> Vec3A {
        (c - self.lo) * self.scale
    }

    /// Sets `bins` (three axes' worth, axis-major) to the bins of `refs`, reading each
    /// reference once; `counting` (twice as long as `bins`) is scratch. Even references
    /// go to one set of counting bins, odd ones to the other, merged at the end: a mesh's
    /// triangles come in order, so neighbours often land in the same bins, and with one
    /// set each update waited for the store of the one before it. Unions and counts are
    /// exact, so the bins are the same.
    fn fill(&self, refs: &[PrimRef], bins: &mut [Bin], counting: &mut [CountingBin]) {
        debug_assert!(refs.len() < 1 << 24, "counts in f32 stay exact");
        let (even, odd) = counting[..2 * bins.len()].split_at_mut(bins.len());
        even.fill(CountingBin::EMPTY);
        odd.fill(CountingBin::EMPTY);
        let pairs = refs.chunks_exact(2);
        let last = pairs.remainder();
        for pair in pairs {
            self.add(&pair[0], even);
            self.add(&pair[1], odd);
        }
        for r in last {
            self.add(r, even);
        }
        for ((bin, a), b) in bins.iter_mut().zip(even.iter()).zip(odd.iter()) {
            *bin = a.merge(b).to_bin();
        }
    }

    /// Adds one reference to the bins of its centroid on the three axes.
    #[inline(always)]
    fn add(&self, r: &PrimRef, bins: &mut [CountingBin]) {
        let nb = self.bins;
        let (min, max) = (r.min(), r.max());
        let [bx, by, bz] = self.bins_of(0.5 * (min + max));
        let max4 = r.max4();
        for bin in [bx, nb + by, 2 * nb + bz] {
            bins[bin].add(min, max4);
        }
    }
}

impl SplitRule for BinnedSah {
    type Scratch = Sweep;

    fn collapse(&self) -> Option<(f32, usize)> {
        self.inside
            .then_some((self.traversal_cost, self.max_leaf_size))
    }

    fn scratch(&self) -> Sweep {
        Sweep {
            bins: vec![Bin::EMPTY; 3 * self.bins],
            counting: vec![CountingBin::EMPTY; 6 * self.bins],
            right_area: vec![0.0; self.bins],
            right_volume: vec![0.0; self.bins],
            right_count: vec![0; self.bins],
            right_lanes: vec![[Vec3A::ZERO; 3]; self.bins],
        }
    }

    fn split(
        &self,
        prims: &BuildPrims,
        sweep: &mut Sweep,
        refs: &mut [PrimRef],
        bounds: &Aabb,
        centroid_bounds: &Aabb,
    ) -> Option<Split> {
        let n = refs.len();
        // Every split costs at least one traversal step, so where a leaf costs no more the
        // split below could never win (this answers most nodes of a few primitives).
        if n <= self.max_leaf_size && prims.leaf_cost(n) <= self.traversal_cost {
            return None;
        }
        // A node takes a bin per eight primitives, at least four, at most `bins` (Embree
        // scales its bins the same way). The bins' clearing and sweep are paid per node,
        // and the many small nodes near the leaves paid more for them than for binning
        // their few primitives; the SAH costs of the trees came out lower, not higher
        // (docs/journal/performance.md, the tenth step).
        let nb = self.bins.min((n / 8).max(4));
        let extent = centroid_bounds.max - centroid_bounds.min;
        let scale = Vec3::select(extent.cmpgt(Vec3::ZERO), nb as f32 / extent, Vec3::ZERO);
        let binning = Binning {
            lo: centroid_bounds.min.into(),
            scale: scale.into(),
            last: Vec3A::splat((nb - 1) as f32),
            bins: nb,
        };
        let bins = &mut sweep.bins[..3 * nb];
        self.fill_bins(&binning, refs, bins, &mut sweep.counting);
        let best = self
            .best_split_in_lanes(sweep, nb, bounds, prims)
            .unwrap_or_else(|| self.best_split(sweep, nb, bounds, scale, prims));
        match best {
            Some((axis, k, cost)) => {
                // From inside, a node small enough for a leaf is split all the same, and
                // collapsed afterwards if its subtree costs more (`SplitRule::collapse`).
                if !self.inside && n <= self.max_leaf_size && cost >= prims.leaf_cost(n) {
                    return None;
                }
                let (mid, centroids) = partition(refs, &binning, axis, k);
                let bins = &sweep.bins[axis * nb..][..nb];
                let side = |bins: &[Bin]| bins.iter().fold(Bin::EMPTY, |a, b| a.merge(b));
                let (left, right) = (side(&bins[..=k]), side(&bins[k + 1..]));
                debug_assert!(mid == left.count as usize && mid > 0 && mid < n);
                Some(Split {
                    mid,
                    sides: Some([
                        (left.bounds.to_aabb(), centroids[0].to_aabb()),
                        (right.bounds.to_aabb(), centroids[1].to_aabb()),
                    ]),
                })
            }
            // All centroids coincide: SAH cannot separate them, so split the list in half
            // (if it is too big for a leaf) to keep leaves bounded.
            None if n <= self.max_leaf_size => None,
            None => Some(Split::at(n / 2)),
        }
    }
}

impl BinnedSah {
    /// Bins `refs` on all three axes, in parallel chunks for the nodes near the top.
    fn fill_bins(
        &self,
        binning: &Binning,
        refs: &[PrimRef],
        bins: &mut [Bin],
        counting: &mut [CountingBin],
    ) {
        if refs.len() < PARALLEL_PASS {
            binning.fill(refs, bins, counting);
            return;
        }
        // Unions and counts are exact, so how rayon merges the chunks cannot change them.
        let merged = refs
            .par_chunks(PARALLEL_PASS / 2)
            .map(|chunk| {
                let mut local = vec![Bin::EMPTY; bins.len()];
                let mut counting = vec![CountingBin::EMPTY; 2 * bins.len()];
                binning.fill(chunk, &mut local, &mut counting);
                local
            })
            .reduce(
                || vec![Bin::EMPTY; bins.len()],
                |a, b| a.iter().zip(&b).map(|(x, y)| x.merge(y)).collect(),
            );
        bins.copy_from_slice(&merged);
    }

    /// The cheapest binned split as (axis, last bin on the left, SAH cost in units of one
    /// primitive test), or `None` when all centroids coincide.
    fn best_split(
        &self,
        sweep: &mut Sweep,
        nb: usize,
        bounds: &Aabb,
        scale: Vec3,
        prims: &BuildPrims,
    ) -> Option<(usize, usize, f32)> {
        let mut best: Option<(usize, usize, f32)> = None;
        let mut best_sides = f32::INFINITY;
        let parent_area = bounds.surface_area().max(f32::MIN_POSITIVE);
        let parent_volume = bounds.volume();
        let Sweep {
            bins,
            right_area,
            right_volume,
            right_count,
            ..
        } = sweep;
        for axis in 0..3 {
            if scale[axis] <= 0.0 {
                continue;
            }
            let bins = &bins[axis * nb..][..nb];
            // Sweep from the right, then from the left, evaluating the split after bin k.
            // A side's area is only used when it holds primitives (so its box is not empty).
            let (mut acc, mut count) = (SimdBox::EMPTY, 0);
            for k in (1..nb).rev() {
                acc = acc.union(&bins[k].bounds);
                count += bins[k].count;
                right_area[k] = acc.surface_area();
                if self.inside {
                    right_volume[k] = acc.volume();
                }
                right_count[k] = count;
            }
            let (mut acc, mut count) = (SimdBox::EMPTY, 0);
            for k in 0..nb - 1 {
                acc = acc.union(&bins[k].bounds);
                count += bins[k].count;
                if count == 0 || right_count[k + 1] == 0 {
                    continue;
                }
                let (left_cost, right_cost) = (
                    prims.leaf_cost(count as usize),
                    prims.leaf_cost(right_count[k + 1] as usize),
                );
                let sides = if self.inside {
                    // In units of the parent's area, as `sides` is below.
                    let share = |a: f32, v: f32| inside_share(a, v, parent_area, parent_volume);
                    parent_area
                        * (share(acc.surface_area(), acc.volume()) * left_cost
                            + share(right_area[k + 1], right_volume[k + 1]) * right_cost)
                } else {
                    acc.surface_area() * left_cost + right_area[k + 1] * right_cost
                };
                // The cost rounds monotonically in `sides`, so a split whose `sides`
                // exceeds the best one's cannot cost strictly less: skip its division.
                if sides > best_sides {
                    continue;
                }
                let cost = self.traversal_cost + sides / parent_area;
                if best.is_none_or(|(_, _, c)| cost < c) {
                    best = Some((axis, k, cost));
                    best_sides = sides;
                }
            }
        }
        best
    }

    /// `best_split` with the three axes in SIMD lanes: per candidate the same operations
    /// in the same order, lane by lane, so the same costs bit for bit, and the same choice
    /// (the first strict minimum in axis-major order). `None` where a candidate's cost is
    /// NaN (boxes with NaN or opposite infinities), whose choice the scalar sweep's order
    /// decides: the caller asks it. The scalar sweep (its areas one box at a time, a
    /// branch on every candidate) was a seventh of a build.
    fn best_split_in_lanes(
        &self,
        sweep: &mut Sweep,
        nb: usize,
        bounds: &Aabb,
        prims: &BuildPrims,
    ) -> Option<Option<(usize, usize, f32)>> {
        let parent_area = bounds.surface_area().max(f32::MIN_POSITIVE);
        let parent_volume = bounds.volume();
        let Sweep {
            bins, right_lanes, ..
        } = sweep;
        let bin = |axis: usize, k: usize| &bins[axis * nb + k];
        // The three axes' boxes as one box per axis: their areas and (from inside) volumes
        // in lanes (x, y, z = the axis binned), each lane `SimdBox::surface_area`'s and
        // `SimdBox::volume`'s operations.
        let measures = |acc: &[SimdBox; 3]| {
            let e = Mat3A::from_cols(
                acc[0].max - acc[0].min,
                acc[1].max - acc[1].min,
                acc[2].max - acc[2].min,
            )
            .transpose();
            let (x, y, z) = (e.x_axis, e.y_axis, e.z_axis);
            let volume = if self.inside { x * y * z } else { Vec3A::ZERO };
            (2.0 * (x * y + y * z + z * x), volume)
        };
        // `inside_share` lane by lane.
        let share = |area: Vec3A, volume: Vec3A| {
            if parent_volume > 0.0 {
                0.5 * (area / parent_area) + 0.5 * (volume / parent_volume)
            } else {
                area / parent_area
            }
        };
        let costs = |count: [u32; 3]| Vec3A::from_array(count.map(|c| prims.leaf_cost(c as usize)));
        let (mut acc, mut count) = ([SimdBox::EMPTY; 3], [0u32; 3]);
        for k in (1..nb).rev() {
            for axis in 0..3 {
                acc[axis] = acc[axis].union(&bin(axis, k).bounds);
                count[axis] += bin(axis, k).count;
            }
            let (area, volume) = measures(&acc);
            right_lanes[k] = [area, volume, costs(count)];
        }
        // Per lane: whether a candidate was found, the best cost and its bin.
        let (mut found, mut best, mut best_k) = (BVec3A::FALSE, Vec3A::INFINITY, Vec3A::ZERO);
        let mut nan = BVec3A::FALSE;
        let (mut acc, mut count) = ([SimdBox::EMPTY; 3], [0u32; 3]);
        for k in 0..nb - 1 {
            for axis in 0..3 {
                acc[axis] = acc[axis].union(&bin(axis, k).bounds);
                count[axis] += bin(axis, k).count;
            }
            let [right_area, right_volume, right_cost] = right_lanes[k + 1];
            let left_cost = costs(count);
            // A side without primitives costs 0 (and only then): no split there.
            let valid = left_cost.cmpgt(Vec3A::ZERO) & right_cost.cmpgt(Vec3A::ZERO);
            let (area, volume) = measures(&acc);
            let sides = if self.inside {
                parent_area
                    * (share(area, volume) * left_cost
                        + share(right_area, right_volume) * right_cost)
            } else {
                area * left_cost + right_area * right_cost
            };
            let cost = self.traversal_cost + sides / parent_area;
            nan |= valid & cost.is_nan_mask();
            let better = valid & (cost.cmplt(best) | !found);
            best = Vec3A::select(better, cost, best);
            best_k = Vec3A::select(better, Vec3A::splat(k as f32), best_k);
            found |= valid;
        }
        if nan.any() {
            return None;
        }
        let mut choice: Option<(usize, usize, f32)> = None;
        for axis in (0..3).filter(|&a| found.test(a)) {
            if choice.is_none_or(|(_, _, c)| best[axis] < c) {
                choice = Some((axis, best_k[axis] as usize, best[axis]));
            }
        }
        Some(choice)
    }
}

/// Truncates lanes known to lie in [0, 2²³) to integers without `as`, which would check
/// each lane for NaN and overflow (a fifth of binning's time), and without `floor`, which
/// baseline x86-64 (SSE2) emulates in a dozen instructions: a float plus 2²³ rounds to
/// the nearest integer and holds it in its mantissa's bits; a lane that rounded up is
/// one less.
#[inline(always)]
pub(super) fn truncate_lanes(v: Vec3A) -> [usize; 3] {
    const MANTISSA: u32 = (1 << 23) - 1;
    let magic = Vec3A::splat(8_388_608.0);
    let f = v + magic;
    let up = (f - magic).cmpgt(v).bitmask() as usize;
    [
        (f.x.to_bits() & MANTISSA) as usize - (up & 1),
        (f.y.to_bits() & MANTISSA) as usize - ((up >> 1) & 1),
        (f.z.to_bits() & MANTISSA) as usize - ((up >> 2) & 1),
    ]
}

/// Moves the references whose bin on `axis` is at most `last_left` to the front, and
/// returns how many they are and the centroid bounds of both sides. Two cursors swap
/// misplaced pairs, so each reference moves at most once.
fn partition(
    refs: &mut [PrimRef],
    binning: &Binning,
    axis: usize,
    last_left: usize,
) -> (usize, [SimdBox; 2]) {
    // bins_of(c)[axis] <= last_left exactly when the unclamped position is below the next
    // bin's start (NaN, which bins_of sends to bin 0, compares false and goes left too),
    // which saves the conversion to an integer.
    let next = (last_left + 1) as f32;
    let goes_right = |c: Vec3A| binning.position(c)[axis] >= next;
    let (mut left, mut right) = (SimdBox::EMPTY, SimdBox::EMPTY);
    let (mut i, mut j) = (0, refs.len());
    loop {
        // Advance i over references that belong left, j back over those that belong right.
        while i < j {
            let c = refs[i].centroid();
            if goes_right(c) {
                break;
            }
            left.grow_point(c);
            i += 1;
        }
        while i < j {
            let c = refs[j - 1].centroid();
            if !goes_right(c) {
                break;
            }
            right.grow_point(c);
            j -= 1;
        }
        if i == j {
            return (i, [left, right]);
        }
        // refs[i] belongs right and refs[j - 1] left: swap them into place.
        refs.swap(i, j - 1);
        left.grow_point(refs[i].centroid());
        right.grow_point(refs[j - 1].centroid());
        i += 1;
        j -= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::hash::uniform;

    /// References with centroids spread over [lo, lo + 16·size) on every axis, a quarter of
    /// them exactly on bin borders (where truncation and the partition's comparison must
    /// agree).
    fn references(n: u32, lo: f32, size: f32) -> Vec<PrimRef> {
        (0..n)
            .map(|i| {
                let c = Vec3::from_array(std::array::from_fn(|a| {
                    let u = uniform(i, 0, 0, a as u32, 7) * 16.0;
                    lo + size * if i % 4 == 0 { u.floor() } else { u }
                }));
                PrimRef::new(i, &Aabb::new(c, c))
            })
            .collect()
    }

    #[test]
    fn the_partition_splits_where_the_bins_do() {
        for (lo, size) in [(-3.0, 1e-3), (0.0, 1.0), (1e3, 1e3)] {
            let refs = references(500, lo, size);
            let extent = refs.iter().fold(SimdBox::EMPTY, |mut b, r| {
                b.grow_point(r.centroid());
                b
            });
            let nb = 16;
            let binning = Binning {
                lo: extent.min,
                scale: nb as f32 / (extent.max - extent.min),
                last: Vec3A::splat((nb - 1) as f32),
                bins: nb,
            };
            let mut bins = vec![Bin::EMPTY; 3 * nb];
            binning.fill(&refs, &mut bins, &mut vec![CountingBin::EMPTY; 6 * nb]);
            for axis in 0..3 {
                let axis_bins = &bins[axis * nb..][..nb];
                assert_eq!(axis_bins.iter().map(|b| b.count).sum::<u32>(), 500);
                for k in 0..nb - 1 {
                    let mut moved = refs.clone();
                    let (mid, [left, right]) = partition(&mut moved, &binning, axis, k);
                    let expected: u32 = axis_bins[..=k].iter().map(|b| b.count).sum();
                    assert_eq!(mid, expected as usize, "scale {size}, axis {axis}, bin {k}");
                    for (i, r) in moved.iter().enumerate() {
                        let bin = binning.bins_of(r.centroid())[axis];
                        assert_eq!(bin <= k, i < mid, "scale {size}, axis {axis}, bin {k}");
                        let side = if i < mid { left } else { right };
                        let c = r.centroid();
                        assert!(side.min.cmple(c).all() && side.max.cmpge(c).all());
                    }
                    let mut indices: Vec<u32> = moved.iter().map(PrimRef::index).collect();
                    indices.sort_unstable();
                    assert!(indices.iter().copied().eq(0..500));
                }
            }
        }
    }

    /// The two sets of bins merge into exactly the bins of one reference at a time, for
    /// an odd and an even number of references.
    #[test]
    fn two_sets_of_bins_merge_into_the_bins_of_one() {
        let nb = 16;
        for n in [1, 2, 499, 500] {
            let refs = references(n, -3.0, 0.5);
            let extent = refs.iter().fold(SimdBox::EMPTY, |mut b, r| {
                b.grow_point(r.centroid());
                b
            });
            let binning = Binning {
                lo: extent.min,
                scale: Vec3A::select(
                    (extent.max - extent.min).cmpgt(Vec3A::ZERO),
                    nb as f32 / (extent.max - extent.min),
                    Vec3A::ZERO,
                ),
                last: Vec3A::splat((nb - 1) as f32),
                bins: nb,
            };
            let mut bins = vec![Bin::EMPTY; 3 * nb];
            binning.fill(&refs, &mut bins, &mut vec![CountingBin::EMPTY; 6 * nb]);
            // The bins one reference at a time, boxes grown and counts in integers.
            let mut one = vec![Bin::EMPTY; 3 * nb];
            for r in &refs {
                let [bx, by, bz] = binning.bins_of(r.centroid());
                for bin in [bx, nb + by, 2 * nb + bz] {
                    one[bin].count += 1;
                    one[bin].bounds.grow(r.min(), r.max());
                }
            }
            for (a, b) in bins.iter().zip(&one) {
                assert_eq!(a.count, b.count, "{n} references");
                assert_eq!(a.bounds.min.to_array(), b.bounds.min.to_array());
                assert_eq!(a.bounds.max.to_array(), b.bounds.max.to_array());
            }
            assert_eq!(bins.iter().map(|b| b.count).sum::<u32>(), 3 * n);
        }
    }

    /// The sweep in lanes picks the scalar sweep's split (axis, bin and cost, bit for
    /// bit) on references spread over every axis, flat on one or two axes (flat parents
    /// have no volume), in clumps (ties between candidates), at three scales, for single
    /// primitives and packs, for rays from outside and from inside.
    #[test]
    fn the_sweep_in_lanes_is_the_scalar_sweep() {
        let mut cases = 0;
        for (lo, size) in [(-3.0, 1e-3), (0.0, 1.0), (1e3, 1e3)] {
            for n in [2, 5, 9, 40, 300] {
                for flat in 0..4u32 {
                    let refs: Vec<PrimRef> = references(n, lo, size)
                        .into_iter()
                        .enumerate()
                        .map(|(i, r)| {
                            let (mut min, mut max) = (r.min(), r.max());
                            for axis in 0..3 {
                                // flat 1 and 2: the first axes all on one plane; 3:
                                // every primitive in one of two clumps.
                                if (axis as u32) < flat.min(2) || (flat == 3 && i % 2 == 0) {
                                    min[axis] = lo;
                                    max[axis] = lo + size;
                                }
                            }
                            PrimRef::new(i as u32, &Aabb::new(min.into(), max.into()))
                        })
                        .collect();
                    for test_block in [1, 4] {
                        let prims = BuildPrims {
                            bounds: Vec::new(),
                            test_block,
                            triangles: Vec::new(),
                        };
                        for inside in [false, true] {
                            let rule = BinnedSah {
                                bins: 32,
                                max_leaf_size: 8,
                                traversal_cost: if inside { 0.33 } else { 1.0 },
                                inside,
                            };
                            let (mut bounds, mut centroids) = (SimdBox::EMPTY, SimdBox::EMPTY);
                            for r in &refs {
                                bounds.grow(r.min(), r.max());
                                centroids.grow_point(r.centroid());
                            }
                            let (bounds, centroids) = (bounds.to_aabb(), centroids.to_aabb());
                            let nb = rule.bins.min((refs.len() / 8).max(4));
                            let extent = centroids.max - centroids.min;
                            let scale = Vec3::select(
                                extent.cmpgt(Vec3::ZERO),
                                nb as f32 / extent,
                                Vec3::ZERO,
                            );
                            let binning = Binning {
                                lo: centroids.min.into(),
                                scale: scale.into(),
                                last: Vec3A::splat((nb - 1) as f32),
                                bins: nb,
                            };
                            let mut sweep = rule.scratch();
                            let bins = &mut sweep.bins[..3 * nb];
                            rule.fill_bins(&binning, &refs, bins, &mut sweep.counting);
                            let scalar = rule.best_split(&mut sweep, nb, &bounds, scale, &prims);
                            let lanes = rule.best_split_in_lanes(&mut sweep, nb, &bounds, &prims);
                            let case = format!("{n} references, scale {size}, flat {flat}");
                            assert_eq!(
                                lanes,
                                Some(scalar),
                                "{case}, block {test_block}, inside {inside}"
                            );
                            cases += usize::from(scalar.is_some());
                        }
                    }
                }
            }
        }
        assert!(cases > 200, "only {cases} cases had a split");
    }

    #[test]
    fn truncation_is_the_integer_part() {
        for x in [
            0.0,
            0.25,
            0.999_999_9,
            1.0,
            7.5,
            15.0,
            15.999_999,
            31.0,
            4_194_303.5,
        ] {
            let v = Vec3A::new(x, x * 0.5, (x * 0.25).floor());
            assert_eq!(
                truncate_lanes(v),
                [x as usize, (x * 0.5) as usize, (x * 0.25).floor() as usize]
            );
        }
        // Every integer up to 64, the floats next to it, and halves (which round to even).
        for i in 0..64u32 {
            let x = i as f32;
            let below = f32::from_bits(x.to_bits().saturating_sub(1)).max(0.0);
            let above = f32::from_bits(x.to_bits() + 1);
            let v = Vec3A::new(below, above, x + 0.5);
            assert_eq!(
                truncate_lanes(v),
                [below as usize, above as usize, i as usize],
                "{below} {above} {}",
                x + 0.5
            );
        }
    }
}
