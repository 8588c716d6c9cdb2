//! Which part of the plane the figure shows.

use super::frame::Frame;
use super::Drawn;
use crate::scene::Scene;
use crate::trace::RayNode;

/// The window: the eye, the camera ray's hit and the object it hit make the core; the
/// other rays' ends and lights join when they are not far outside it (rays to farther
/// points are cut at the figure's edge, which keeps the first hit readable). Every event
/// counts, drawn or not: a storyboard (`events: Some(k)`) keeps one view throughout.
/// Returns the window's centre, width and height in plane coordinates.
pub(super) fn window(
    scene: &Scene,
    frame: &Frame,
    tree: &RayNode,
    every: &[Drawn],
) -> ((f64, f64), f64, f64) {
    let bbox = |pts: &[(f64, f64)]| {
        pts.iter()
            .fold((f64::MAX, f64::MAX, f64::MIN, f64::MIN), |b, p| {
                (b.0.min(p.0), b.1.min(p.1), b.2.max(p.0), b.3.max(p.1))
            })
    };
    let eye2 = frame.to2(tree.origin);
    let mut pts: Vec<(f64, f64)> = vec![eye2];
    match &tree.hit {
        Some(h) => {
            pts.push(frame.to2(h.point));
            let reach = (h.point - tree.origin).length();
            if let Some(b) = scene
                .objects
                .iter()
                .find(|o| o.name == h.object)
                .and_then(|o| o.bounds)
            {
                let c: Vec<(f64, f64)> = b.corners().iter().map(|p| frame.to2(*p)).collect();
                let cb = bbox(&c);
                if (cb.2 - cb.0).max(cb.3 - cb.1) < 1.5 * reach {
                    pts.extend(c);
                }
            }
        }
        None => pts.push(frame.to2(tree.origin + tree.direction.normalize_or_zero() * 4.0)),
    }
    let core = bbox(&pts);
    let core_extent = (core.2 - core.0).max(core.3 - core.1).max(1e-6);
    let core_center = ((core.0 + core.2) / 2.0, (core.1 + core.3) / 2.0);
    let near =
        |p: (f64, f64)| (p.0 - core_center.0).hypot(p.1 - core_center.1) <= 1.3 * core_extent;
    for e in every {
        let mut ends = vec![frame.to2(e.start)];
        if let Some(p) = e.end {
            ends.push(frame.to2(p));
        }
        if let Some((Some(p), _)) = &e.light {
            ends.push(frame.to2(*p));
        }
        pts.extend(ends.into_iter().filter(|p| near(*p)));
    }
    let b = bbox(&pts);
    let (mut w, mut h) = (b.2 - b.0, b.3 - b.1);
    let extent = w.max(h);
    let extent = if extent < 1e-6 { 4.0 } else { extent };
    w = w.max(extent * 0.35);
    h = h.max(extent * 0.35);
    let (w, h) = (w * 1.16 + extent * 0.04, h * 1.16 + extent * 0.04);
    let center = ((b.0 + b.2) / 2.0, (b.1 + b.3) / 2.0);
    (center, w, h)
}
