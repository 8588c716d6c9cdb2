//! `rtlab intersect box --bundle-to X,Y,Z`: a bundle of rays against one box as a BVH node
//! holds it, through the bundle walk's own two tests (chapter 13, "Beam tracing"): the
//! interval test, which bounds every ray at once, and the lane test, each ray's own slab
//! test. The numbers come from [`crate::accel::bundle_working`]; nothing here tests anything.
//!
//! `--format json` (an addition to DESIGN §3's `intersect` output, only with `--bundle-to`):
//! `{"shape": "box", "box": {"min", "max"}, "rays": [{"origin", "direction", "lane_test",
//! "own_test", "t_enter"}], "sign_coherent", "sign_coherent_axes", "shared_origin",
//! "interval_test": {"axes": [null | {"entry", "exit"}] (x, y, z), "together": null |
//! {"entry", "exit"}, "kept": null | bool}}`. The bounds and `t_enter` are the `f32`
//! values the walk computes (the origins and directions are the f64 rays, as given);
//! `t_enter` is null for a ray that misses; `lane_test`, `together` and `kept` are null
//! when the bundle is not sign-coherent (no bundle test is made). `sign_coherent_axes`
//! (added later; fields are only ever added) is `[bool; 3]`, x, y, z: false for an axis
//! along which the directions change sign; `sign_coherent` is all three.

use super::emit;
use super::intersect_args::{bounded_vec3, box_corners, direction, Args, MIN_LENGTH};
use crate::accel::{bundle_working, BundleWorking, BUNDLE};
use crate::error::{Error, Result};
use crate::math::Ray;
use crate::shapes::working::{tiny, vector};
use crate::shapes::Aabb;
use glam::DVec3;
use serde::Serialize;

use std::fmt::Write as _;

/// The bundle the arguments describe: `--rays` rays (16 unless given) from `--origin`, their
/// directions spread evenly from `--dir` to `--bundle-to`, and the box.
pub fn bundle_and_box(args: &Args, to: &str) -> Result<(Vec<Ray>, Aabb)> {
    if args.shape != "box" {
        return Err(Error::arg(
            "--bundle-to",
            format!(
                "only box takes a bundle of rays (the box of a BVH node), not {}",
                args.shape
            ),
        ));
    }
    if args.spec.is_some() {
        return Err(Error::arg(
            "--spec",
            "only csg and blob take --spec, not box",
        ));
    }
    let n = match &args.rays {
        None => BUNDLE,
        Some(s) => match s.trim().parse::<usize>() {
            Ok(n) if (2..=BUNDLE).contains(&n) => n,
            _ => {
                return Err(Error::arg(
                    "--rays",
                    format!("\"{s}\" is not a number of rays: a bundle holds a whole number from 2 to {BUNDLE}"),
                ))
            }
        },
    };
    // The walk's tests run in f32: numbers as large as a scene may hold (its loader's
    // limit), and directions long enough that 1/d is a number.
    let origin = bounded_vec3("--origin", &args.origin)?;
    let (first, last) = (
        direction("--dir", bounded_vec3("--dir", &args.dir)?)?,
        direction("--bundle-to", bounded_vec3("--bundle-to", to)?)?,
    );
    let (min, max) = box_corners(args)?;
    // The first and last rays exactly as given, those between spread evenly as weights of
    // the two, so that a signed zero both share is every ray's (-0 in a direction picks the
    // slab test's far side, and splits a bundle as the walk does).
    let rays: Vec<Ray> = (0..n)
        .map(|i| match i {
            0 => Ray::new(origin, first),
            _ if i == n - 1 => Ray::new(origin, last),
            _ => {
                let s = i as f64 / (n - 1) as f64;
                Ray::new(origin, first * (1.0 - s) + last * s)
            }
        })
        .collect();
    if let Some(i) = rays.iter().position(|r| r.dir.length() < MIN_LENGTH) {
        return Err(Error::arg(
            "--bundle-to",
            format!(
                "ray {i}'s direction, between --dir and --bundle-to, is shorter than {MIN_LENGTH:e}: \
                 they must not point (nearly) opposite ways, and not be that short themselves"
            ),
        ));
    }
    Ok((rays, Aabb::new(min, max)))
}

