//! Which facets a beam can see: a small bounding-box hierarchy over the facets, walked
//! with the beam's bounding planes (its four sides through the apex, and the interface it
//! left through), so each beam touches only the facets near it. Conservative: a facet it
//! keeps may still fall outside the beam; clipping removes it exactly.

use super::facets::Facet;
use glam::DVec3;

/// A bounding-box hierarchy over the bounded facets; infinite planes are always kept.
pub(crate) struct Cull {
    nodes: Vec<Node>,
    /// Facet indices in leaf order.
    order: Vec<u32>,
    /// Facets without bounds (infinite planes).
    unbounded: Vec<u32>,
}

struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: `order[start..start + count]`; inner: children at `start` and `start + 1`.
    start: u32,
    count: u32,
}

const LEAF: usize = 4;

impl Cull {
    /// The hierarchy over `facets` (median splits along the longest axis of the centres).
    pub(crate) fn new(facets: &[Facet]) -> Cull {
        let mut items: Vec<(u32, DVec3, DVec3)> = Vec::new();
        let mut unbounded = Vec::new();
        for (i, f) in facets.iter().enumerate() {
            match f.bounds {
                Some((lo, hi)) => items.push((i as u32, lo, hi)),
                None => unbounded.push(i as u32),
            }
        }
        let mut cull = Cull {
            nodes: Vec::new(),
            order: Vec::with_capacity(items.len()),
            unbounded,
        };
        if !items.is_empty() {
            cull.nodes.push(Node {
                lo: DVec3::ZERO,
                hi: DVec3::ZERO,
                start: 0,
                count: 0,
            });
            cull.build(0, &mut items);
        }
        cull
    }

    fn build(&mut self, node: usize, items: &mut [(u32, DVec3, DVec3)]) {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for &(_, a, b) in items.iter() {
            lo = lo.min(a);
            hi = hi.max(b);
        }
        if items.len() <= LEAF {
            self.nodes[node] = Node {
                lo,
                hi,
                start: self.order.len() as u32,
                count: items.len() as u32,
            };
            self.order.extend(items.iter().map(|it| it.0));
            return;
        }
        let ext = hi - lo;
        let axis = if ext.x >= ext.y && ext.x >= ext.z {
            0
        } else if ext.y >= ext.z {
            1
        } else {
            2
        };
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |a, b| {
            (a.1[axis] + a.2[axis]).total_cmp(&(b.1[axis] + b.2[axis]))
        });
        let first = self.nodes.len();
        for _ in 0..2 {
            self.nodes.push(Node {
                lo: DVec3::ZERO,
                hi: DVec3::ZERO,
                start: 0,
                count: 0,
            });
        }
        self.nodes[node] = Node {
            lo,
            hi,
            start: first as u32,
            count: 0,
        };
        let (left, right) = items.split_at_mut(mid);
        self.build(first, left);
        self.build(first + 1, right);
    }

    /// Facets whose bounds meet every half-space n·X + c ≥ 0 of `planes`, and every
    /// infinite plane, appended to `out`.
    pub(crate) fn query(&self, planes: &[(DVec3, f64)], out: &mut Vec<u32>) {
        out.extend_from_slice(&self.unbounded);
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let node = &self.nodes[i];
            // The box corner furthest along each plane's normal.
            let outside = planes.iter().any(|&(n, c)| {
                let far = DVec3::new(
                    if n.x >= 0.0 { node.hi.x } else { node.lo.x },
                    if n.y >= 0.0 { node.hi.y } else { node.lo.y },
                    if n.z >= 0.0 { node.hi.z } else { node.lo.z },
                );
                n.dot(far) + c < 0.0
            });
            if outside {
                continue;
            }
            if node.count > 0 {
                let s = node.start as usize;
                out.extend_from_slice(&self.order[s..s + node.count as usize]);
            } else {
                stack.push(node.start as usize);
                stack.push(node.start as usize + 1);
            }
        }
    }
}
