//! `rtlab intersect`: one ray against one canonical shape, with all the working shown.
//!
//! The numbers come from the shape's own intersection routine (`src/shapes/`), the one the
//! tracer runs, watched by a `Working` observer; nothing here solves anything itself.
//! The 2D `circle` is the sphere routine in the plane z = 0.
//!
//! Output format (DESIGN §3, version 1), `--format json`:
//! `{"shape", "ray": {"origin", "direction"}, "quadratic": null | {"a", "b", "c",
//! "discriminant", "roots", "rounded_to_zero"}, "candidates": [{"t", "point", "surface",
//! "on_shape", "in_front", "note"}], "barycentric": {"alpha", "beta", "gamma", "determinant",
//! "t"} (triangles only), "hit": null | {"t", "point", "normal", "surface"}}`.
//! Points of the circle have two coordinates. Full f64 precision.

use crate::error::{Error, Result};
use crate::shapes::working::{short, tiny, vector};
use crate::shapes::{Roots, Shape, TANGENT_TOLERANCE};
use glam::DVec3;
use std::fmt::Write as _;

// The arguments and their parsing have their own module; re-exported where they used to live.
use super::intersect_args::{bounded_vec3, direction};
pub use super::intersect_args::{shape_and_ray, Args, SHAPES};

// The report is a library type; re-exported here where it used to live.
pub use crate::report::intersect::{
    report, BarycentricJson, CandidateJson, HitJson, LinearJson, QuadraticJson, RayJson, Report,
};

fn pv(v: &[f64]) -> String {
    vector(v, short)
}

/// A coefficient as the equation shows it: "+ 6" or "− 6".
fn signed(x: f64) -> String {
    if x < 0.0 {
        format!("− {}", short(-x))
    } else {
        format!("+ {}", short(x))
    }
}

/// The substituted equation of each shape, in words a student can check by hand.
fn equation(r: &Report) -> &'static str {
    match r.shape {
        "circle" => "(x − cx)² + (y − cy)² − r² = 0 becomes (d·d) t² + 2 d·(P − C) t + |P − C|² − r² = 0",
        "sphere" => "|Q − C|² − r² = 0 becomes (d·d) t² + 2 d·(P − C) t + |P − C|² − r² = 0",
        "cylinder" => "body x² + z² − r² = 0 becomes (dx² + dz²) t² + 2(Px·dx + Pz·dz) t + Px² + Pz² − r² = 0; caps: y = y_max and y = y_min give t = (y_cap − Py)/dy",
        "cone" => "body x² + z² − k²y² = 0 becomes (dx² + dz² − k²dy²) t² + 2(Px·dx + Pz·dz − k²Py·dy) t + Px² + Pz² − k²Py² = 0; caps: t = (y_cap − Py)/dy",
        "plane" => "n·(Q − Q0) = 0 becomes t = n·(Q0 − P) / (n·d)",
        "box" => "each face plane x = min.x, x = max.x, y = ..., z = ... gives t = (plane − P)/d on that axis; a root counts if the point is inside the face",
        _ => "P + t·d = a + β(b − a) + γ(c − a), solved for (β, γ, t) by Cramer's rule; α = 1 − β − γ",
    }
}