#[derive(Serialize)]
struct Json {
    shape: &'static str,
    #[serde(rename = "box")]
    bounds: BoxJson,
    rays: Vec<RayJson>,
    sign_coherent: bool,
    sign_coherent_axes: [bool; 3],
    shared_origin: bool,
    interval_test: IntervalJson,
}

#[derive(Serialize)]
struct BoxJson {
    min: [f32; 3],
    max: [f32; 3],
}

#[derive(Serialize)]
struct RayJson {
    origin: [f64; 3],
    direction: [f64; 3],
    lane_test: Option<bool>,
    own_test: bool,
    t_enter: Option<f32>,
}

#[derive(Serialize)]
struct AxisJson {
    entry: f32,
    exit: f32,
}

#[derive(Serialize)]
struct IntervalJson {
    axes: [Option<AxisJson>; 3],
    together: Option<AxisJson>,
    kept: Option<bool>,
}

fn json(rays: &[Ray], w: &BundleWorking) -> String {
    let j = Json {
        shape: "box",
        bounds: BoxJson {
            min: w.min,
            max: w.max,
        },
        rays: rays
            .iter()
            .zip(&w.rays)
            .map(|(r, v)| RayJson {
                origin: r.origin.to_array(),
                direction: r.dir.to_array(),
                lane_test: v.lane,
                own_test: v.own,
                t_enter: v.own.then_some(v.t_enter),
            })
            .collect(),
        sign_coherent: w.coherent,
        sign_coherent_axes: w.coherent_axes,
        shared_origin: w.shared_origin,
        interval_test: IntervalJson {
            axes: w
                .axes
                .map(|a| a.map(|(entry, exit)| AxisJson { entry, exit })),
            together: w.together.map(|(entry, exit)| AxisJson { entry, exit }),
            kept: w.kept,
        },
    };
    serde_json::to_string_pretty(&j).expect("serialisable") + "\n"
}

fn v3(v: DVec3) -> String {
    vector(&v.to_array(), tiny)
}

fn f3(v: [f32; 3]) -> String {
    format!("({}, {}, {})", v[0], v[1], v[2])
}

/// The working as text: the bundle, the interval test axis by axis, then every ray's lane.
pub fn text(rays: &[Ray], w: &BundleWorking) -> String {
    let n = rays.len();
    let mut s = String::new();
    let (first, last) = (rays[0].dir, rays[n - 1].dir);
    let _ = writeln!(s, "A bundle of {n} rays against one box of a BVH node");
    let _ = writeln!(
        s,
        "  box (as the BVH stores it, its corners rounded outwards to f32): from {} to {}",
        f3(w.min),
        f3(w.max)
    );
    let _ = writeln!(
        s,
        "  rays: from P = {}, directions spread evenly from d = {} to {}",
        v3(rays[0].origin),
        v3(first),
        v3(last)
    );
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "1. The interval test: the whole bundle against the box at once"
    );
    let Some(kept) = w.kept else {
        let _ = writeln!(
            s,
            "  the directions change sign along {}: the bundle is not sign-coherent, so there\n  \
             is no interval test for the box (on any axis); the walk sends each ray alone",
            w.mixed_axes()
        );
        for k in 0..3 {
            let _ = writeln!(s, "    {}", axis_signs(rays, w, k));
        }
        lanes(&mut s, rays, w, false);
        return s;
    };
    let _ = writeln!(
        s,
        "  every direction has one sign per axis (sign-coherent); per axis, a t no later than\n  \
         any ray's entry into the slab and one no earlier than any ray's exit:"
    );
    for (k, axis) in w.axes.iter().enumerate() {
        let name = ["x", "y", "z"][k];
        match axis {
            Some((a, b)) => {
                let _ = writeln!(s, "    {name}: entry ≥ {a}, exit ≤ {b}");
            }
            None => {
                let _ = writeln!(
                    s,
                    "    {name}: no bound (some ray's 1/d along {name} is ±∞: its direction there is 0)"
                );
            }
        }
    }
    let (entry, exit) = w.together.unwrap_or((0.0, f32::INFINITY));
    let _ = writeln!(
        s,
        "  together (the latest entry bound, from t = 0, and the earliest exit bound, each\n  \
         widened by a few units in the last place for rounding): no ray enters the box\n  \
         before t = {entry}, and every ray has left it by t = {exit}"
    );
    if kept {
        let _ = writeln!(
            s,
            "  → kept: the bounds leave room for a ray to enter; each ray now gets the lane test"
        );
    } else {
        let _ = writeln!(
            s,
            "  → culled: even the bounds enter after they leave, so every ray misses: one test\n    \
             skips the box, and everything under it, for all {n} rays"
        );
    }
    lanes(&mut s, rays, w, !kept);
    s
}

