//! The bundle figure: one 4×4 bundle of camera rays over a mesh's BVH, seen from above
//! (the mesh's own x–z plane, y dropped), one panel per level of the tree: the boxes the
//! bundle tested there, those some ray entered and those it culled because every one of its
//! rays missed them, and the rays up to their hits.

use super::canvas::{Anchor, Canvas};
use super::style;
use crate::accel::{BundleWork, BUNDLE};
use crate::math::Ray;
use crate::sampling::bundles::{bundle_of_within, NoBundle};
use crate::scene::Scene;
use crate::shapes::Shape;
use glam::DVec3;

mod opened;
mod panel;
mod words;
use opened::{draw_zoomed, letter_boxes};
use panel::{culled_color, entered_fill, frustum_fill, plated_text, Panel};
use words::{coming_from, opened_at, pixels_caption, plural, unopened, wrap};

/// Figure size in pixels.
const W: f32 = 960.0;
const H: f32 = 480.0;
/// Levels of the tree drawn below the root, one panel each (deeper boxes are too small to
/// read).
const LEVELS: usize = 2;

/// Draws the bundle in which a render with the scene's settings traces sample `k` of pixel
/// (x, y) ([`crate::sampling::bundles::bundle_of`]: the renderer's own block and rays, the block's pixels that trace a
/// sample `k`), walking the first mesh of the scene. Fails, with a message naming the reason,
/// when the scene has no mesh or the render traces no such bundle: `--traversal single`, a
/// reason the camera rays go alone ([`crate::sampling::bundles::alone_because`]), or a pixel
/// with no sample `k` (one `--subsample` skips).
pub fn draw(scene: &Scene, x: u32, y: u32, k: u32) -> Result<Canvas, String> {
    draw_within(scene, x, y, k, u64::MAX)
}