/// The readable form.
pub fn text(r: &Report) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "{}: {}", r.shape, describe(&r.solid, r.is_2d()));
    let _ = writeln!(
        o,
        "ray: P = {}, d = {}",
        pv(&r.ray.origin),
        pv(&r.ray.direction)
    );
    let len = r.ray3.dir.length();
    if (len - 1.0).abs() > 1e-9 {
        let _ = writeln!(
            o,
            "  note: |d| = {} is not 1, so t is not a distance (distance = t·|d|); d is used as given",
            short(len)
        );
    }
    let _ = writeln!(o, "equation: {}", equation(r));
    if let Some(q) = &r.quadratic {
        let _ = writeln!(
            o,
            "  a = {}, b = {}, c = {}:  {}·t² {}·t {} = 0",
            short(q.a),
            short(q.b),
            short(q.c),
            short(q.a),
            signed(q.b),
            signed(q.c)
        );
        if q.rounded_to_zero {
            let _ = writeln!(
                o,
                "discriminant D = b² − 4ac = 0  (floating point computed {}; see below)",
                tiny(q.discriminant)
            );
        } else {
            let _ = writeln!(o, "discriminant D = b² − 4ac = {}", tiny(q.discriminant));
        }
        let verdict = match q.roots {
            Roots::Two => "D > 0: two roots, the ray enters and leaves",
            Roots::Tangent => "D = 0: one root t = −b/2a, the ray grazes the surface (tangent)",
            Roots::One => "a = 0: the equation is linear, one root t = −c/b",
            Roots::None => "D < 0: no real root, the ray misses this surface",
        };
        let _ = writeln!(o, "  verdict: {verdict}");
        if q.rounded_to_zero {
            let scale = (q.b * q.b).max((4.0 * q.a * q.c).abs());
            let _ = writeln!(
                o,
                "  why D is taken as 0: in exact arithmetic D = 0 here, but b² = {} and 4ac = {} are each \
                 rounded to the nearest double (about 1e-16 of their size), so their difference comes out \
                 as {} instead of 0. rtlab treats |D| ≤ {:e} · max(b², |4ac|) = {:.1e} as zero \
                 (TANGENT_TOLERANCE in src/shapes/quadratic.rs): a tangent, not a miss.",
                short(q.b * q.b),
                short(4.0 * q.a * q.c),
                tiny(q.discriminant),
                TANGENT_TOLERANCE,
                TANGENT_TOLERANCE * scale
            );
        }
    }
    if let Some(l) = &r.linear {
        if l.denominator == 0.0 {
            let _ = writeln!(
                o,
                "  n·d = 0: the ray is parallel to the plane, no root (n·(Q0 − P) = {}: {})",
                short(l.numerator),
                if l.numerator == 0.0 {
                    "the ray lies in the plane"
                } else {
                    "it runs beside it"
                }
            );
        } else {
            let _ = writeln!(
                o,
                "  n·(Q0 − P) = {}, n·d = {}: t = {} / {} = {}",
                short(l.numerator),
                short(l.denominator),
                short(l.numerator),
                short(l.denominator),
                short(l.numerator / l.denominator)
            );
        }
    }
    if let Some(b) = &r.barycentric {
        match (b.alpha, b.beta, b.gamma, b.t) {
            (Some(al), Some(be), Some(ga), Some(t)) => {
                let d = b.determinant;
                let _ = writeln!(
                    o,
                    "Cramer's rule: columns e1 = b − a, e2 = c − a, −d; right-hand side s = P − a"
                );
                let _ = writeln!(o, "  det[e1 e2 −d] = {}", short(d));
                let _ = writeln!(
                    o,
                    "  det[s e2 −d] = {}  → beta  = {} / {} = {}",
                    short(be * d),
                    short(be * d),
                    short(d),
                    short(be)
                );
                let _ = writeln!(
                    o,
                    "  det[e1 s −d] = {}  → gamma = {} / {} = {}",
                    short(ga * d),
                    short(ga * d),
                    short(d),
                    short(ga)
                );
                let _ = writeln!(
                    o,
                    "  det[e1 e2 s] = {}  → t     = {} / {} = {}",
                    short(t * d),
                    short(t * d),
                    short(d),
                    short(t)
                );
                let _ = writeln!(o, "  alpha = 1 − beta − gamma = {}", short(al));
                let inside = be >= 0.0 && ga >= 0.0 && be + ga <= 1.0;
                let _ = writeln!(
                    o,
                    "  inside iff beta ≥ 0, gamma ≥ 0, beta + gamma ≤ 1: {}",
                    if inside {
                        "yes"
                    } else {
                        "no, the ray meets the plane outside the triangle"
                    }
                );
            }
            _ => {
                let _ = writeln!(
                    o,
                    "Cramer's rule: det[e1 e2 −d] = 0, no unique solution: the ray is parallel to the \
                     triangle's plane, or the triangle is degenerate (its corners are on one line)"
                );
            }
        }
    }
    if r.candidates.is_empty() {
        let _ = writeln!(o, "candidates: none");
    } else {
        let _ = writeln!(o, "candidates (every root, sorted by t):");
        for (i, c) in r.candidates.iter().enumerate() {
            let name = if r.candidates.len() == 1 {
                "t".to_string()
            } else {
                format!("t{}", i + 1)
            };
            let _ = writeln!(
                o,
                "  {name:<3} = {:<9} {:<10} point {}: {}",
                short(c.t),
                c.surface,
                pv(&c.point),
                c.note
            );
        }
    }
    match &r.hit {
        Some(h) => {
            let _ = writeln!(
                o,
                "hit: t = {} on {}, point {}, normal {}",
                short(h.t),
                h.surface,
                pv(&h.point),
                pv(&h.normal)
            );
        }
        None => {
            let _ = writeln!(o, "hit: none, the ray misses");
        }
    }
    o
}

