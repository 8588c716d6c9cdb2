//! Clipping what a figure draws to its panel.

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

#[cfg(test)]
mod tests {
    use super::*;

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
