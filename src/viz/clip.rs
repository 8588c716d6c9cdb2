//! Clipping what a figure draws to its panel, and the convex regions it shades there.

use glam::DVec2;

/// The part of segment a–b inside the rectangle `min`–`max` (Liang–Barsky: the segment's
/// parameter range narrowed edge by edge), or `None` when none of it is (or an end is not
/// finite).
pub fn segment(a: DVec2, b: DVec2, min: DVec2, max: DVec2) -> Option<(DVec2, DVec2)> {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x - min.x),
        (d.x, max.x - a.x),
        (-d.y, a.y - min.y),
        (d.y, max.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    (t0 <= t1 && a.is_finite() && b.is_finite()).then(|| (a + d * t0, a + d * t1))
}

/// The part of the convex polygon `poly` inside the rectangle `min`–`max` (Sutherland–Hodgman:
/// the polygon cut by each of the rectangle's edges in turn); empty when none of it is.
pub fn polygon(poly: Vec<DVec2>, min: DVec2, max: DVec2) -> Vec<DVec2> {
    // Each edge: its axis, where it is, and whether the inside is at or above it.
    let edges: [(usize, f64, bool); 4] = [
        (0, min.x, true),
        (0, max.x, false),
        (1, min.y, true),
        (1, max.y, false),
    ];
    let mut out = poly;
    for (axis, v, low) in edges {
        let inside = |p: DVec2| if low { p[axis] >= v } else { p[axis] <= v };
        let input = std::mem::take(&mut out);
        for (i, &p) in input.iter().enumerate() {
            let q = input[(i + 1) % input.len()];
            if inside(p) {
                out.push(p);
            }
            if inside(p) != inside(q) {
                let t = (v - p[axis]) / (q[axis] - p[axis]);
                out.push(p + t * (q - p));
            }
        }
        if out.is_empty() {
            break;
        }
    }
    // A corner on an edge comes back twice: once is enough.
    out.dedup();
    if out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    out
}

/// The convex hull of `points` (Andrew's monotone chain), its corners in order around it,
/// without repeats and without corners on a straight edge; fewer than three points, or all on
/// one line, give fewer than three corners.
pub fn convex_hull(mut points: Vec<DVec2>) -> Vec<DVec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let turn = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    // The lower chain left to right, then the upper one back: each drops the corners that do
    // not turn the same way as the chain.
    let mut hull: Vec<DVec2> = Vec::with_capacity(points.len() + 1);
    for chain in [points.clone(), points.into_iter().rev().collect()] {
        let start = hull.len();
        for p in chain {
            while hull.len() >= start + 2
                && turn(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop(); // the chain's last corner is the next chain's first
    }
    hull
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hull of a square's corners, its centre, a point on an edge and a repeated corner is
    /// the four corners, in order around it; a line of points has no area.
    #[test]
    fn the_hull_keeps_the_corners_only() {
        let v = |x, y| DVec2::new(x, y);
        let pts = vec![
            v(1.0, 1.0),
            v(0.0, 0.0),
            v(2.0, 0.0),
            v(2.0, 2.0),
            v(0.0, 2.0),
            v(1.0, 0.0),
            v(2.0, 2.0),
        ];
        let hull = convex_hull(pts);
        assert_eq!(hull.len(), 4, "{hull:?}");
        for c in [v(0.0, 0.0), v(2.0, 0.0), v(2.0, 2.0), v(0.0, 2.0)] {
            assert!(hull.contains(&c), "{c} in {hull:?}");
        }
        // In order around it: every turn the same way.
        let turns: Vec<f64> = (0..4)
            .map(|i| (hull[(i + 1) % 4] - hull[i]).perp_dot(hull[(i + 2) % 4] - hull[(i + 1) % 4]))
            .collect();
        assert!(
            turns.iter().all(|&t| t > 0.0) || turns.iter().all(|&t| t < 0.0),
            "{turns:?}"
        );
        assert!(convex_hull(vec![v(0.0, 0.0), v(1.0, 1.0), v(2.0, 2.0)]).len() < 3);
    }

    /// A wedge from far below the rectangle, leaving it through the top and right edges, keeps
    /// the corner between them: the part inside is the wedge's, corner included.
    #[test]
    fn a_polygon_is_cut_to_the_rectangle_corner_included() {
        let v = |x, y| DVec2::new(x, y);
        let (min, max) = (v(0.0, 0.0), v(4.0, 4.0));
        let wedge = vec![v(2.0, -10.0), v(20.0, 10.0), v(-10.0, 10.0)];
        let cut = polygon(wedge, min, max);
        assert!(
            cut.iter()
                .all(|p| p.x >= 0.0 && p.x <= 4.0 && p.y >= 0.0 && p.y <= 4.0),
            "{cut:?}"
        );
        assert!(
            cut.contains(&v(4.0, 4.0)) && cut.contains(&v(0.0, 4.0)),
            "{cut:?}"
        );
        assert!(polygon(vec![v(10.0, 10.0), v(11.0, 10.0), v(10.0, 11.0)], min, max).is_empty());
        // Touching the rectangle at one corner only: a point, not a polygon.
        let touching = polygon(vec![v(0.0, 1.0), v(-2.0, 0.0), v(-2.0, 2.0)], min, max);
        assert!(touching.len() < 3, "{touching:?}");
    }

    #[test]
    fn a_segment_is_cut_at_the_edges_it_crosses() {
        let (min, max) = (DVec2::ZERO, DVec2::new(4.0, 2.0));
        let v = |x, y| DVec2::new(x, y);
        assert_eq!(
            segment(v(-2.0, 1.0), v(6.0, 1.0), min, max),
            Some((v(0.0, 1.0), v(4.0, 1.0)))
        );
        assert_eq!(
            segment(v(1.0, 1.0), v(2.0, 1.5), min, max),
            Some((v(1.0, 1.0), v(2.0, 1.5)))
        );
        assert_eq!(segment(v(-1.0, 3.0), v(5.0, 3.0), min, max), None);
        assert_eq!(segment(v(1.0, 1.0), v(f64::NAN, 1.0), min, max), None);
    }
}
