//! Reinsertion (Bittner, Hapala, Havran 2013, "Fast insertion-based optimization of
//! bounding volume hierarchies"): repeatedly take the subtrees whose boxes are most
//! wasteful, cut each out, and put it back where a branch-and-bound search over the tree
//! finds the smallest growth in total box area.
//!
//! Leaves are moved whole and keep their primitives, so the SAH cost changes only through
//! the interior nodes' areas: minimising their sum minimises the cost for any traversal
//! cost. Each move is never worse than putting the subtree back where it was (that spot is
//! a candidate), no move makes the tree deeper than the builders may, and the result is
//! returned only if its cost beats the input's.

use super::{Node, MAX_DEPTH};
use crate::math::Aabb;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// The deepest a leaf may sit, as in the builders (the root has depth 1).
const DEPTH_LIMIT: u32 = MAX_DEPTH as u32 - 1;
/// Rounds of (rank, reinsert a batch); the first few give most of the gain, and a round
/// on a million-node tree takes a few hundred milliseconds.
const MAX_ROUNDS: usize = 10;
/// Stop once a round gains less than this fraction of the interior area.
const MIN_GAIN: f64 = 5e-4;
/// The fraction of the nodes reinserted per round.
const BATCH_FRACTION: usize = 50;
const NONE: u32 = u32::MAX;

/// The tree with the same leaves and a total interior area no larger than the input's.
pub(super) fn optimize(nodes: Vec<Node>) -> Vec<Node> {
    if nodes.len() < 5 {
        return nodes;
    }
    let input_area = interior_area(&nodes);
    let mut tree = Tree::from_nodes(&nodes);
    let mut area = input_area;
    // Nodes already reinserted sit out later rounds, so each round reaches new ones rather
    // than retrying the same few worst, which after one round stay where they are.
    let mut done = vec![false; nodes.len()];
    for _ in 0..MAX_ROUNDS {
        let batch = tree.worst_nodes(nodes.len().div_ceil(BATCH_FRACTION), &done);
        if batch.is_empty() {
            break;
        }
        for n in batch {
            done[n as usize] = true;
            tree.reinsert(n);
        }
        let new_area = tree.interior_area();
        let gain = area - new_area;
        area = new_area;
        if gain < MIN_GAIN * area {
            break;
        }
    }
    let optimized = tree.into_nodes();
    // A margin far above the rounding of the sums, so "better" holds for any summation order.
    if interior_area(&optimized) < input_area * (1.0 - 1e-9) {
        optimized
    } else {
        nodes
    }
}

/// Sum of the interior nodes' surface areas.
fn interior_area(nodes: &[Node]) -> f64 {
    nodes
        .iter()
        .filter(|n| !n.is_leaf())
        .map(|n| n.bounds().surface_area() as f64)
        .sum()
}

/// The hierarchy with parent links, in which subtrees can be cut out and put back.
struct Tree {
    bounds: Vec<Aabb>,
    area: Vec<f32>,
    parent: Vec<u32>,
    /// `[NONE, NONE]` for leaves.
    children: Vec<[u32; 2]>,
    /// Levels of the subtree (a leaf has height 1).
    height: Vec<u32>,
    /// The leaves' primitive ranges.
    leaf: Vec<(u32, u32)>,
    root: u32,
}

impl Tree {
    fn from_nodes(nodes: &[Node]) -> Tree {
        let n = nodes.len();
        let mut tree = Tree {
            bounds: nodes.iter().map(Node::bounds).collect(),
            area: nodes.iter().map(|n| n.bounds().surface_area()).collect(),
            parent: vec![NONE; n],
            children: vec![[NONE; 2]; n],
            height: vec![1; n],
            leaf: nodes.iter().map(|n| (n.first, n.count)).collect(),
            root: 0,
        };
        for (i, node) in nodes.iter().enumerate() {
            if !node.is_leaf() {
                let c = [node.first, node.first + 1];
                tree.children[i] = c;
                tree.parent[c[0] as usize] = i as u32;
                tree.parent[c[1] as usize] = i as u32;
            }
        }
        // Children sit after their parents in the array, so a backward pass sees every
        // child before its parent.
        for i in (0..n).rev() {
            let [a, b] = tree.children[i];
            if a != NONE {
                tree.height[i] = 1 + tree.height[a as usize].max(tree.height[b as usize]);
            }
        }
        tree
    }

    fn is_leaf(&self, n: u32) -> bool {
        self.children[n as usize][0] == NONE
    }

    fn interior_area(&self) -> f64 {
        self.reachable()
            .into_iter()
            .filter(|&n| !self.is_leaf(n))
            .map(|n| self.area[n as usize] as f64)
            .sum()
    }

    /// Every node in the tree (all of them: cutting and reinserting reuses the cut node).
    fn reachable(&self) -> Vec<u32> {
        let mut out = Vec::with_capacity(self.parent.len());
        let mut stack = vec![self.root];
        while let Some(n) = stack.pop() {
            out.push(n);
            if !self.is_leaf(n) {
                stack.extend(self.children[n as usize]);
            }
        }
        out
    }

