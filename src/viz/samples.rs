//! Where each sampler puts its samples: a 3×3 patch of pixels per sampler, the middle
//! pixel's own samples in colour, its neighbours' in grey. The adaptive panel samples a
//! made-up picture, a straight edge between dark and light, to show where it refines.

use super::{style, Anchor, Canvas};
use crate::sampling::sample_pixel;
use crate::scene::{RenderSettings, SamplerKind};
use glam::{DVec2, DVec3};

const PATCH: u32 = 3;
const CELL: f32 = 64.0;

/// The made-up picture of the adaptive panel: light right of the line through `EDGE`.
const EDGE: [(f64, f64); 2] = [(0.9, 0.0), (2.0, 3.0)];

fn edge_colour(p: DVec2) -> DVec3 {
    let (a, b) = (DVec2::from(EDGE[0]), DVec2::from(EDGE[1]));
    let side = (b - a).perp_dot(p - a);
    DVec3::splat(if side < 0.0 { 0.9 } else { 0.1 })
}

/// Draws one panel per (sampler, spp).
pub fn figure(runs: &[(SamplerKind, u32)], seed: u64) -> Canvas {
    let cols = runs.len().min(3) as u32;
    let rows = (runs.len() as u32).div_ceil(3);
    let side = CELL * PATCH as f32;
    let (margin, title, caption, gap) = (18.0f32, 26.0f32, 22.0f32, 26.0f32);
    let pw = side + gap;
    let ph = title + side + caption + gap;
    let mut c = Canvas::new(
        (2.0 * margin + cols as f32 * pw - gap) as u32,
        (2.0 * margin + rows as f32 * ph - gap) as u32,
        style::background(),
    );
    let own = style::hit();
    let other = style::rgb(120, 120, 130);
    for (i, &(kind, spp)) in runs.iter().enumerate() {
        let x0 = margin + (i as u32 % 3) as f32 * pw;
        let y0 = margin + (i as u32 / 3) as f32 * ph;
        let to = |p: DVec2| (x0 + p.x as f32 * CELL, y0 + title + p.y as f32 * CELL);
        let name = if kind == SamplerKind::Adaptive {
            format!("adaptive, up to {spp} spp")
        } else if matches!(kind, SamplerKind::Center | SamplerKind::Corners) {
            kind.name().to_string()
        } else {
            format!("{}, {spp} spp", kind.name())
        };
        c.text(
            (x0 + side / 2.0, y0 + title / 2.0),
            &name,
            15.0,
            style::ink(),
            Anchor::Center,
        );
        // The middle pixel, shaded; then strata, then pixel borders.
        c.rect(
            to(DVec2::ONE),
            (CELL, CELL),
            None,
            Some(style::rgb(255, 244, 214)),
        );
        if kind == SamplerKind::Adaptive {
            let (a, b) = (DVec2::from(EDGE[0]), DVec2::from(EDGE[1]));
            let mut poly = vec![
                to(a),
                to(b),
                to(DVec2::new(3.0, 3.0)),
                to(DVec2::new(3.0, 0.0)),
            ];
            poly.dedup();
            c.polygon(&poly, None, Some(style::rgba(40, 40, 60, 60)));
        }
        if matches!(kind, SamplerKind::Grid | SamplerKind::Jittered) {
            let n = (spp as f64).sqrt().round() as u32;
            for k in 1..PATCH * n {
                let t = k as f64 / n as f64;
                c.line(
                    to(DVec2::new(t, 0.0)),
                    to(DVec2::new(t, 3.0)),
                    style::grid(),
                    1.0,
                    false,
                );
                c.line(
                    to(DVec2::new(0.0, t)),
                    to(DVec2::new(3.0, t)),
                    style::grid(),
                    1.0,
                    false,
                );
            }
        }
        for k in 0..=PATCH {
            let t = k as f64;
            c.line(
                to(DVec2::new(t, 0.0)),
                to(DVec2::new(t, 3.0)),
                style::muted(),
                1.5,
                false,
            );
            c.line(
                to(DVec2::new(0.0, t)),
                to(DVec2::new(3.0, t)),
                style::muted(),
                1.5,
                false,
            );
        }
        let settings = RenderSettings {
            sampler: kind,
            spp,
            seed,
            adaptive_threshold: 0.1,
            ..RenderSettings::default()
        };
        let mut middle = 0;
        for y in 0..PATCH {
            for x in 0..PATCH {
                let samples = sample_pixel(&settings, PATCH, PATCH, x, y, |_, f| edge_colour(f));
                let mine = (x, y) == (1, 1);
                if mine {
                    middle = samples.len();
                }
                for s in samples {
                    let r = if mine { 4.0 } else { 3.0 };
                    c.circle(to(s.film), r, None, Some(if mine { own } else { other }));
                }
            }
        }
        let note = match kind {
            SamplerKind::Corners => format!("middle pixel traces {middle}, uses 5"),
            _ => format!("middle pixel traces {middle}"),
        };
        c.text(
            (x0 + side / 2.0, y0 + title + side + caption / 2.0 + 2.0),
            &note,
            12.0,
            style::muted(),
            Anchor::Center,
        );
    }
    c
}
