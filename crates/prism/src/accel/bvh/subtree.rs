//! Ways into a BVH below its root, for a structure that knows which part of the scene a ray
//! can meet (the light buffer's cells, `integrator/light_buffer.rs`): the subtrees a wide
//! node's lanes hold, entry nodes made of a few of them in the tree's own layout, and the
//! query from an entry node. That query is the tree's own walk and leaf tests, started
//! lower down: over subtrees holding every primitive a ray may meet, it answers exactly as
//! `Accel::query` does (the tie rule makes the nearest hit among any superset of the
//! primitives a ray meets the brute-force one).

use super::accel::Root;
use super::wide::{Lanes, Wide8Node, WideNode};
use super::Bvh;
use crate::accel::{Hit, PacketQuery, QueryMode};
use crate::geometry::Geometry;
use crate::math::{Aabb, TraceRay};
use crate::stats::Stats;

/// One subtree: a wide node's lane (its box, and an interior child's node or a leaf's
/// primitives or packs), or the root when the root is a leaf.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Subtree {
    /// Its box, which holds all of its primitives.
    pub bounds: Aabb,
    child: u32,
    count: u32,
}

impl Subtree {
    /// Whether it is a leaf (its primitives are tested directly).
    pub fn is_leaf(&self) -> bool {
        self.count > 0
    }

    fn lane(&self) -> (Aabb, u32, u32) {
        (self.bounds, self.child, self.count)
    }
}

/// Entry nodes over one tree, in its layout (`Bvh::entry_nodes`).
pub struct EntryNodes {
    layout: Layout,
}

enum Layout {
    Four(Vec<WideNode>),
    Eight(Vec<Wide8Node>),
}

/// One entry node, where `Bvh::query_entry` starts.
#[derive(Clone, Copy)]
pub struct Entry<'a>(Root<'a>);

impl EntryNodes {
    /// Entry node `index`.
    #[inline(always)]
    pub fn get(&self, index: u32) -> Entry<'_> {
        Entry(match &self.layout {
            Layout::Four(n) => Root::Four(&n[index as usize]),
            Layout::Eight(n) => Root::Eight(&n[index as usize]),
        })
    }

    /// How many there are.
    pub fn len(&self) -> usize {
        match &self.layout {
            Layout::Four(n) => n.len(),
            Layout::Eight(n) => n.len(),
        }
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Bytes they take.
    pub fn memory_bytes(&self) -> usize {
        match &self.layout {
            Layout::Four(n) => std::mem::size_of_val(n.as_slice()),
            Layout::Eight(n) => std::mem::size_of_val(n.as_slice()),
        }
    }
}

impl Bvh {
    /// The subtrees the root holds: its wide node's lanes, or the root itself when it is a
    /// leaf; none for an empty tree.
    pub fn root_subtrees(&self) -> Vec<Subtree> {
        let Some(root) = self.nodes.first() else {
            return Vec::new();
        };
        if root.is_leaf() {
            return vec![Subtree {
                bounds: root.bounds(),
                child: root.first,
                count: root.count,
            }];
        }
        if self.wide8.is_empty() {
            lanes(&self.wide[0])
        } else {
            lanes(&self.wide8[0])
        }
    }

    /// The subtrees interior subtree `s` holds (its node's lanes); none for a leaf.
    pub fn subtrees_of(&self, s: &Subtree) -> Vec<Subtree> {
        if s.is_leaf() {
            Vec::new()
        } else if self.wide8.is_empty() {
            lanes(&self.wide[s.child as usize])
        } else {
            lanes(&self.wide8[s.child as usize])
        }
    }

    /// The most subtrees an entry node holds: the width of the tree's nodes.
    pub fn entry_width(&self) -> usize {
        match self.empty_layout() {
            Layout::Four(_) => WideNode::WIDTH,
            Layout::Eight(_) => Wide8Node::WIDTH,
        }
    }

    /// One entry node per list, each of at most `entry_width()` of this tree's subtrees.
    pub fn entry_nodes<'a>(&self, lists: impl IntoIterator<Item = &'a [Subtree]>) -> EntryNodes {
        let node = |l: &[Subtree]| l.iter().map(Subtree::lane).collect::<Vec<_>>();
        let layout = match self.empty_layout() {
            Layout::Four(mut v) => {
                v.extend(lists.into_iter().map(|l| WideNode::of_lanes(&node(l))));
                Layout::Four(v)
            }
            Layout::Eight(mut v) => {
                v.extend(lists.into_iter().map(|l| Wide8Node::of_lanes(&node(l))));
                Layout::Eight(v)
            }
        };
        EntryNodes { layout }
    }

    /// The 8-wide layout where the tree has it; the 4-wide one otherwise (also for a tree
    /// whose root is a leaf, which has neither: a walk over leaves needs no wide node).
    fn empty_layout(&self) -> Layout {
        if self.wide8.is_empty() {
            Layout::Four(Vec::new())
        } else {
            Layout::Eight(Vec::new())
        }
    }

    /// What `Accel::query` answers over the primitives of `entry`'s subtrees (an entry
    /// node this tree made).
    #[inline(always)]
    pub fn query_entry(
        &self,
        entry: Entry,
        geometry: &Geometry,
        ray: &TraceRay,
        t_max: f32,
        mode: QueryMode,
        stats: &mut Stats,
    ) -> Option<Hit> {
        self.walk_from(entry.0, geometry, ray, t_max, mode, stats)
    }

    /// `query_entry` for a packet of rays (at most `accel::PACKET_MAX`), walked together
    /// where they are coherent: `answers[i]` is what `query_entry` gives ray i.
    pub fn query_entry_packet(
        &self,
        entry: Entry,
        packet: &PacketQuery,
        answers: &mut [Option<Hit>],
        stats: &mut Stats,
    ) {
        super::packet::query(self, Some(entry.0), packet, answers, stats)
    }
}

fn lanes<N: Lanes>(node: &N) -> Vec<Subtree> {
    (0..N::WIDTH)
        .filter_map(|k| node.lane(k))
        .map(|(bounds, child, count)| Subtree {
            bounds,
            child,
            count,
        })
        .collect()
}
