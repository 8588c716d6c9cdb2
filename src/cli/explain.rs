//! `rtlab explain`: the ray tree of one pixel, from the same tracer `render` runs.
//!
//! Output format (DESIGN §3, version 1): `{"pixel", "color", "encoded", "samples": [{"index",
//! "film", "weight", "color", "camera", "ray"}]}` with `ray` a [`crate::trace::RayNode`] tree. JSON and YAML
//! carry full f64 precision; `--format text` is the readable form.

use super::RenderArgs;
use crate::error::{Error, Result};
use std::path::PathBuf;

// The report is a library type; re-exported here where it used to live.
pub use crate::report::explain::{
    explain, parse_pixel, rounded, CameraNode, Explanation, SampleNode,
};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene file: native rtlab JSON or a CS1230 scenefile.
    pub scene: PathBuf,
    /// The pixel: x from the left, y from the top.
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub pixel: String,
    /// Show only this sample of the pixel (0-based).
    #[arg(long, value_name = "K")]
    pub sample: Option<u32>,
    /// text (default), json or yaml.
    #[arg(long, default_value = "text")]
    pub format: String,
    /// Also draw the pixel's ray tree in a 2D slice of the scene to this PNG.
    #[arg(long, value_name = "OUT.png")]
    pub diagram: Option<PathBuf>,
    /// The slice of --diagram: camera (the camera ray and the camera's up vector) or bounce
    /// (the camera ray and its first reflection or refraction).
    #[arg(long, value_name = "camera|bounce", default_value = "camera")]
    pub diagram_plane: String,
    /// Draw the bundle of camera rays in which the render traces this pixel's sample (the
    /// one --sample chose, else 0): the rays of that sample of its 4×4 block of pixels (of
    /// traced pixels under --subsample, within the pixel's 16×16 tile), over
    /// the first mesh's BVH (seen from above: the boxes it opened and the ones it culled),
    /// to this PNG. Refused where the render traces no such bundle.
    #[arg(long, value_name = "OUT.png")]
    pub bundle_diagram: Option<PathBuf>,
    #[command(flatten)]
    pub render: RenderArgs,
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    if !["text", "json", "yaml"].contains(&args.format.as_str()) {
        return Err(Error::arg(
            "--format",
            format!(
                "unknown format \"{}\" (expected text, json or yaml)",
                args.format
            ),
        ));
    }
    let plane = crate::viz::slice::SlicePlane::parse(&args.diagram_plane).ok_or_else(|| {
        Error::arg(
            "--diagram-plane",
            format!(
                "unknown plane \"{}\" (expected camera or bounce)",
                args.diagram_plane
            ),
        )
    })?;
    let diagrams: Vec<(&std::path::Path, &str)> = [
        (&args.diagram, "--diagram"),
        (&args.bundle_diagram, "--bundle-diagram"),
    ]
    .into_iter()
    .filter_map(|(d, arg)| Some((d.as_deref()?, arg)))
    .collect();
    for &(d, arg) in &diagrams {
        crate::output::check_png(d, arg)?;
        crate::output::check_not_input(d, arg, &[(&args.scene, "the scene")])?;
    }
    crate::output::check_distinct(&diagrams)?;
    let scene = args.render.load(&args.scene)?;
    for &(d, arg) in &diagrams {
        crate::output::check_not_read(d, arg)?; // a texture or mesh of the scene
    }
    let (x, y) = parse_pixel(&args.pixel, scene.camera.width, scene.camera.height)?;
    let mut e = explain(&scene, x, y);
    // Ctrl-C inside a huge tree cuts it short: print nothing rather than a partial tree.
    crate::interrupt::check()?;
    if let Some(k) = args.sample {
        // The pixel's own samples (the adaptive sampler decides how many while tracing).
        crate::report::explain::check_sample(&scene, (x, y), k, e.own_samples())
            .map_err(|m| Error::arg("--sample", m))?;
    }
    if let Some(k) = args.sample {
        e.samples.retain(|s| s.pixel == [x, y] && s.index == k);
    }
    // Both figures are drawn before either is written: a refusal writes no file.
    let bundle = match &args.bundle_diagram {
        Some(path) => Some((
            path,
            crate::viz::bundle::draw(&scene, x, y, args.sample.unwrap_or(0))
                .map_err(|m| Error::arg("--bundle-diagram", m))?,
        )),
        None => None,
    };
    let diagram = match &args.diagram {
        Some(path) => {
            // The first sample of the pixel itself (the one --sample chose, if given).
            let s = e
                .samples
                .iter()
                .find(|s| s.pixel == [x, y])
                .ok_or_else(|| {
                    Error::arg(
                        "--diagram",
                        format!(
                            "{}: no ray to draw; pick a traced pixel",
                            crate::report::explain::not_traced(x, y)
                        ),
                    )
                })?;
            let opts = crate::viz::slice::SliceOptions {
                plane,
                caption: Some(format!("pixel ({x}, {y}), sample {}", s.index)),
                ..Default::default()
            };
            Some((path, crate::viz::slice::draw(&scene, &s.ray, &opts)?))
        }
        None => None,
    };
    for (path, figure) in bundle.iter().chain(&diagram) {
        figure.write_png(path)?;
    }
    // `--mistake`: the pixel again without the mistakes, and what differs.
    if args.format == "json" {
        return super::emit(
            out,
            &crate::report::mistakes::to_json(&scene, x, y, args.sample, &e),
        );
    }
    let diffs = crate::report::mistakes::differences(&scene, x, y, args.sample, &e);
    let text = match (args.format.as_str(), &diffs) {
        ("yaml", Some(d)) => serde_norway::to_string(&d.annotate(&e)).expect("serialisable"),
        ("yaml", None) => serde_norway::to_string(&e).expect("serialisable"),
        (_, d) => {
            crate::cli::explain_text::text(&scene, &e)
                + &d.as_ref().map_or(String::new(), |d| d.text())
        }
    };
    super::emit(out, &text)
}
