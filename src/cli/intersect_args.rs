//! The arguments of `rtlab intersect` and their parsing into a shape and a ray (or, with
//! `--bundle-to`, a box for a bundle of rays): every option checked, each error naming it.

use super::parse_list;
use crate::error::{Error, Result};
use crate::math::Ray;
use crate::scene::json::{MAX_MAGNITUDE, MIN_SIZE};
use crate::shapes::{Cone, Cuboid, Cylinder, Plane, Shape, Sphere, Triangle};
use glam::DVec3;
use std::path::PathBuf;

// The doc comments are `--help` text: `[1]` is a default, not a link.
#[allow(rustdoc::broken_intra_doc_links)]
#[derive(Debug, clap::Args)]
pub struct Args {
    /// circle (2D), sphere, plane, cylinder, cone, box or triangle; csg or blob with --spec.
    pub shape: String,
    /// Ray origin P (X,Y for the circle, X,Y,Z otherwise).
    #[arg(long, allow_hyphen_values = true)]
    pub origin: String,
    /// Ray direction d, used as given (not normalised): points are P + t·d.
    #[arg(long, allow_hyphen_values = true)]
    pub dir: String,
    /// circle, sphere: centre [0,0(,0)].
    #[arg(long, allow_hyphen_values = true)]
    pub center: Option<String>,
    /// circle, sphere, cylinder: radius [1].
    #[arg(long, allow_hyphen_values = true)]
    pub radius: Option<String>,
    /// plane: a point on it [0,0,0].
    #[arg(long, allow_hyphen_values = true)]
    pub point: Option<String>,
    /// plane: its normal [0,1,0] (normalised).
    #[arg(long, allow_hyphen_values = true)]
    pub normal: Option<String>,
    /// cylinder, cone: lower end [-1].
    #[arg(long, allow_hyphen_values = true)]
    pub y_min: Option<String>,
    /// cylinder, cone: upper end [1].
    #[arg(long, allow_hyphen_values = true)]
    pub y_max: Option<String>,
    /// cone: k in x² + z² = (k·y)² [1].
    #[arg(long, allow_hyphen_values = true)]
    pub slope: Option<String>,
    /// cylinder, cone: no caps.
    #[arg(long)]
    pub open: bool,
    /// box: lower corner [-1,-1,-1].
    #[arg(long, allow_hyphen_values = true)]
    pub min: Option<String>,
    /// box: upper corner [1,1,1].
    #[arg(long, allow_hyphen_values = true)]
    pub max: Option<String>,
    /// triangle: corner a.
    #[arg(long, allow_hyphen_values = true)]
    pub a: Option<String>,
    /// triangle: corner b.
    #[arg(long, allow_hyphen_values = true)]
    pub b: Option<String>,
    /// triangle: corner c.
    #[arg(long, allow_hyphen_values = true)]
    pub c: Option<String>,
    /// csg, blob: a JSON file describing the solid, written as an object of a scene's
    /// "objects" (e.g. specs/dented-column.json).
    #[arg(long, value_name = "FILE")]
    pub spec: Option<PathBuf>,
    /// text (default) or json.
    #[arg(long, default_value = "text")]
    pub format: String,
    /// Also draw the figure to this PNG.
    #[arg(short = 'o', long = "output", value_name = "FIG.png")]
    pub output: Option<PathBuf>,
    /// box: test a bundle of rays against it as a BVH node's box (the bundle walk's interval
    /// and lane tests, book chapter 13): rays from --origin, their directions spread evenly
    /// from --dir to this one.
    #[arg(long, allow_hyphen_values = true, value_name = "X,Y,Z")]
    pub bundle_to: Option<String>,
    /// With --bundle-to: how many rays, 2 to 16 [16].
    #[arg(long, allow_hyphen_values = true)]
    pub rays: Option<String>,
}

pub const SHAPES: [&str; 7] = [
    "circle", "sphere", "plane", "cylinder", "cone", "box", "triangle",
];

