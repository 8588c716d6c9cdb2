use serde::Serialize;

/// How many real roots a quadratic has, as the lecture names the cases.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Roots {
    /// D > 0: the ray enters and leaves.
    Two,
    /// D = 0 (within rounding): the ray grazes the surface.
    Tangent,
    /// a = 0: the equation degenerated to a linear one.
    One,
    /// D < 0: the ray misses.
    None,
}

// ANCHOR: quadratic
/// The quadratic a·t² + b·t + c = 0 that substituting the ray into an implicit surface gives,
/// with its discriminant D = b² − 4ac and the verdict.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Quadratic {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub discriminant: f64,
    pub roots: Roots,
    /// True when D came out nonzero but within rounding of zero, and was taken as tangent.
    #[serde(skip)]
    pub rounded_to_zero: bool,
}

/// D is treated as zero when it is this small relative to the size of b² and 4ac: the two
/// products each carry a rounding error of about 1e-16 of their size, so a D of −7e-15 from
/// 36 − 36 (the lecture's circle) is a tangent, not a miss.
pub const TANGENT_TOLERANCE: f64 = 1e-10;

impl Quadratic {
    pub fn new(a: f64, b: f64, c: f64) -> Quadratic {
        let discriminant = b * b - 4.0 * a * c;
        let scale = (b * b).max((4.0 * a * c).abs());
        let degenerate = a.abs() <= 1e-14 * (b.abs() + c.abs()) || a == 0.0;
        let (roots, rounded_to_zero) = if degenerate {
            (if b != 0.0 { Roots::One } else { Roots::None }, false)
        } else if discriminant.abs() <= TANGENT_TOLERANCE * scale {
            (Roots::Tangent, discriminant != 0.0)
        } else if discriminant > 0.0 {
            (Roots::Two, false)
        } else {
            (Roots::None, false)
        };
        Quadratic {
            a,
            b,
            c,
            discriminant,
            roots,
            rounded_to_zero,
        }
    }

    /// The real roots, smallest first: two, one (tangent or linear) or none.
    /// Uses the cancellation-free form q = −(b + sign(b)·√D)/2, t = q/a and c/q.
    pub fn solve(&self) -> ([f64; 2], usize) {
        let Quadratic {
            a,
            b,
            c,
            discriminant,
            roots,
            ..
        } = *self;
        match roots {
            Roots::Two => {
                let q = -0.5 * (b + b.signum() * discriminant.sqrt());
                let (t1, t2) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
                ([t1.min(t2), t1.max(t2)], 2)
            }
            Roots::Tangent => ([-b / (2.0 * a), 0.0], 1),
            Roots::One => ([-c / b, 0.0], 1),
            Roots::None => ([0.0; 2], 0),
        }
    }
}
// ANCHOR_END: quadratic

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn lecture_circle_is_tangent_despite_rounding() {
        // P = (-3, 1), d = (0.8, -0.6), unit circle: t² - 6t + 9 = 0.
        let (p, d) = ([-3.0f64, 1.0], [0.8f64, -0.6]);
        let a = d[0] * d[0] + d[1] * d[1];
        let b = 2.0 * (p[0] * d[0] + p[1] * d[1]);
        let c = p[0] * p[0] + p[1] * p[1] - 1.0;
        let q = Quadratic::new(a, b, c);
        // Exactly 0 in real arithmetic; in f64 b = -6.000000000000001 and D = +1.4e-14 (other
        // evaluation orders give a tiny negative number instead). Either way: a tangent.
        assert!(
            q.discriminant != 0.0 && q.discriminant.abs() < 1e-13,
            "D = {}",
            q.discriminant
        );
        assert_eq!(q.roots, Roots::Tangent);
        assert!(q.rounded_to_zero);
        let (t, n) = q.solve();
        assert_eq!(n, 1);
        assert!((t[0] - 3.0).abs() < 1e-12);
    }
    #[test]
    fn two_roots_are_ordered_and_accurate() {
        let q = Quadratic::new(1.0, -1e8, 1.0); // roots 1e-8 and 1e8: the naive formula loses the small one
        let (t, n) = q.solve();
        assert_eq!(n, 2);
        assert!((t[0] - 1e-8).abs() < 1e-20);
        assert!((t[1] - 1e8).abs() < 1e-6);
    }
    #[test]
    fn degenerate_and_missing() {
        assert_eq!(Quadratic::new(0.0, 2.0, -4.0).solve(), ([2.0, 0.0], 1));
        assert_eq!(Quadratic::new(1.0, 0.0, 1.0).roots, Roots::None);
        assert_eq!(Quadratic::new(0.0, 0.0, 1.0).roots, Roots::None);
    }
}