/// The shape's parameters in one line.
pub fn describe(shape: &Shape, two_d: bool) -> String {
    let v3 = |v: DVec3| pv(&[v.x, v.y, v.z]);
    match shape {
        Shape::Sphere(s) if two_d => format!(
            "centre {}, radius {}",
            pv(&[s.center.x, s.center.y]),
            short(s.radius)
        ),
        Shape::Sphere(s) => format!("centre {}, radius {}", v3(s.center), short(s.radius)),
        Shape::Plane(p) => format!("through {}, normal {}", v3(p.point), v3(p.normal)),
        Shape::Cylinder(c) => format!(
            "x² + z² = {}², {} ≤ y ≤ {}, {}",
            short(c.radius),
            short(c.y_min),
            short(c.y_max),
            if c.capped { "capped" } else { "open" }
        ),
        Shape::Cone(c) => format!(
            "x² + z² = ({}·y)², {} ≤ y ≤ {}, {}",
            short(c.slope),
            short(c.y_min),
            short(c.y_max),
            if c.capped { "capped" } else { "open" }
        ),
        Shape::Box(b) => format!("from {} to {}", v3(b.min), v3(b.max)),
        Shape::Triangle(t) => format!("a = {}, b = {}, c = {}", v3(t.v[0]), v3(t.v[1]), v3(t.v[2])),
        Shape::Mesh(_) => "mesh".into(),
        Shape::Csg(_) => "CSG solid".into(),
        Shape::Blob(_) => "blob".into(),
    }
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    if args.format != "text" && args.format != "json" {
        return Err(Error::arg(
            "--format",
            format!("unknown format \"{}\" (expected text or json)", args.format),
        ));
    }
    if let Some(o) = &args.output {
        crate::output::check_png(o, "-o")?;
    }
    if let Some(to) = &args.bundle_to {
        return super::intersect_bundle::run(&args, to, out);
    }
    if args.rays.is_some() {
        return Err(Error::arg(
            "--rays",
            "--rays counts the rays of a bundle: it goes with --bundle-to",
        ));
    }
    if args.shape == "csg" || args.shape == "blob" {
        // Solids built from other solids: intervals along the ray, or a field's profile.
        let spec = args.spec.as_deref().ok_or_else(|| {
            Error::arg(
                "--spec",
                format!(
                    "{} needs --spec FILE (a JSON description of the solid)",
                    args.shape
                ),
            )
        })?;
        let origin = bounded_vec3("--origin", &args.origin)?;
        let dir = direction("--dir", bounded_vec3("--dir", &args.dir)?)?;
        return super::intersect_solids::run(
            &args.shape,
            spec,
            origin,
            dir,
            args.format == "json",
            args.output.as_deref(),
            out,
        );
    }
    if args.spec.is_some() {
        return Err(Error::arg(
            "--spec",
            format!("only csg and blob take --spec, not {}", args.shape),
        ));
    }
    let (name, shape, ray) = shape_and_ray(&args)?;
    let r = report(name, shape, ray);
    if let Some(o) = &args.output {
        crate::viz::intersect::figure(&r).write_png(o)?;
    }
    let s = if args.format == "json" {
        serde_json::to_string_pretty(&r).expect("serialisable") + "\n"
    } else {
        text(&r)
    };
    super::emit(out, &s)
}
