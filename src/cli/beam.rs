//! `rtlab beam`: Heckbert and Hanrahan's beam tracing in the plane. One beam from an eye,
//! clipped against walls and mirrors nearest first; each mirror's piece reflected in turn.
//! Prints the pieces and, with `-o`, draws them ([`crate::viz::beam`]).

use super::intersect_args::bounded_list;
use crate::accel::beam::{self, name, Beam, Piece, Segment};
use crate::error::{Error, Result};
use crate::output::check_png;
use crate::shapes::working::tiny;
use glam::DVec2;
use std::path::PathBuf;

/// The most reflections a beam is followed through, and the most walls and mirrors
/// together: each beam has at most 2·16 + 1 pieces, so a beam and its reflections stay
/// under 33 · 16³ pieces however the mirrors face each other.
pub const MAX_DEPTH: u32 = 3;
pub const MAX_SEGMENTS: usize = 16;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Where the beam starts (the eye): X,Y.
    #[arg(
        long,
        value_name = "X,Y",
        default_value = "0,0",
        allow_hyphen_values = true
    )]
    pub eye: String,
    /// One edge of the beam, a direction: DX,DY.
    #[arg(long, value_name = "DX,DY", allow_hyphen_values = true)]
    pub from: String,
    /// The other edge of the beam (the beam is the narrower wedge between the two).
    #[arg(long, value_name = "DX,DY", allow_hyphen_values = true)]
    pub to: String,
    /// A wall, which stops the beam: X1,Y1,X2,Y2 (repeat for more).
    #[arg(long, value_name = "X1,Y1,X2,Y2", allow_hyphen_values = true)]
    pub wall: Vec<String>,
    /// A mirror, which reflects the part of the beam it sees, on either side: X1,Y1,X2,Y2
    /// (repeat for more).
    #[arg(long, value_name = "X1,Y1,X2,Y2", allow_hyphen_values = true)]
    pub mirror: Vec<String>,
    /// How many reflections to follow (0 to 3).
    #[arg(
        long,
        value_name = "N",
        default_value_t = 1,
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u32).range(0..=MAX_DEPTH as i64)
    )]
    pub depth: u32,
    /// Output format: text or json (`{"eye", "from", "to", "degrees", "pieces": [{"from",
    /// "to", "degrees", "near", "seen_by": {"name", "mirror", "points"} | null,
    /// "reflected": {"apex", "pieces"} | null}]}`).
    #[arg(long, default_value = "text", value_name = "text|json")]
    pub format: String,
    /// Also draw the beam and its pieces (PNG).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
}

/// The eye, the beam and the segments the arguments describe, checked.
pub fn parse(args: &Args) -> Result<(Beam, Vec<Segment>)> {
    let point = |arg: &str, s: &str| -> Result<DVec2> {
        let v = bounded_list(arg, s, 2)?;
        Ok(DVec2::new(v[0], v[1]))
    };
    // A direction in the plane, checked by the same rule as a ray's (`intersect`).
    let dir = |arg: &str, s: &str| -> Result<DVec2> {
        let d = point(arg, s)?;
        super::intersect_args::direction(arg, glam::DVec3::new(d.x, d.y, 0.0))?;
        Ok(d)
    };
    let eye = point("--eye", &args.eye)?;
    let beam = Beam::between(eye, dir("--from", &args.from)?, dir("--to", &args.to)?);
    beam::width(&beam).map_err(|p| Error::arg("--from/--to", p.message(&[])))?;
    if args.depth > MAX_DEPTH {
        return Err(Error::arg(
            "--depth",
            format!("{} reflections is more than {MAX_DEPTH}", args.depth),
        ));
    }
    let mut segments = Vec::new();
    for (arg, list, mirror) in [
        ("--wall", &args.wall, false),
        ("--mirror", &args.mirror, true),
    ] {
        for s in list {
            let v = bounded_list(arg, s, 4)?;
            segments.push(Segment {
                a: DVec2::new(v[0], v[1]),
                b: DVec2::new(v[2], v[3]),
                mirror,
            });
        }
    }
    if segments.is_empty() {
        return Err(Error::arg(
            "--wall/--mirror",
            "give at least one wall or mirror for the beam to meet",
        ));
    }
    if segments.len() > MAX_SEGMENTS {
        return Err(Error::arg(
            "--wall/--mirror",
            format!("{} segments is more than {MAX_SEGMENTS}", segments.len()),
        ));
    }
    beam::check(eye, &segments).map_err(|p| Error::arg("--wall/--mirror", p.message(&segments)))?;
    Ok((beam, segments))
}