/// The shortest direction a ray may have: shorter ones make a, the square of its length, fall
/// below what f64 holds (and 1/d overflow in the bundle's f32).
pub const MIN_LENGTH: f64 = 1e-12;

/// `n` comma-separated numbers, each within the limits a scene's loader sets on coordinates
/// ([`MAX_MAGNITUDE`]): beyond them the working's squares overflow and its answers would be
/// infinities and NaN.
pub fn bounded_list(arg: &str, s: &str, n: usize) -> Result<Vec<f64>> {
    let l = parse_list(arg, s, n)?;
    within(arg, &l)?;
    Ok(l)
}

/// Refuses coordinates beyond [`MAX_MAGNITUDE`].
pub fn within(arg: &str, l: &[f64]) -> Result<()> {
    match l.iter().find(|x| x.abs() > MAX_MAGNITUDE) {
        Some(x) => Err(Error::arg(
            arg,
            format!("{x:e} is out of range: coordinates up to {MAX_MAGNITUDE:e}, as in a scene"),
        )),
        None => Ok(()),
    }
}

/// X,Y,Z within the limits ([`bounded_list`]).
pub fn bounded_vec3(arg: &str, s: &str) -> Result<DVec3> {
    let v = bounded_list(arg, s, 3)?;
    Ok(DVec3::new(v[0], v[1], v[2]))
}

/// A ray's direction: not zero, not shorter than [`MIN_LENGTH`].
pub fn direction(arg: &str, d: DVec3) -> Result<DVec3> {
    if d.length() < MIN_LENGTH {
        return Err(Error::arg(
            arg,
            format!("the direction must not be zero (or shorter than {MIN_LENGTH:e})"),
        ));
    }
    Ok(d)
}

fn num(arg: &str, s: &Option<String>, default: f64) -> Result<f64> {
    match s {
        None => Ok(default),
        Some(s) => Ok(bounded_list(arg, s, 1)?[0]),
    }
}

fn vec3(arg: &str, s: &Option<String>, default: DVec3) -> Result<DVec3> {
    match s {
        None => Ok(default),
        Some(s) => bounded_vec3(arg, s),
    }
}

/// Rejects options that do not belong to `shape`, so a typo is not silently ignored.
fn only(args: &Args, allowed: &[&str]) -> Result<()> {
    let given = [
        ("--center", args.center.is_some()),
        ("--radius", args.radius.is_some()),
        ("--point", args.point.is_some()),
        ("--normal", args.normal.is_some()),
        ("--y-min", args.y_min.is_some()),
        ("--y-max", args.y_max.is_some()),
        ("--slope", args.slope.is_some()),
        ("--open", args.open),
        ("--min", args.min.is_some()),
        ("--max", args.max.is_some()),
        ("--a", args.a.is_some()),
        ("--b", args.b.is_some()),
        ("--c", args.c.is_some()),
    ];
    for (name, set) in given {
        if set && !allowed.contains(&name) {
            return Err(Error::arg(
                name,
                format!(
                    "{} has no {name} (its parameters: {})",
                    args.shape,
                    if allowed.is_empty() {
                        "none".to_string()
                    } else {
                        allowed.join(" ")
                    }
                ),
            ));
        }
    }
    Ok(())
}

