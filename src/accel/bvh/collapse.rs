//! The binary tree the SAH builds ([`super::build`]), collapsed into the four-wide
//! [`Node`]s rays walk, on all threads, with the same layout on any number of them.

use super::binary::BinNode;
use super::{Node, WIDTH};
use crate::accel::pages::vec_on_huge_pages;
use arrayvec::ArrayVec;

/// The collapse into wide nodes shares the tree among threads in this many subtrees.
const COLLAPSE_SUBTREES: usize = 64;

/// Turns the binary tree into four-wide nodes: each wide node takes a binary node's two
/// children, then keeps replacing the inner child with the largest surface by its own two
/// children until it holds four (or only leaves are left). Halves the depth, so a ray opens
/// about half as many nodes and tests four boxes with each.
pub(super) fn collapse(binary: &[BinNode]) -> Vec<Node> {
    // Only the top of the tree goes here; the whole array is made once its size is known.
    let mut nodes = Vec::with_capacity(WIDTH * COLLAPSE_SUBTREES);
    nodes.push(Node::EMPTY);
    // The top of the tree breadth first, until there are subtrees enough to share among the
    // threads; each is then collapsed on its own and appended in this order (so the layout
    // does not depend on the number of threads).
    let mut frontier = std::collections::VecDeque::from([(0usize, 0usize)]);
    while frontier.len() < COLLAPSE_SUBTREES {
        let Some((b, w)) = frontier.pop_front() else {
            break;
        };
        nodes[w] = wide_node(binary, b, &mut nodes, &mut frontier);
    }
    let frontier = Vec::from(frontier);
    use rayon::prelude::*;
    let parts: Vec<Vec<Node>> = frontier
        .par_iter()
        .map(|&(b, _)| {
            let mut part = vec![Node::EMPTY];
            let mut todo = vec![(b, 0)];
            while let Some((b, w)) = todo.pop() {
                part[w] = wide_node(binary, b, &mut part, &mut todo);
            }
            part
        })
        .collect();
    // Part i's node j ≥ 1 lands at shift_i + j; its root replaces the placeholder at w.
    let mut shifts = Vec::with_capacity(parts.len());
    let mut end = nodes.len();
    for part in &parts {
        shifts.push((end - 1) as u32);
        end += part.len() - 1;
    }
    // Inner lanes are those with no primitives and a child other than 0 (the root is
    // nobody's child; unused lanes point at 0), whatever their box.
    let fix = |n: &Node, shift: u32| {
        let mut n = *n;
        for lane in 0..WIDTH {
            if n.count[lane] == 0 && n.child[lane] != 0 {
                n.child[lane] += shift;
            }
        }
        n
    };
    for ((&(_, w), part), &shift) in frontier.iter().zip(&parts).zip(&shifts) {
        nodes[w] = fix(&part[0], shift);
    }
    // The rest is copied in parallel, each part into its own stretch of the array, which is
    // made here at its final size (on huge pages when big: `crate::accel::pages`).
    let top = nodes.len();
    let mut nodes = {
        let mut all = vec_on_huge_pages(end);
        all.extend_from_slice(&nodes);
        all
    };
    nodes.par_extend(rayon::iter::repeat_n(Node::EMPTY, end - top));
    let mut stretches = Vec::with_capacity(parts.len());
    let mut free = &mut nodes[top..];
    for part in &parts {
        let (stretch, rest) = free.split_at_mut(part.len() - 1);
        stretches.push(stretch);
        free = rest;
    }
    stretches
        .into_par_iter()
        .zip(parts.into_par_iter().zip(shifts))
        .for_each(|(stretch, (part, shift))| {
            for (slot, n) in stretch.iter_mut().zip(&part[1..]) {
                *slot = fix(n, shift);
            }
        });
    nodes
}

// ANCHOR: collapse
/// The wide node for binary node `b`: its two children, then the inner child with the
/// largest surface replaced by its own two children until there are four (or only leaves).
/// Inner lanes get a placeholder appended to `nodes`, and (binary node, its index) goes to
/// `pending` to be filled in later.
fn wide_node(
    binary: &[BinNode],
    b: usize,
    nodes: &mut Vec<Node>,
    pending: &mut impl Extend<(usize, usize)>,
) -> Node {
    let root = &binary[b];
    let mut kids = ArrayVec::<usize, WIDTH>::new();
    if root.is_leaf() {
        kids.push(b); // a one-leaf tree: the root node holds just that leaf
    } else {
        kids.extend([root.first as usize, root.first as usize + 1]);
    }
    while kids.len() < WIDTH {
        let widest = kids
            .iter()
            .enumerate()
            .filter(|(_, &k)| !binary[k].is_leaf())
            .max_by(|(i, &a), (j, &b)| {
                binary[a]
                    .half_area()
                    .total_cmp(&binary[b].half_area())
                    .then(j.cmp(i)) // ties: the leftmost
            })
            .map(|(i, _)| i);
        let Some(i) = widest else { break };
        let first = binary[kids[i]].first as usize;
        kids[i] = first;
        kids.insert(i + 1, first + 1);
    }
    let mut node = Node::EMPTY;
    for (lane, &k) in kids.iter().enumerate() {
        let bn = &binary[k];
        for axis in 0..3 {
            node.planes[0][axis][lane] = bn.min[axis];
            node.planes[1][axis][lane] = bn.max[axis];
        }
        node.count[lane] = bn.count;
        node.child[lane] = if bn.is_leaf() {
            bn.first
        } else {
            nodes.push(Node::EMPTY);
            pending.extend([(k, nodes.len() - 1)]);
            (nodes.len() - 1) as u32
        };
    }
    node
}
// ANCHOR_END: collapse