fn xy(p: DVec2) -> [f64; 2] {
    [p.x, p.y]
}

/// What a coordinate must exceed, relative to the scale it is computed at, not to be
/// rounding noise: the text prints such noise as 0, and the JSON writes it as 0 too, so the
/// two agree ("from (2, 3) to (0, 3)", not "to (3.3e-16, 3)").
const NOISE: f64 = 1e-12;

/// How the plane's numbers are shown, text and JSON alike: noise cleared to 0. A direction's
/// noise is relative to its own length; a point's to the larger of its own size and `scale`,
/// the size of what the first beam reaches (the eye and where it meets segments), not of the
/// segments' far ends: a mirror 10¹² long does not make (0.5, 2) noise.
struct Clean {
    scale: f64,
}

impl Clean {
    fn new(beam: &Beam, pieces: &[Piece]) -> Clean {
        let reach = pieces
            .iter()
            .filter_map(|p| p.hit)
            .flat_map(|(_, h)| h)
            .chain([beam.apex]);
        Clean {
            scale: reach.map(|p| p.abs().max_element()).fold(0.0, f64::max),
        }
    }

    fn point(&self, p: DVec2) -> DVec2 {
        zero_below(p, NOISE * p.abs().max_element().max(self.scale))
    }

    fn dir(&self, d: DVec2) -> DVec2 {
        zero_below(d, NOISE * d.abs().max_element())
    }
}

/// `p` with each coordinate no larger than `t` (and -0) written as 0.
fn zero_below(p: DVec2, t: f64) -> DVec2 {
    let z = |x: f64| if x.abs() <= t { 0.0 } else { x };
    DVec2::new(z(p.x), z(p.y))
}

/// The pieces as JSON (the shape `--format` documents): full precision, rounding noise 0.
fn to_json(segments: &[Segment], pieces: &[Piece], clean: &Clean) -> Vec<serde_json::Value> {
    let pt = |p: DVec2| xy(clean.point(p));
    let dir = |d: DVec2| xy(clean.dir(d));
    pieces
        .iter()
        .map(|p| {
            serde_json::json!({
                "from": dir(p.from),
                "to": dir(p.to),
                "degrees": p.degrees,
                "near": [pt(p.near[0]), pt(p.near[1])],
                "seen_by": p.hit.map(|(i, [a, b])| serde_json::json!({
                    "name": name(segments, i),
                    "mirror": segments[i].mirror,
                    "points": [pt(a), pt(b)],
                })),
                "reflected": p.reflected.as_ref().map(|(r, sub)| serde_json::json!({
                    "apex": pt(r.apex),
                    "pieces": to_json(segments, sub, clean),
                })),
            })
        })
        .collect()
}

/// `x` with `decimals` decimals (four: [`tiny`]), trailing zeros dropped; below 1e-4, in
/// scientific form with as many significant digits.
fn number(x: f64, decimals: usize) -> String {
    if decimals <= 4 {
        return tiny(x);
    }
    if x != 0.0 && x.abs() < 1e-4 {
        let s = format!("{x:.*e}", decimals - 3);
        let (mantissa, exp) = s.split_once('e').expect("scientific form");
        let mantissa = mantissa.trim_end_matches('0');
        let mantissa = match mantissa.strip_suffix('.') {
            Some(m) => format!("{m}.0"),
            None => mantissa.to_string(),
        };
        return format!("{mantissa}e{exp}");
    }
    let s = format!("{x:.decimals$}");
    match s.trim_end_matches('0').trim_end_matches('.') {
        "-0" => "0".to_string(),
        t => t.to_string(),
    }
}