    /// The `count` nodes not `done` with the worst boxes by Bittner's combined measure:
    /// large, and much larger than their children. Nodes next to the root are not moved.
    fn worst_nodes(&self, count: usize, done: &[bool]) -> Vec<u32> {
        let mut ranked: Vec<(f32, u32)> = self
            .reachable()
            .into_iter()
            .filter(|&n| !done[n as usize])
            .filter(|&n| n != self.root && self.parent[n as usize] != self.root)
            .map(|n| (self.inefficiency(n), n))
            .collect();
        let count = count.min(ranked.len());
        if count == 0 {
            return Vec::new();
        }
        let worst_first = |a: &(f32, u32), b: &(f32, u32)| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1));
        ranked.select_nth_unstable_by(count - 1, worst_first);
        ranked.truncate(count);
        ranked.sort_unstable_by(worst_first);
        ranked.into_iter().map(|(_, n)| n).collect()
    }

    fn inefficiency(&self, n: u32) -> f32 {
        let a = self.area[n as usize];
        if self.is_leaf(n) {
            return a;
        }
        let [l, r] = self.children[n as usize].map(|c| self.area[c as usize]);
        let tiny = f32::MIN_POSITIVE;
        let m_sum = a / (0.5 * (l + r)).max(tiny);
        let m_min = a / l.min(r).max(tiny);
        m_sum * m_min * a
    }

    /// Recomputes boxes and heights from `n` up to the root.
    fn refit_from(&mut self, mut n: u32) {
        while n != NONE {
            let [a, b] = self.children[n as usize];
            let bounds = self.bounds[a as usize].union(&self.bounds[b as usize]);
            self.bounds[n as usize] = bounds;
            self.area[n as usize] = bounds.surface_area();
            self.height[n as usize] = 1 + self.height[a as usize].max(self.height[b as usize]);
            n = self.parent[n as usize];
        }
    }

    fn replace_child(&mut self, parent: u32, old: u32, new: u32) {
        let slot = &mut self.children[parent as usize];
        let k = (slot[1] == old) as usize;
        slot[k] = new;
        self.parent[new as usize] = parent;
    }

    /// Cuts `n` out and puts it back where the tree's interior area grows least.
    fn reinsert(&mut self, n: u32) {
        let p = self.parent[n as usize];
        if n == self.root || p == NONE || p == self.root {
            return;
        }
        // Cut: the sibling takes the parent's place, and the parent node is free.
        let [a, b] = self.children[p as usize];
        let sibling = if a == n { b } else { a };
        let grandparent = self.parent[p as usize];
        self.replace_child(grandparent, p, sibling);
        self.refit_from(grandparent);

        let target = self.best_sibling_for(n).unwrap_or(sibling);
        // Insert: the freed node becomes the parent of `n` and the target.
        let above = self.parent[target as usize];
        if above == NONE {
            self.root = p;
            self.parent[p as usize] = NONE;
        } else {
            self.replace_child(above, target, p);
        }
        self.children[p as usize] = [target, n];
        self.parent[target as usize] = p;
        self.parent[n as usize] = p;
        self.refit_from(p);
    }

    /// Branch and bound (Bittner et al.): making `n` the sibling of `x` costs the new
    /// parent's area, A(x ∪ n), plus the growth of every ancestor of `x` (the induced
    /// cost). A subtree below `x` costs at least A(n) plus the induced cost at its root,
    /// which prunes the search. `None` only if no place keeps the depth limit, which the old place does in any tree
    /// the builders make.
    fn best_sibling_for(&self, n: u32) -> Option<u32> {
        let n_bounds = self.bounds[n as usize];
        let n_area = self.area[n as usize];
        let n_height = self.height[n as usize];
        let mut best = (f32::INFINITY, NONE);
        let mut queue = BinaryHeap::new();
        queue.push(Candidate {
            induced: 0.0,
            node: self.root,
            depth: 1,
        });
        while let Some(Candidate {
            induced,
            node: x,
            depth,
        }) = queue.pop()
        {
            if induced + n_area >= best.0 {
                break;
            }
            let direct = self.bounds[x as usize].union(&n_bounds).surface_area();
            let total = induced + direct;
            let fits = depth + n_height.max(self.height[x as usize]) <= DEPTH_LIMIT;
            if total < best.0 && fits {
                best = (total, x);
            }
            if !self.is_leaf(x) {
                let induced = induced + direct - self.area[x as usize];
                if induced + n_area < best.0 {
                    for c in self.children[x as usize] {
                        queue.push(Candidate {
                            induced,
                            node: c,
                            depth: depth + 1,
                        });
                    }
                }
            }
        }
        (best.1 != NONE).then_some(best.1)
    }

    /// Back to the flat array: each interior node's children side by side, depth first.
    fn into_nodes(self) -> Vec<Node> {
        let mut out = Vec::with_capacity(self.parent.len());
        out.push(Node::leaf(Aabb::EMPTY, 0, 0));
        let mut stack = vec![(self.root, 0usize)];
        while let Some((n, slot)) = stack.pop() {
            let bounds = self.bounds[n as usize];
            if self.is_leaf(n) {
                let (first, count) = self.leaf[n as usize];
                out[slot] = Node::leaf(bounds, first, count as usize);
            } else {
                let first = out.len();
                out[slot] = Node::interior(bounds, first as u32);
                out.extend([Node::leaf(Aabb::EMPTY, 0, 0); 2]);
                let [a, b] = self.children[n as usize];
                stack.push((b, first + 1));
                stack.push((a, first));
            }
        }
        out
    }
}

/// A queued search position, popped cheapest induced cost first.
struct Candidate {
    induced: f32,
    node: u32,
    depth: u32,
}

impl Ord for Candidate {
    fn cmp(&self, other: &Self) -> Ordering {
        // Reversed: BinaryHeap is a max-heap. Ties by node for determinism.
        other
            .induced
            .total_cmp(&self.induced)
            .then(other.node.cmp(&self.node))
    }
}

impl PartialOrd for Candidate {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Candidate {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Candidate {}
