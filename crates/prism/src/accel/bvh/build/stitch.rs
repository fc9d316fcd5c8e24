//! Subtrees built on separate threads, and their stitching into the one node array that a
//! serial depth-first build would have produced: a node, then its two children side by
//! side, then the left child's descendants, then the right child's.

use super::super::Node;

pub(in crate::accel::bvh) enum NodeBlock {
    /// Built on one thread: `nodes[0]` is the root and the rest its descendants in build
    /// order, children indices counted from the start of this vector.
    Serial(Vec<Node>),
    /// A root whose two subtrees were built separately; its descendants are the two child
    /// roots, then the left child's descendants, then the right child's.
    Split {
        root: Node,
        left: Box<NodeBlock>,
        right: Box<NodeBlock>,
        descendants: usize,
    },
}

impl NodeBlock {
    pub(super) fn leaf(node: Node) -> NodeBlock {
        NodeBlock::Serial(vec![node])
    }

    /// An interior node over two subtrees (its `first` is set when stitched).
    pub(super) fn split(root: Node, left: NodeBlock, right: NodeBlock) -> NodeBlock {
        NodeBlock::Split {
            root,
            descendants: 2 + left.descendants() + right.descendants(),
            left: Box::new(left),
            right: Box::new(right),
        }
    }

    pub(super) fn root(&self) -> &Node {
        match self {
            NodeBlock::Serial(nodes) => &nodes[0],
            NodeBlock::Split { root, .. } => root,
        }
    }

    fn descendants(&self) -> usize {
        match self {
            NodeBlock::Serial(nodes) => nodes.len() - 1,
            NodeBlock::Split { descendants, .. } => *descendants,
        }
    }

    /// The root, its children index moved for descendants that start at `base` (>= 1).
    fn root_at(&self, base: u32) -> Node {
        match self {
            NodeBlock::Serial(nodes) => nodes[0].relocated(base - 1),
            NodeBlock::Split { root, .. } => Node {
                first: base,
                ..*root
            },
        }
    }

    /// Appends the descendants to `out`, which holds `base` nodes.
    fn write_descendants(&self, base: u32, out: &mut Vec<Node>) {
        debug_assert_eq!(out.len(), base as usize);
        match self {
            NodeBlock::Serial(nodes) => {
                out.extend(nodes[1..].iter().map(|n| n.relocated(base - 1)));
            }
            NodeBlock::Split { left, right, .. } => {
                let left_base = base + 2;
                let right_base = left_base + left.descendants() as u32;
                out.push(left.root_at(left_base));
                out.push(right.root_at(right_base));
                left.write_descendants(left_base, out);
                right.write_descendants(right_base, out);
            }
        }
    }

    /// The whole tree as one array, root first.
    pub(super) fn into_nodes(self) -> Vec<Node> {
        match self {
            NodeBlock::Serial(nodes) => nodes,
            block => {
                let mut out = Vec::with_capacity(1 + block.descendants());
                out.push(block.root_at(1));
                block.write_descendants(1, &mut out);
                out
            }
        }
    }
}