/// Parses the arguments into a shape and a ray (both 3D; the circle lives in z = 0).
pub fn shape_and_ray(args: &Args) -> Result<(&'static str, Shape, Ray)> {
    let name = SHAPES
        .iter()
        .find(|s| **s == args.shape)
        .copied()
        .ok_or_else(|| {
            Error::arg(
                "SHAPE",
                format!(
                    "unknown shape \"{}\" (expected one of: {})",
                    args.shape,
                    SHAPES.join(", ")
                ),
            )
        })?;
    let two_d = name == "circle";
    let n = if two_d { 2 } else { 3 };
    let v = |arg: &str, s: &str| -> Result<DVec3> {
        let l = bounded_list(arg, s, n)?;
        Ok(DVec3::new(l[0], l[1], if two_d { 0.0 } else { l[2] }))
    };
    let origin = v("--origin", &args.origin)?;
    let dir = direction("--dir", v("--dir", &args.dir)?)?;
    // A size as a scene's loader takes it: positive, and not below MIN_SIZE.
    let positive = |arg: &str, x: f64| -> Result<f64> {
        if x <= 0.0 {
            Err(Error::arg(arg, format!("must be positive, found {x}")))
        } else if x < MIN_SIZE {
            Err(Error::arg(
                arg,
                format!("{x:e} is too small: sizes must be at least {MIN_SIZE:e}"),
            ))
        } else {
            Ok(x)
        }
    };
    let range = |lo: f64, hi: f64| -> Result<()> {
        if lo < hi {
            Ok(())
        } else {
            Err(Error::arg(
                "--y-min/--y-max",
                format!("--y-min ({lo}) must be below --y-max ({hi})"),
            ))
        }
    };
    let shape = match name {
        "circle" | "sphere" => {
            only(args, &["--center", "--radius"])?;
            let center = match &args.center {
                None => DVec3::ZERO,
                Some(s) => v("--center", s)?,
            };
            Shape::Sphere(Sphere {
                center,
                radius: positive("--radius", num("--radius", &args.radius, 1.0)?)?,
            })
        }
        "plane" => {
            only(args, &["--point", "--normal"])?;
            let normal = vec3("--normal", &args.normal, DVec3::Y)?
                .try_normalize()
                .ok_or_else(|| Error::arg("--normal", "the normal must not be zero"))?;
            Shape::Plane(Plane {
                point: vec3("--point", &args.point, DVec3::ZERO)?,
                normal,
            })
        }
        "cylinder" => {
            only(args, &["--radius", "--y-min", "--y-max", "--open"])?;
            let (lo, hi) = (
                num("--y-min", &args.y_min, -1.0)?,
                num("--y-max", &args.y_max, 1.0)?,
            );
            range(lo, hi)?;
            Shape::Cylinder(Cylinder {
                radius: positive("--radius", num("--radius", &args.radius, 1.0)?)?,
                y_min: lo,
                y_max: hi,
                capped: !args.open,
            })
        }
        "cone" => {
            only(args, &["--slope", "--y-min", "--y-max", "--open"])?;
            let (lo, hi) = (
                num("--y-min", &args.y_min, -1.0)?,
                num("--y-max", &args.y_max, 1.0)?,
            );
            range(lo, hi)?;
            Shape::Cone(Cone {
                slope: positive("--slope", num("--slope", &args.slope, 1.0)?)?,
                y_min: lo,
                y_max: hi,
                capped: !args.open,
            })
        }
        "box" => {
            let (min, max) = box_corners(args)?;
            Shape::Box(Cuboid { min, max })
        }
        _ => {
            only(args, &["--a", "--b", "--c"])?;
            let corner = |arg: &str, s: &Option<String>| -> Result<DVec3> {
                match s {
                    Some(s) => bounded_vec3(arg, s),
                    None => Err(Error::arg(
                        arg,
                        "a triangle needs its three corners: --a X,Y,Z --b X,Y,Z --c X,Y,Z",
                    )),
                }
            };
            Shape::Triangle(Triangle::new([
                corner("--a", &args.a)?,
                corner("--b", &args.b)?,
                corner("--c", &args.c)?,
            ]))
        }
    };
    Ok((name, shape, Ray::new(origin, dir)))
}

/// The box's corners (`--min`, `--max`), checked; no other shape's options.
pub fn box_corners(args: &Args) -> Result<(DVec3, DVec3)> {
    only(args, &["--min", "--max"])?;
    let (min, max) = (
        vec3("--min", &args.min, DVec3::splat(-1.0))?,
        vec3("--max", &args.max, DVec3::ONE)?,
    );
    if !min.cmplt(max).all() {
        return Err(Error::arg(
            "--min/--max",
            "every coordinate of --min must be below that of --max",
        ));
    }
    Ok((min, max))
}
