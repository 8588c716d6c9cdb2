//! The bundle figure's second panel when the bundle opened boxes one level down: each box
//! it opened on its own, zoomed to fill a part of the panel, with the children the bundle
//! tested in it. Drawn together over the root, a box's children share edges with it and
//! with the other box's children, and the boxes could not be counted.

use super::super::canvas::{Anchor, Canvas};
use super::super::labels::{text_box, Box2, Labels};
use super::super::style;
use super::panel::{opened_color, Panel};
use crate::accel::Node;
use crate::math::Ray;
use crate::shapes::{Aabb, LocalHit};

/// The letter that names the `i`th box opened (A, B, …; a bundle opens at most four of the
/// root's children).
pub(super) fn letter(i: usize) -> char {
    (b'A' + (i % 26) as u8) as char
}

/// Height of a zoomed box's caption line above its frame.
const CAPTION: f32 = 16.0;
/// Space between the zoomed boxes.
const SPACE: f32 = 12.0;
/// Caption text size.
const SIZE: f32 = 11.0;

/// Draws each box of `opened` (node, lane: the boxes opened one level up) in its own part of
/// the area `at`, `size`: in one row, or in two, whichever draws them larger. Each part
/// is captioned with the box's letter and what its children did, framed, and shows the box
/// (dark grey), its children as tested (`tested`: node, lane, the rays that entered; drawn
/// `inset` pixels inside their edges), the bundle's frustum and its rays.
#[allow(clippy::too_many_arguments)]
pub(super) fn draw_zoomed(
    c: &mut Canvas,
    (at, size): ((f32, f32), (f32, f32)),
    opened: &[(usize, usize)],
    tested: &[(usize, usize, u32)],
    nodes: &[Node],
    rays: &[Ray],
    hits: &[Option<LocalHit>],
    inset: f32,
) {
    let k = opened.len();
    let cell_of = |cols: usize, rows: usize| {
        (
            (size.0 - SPACE * (cols as f32 - 1.0)) / cols as f32,
            (size.1 - SPACE * (rows as f32 - 1.0)) / rows as f32,
        )
    };
    // Each box's caption: its letter, and what its children did.
    let captions: Vec<String> = opened
        .iter()
        .enumerate()
        .map(|(i, &(node, lane))| {
            let child = nodes[node].child[lane] as usize;
            let children = tested.iter().filter(|t| t.0 == child);
            let entered = children.clone().filter(|t| t.2 != 0).count();
            let culled = children.count() - entered;
            format!("{}: {entered} entered, {culled} culled", letter(i))
        })
        .collect();
    let widest = captions
        .iter()
        .map(|t| Canvas::text_width(t, SIZE))
        .fold(0.0, f32::max);
    // One row, or two: whichever draws the smallest of the boxes the largest, with room
    // for the captions.
    let smallest = |cols: usize, rows: usize| {
        let cell = cell_of(cols, rows);
        if widest > cell.0 {
            return 0.0;
        }
        opened
            .iter()
            .map(|&(node, lane)| {
                let fit = Panel::fit(
                    &nodes[node].bounds(lane),
                    (0.0, 0.0),
                    (cell.0, cell.1 - CAPTION),
                );
                fit.scale()
            })
            .fold(f64::INFINITY, f64::min)
    };
    let (cols, rows) = [(k, 1), (k.div_ceil(2), 2.min(k))]
        .into_iter()
        .max_by(|a, b| smallest(a.0, a.1).total_cmp(&smallest(b.0, b.1)))
        .expect("two layouts");
    let cell = cell_of(cols, rows);
    for (i, &(node, lane)) in opened.iter().enumerate() {
        let corner = (
            at.0 + (i % cols) as f32 * (cell.0 + SPACE),
            at.1 + (i / cols) as f32 * (cell.1 + SPACE),
        );
        let parent: Aabb = nodes[node].bounds(lane);
        let child = nodes[node].child[lane] as usize;
        let children: Vec<(usize, usize, u32)> =
            tested.iter().copied().filter(|t| t.0 == child).collect();
        c.text(
            (corner.0, corner.1 + SIZE * 0.5),
            &captions[i],
            SIZE,
            style::ink(),
            Anchor::Left,
        );
        let view = Panel::fit(
            &parent,
            (corner.0, corner.1 + CAPTION),
            (cell.0, cell.1 - CAPTION),
        );
        c.rect(view.at, view.size, Some((style::grid(), 1.0)), None);
        // The box first, under its children: a child as big as its box (they often are)
        // shows its own edge just inside the box's.
        view.outline(c, &parent, opened_color(), 2.2, false);
        for want in [false, true] {
            for &(n, l, mask) in &children {
                if (mask != 0) == want {
                    view.level_box(c, &nodes[n].bounds(l), want, inset);
                }
            }
        }
        view.frustum(c, rays, &parent);
        view.rays(c, rays, hits, &parent);
    }
}

/// Puts each opened box's letter on the first panel (`view`): inside a corner of its box,
/// the top left first, wherever it is clear of the other letters and of the root's name
/// (`root`, its box); further along the box's top edge when boxes coincide seen from above.
/// On a pale backing, so that the rays under it do not cross it.
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
    for (i, &(node, lane)) in opened.iter().enumerate() {
        let b = nodes[node].bounds(lane);
        let (p, q) = (view.map(b.min), view.map(b.max));
        let (min, max) = ((p.0.min(q.0), p.1.min(q.1)), (p.0.max(q.0), p.1.max(q.1)));
        let mut candidates = vec![
            ((min.0 + 5.0, min.1 + 10.0), Anchor::Left),
            ((max.0 - 5.0, min.1 + 10.0), Anchor::Right),
            ((min.0 + 5.0, max.1 - 10.0), Anchor::Left),
            ((max.0 - 5.0, max.1 - 10.0), Anchor::Right),
        ];
        for step in 1..6 {
            let dx = 16.0 * step as f32;
            candidates.push(((min.0 + 5.0 + dx, min.1 + 10.0), Anchor::Left));
            candidates.push(((min.0 + 5.0 + dx, max.1 - 10.0), Anchor::Left));
        }
        let text = letter(i).to_string();
        let Some((at, anchor)) = labels.reserve(&candidates, &text, 12.0, true) else {
            continue;
        };
        let [bx0, by0, bx1, by1] = text_box(at, &text, 12.0, anchor);
        c.rect(
            (bx0, by0),
            (bx1 - bx0, by1 - by0),
            None,
            Some(style::rgba(255, 255, 255, 225)),
        );
        c.text(at, &text, 12.0, style::ink(), anchor);
    }
}
