//! The bundle figure's words: its title's pixels, which side the rays come from, what
//! became of the boxes the bundle entered but did not open, plurals and line wrapping.

use crate::accel::FEW;
use crate::math::Ray;
use crate::report::ordinal;
use crate::viz::canvas::Canvas;
use glam::DVec3;

/// `one` for a count of 1, `many` for any other.
pub(super) fn plural<'a>(count: usize, one: &'a str, many: &'a str) -> &'a str {
    if count == 1 {
        one
    } else {
        many
    }
}

/// `text` in lines no wider than `width` at `size`, broken at spaces (a word wider than
/// the width has a line of its own).
pub(super) fn wrap(text: &str, size: f32, width: f32) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(line) if Canvas::text_width(&format!("{line} {word}"), size) <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// The boxes some ray entered at one level of the walk, and what became of those the bundle
/// did not open: read off the walk's record (`tested`: node, lane, the rays that entered)
/// and the tree (a leaf lane holds primitives; an opened node was recorded).
pub(super) struct Unopened {
    pub(super) entered: usize,
    /// Leaves: their primitives were tested, nothing below them to open.
    pub(super) leaves: usize,
    /// Subtrees entered by no more than [`FEW`] rays: left to the single-ray walk.
    pub(super) alone: usize,
    /// Subtrees more rays entered, never opened: by the time the bundle came to them its
    /// rays had found nearer hits (any few still left went on alone).
    pub(super) passed: usize,
}

pub(super) fn unopened(
    tested: &[(usize, usize, u32)],
    depth: &[usize],
    nodes: &[crate::accel::Node],
    level: usize,
) -> Unopened {
    let mut u = Unopened {
        entered: 0,
        leaves: 0,
        alone: 0,
        passed: 0,
    };
    for &(node, lane, mask) in tested {
        if depth[node] != level || mask == 0 {
            continue;
        }
        u.entered += 1;
        let child = nodes[node].child[lane] as usize;
        if nodes[node].count[lane] > 0 {
            u.leaves += 1;
        } else if !tested.iter().any(|t| t.0 == child) {
            if mask.count_ones() <= FEW {
                u.alone += 1;
            } else {
                u.passed += 1;
            }
        }
    }
    u
}

/// The boxes entered at `level` that the bundle then opened, as (node, lane): the inner
/// children whose own children were tested one level down.
pub(super) fn opened_at(
    tested: &[(usize, usize, u32)],
    depth: &[usize],
    nodes: &[crate::accel::Node],
    level: usize,
) -> Vec<(usize, usize)> {
    tested
        .iter()
        .filter(|&&(node, lane, mask)| {
            let child = nodes[node].child[lane] as usize;
            depth[node] == level
                && mask != 0
                && nodes[node].count[lane] == 0
                && tested.iter().any(|t| t.0 == child)
        })
        .map(|&(node, lane, _)| (node, lane))
        .collect()
}

impl Unopened {
    /// What became of the boxes entered above that the bundle did not open, for a panel's
    /// note (`None`: it opened them all).
    pub(super) fn note(&self) -> Option<String> {
        let subject = |k: usize| match (k == self.entered, k) {
            (true, 1) => "the box entered".to_string(),
            (true, 2) => "both boxes entered".to_string(),
            (true, k) => format!("the {k} boxes entered"),
            (false, k) => format!("{k} of the boxes entered"),
        };
        let few = match FEW {
            1 => "one ray".to_string(),
            k => format!("{k} or fewer rays"),
        };
        let mut parts = Vec::new();
        if self.leaves > 0 {
            let k = self.leaves;
            parts.push(format!(
                "{} {}: {} triangles are tested, nothing further to open",
                subject(k),
                plural(k, "is a leaf", "are leaves"),
                plural(k, "its", "their")
            ));
        }
        if self.alone > 0 {
            let k = self.alone;
            parts.push(format!(
                "{} had {few}{}: {} on alone (the single-ray walk)",
                subject(k),
                plural(k, "", " each"),
                match (FEW, k) {
                    (1, 1) => "it went",
                    (1, _) => "each went",
                    _ => "those went",
                }
            ));
        }
        if self.passed > 0 {
            let k = self.passed;
            parts.push(format!(
                "{} {} not opened: by then {} rays had found nearer hits (or {} \
                 went on alone)",
                subject(k),
                plural(k, "was", "were"),
                plural(k, "its", "their"),
                if FEW == 1 {
                    "only one ray was left, and it".to_string()
                } else {
                    format!("{FEW} or fewer were left, and they")
                }
            ));
        }
        if parts.is_empty() {
            return None;
        }
        let mut text = parts.join("; ");
        text[..1].make_ascii_uppercase();
        text.push('.');
        Some(text)
    }
}

