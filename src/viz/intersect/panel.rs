//! The text under each figure: the ray, the equation, the discriminant or Cramer's
//! determinants, the verdict and every candidate root with its reason.

use super::{PLOT, WIDTH};
use crate::report::intersect::Report;
use crate::shapes::working::short;
use crate::shapes::Roots;
use crate::viz::style;
use crate::viz::{Anchor, Canvas};
use tiny_skia::Color;

/// The figure's height: the plot and as many panel lines as the report needs.
pub fn height(r: &Report) -> u32 {
    let lines = 1
        + 2 * r.quadratic.is_some() as usize
        + r.barycentric.is_some() as usize
        + r.linear.is_some() as usize
        + r.candidates.len().max(1)
        + r.hit.is_none() as usize;
    (PLOT[3] + 12.0 + 18.0 * lines as f32 + 10.0).ceil() as u32
}

/// The text under the drawing: equation, discriminant, verdict, candidates.
pub(super) fn panel(c: &mut Canvas, r: &Report) {
    let mut y = PLOT[3] + 18.0;
    let x = 24.0;
    let mut say = |c: &mut Canvas, text: &str, color: Color, size: f32| {
        c.text((x, y), text, size, color, Anchor::Left);
        y += size + 5.0;
    };
    c.line(
        (16.0, PLOT[3] + 4.0),
        (WIDTH as f32 - 16.0, PLOT[3] + 4.0),
        style::grid(),
        1.0,
        false,
    );
    let ray = format!(
        "P = ({}),  d = ({})",
        r.ray
            .origin
            .iter()
            .map(|x| short(*x))
            .collect::<Vec<_>>()
            .join(", "),
        r.ray
            .direction
            .iter()
            .map(|x| short(*x))
            .collect::<Vec<_>>()
            .join(", ")
    );
    say(c, &ray, style::ink(), 13.0);
    if let Some(q) = &r.quadratic {
        let sgn = |x: f64| {
            if x < 0.0 {
                format!("− {}", short(-x))
            } else {
                format!("+ {}", short(x))
            }
        };
        let surface = match r.shape {
            "cylinder" | "cone" => "body: ",
            _ => "",
        };
        say(
            c,
            &format!(
                "{surface}{}·t² {}·t {} = 0      (a = {}, b = {}, c = {})",
                short(q.a),
                sgn(q.b),
                sgn(q.c),
                short(q.a),
                short(q.b),
                short(q.c)
            ),
            style::ink(),
            13.0,
        );
        let verdict = match q.roots {
            Roots::Two => "D > 0: two roots".to_string(),
            Roots::Tangent if q.rounded_to_zero => format!(
                "D = 0 → tangent (floating point gave {:.1e}: within rounding of 0, so taken as 0)",
                q.discriminant
            ),
            Roots::Tangent => "D = 0: tangent, one root".to_string(),
            Roots::One => "a = 0: linear, one root".to_string(),
            Roots::None => "D < 0: no real root, a miss".to_string(),
        };
        let dtext = if q.rounded_to_zero {
            verdict
        } else {
            format!("D = b² − 4ac = {}  →  {verdict}", short(q.discriminant))
        };
        say(c, &dtext, style::ink(), 13.0);
    }
    if let Some(l) = &r.linear {
        let text = if l.denominator == 0.0 {
            "n·d = 0: the ray is parallel to the plane, no root".to_string()
        } else {
            format!(
                "t = n·(Q0 − P) / (n·d) = {} / {} = {}",
                short(l.numerator),
                short(l.denominator),
                short(l.numerator / l.denominator)
            )
        };
        say(c, &text, style::ink(), 13.0);
    }
    if let Some(b) = &r.barycentric {
        let text = match (b.alpha, b.beta, b.gamma, b.t) {
            (Some(a), Some(be), Some(g), Some(t)) => format!(
                "Cramer: det = {},  β = {},  γ = {},  t = {},  α = 1 − β − γ = {}",
                short(b.determinant),
                short(be),
                short(g),
                short(t),
                short(a)
            ),
            _ => "Cramer: det[e1 e2 −d] = 0: the ray is parallel to the plane, or the triangle is degenerate".into(),
        };
        say(c, &text, style::ink(), 13.0);
    }
    if r.candidates.is_empty() {
        say(c, "no candidate root: the ray misses", style::muted(), 12.0);
    }
    for (i, cand) in r.candidates.iter().enumerate() {
        let kept = cand.note.starts_with("kept");
        let name = if r.candidates.len() == 1 {
            "t".to_string()
        } else {
            format!("t{}", i + 1)
        };
        let text = format!(
            "{name} = {} on {}: {}",
            short(cand.t),
            cand.surface,
            cand.note
        );
        let color = if kept {
            style::hit()
        } else {
            style::rgb(120, 120, 128)
        };
        let text = fit_text(&text, 12.0, WIDTH as f32 - 48.0);
        say(c, &text, color, 12.0);
    }
    if r.hit.is_none() {
        say(c, "no hit", style::ink(), 12.0);
    }
}

/// Shortens `text` with an ellipsis so it fits in `width` pixels.
fn fit_text(text: &str, size: f32, width: f32) -> String {
    if Canvas::text_width(text, size) <= width {
        return text.to_string();
    }
    let mut s: Vec<char> = text.chars().collect();
    while !s.is_empty() && Canvas::text_width(&(s.iter().collect::<String>() + "…"), size) > width
    {
        s.pop();
    }
    s.into_iter().collect::<String>() + "…"
}