const AXES: [&str; 3] = BundleWorking::AXES;

/// One axis's signs for a bundle that is not sign-coherent: "x: dx from -0.3 to 0.3, changes
/// sign ...", "z: dz = 1 for every ray, one sign (positive); ...", or for a zero, "y: dy = 0
/// for every ray (+0, which the walk's 1/d counts as positive); ...". The figure's rows say
/// the same.
fn axis_signs(rays: &[Ray], w: &BundleWorking, k: usize) -> String {
    let (lo, hi) = rays
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
            (lo.min(r.dir[k]), hi.max(r.dir[k]))
        });
    let name = AXES[k];
    let range = if lo == hi {
        format!("d{name} = {} for every ray", tiny(lo))
    } else {
        format!("d{name} from {} to {}", tiny(lo), tiny(hi))
    };
    if w.coherent_axes[k] {
        // The sign the walk sees is that of 1/d: a zero is +0 or −0, which 1/d makes +∞ or
        // −∞, so the walk counts it as positive or negative; the text says so rather than
        // call a zero positive.
        let negative = rays[0].dir[k].is_sign_negative();
        let (sign, zero) = if negative {
            ("negative", "−0")
        } else {
            ("positive", "+0")
        };
        let counted = format!("{zero}, which the walk's 1/d counts as {sign}");
        let signs = if hi == 0.0 && lo == 0.0 {
            format!(" ({counted})")
        } else if lo == 0.0 || hi == 0.0 {
            format!(", one sign ({sign}, with {counted})")
        } else {
            format!(", one sign ({sign})")
        };
        format!("{name}: {range}{signs}; unused, as the bundle is mixed")
    } else {
        format!("{name}: {range}, changes sign (1/d{name} would pass through ±∞): no bound")
    }
}

fn lanes(s: &mut String, rays: &[Ray], w: &BundleWorking, culled: bool) {
    let _ = writeln!(s);
    let together = w.kept.is_some();
    if together {
        let _ = writeln!(
            s,
            "2. The lane test: each ray's own slab test, all {} in one pass{}",
            rays.len(),
            if culled {
                " (the walk skips it after a cull;\n   shown here to check it)"
            } else {
                ""
            }
        );
    } else {
        let _ = writeln!(s, "2. Each ray alone: its own slab test");
    }
    let _ = writeln!(s, "    ray  direction                 enters  entry t");
    for (i, (r, v)) in rays.iter().zip(&w.rays).enumerate() {
        let _ = writeln!(
            s,
            "    {i:>3}  {:<24}  {:<6}  {}",
            v3(r.dir),
            if v.lane.unwrap_or(v.own) { "yes" } else { "no" },
            if v.own {
                v.t_enter.to_string()
            } else {
                "-".into()
            }
        );
    }
    let entering = w.rays.iter().filter(|v| v.lane.unwrap_or(v.own)).count();
    let _ = write!(s, "  {entering} of {} rays enter", rays.len());
    if together {
        let agree = w.rays.iter().all(|v| v.lane == Some(v.own));
        let _ = write!(
            s,
            "; {}",
            if agree {
                "each lane says what that ray's own slab test says (the single-ray walk's)"
            } else {
                "A LANE DISAGREES with its ray's own slab test: a bug, please report it"
            }
        );
    }
    let _ = writeln!(s);
}

/// `rtlab intersect box --bundle-to ...`.
pub fn run(args: &Args, to: &str, out: &mut dyn std::io::Write) -> Result<()> {
    let (rays, bounds) = bundle_and_box(args, to)?;
    let w = bundle_working(&rays, &bounds);
    if let Some(o) = &args.output {
        crate::viz::interval::figure(&rays, &w).write_png(o)?;
    }
    let s = if args.format == "json" {
        json(&rays, &w)
    } else {
        text(&rays, &w)
    };
    emit(out, &s)
}