/// The bundle's pixels for the title: "pixels x 8–10, y 4–7" for a block of whole rows and
/// columns, "pixels x 320–332 and y 240–252, every 4th" where `--subsample` skips some (a
/// range wherever they are evenly spaced, "320/322/327" where not), "N pixels within x …,
/// y …" when they do not fill their rows and columns.
pub(super) fn pixels_caption(pixels: &[(u32, u32)]) -> String {
    let values = |of: fn(&(u32, u32)) -> u32| {
        let mut v: Vec<u32> = pixels.iter().map(of).collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    let (xs, ys) = (values(|p| p.0), values(|p| p.1));
    // The spacing of evenly spaced values (at least two of them).
    let step = |v: &[u32]| match v {
        [a, b, ..] if v.windows(2).all(|w| w[1] - w[0] == b - a) => Some(b - a),
        _ => None,
    };
    let (sx, sy) = (step(&xs), step(&ys));
    let common = match (sx, sy) {
        (Some(a), Some(b)) if a == b && a > 1 => Some(a),
        _ => None,
    };
    let list = |v: &[u32], step: Option<u32>| match (v, step) {
        ([], _) => String::new(),
        ([a], _) => a.to_string(),
        ([a, .., z], Some(1)) => format!("{a}–{z}"),
        ([a, .., z], Some(_)) if common.is_some() => format!("{a}–{z}"),
        ([a, .., z], Some(d)) => format!("{a}–{z} every {}", ordinal(d)),
        _ => v.iter().map(u32::to_string).collect::<Vec<_>>().join("/"),
    };
    let (x, y) = (list(&xs, sx), list(&ys, sy));
    let within = match common {
        Some(d) => format!("x {x} and y {y}, every {}", ordinal(d)),
        None => format!("x {x}, y {y}"),
    };
    match pixels.len() {
        1 => format!("pixel ({x}, {y})"),
        n if n == xs.len() * ys.len() => format!("pixels {within}"),
        n => format!("{n} pixels within {within}"),
    }
}

/// Which side of the figure the rays come in from (object-space x right, z down): the
/// opposite of where their summed direction points; or, for rays within about 27° of
/// straight down or up (y), that they come from above or below the figure.
pub(super) fn coming_from(rays: &[Ray]) -> &'static str {
    let d: DVec3 = rays.iter().map(|r| r.dir).sum();
    if d.x.hypot(d.z) < 0.5 * d.y.abs() {
        return if d.y < 0.0 {
            "above the figure, looking down"
        } else {
            "below the figure, looking up"
        };
    }
    match (d.x.abs() > d.z.abs(), d.x > 0.0, d.z > 0.0) {
        (true, true, _) => "left",
        (true, false, _) => "right",
        (false, _, true) => "top",
        (false, _, false) => "bottom",
    }
}

#[cfg(test)]
mod tests {
    use super::{coming_from, opened_at, Unopened};
    use crate::accel::{Node, WIDTH};
    use crate::math::Ray;
    use glam::DVec3;

    /// Rays within about 27° of straight down come from above the figure, of straight up
    /// from below; past that, from the side their directions leave (x right, z down).
    #[test]
    fn the_rays_come_from_a_side_or_from_above_or_below() {
        let from = |d: DVec3| coming_from(&[Ray::new(DVec3::ZERO, d)]);
        assert_eq!(
            from(DVec3::new(0.1, -1.0, 0.2)),
            "above the figure, looking down"
        );
        assert_eq!(
            from(DVec3::new(0.1, 1.0, 0.2)),
            "below the figure, looking up"
        );
        assert_eq!(from(DVec3::new(0.0, -0.4, -1.0)), "bottom");
        assert_eq!(from(DVec3::new(0.0, -0.4, 1.0)), "top");
        assert_eq!(from(DVec3::new(1.0, 0.3, 0.2)), "left");
        assert_eq!(from(DVec3::new(-1.0, 0.3, 0.2)), "right");
        // At the boundary, |(x, z)| = |y| / 2: a side; just inside it, above.
        assert_eq!(from(DVec3::new(0.0, -2.0, -1.0)), "bottom");
        assert_eq!(
            from(DVec3::new(0.0, -2.0, -0.999)),
            "above the figure, looking down"
        );
    }

    /// Of the root's entered children, only the inner one the bundle went on to open is an
    /// opened box: not a culled one, not a leaf, not a subtree its rays walked alone.
    #[test]
    fn opened_boxes_are_the_entered_inner_children_that_were_opened() {
        let node = |child, count| Node {
            planes: [[[0.0; WIDTH]; 3], [[1.0; WIDTH]; 3]],
            child,
            count,
        };
        let leafless = node([0; WIDTH], [1; WIDTH]);
        let nodes = [
            node([1, 2, 0, 3], [0, 0, 2, 0]),
            leafless,
            leafless,
            leafless,
        ];
        let depth = [0, 1, 1, 1];
        // Lane 0 entered and opened (node 1 tested below), lane 1 entered by one ray that
        // walked alone (node 2 never tested), lane 2 a leaf, lane 3 culled.
        let tested = [
            (0, 0, 0b11),
            (0, 1, 0b1),
            (0, 2, 0b1),
            (0, 3, 0),
            (1, 0, 0b1),
        ];
        assert_eq!(opened_at(&tested, &depth, &nodes, 0), vec![(0, 0)]);
        assert_eq!(opened_at(&tested, &depth, &nodes, 1), vec![]);
    }

    /// The note names what became of each unopened box, in sentences that read: leaves,
    /// boxes with one ray (it went on alone), boxes passed over.
    #[test]
    fn the_note_for_unopened_boxes_reads() {
        let u = Unopened {
            entered: 4,
            leaves: 1,
            alone: 2,
            passed: 1,
        };
        assert_eq!(
            u.note().unwrap(),
            "1 of the boxes entered is a leaf: its triangles are tested, nothing further to \
             open; 2 of the boxes entered had one ray each: each went on alone (the single-ray \
             walk); 1 of the boxes entered was not opened: by then its rays had found nearer \
             hits (or only one ray was left, and it went on alone)."
        );
        let one = Unopened {
            entered: 1,
            leaves: 0,
            alone: 1,
            passed: 0,
        };
        assert_eq!(
            one.note().unwrap(),
            "The box entered had one ray: it went on alone (the single-ray walk)."
        );
    }
}