/// [`draw`], refused when the pixel's tile would plan more than `max_plan` samples (the
/// bundle is found as the render finds it, planning the whole tile: a server bounds that).
pub fn draw_within(scene: &Scene, x: u32, y: u32, k: u32, max_plan: u64) -> Result<Canvas, String> {
    let (object, mesh) = scene
        .objects
        .iter()
        .find_map(|o| match &o.shape {
            Shape::Mesh(m) => Some((o, m)),
            _ => None,
        })
        .ok_or("the bundle figure needs a scene with a mesh")?;
    let within = bundle_of_within(scene, &scene.render, (x, y), k, max_plan);
    let bundle = within.map_err(|why| match why {
        NoBundle::Single => "no bundle to draw: with --traversal single every camera ray walks \
            the BVHs alone (the default, --traversal bundle, traces bundles)"
            .to_string(),
        NoBundle::Alone(why) => format!(
            "no bundle to draw: {why}, so the render's camera rays go alone even with \
            --traversal bundle"
        ),
        NoBundle::NoSample => format!(
            "{}: no bundle to draw; pick a traced pixel",
            crate::report::explain::not_traced(x, y)
        ),
        NoBundle::TooMany { tile, samples } => format!(
            "the bundle figure plans pixel ({x}, {y})'s tile of {}×{} pixels: {samples} \
             samples, more than {max_plan} here; rtlab explain --pixel {x},{y} \
             --bundle-diagram FIG.png draws it",
            tile.0, tile.1
        ),
    })?;
    let rays: Vec<Ray> = bundle
        .rays
        .iter()
        .map(|r| object.transform.ray_to_object(r))
        .collect();
    let n = rays.len();
    // The walk itself, recording every tested child: (node, lane) -> rays that entered it.
    let mut tested: Vec<(usize, usize, u32)> = Vec::new();
    let mut work = BundleWork::default();
    let mut tests = [0u32; BUNDLE];
    let mut hits = [None; BUNDLE];
    mesh.intersect_bundle_seen(
        &rays,
        (1u32 << n) - 1,
        0.0,
        [f64::INFINITY; BUNDLE],
        &mut work,
        &mut tests,
        |node, lane, mask| tested.push((node, lane, mask)),
        |i, hit| hits[i] = Some(hit),
    );
    // Depth of each node (root 0), from the tree itself.
    let nodes = &mesh.bvh.nodes;
    let mut depth = vec![usize::MAX; nodes.len()];
    if !nodes.is_empty() {
        depth[0] = 0;
        for i in 0..nodes.len() {
            for lane in 0..crate::accel::WIDTH {
                if !nodes[i].is_empty(lane) && nodes[i].count[lane] == 0 {
                    depth[nodes[i].child[lane] as usize] = depth[i] + 1;
                }
            }
        }
    }

    let b = mesh.bounds;
    let counts = |level: usize, entered: bool| {
        tested
            .iter()
            .filter(|&&(node, _, mask)| depth[node] == level && (mask != 0) == entered)
            .count()
    };
    let hit_count = hits.iter().flatten().count();

    // The header, top down: the title and the line under it (each wrapped to the width when
    // it does not fit), then the legend's two rows.
    let width = W - 2.0 * SIDE_MARGIN;
    let head = format!(
        "A bundle of {n} camera {} walking the mesh's BVH, seen from above",
        plural(n, "ray", "rays")
    );
    let of = format!(
        "sample {} of {}",
        bundle.sample,
        pixels_caption(&bundle.pixels)
    );
    let title = match format!("{head}: {of}") {
        one if Canvas::text_width(&one, TITLE) <= width => vec![one],
        _ => [
            wrap(&format!("{head}:"), TITLE, width),
            wrap(&of, TITLE, width),
        ]
        .concat(),
    };
    let subsampled = match scene.render.subsample {
        0 | 1 => String::new(),
        k => format!(" (--subsample {k}: traced pixels only)"),
    };
    let hit_text = match (n, hit_count) {
        (1, 1) => "the ray hits (red dot)".to_string(),
        (1, _) => "the ray hits nothing".to_string(),
        (_, 1) => format!("1 of {n} rays hits (red dot)"),
        _ => format!("{hit_count} of {n} rays hit (red dots)"),
    };
    let sub = wrap(
        &format!(
            "object-space x (right) and z (down); the {} from the camera ({}){subsampled}; {hit_text}",
            plural(n, "ray comes", "rays come"),
            coming_from(&rays)
        ),
        SUB,
        width,
    );
    let sub_y = 22.0 + TITLE_STEP * (title.len() - 1) as f32 + 22.0;
    let ly = sub_y + SUB_STEP * (sub.len() - 1) as f32 + 26.0;
    let top = ly + 36.0;

    // One heading per panel, and under it, where the walk did something the boxes do not
    // show, a note: boxes entered above that the bundle did not open (leaves, subtrees left
    // to the single-ray walk), or a root the bundle never opened.
    let panel_w = (W - 2.0 * SIDE_MARGIN - GAP) / 2.0;
    let root_opened = tested.iter().any(|t| t.0 == 0);
    let headings: Vec<(String, Vec<String>)> = (0..LEVELS)
        .map(|level| {
            let (entered, culled) = (counts(level, true), counts(level, false));
            let (heading, note) = if level == 0 {
                let children = if nodes.is_empty() {
                    0
                } else {
                    (0..crate::accel::WIDTH)
                        .filter(|&lane| !nodes[0].is_empty(lane))
                        .count()
                };
                let whose = match children {
                    1 => "1. The root's only child".to_string(),
                    k => format!("1. The root's {k} children"),
                };
                if root_opened || nodes.is_empty() {
                    (format!("{whose}: {entered} entered, {culled} culled"), None)
                } else {
                    (
                        format!("{whose}: not tested by the bundle"),
                        Some(
                            "The bundle never opened the root: its rays' directions differ \
                             in sign, so each ray walked the tree alone."
                                .to_string(),
                        ),
                    )
                }
            } else {
                let above = unopened(&tested, &depth, nodes, level - 1);
                let heading = if entered + culled > 0 {
                    format!(
                        "{}. One level down, in the boxes opened: {entered} entered, {culled} culled",
                        level + 1
                    )
                } else if !root_opened {
                    format!("{}. One level down: the rays walked alone", level + 1)
                } else if above.entered == 0 {
                    format!(
                        "{}. One level down: nothing to test (no ray entered a box above)",
                        level + 1
                    )
                } else {
                    format!("{}. One level down: no box opened", level + 1)
                };
                (heading, above.note())
            };
            let note = note.map_or(Vec::new(), |t| wrap(&t, NOTE, panel_w));
            (heading, note)
        })
        .collect();
    let notes = headings.iter().map(|h| h.1.len()).max().unwrap_or(0);
    let drop = PANEL_DROP + NOTE_STEP * notes as f32;

    // The footer, wrapped to the width; the panels end above it.
    let slab_tests = work.ray_nodes.iter().sum::<u32>() as usize;
    // Panel 2 shows the boxes opened in panel 1, each on its own, when there are some.
    let opened = opened_at(&tested, &depth, nodes, 0);
    let parents = if opened.is_empty() {
        ""
    } else {
        " Panel 2: each box the bundle opened (lettered in panel 1) on its own frame, \
         outlined dark grey, its children drawn a little inside their edges so that shared \
         edges show twice."
    };
    let footer = [
        format!(
            "Thin grey: the root, the mesh's own box.{parents} Seen from above, a ray or its \
             hit can seem to lie in a culled box it passes over or under (y is not drawn)."
        ),
        format!(
            "The whole walk: the bundle opened {} {}, each once for all its rays; its {} made {slab_tests} slab {} (a ray against a node's four boxes), in it or alone.",
            work.opened,
            plural(work.opened as usize, "node", "nodes"),
            plural(n, "ray", "rays"),
            plural(slab_tests, "test", "tests"),
        ),
    ]
    .iter()
    .flat_map(|t| wrap(t, FOOTER, width))
    .collect::<Vec<_>>();
    let bottom = FOOTER_STEP * footer.len() as f32 + 12.0;

    let mut c = Canvas::new(W as u32, H as u32, style::background());
    // One panel per level: the root's children over the root's outline, then each box the
    // bundle opened among them on a frame of its own with its children; the bundle's
    // frustum and rays over the boxes, every one clipped to its frame.
    for (level, (heading, note)) in headings.iter().enumerate() {
        let x0 = SIDE_MARGIN + level as f32 * (panel_w + GAP);
        let area = ((x0, top + drop), (panel_w, H - top - drop - bottom));
        c.text(
            (x0, top + 8.0),
            heading,
            HEADING,
            style::ink(),
            Anchor::Left,
        );
        for (i, line) in note.iter().enumerate() {
            c.text(
                (x0, top + 8.0 + NOTE_STEP * (i + 1) as f32),
                line,
                NOTE,
                style::ink(),
                Anchor::Left,
            );
        }
        if level == 1 && !opened.is_empty() {
            // The boxes opened in panel 1, each in its own part of the panel.
            draw_zoomed(&mut c, area, &opened, &tested, nodes, (&rays, &hits));
            continue;
        }
        // The root (and, when the bundle opened no box at the root, nothing below it).
        let view = Panel::fit(&b, area.0, area.1);
        c.rect(view.at, view.size, Some((style::grid(), 1.0)), None);
        view.outline(&mut c, &b, style::muted(), 1.2, false);
        // The root's name, on a pale backing (the boxes' edges often run through it).
        // (Drawn after the rays, with the letters of the boxes opened.)
        let root_label = (level == 0).then(|| {
            let (bx, by) = view.map(DVec3::new(b.min.x, 0.0, b.min.z));
            (bx + 4.0, by + 12.0)
        });
        // Culled boxes first, under the entered ones.
        for want in [false, true] {
            for &(node, slot, mask) in tested.iter().filter(|t| depth[t.0] == level) {
                if (mask != 0) == want {
                    view.level_box(&mut c, &nodes[node].bounds(slot), want, 0.0);
                }
            }
        }
        // Under the rays, the bundle's frustum: the region of the panel its rays sweep.
        view.frustum(&mut c, &rays, &b);
        let crossed = view.rays(&mut c, &rays, &hits, &b);
        if let Some(at) = root_label {
            let taken = plated_text(&mut c, at, "root", 11.0, style::muted(), Anchor::Left, 0.0);
            letter_boxes(&mut c, &view, &opened, nodes, taken);
        }
        if crossed == 0 {
            // Nothing of the bundle in the panel: say where it went rather than leave it blank.
            let why = "No ray of the bundle crosses this view: seen from above, all its rays \
                       pass beside the mesh's box, so every one misses it.";
            let lines = wrap(why, NOTE, view.size.0 - 24.0);
            let (cx, cy) = (view.at.0 + view.size.0 * 0.5, view.at.1 + view.size.1 * 0.5);
            for (i, line) in lines.iter().enumerate() {
                let at = (
                    cx,
                    cy + NOTE_STEP * (i as f32 - (lines.len() - 1) as f32 * 0.5),
                );
                // On a pale backing: the culled boxes' dashes run under it.
                plated_text(&mut c, at, line, NOTE, style::ink(), Anchor::Center, 4.0);
            }
        }
    }

    // Title, legend and footers.
    for (i, line) in title.iter().enumerate() {
        let y = 22.0 + TITLE_STEP * i as f32;
        c.text((SIDE_MARGIN, y), line, TITLE, style::ink(), Anchor::Left);
    }
    for (i, line) in sub.iter().enumerate() {
        let y = sub_y + SUB_STEP * i as f32;
        c.text((SIDE_MARGIN, y), line, SUB, style::ink(), Anchor::Left);
    }
    let lx = SIDE_MARGIN;
    c.rect(
        (lx, ly - 6.0),
        (22.0, 12.0),
        Some((style::shape_stroke(), 1.8)),
        Some(entered_fill()),
    );
    c.text(
        (lx + 30.0, ly),
        "entered: some ray enters it (the bundle goes on into it; a lone ray, alone)",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    c.line(
        (lx, ly + 20.0),
        (lx + 22.0, ly + 20.0),
        culled_color(),
        1.6,
        true,
    );
    c.text(
        (lx + 30.0, ly + 20.0),
        "culled: all the rays miss it (one test skips its whole subtree)",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    // Beside the first legend entry, the frustum's swatch.
    let fx = W / 2.0 + 60.0;
    c.rect((fx, ly - 6.0), (22.0, 12.0), None, Some(frustum_fill()));
    c.text(
        (fx + 30.0, ly),
        "the bundle's frustum: the wedge its rays sweep",
        12.0,
        style::ink(),
        Anchor::Left,
    );
    for (i, line) in footer.iter().enumerate() {
        let y = H - 14.0 - FOOTER_STEP * (footer.len() - 1 - i) as f32;
        c.text((SIDE_MARGIN, y), line, FOOTER, style::ink(), Anchor::Left);
    }
    Ok(c)
}

/// Figure layout: margins, the gap between the panels, the heights above and below them.
const SIDE_MARGIN: f32 = 24.0;
const GAP: f32 = 28.0;
/// The footer's text size and line step.
const FOOTER: f32 = 11.0;
const FOOTER_STEP: f32 = 20.0;
/// From the top of a panel's heading to the top of its frame (and one more step per line
/// of the panels' notes).
const PANEL_DROP: f32 = 22.0;
/// Text sizes, and the step between the lines of one wrapped text.
const TITLE: f32 = 15.0;
const TITLE_STEP: f32 = 20.0;
const SUB: f32 = 12.0;
const SUB_STEP: f32 = 16.0;
const HEADING: f32 = 13.0;
const NOTE: f32 = 11.0;
const NOTE_STEP: f32 = 15.0;
