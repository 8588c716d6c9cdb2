//! The bundle figure's second panel when the bundle opened boxes among the root's children:
//! each box it opened on its own frame, with the children the bundle tested in it; and the
//! letters (A, B, …) that name those boxes in the first panel. Drawn together over the
//! root, a box's children share edges with it and with the other box's children, and the
//! boxes could not be counted.

use super::super::canvas::{Anchor, Canvas};
use super::super::labels::{text_box, Box2, Labels};
use super::super::style;
use super::panel::{opened_color, plated_text, Panel};
use crate::accel::Node;
use crate::math::Ray;
use crate::shapes::{Aabb, LocalHit};

/// The letter that names the `i`th box opened (A, B, …; a bundle opens at most four of the
/// root's children).
fn letter(i: usize) -> char {
    (b'A' + (i % 26) as u8) as char
}

/// Height of a box's caption line above its frame.
const CAPTION: f32 = 16.0;
/// Space between the boxes' frames.
const SPACE: f32 = 12.0;
/// Caption text size.
const SIZE: f32 = 11.0;
/// Pixels a child is drawn inside its edges ([`Panel::level_box`]), so that an edge it
/// shares with its box or a sibling (most of them) shows as two lines.
const CHILD_INSET: f32 = 3.0;

/// Draws each box of `opened` (node, child slot: the boxes the bundle opened among the
/// root's children) in its own part of the area `at`, `size`: in one row, or in two,
/// whichever draws them larger with room for their captions. Each part is captioned with
/// the box's letter and what its children did, framed, and shows the box (dark grey), its
/// children as tested (`tested`: node, slot, the rays that entered), and the bundle's
/// frustum and rays (`bundle`: the rays, their hits).
pub(super) fn draw_zoomed(
    c: &mut Canvas,
    (at, size): ((f32, f32), (f32, f32)),
    opened: &[(usize, usize)],
    tested: &[(usize, usize, u32)],
    nodes: &[Node],
    (rays, hits): (&[Ray], &[Option<LocalHit>]),
) {
    let k = opened.len();
    if k == 0 {
        return;
    }
    let cell_of = |cols: usize, rows: usize| {
        (
            (size.0 - SPACE * (cols as f32 - 1.0)) / cols as f32,
            ((size.1 - SPACE * (rows as f32 - 1.0)) / rows as f32).max(CAPTION + 1.0),
        )
    };
    let children = |node: usize, slot: usize| {
        let child = nodes[node].child[slot] as usize;
        tested.iter().copied().filter(move |t| t.0 == child)
    };
    // Each box's caption: its letter, and what its children did.
    let captions: Vec<String> = opened
        .iter()
        .enumerate()
        .map(|(i, &(node, slot))| {
            let entered = children(node, slot).filter(|t| t.2 != 0).count();
            let culled = children(node, slot).count() - entered;
            format!("{}: {entered} entered, {culled} culled", letter(i))
        })
        .collect();
    let widest = captions
        .iter()
        .map(|t| Canvas::text_width(t, SIZE))
        .fold(0.0, f32::max);
    // The scale of the smallest box drawn in a layout; 0 where the captions do not fit.
    let smallest = |cols: usize, rows: usize| {
        let cell = cell_of(cols, rows);
        if widest > cell.0 {
            return 0.0;
        }
        opened
            .iter()
            .map(|&(node, slot)| {
                let room = (cell.0, cell.1 - CAPTION);
                Panel::fit(&nodes[node].bounds(slot), (0.0, 0.0), room).scale()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let (cols, rows) = [(k, 1), (k.div_ceil(2), 2.min(k))]
        .into_iter()
        .max_by(|a, b| smallest(a.0, a.1).total_cmp(&smallest(b.0, b.1)))
        .expect("two layouts");
    let cell = cell_of(cols, rows);
    for (i, &(node, slot)) in opened.iter().enumerate() {
        let corner = (
            at.0 + (i % cols) as f32 * (cell.0 + SPACE),
            at.1 + (i / cols) as f32 * (cell.1 + SPACE),
        );
        let parent: Aabb = nodes[node].bounds(slot);
        let view = Panel::fit(
            &parent,
            (corner.0, corner.1 + CAPTION),
            (cell.0, cell.1 - CAPTION),
        );
        // The caption over its frame's left edge, moved left only as far as it must to
        // stay in its part of the panel.
        let width = Canvas::text_width(&captions[i], SIZE);
        let x = view.at.0.min(corner.0 + cell.0 - width).max(corner.0);
        let y = corner.1 + SIZE * 0.5;
        c.text((x, y), &captions[i], SIZE, style::ink(), Anchor::Left);
        c.rect(view.at, view.size, Some((style::grid(), 1.0)), None);
        // The box first, under its children: a child as big as its box (they often are)
        // shows its own edge just inside the box's.
        view.outline(c, &parent, opened_color(), 2.2, false);
        for want in [false, true] {
            for (n, s, mask) in children(node, slot) {
                if (mask != 0) == want {
                    view.level_box(c, &nodes[n].bounds(s), want, CHILD_INSET);
                }
            }
        }
        view.frustum(c, rays, &parent);
        view.rays(c, rays, hits, &parent);
    }
}

/// Puts each opened box's letter on the first panel (`view`), inside its box: in a corner,
/// the top left first, or along its top or bottom edge, wherever it is clear of the other
/// letters and of the root's name (`root`, its plate); where no place inside the box is
/// clear (boxes that coincide seen from above), beside the box's top left corner, outside
/// it. Every box gets its letter, on a pale plate, so that the rays under it do not cross
/// it.
pub(super) fn letter_boxes(
    c: &mut Canvas,
    view: &Panel,
    opened: &[(usize, usize)],
    nodes: &[Node],
    root: Box2,
) {
    let (x0, y0) = view.at;
    let mut labels = Labels::new([x0, y0, x0 + view.size.0, y0 + view.size.1]);
    labels.block(root);
    for (i, &(node, slot)) in opened.iter().enumerate() {
        let b = nodes[node].bounds(slot);
        let (p, q) = (view.map(b.min), view.map(b.max));
        let (min, max) = ((p.0.min(q.0), p.1.min(q.1)), (p.0.max(q.0), p.1.max(q.1)));
        let text = letter(i).to_string();
        let mut inside = vec![
            ((min.0 + 5.0, min.1 + 10.0), Anchor::Left),
            ((max.0 - 5.0, min.1 + 10.0), Anchor::Right),
            ((min.0 + 5.0, max.1 - 10.0), Anchor::Left),
            ((max.0 - 5.0, max.1 - 10.0), Anchor::Right),
        ];
        for step in 1..6 {
            let x = min.0 + 5.0 + 16.0 * step as f32;
            inside.push(((x, min.1 + 10.0), Anchor::Left));
            inside.push(((x, max.1 - 10.0), Anchor::Left));
        }
        inside.retain(|&(at, anchor)| {
            let [bx0, by0, bx1, by1] = text_box(at, &text, 12.0, anchor);
            bx0 >= min.0 && by0 >= min.1 && bx1 <= max.0 && by1 <= max.1
        });
        let beside = [
            ((min.0 - 3.0, min.1 + 10.0), Anchor::Right),
            ((min.0 + 5.0, min.1 - 10.0), Anchor::Left),
        ];
        let placed = labels
            .reserve(&inside, &text, 12.0, false)
            .or_else(|| labels.reserve(&beside, &text, 12.0, false))
            .unwrap_or(beside[0]);
        let plate = plated_text(c, placed.0, &text, 12.0, style::ink(), placed.1, 0.0);
        labels.block(plate);
    }
}