fn v2(p: DVec2, decimals: usize) -> String {
    format!("({}, {})", number(p.x, decimals), number(p.y, decimals))
}

/// The value `v2` shows, read back.
fn shown(p: DVec2, decimals: usize) -> DVec2 {
    let back = |x: f64| number(x, decimals).parse::<f64>().unwrap_or(x);
    DVec2::new(back(p.x), back(p.y))
}

/// `a` and `b` with four decimals, or as many more as it takes for the printed values to
/// `differ` (two directions a millionth of a degree apart do not both read "(1, 1)").
fn apart(a: DVec2, b: DVec2, differ: impl Fn(DVec2, DVec2) -> bool) -> (String, String) {
    let decimals = (4..=17)
        .find(|&d| differ(shown(a, d), shown(b, d)))
        .unwrap_or(17);
    (v2(a, decimals), v2(b, decimals))
}

/// Two different directions, not parallel as printed.
fn directions(a: DVec2, b: DVec2) -> (String, String) {
    apart(a, b, |a, b| a.perp_dot(b) != 0.0 || a.dot(b) < 0.0)
}

/// Two different points, not equal as printed.
fn points(a: DVec2, b: DVec2) -> (String, String) {
    apart(a, b, |a, b| a != b)
}

/// A width in degrees: four decimals, or as many more as it takes for a width under the
/// widest a beam may be ([`beam::WIDEST`], 179.9999999°) to read under it.
fn degrees(d: f64) -> String {
    let decimals = (4..=15)
        .find(|&k| d >= beam::WIDEST || number(d, k).parse::<f64>().is_ok_and(|v| v < beam::WIDEST))
        .unwrap_or(15);
    number(d, decimals)
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    if let Some(o) = &args.output {
        check_png(o, "-o")?;
    }
    if args.format != "text" && args.format != "json" {
        return Err(Error::arg(
            "--format",
            format!("unknown format \"{}\" (expected text or json)", args.format),
        ));
    }
    let (beam, segments) = parse(&args)?;
    let pieces = beam::trace(&beam, &segments, args.depth);
    let wide = beam::width(&beam).unwrap_or(0.0);
    let clean = Clean::new(&beam, &pieces);
    if args.format == "json" {
        if let Some(o) = &args.output {
            crate::viz::beam::figure(&beam, &segments, &pieces).write_png(o)?;
        }
        let doc = serde_json::json!({
            "eye": xy(clean.point(beam.apex)),
            "from": xy(clean.dir(beam.from)),
            "to": xy(clean.dir(beam.to)),
            "degrees": wide,
            "pieces": to_json(&segments, &pieces, &clean),
        });
        return super::emit(
            out,
            &(serde_json::to_string_pretty(&doc).expect("plain JSON") + "\n"),
        );
    }
    let (from, to) = directions(clean.dir(beam.from), clean.dir(beam.to));
    let mut text = format!(
        "A beam from the eye at {}, counterclockwise from direction {from} to {to} ({}° wide), \
         clipped against {} segment(s) nearest first (Heckbert and Hanrahan 1984).\n\
         Its pieces, counterclockwise; each is the part of the beam one segment sees, or that meets none:\n",
        v2(clean.point(beam.apex), 4),
        degrees(wide),
        segments.len()
    );
    let list = List {
        segments: &segments,
        clean: &clean,
    };
    list.describe(&mut text, &pieces, "", 1, "");
    let total: f64 = pieces.iter().map(|p| p.degrees).sum();
    text += &format!(
        "Every ray of the beam lies in exactly one piece: their widths add up to {}°.\n",
        degrees(total)
    );
    if let Some(o) = &args.output {
        crate::viz::beam::figure(&beam, &segments, &pieces).write_png(o)?;
    }
    super::emit(out, &text)?;
    // On stderr, as `render` says it: stdout is the description alone.
    if let Some(o) = &args.output {
        eprintln!("wrote {}", o.display());
    }
    Ok(())
}

/// What the printed list of pieces needs besides the pieces.
struct List<'a> {
    segments: &'a [Segment],
    clean: &'a Clean,
}

