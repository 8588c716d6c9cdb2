//! `rtlab beam`: Heckbert and Hanrahan's beam tracing in the plane. One beam from an eye,
//! clipped against walls and mirrors nearest first; each mirror's piece reflected in turn.
//! Prints the pieces and, with `-o`, draws them ([`crate::viz::beam`]).

use super::intersect_args::bounded_list;
use crate::accel::beam::{self, name, Beam, Piece, Segment};
use crate::error::{Error, Result};
use crate::output::check_png;
use crate::shapes::working::{tiny, vector};
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
    /// How many reflections to follow.
    #[arg(long, value_name = "N", default_value_t = 1)]
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

/// The pieces as JSON (the shape `--format` documents).
fn to_json(segments: &[Segment], pieces: &[Piece]) -> Vec<serde_json::Value> {
    pieces
        .iter()
        .map(|p| {
            serde_json::json!({
                "from": xy(p.from),
                "to": xy(p.to),
                "degrees": p.degrees,
                "near": [xy(p.near[0]), xy(p.near[1])],
                "seen_by": p.hit.map(|(i, [a, b])| serde_json::json!({
                    "name": name(segments, i),
                    "mirror": segments[i].mirror,
                    "points": [xy(a), xy(b)],
                })),
                "reflected": p.reflected.as_ref().map(|(r, sub)| serde_json::json!({
                    "apex": xy(r.apex),
                    "pieces": to_json(segments, sub),
                })),
            })
        })
        .collect()
}

fn v2(p: DVec2) -> String {
    vector(&[p.x, p.y], tiny)
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
    if args.format == "json" {
        if let Some(o) = &args.output {
            crate::viz::beam::figure(&beam, &segments, &pieces).write_png(o)?;
        }
        let doc = serde_json::json!({
            "eye": xy(beam.apex),
            "from": xy(beam.from),
            "to": xy(beam.to),
            "degrees": wide,
            "pieces": to_json(&segments, &pieces),
        });
        return super::emit(
            out,
            &(serde_json::to_string_pretty(&doc).expect("plain JSON") + "\n"),
        );
    }
    let mut text = format!(
        "A beam from the eye at {}, counterclockwise from direction {} to {} ({}° wide), clipped \
         against {} segment(s) nearest first (Heckbert and Hanrahan 1984).\n\
         Its pieces, counterclockwise; each is the part of the beam one segment sees:\n",
        v2(beam.apex),
        v2(beam.from),
        v2(beam.to),
        tiny(wide),
        segments.len()
    );
    describe(&mut text, &segments, &pieces, "", 1, "");
    let total: f64 = pieces.iter().map(|p| p.degrees).sum();
    text += &format!(
        "Every ray of the beam lies in exactly one piece: their widths add up to {}°.\n",
        tiny(total)
    );
    if let Some(o) = &args.output {
        crate::viz::beam::figure(&beam, &segments, &pieces).write_png(o)?;
        text += &format!("wrote {}\n", o.display());
    }
    super::emit(out, &text)
}

/// The pieces as indented lines, numbered `prefix` 1, 2, …; a reflected beam's pieces under
/// the piece of the mirror that made it.
fn describe(
    text: &mut String,
    segments: &[Segment],
    pieces: &[Piece],
    prefix: &str,
    level: usize,
    mirrored: &str,
) {
    let pad = "  ".repeat(level);
    for (k, p) in pieces.iter().enumerate() {
        let label = format!("{prefix}{}", k + 1);
        let what = match p.hit {
            Some((i, [a, b])) => {
                format!("{} sees it, from {} to {}", name(segments, i), v2(a), v2(b))
            }
            None => "passes every segment".to_string(),
        };
        *text += &format!("{pad}piece {label}: {}° wide, {what}\n", tiny(p.degrees));
        if let Some((r, sub)) = &p.reflected {
            let m = name(segments, p.hit.map_or(0, |h| h.0));
            let chain = match mirrored {
                "" => format!("the eye mirrored in {m}"),
                before => format!("{before}, then in {m}"),
            };
            *text += &format!(
                "{pad}  reflected: a beam from {} ({chain}), leaving from the mirror:\n",
                v2(r.apex)
            );
            describe(text, segments, sub, &format!("{label}."), level + 2, &chain);
        } else if p.hit.is_some_and(|(i, _)| segments[i].mirror) {
            *text += &format!("{pad}  (not reflected further: --depth)\n");
        }
    }
}