impl List<'_> {
    /// The pieces as indented lines, numbered `prefix` 1, 2, …; a reflected beam's pieces
    /// under the piece of the mirror that made it.
    fn describe(
        &self,
        text: &mut String,
        pieces: &[Piece],
        prefix: &str,
        level: usize,
        mirrored: &str,
    ) {
        let (segments, clean) = (self.segments, self.clean);
        let pad = "  ".repeat(level);
        for (k, p) in pieces.iter().enumerate() {
            let label = format!("{prefix}{}", k + 1);
            let what = match p.hit {
                Some((i, [a, b])) => {
                    let (a, b) = points(clean.point(a), clean.point(b));
                    format!("{} sees it, from {a} to {b}", name(segments, i))
                }
                None => "meets no segment".to_string(),
            };
            *text += &format!("{pad}piece {label}: {}° wide, {what}\n", degrees(p.degrees));
            if let Some((r, sub)) = &p.reflected {
                let m = name(segments, p.hit.map_or(0, |h| h.0));
                let chain = match mirrored {
                    "" => format!("the eye mirrored in {m}"),
                    before => format!("{before}, then in {m}"),
                };
                *text += &format!(
                    "{pad}  reflected: a beam from {} ({chain}), leaving from the mirror:\n",
                    v2(clean.point(r.apex), 4)
                );
                self.describe(text, sub, &format!("{label}."), level + 2, &chain);
            } else if p.hit.is_some_and(|(i, _)| segments[i].mirror) {
                *text += &format!("{pad}  (not reflected further: --depth)\n");
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_width_a_beam_may_have_reads_under_the_widest() {
        assert_eq!(degrees(83.39524), "83.3952");
        assert_eq!(degrees(179.99999988), "179.99999988");
        assert_eq!(degrees(179.999999), "179.999999");
        assert_eq!(degrees(179.99), "179.99");
        assert_eq!(degrees(2.9e-5), "2.9e-5");
    }

    #[test]
    fn two_directions_are_printed_apart() {
        let (a, b) = directions(DVec2::new(1.0, 1.0), DVec2::new(1.0, 1.000001));
        assert_eq!((a.as_str(), b.as_str()), ("(1, 1)", "(1, 1.000001)"));
        // Parallel as printed is not apart either.
        let (a, b) = directions(DVec2::new(1.0, 1.0), DVec2::new(2.0, 2.0000001));
        assert_eq!((a.as_str(), b.as_str()), ("(1, 1)", "(2, 2.0000001)"));
        let (a, b) = points(DVec2::new(1.5, 1.5), DVec2::new(1.4999994, 1.5000006));
        assert_ne!(a, b);
        assert_eq!(directions(DVec2::X, DVec2::Y).0, "(1, 0)");
    }

    #[test]
    fn rounding_noise_is_zero_relative_to_what_the_beam_reaches() {
        let beam = Beam::between(DVec2::ZERO, DVec2::new(-1.0, 1.0), DVec2::new(1.0, 1.0));
        let far = Segment {
            a: DVec2::new(-1e12, 2.0),
            b: DVec2::new(1e12, 2.0),
            mirror: true,
        };
        let pieces = beam::trace(&beam, &[far], 0);
        let clean = Clean::new(&beam, &pieces);
        assert_eq!(clean.point(DVec2::new(2.2e-16, 3.0)), DVec2::new(0.0, 3.0));
        // A mirror 10¹² long does not make small coordinates noise.
        assert_eq!(clean.point(DVec2::new(1e-3, 2.0)), DVec2::new(1e-3, 2.0));
        assert_eq!(clean.dir(DVec2::new(1.1e-16, 1.0)), DVec2::new(0.0, 1.0));
        assert_eq!(
            clean.dir(DVec2::new(-0.0, 1.0)).x.to_bits(),
            0.0f64.to_bits()
        );
        assert_eq!(number(1.0e-7, 8), "1.0e-7");
        assert_eq!(number(1.25e-7, 8), "1.25e-7");
    }
}
