//! `rtlab explain`: the ray tree of one pixel, from the same tracer `render` runs.
//!
//! Output format (DESIGN §3, version 1): `{"pixel", "color", "encoded", "samples": [{"index",
//! "film", "weight", "color", "camera", "ray"}]}` with `ray` a [`RayNode`] tree. JSON and YAML
//! carry full f64 precision; `--format text` is the readable form.

use super::RenderArgs;
use crate::error::{Error, Result};
use crate::sampling::{encode, sample_pixel, Filter};
use crate::scene::Scene;
use crate::trace::{trace_sample, RayNode, TreeRecorder};
use glam::{DVec2, DVec3};
use serde::Serialize;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::PathBuf;

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
    /// Draw the 4×4 bundle of camera rays holding this pixel over the first mesh's BVH
    /// (seen from above: the boxes it opened and the ones it culled) to this PNG.
    #[arg(long, value_name = "OUT.png")]
    pub bundle_diagram: Option<PathBuf>,
    #[command(flatten)]
    pub render: RenderArgs,
}

/// The ray-generation walk of one sample.
#[derive(Debug, Clone, Serialize)]
pub struct CameraNode {
    pub ndc: DVec2,
    pub film_point: DVec3,
    pub world_point: DVec3,
}

#[derive(Debug, Clone, Serialize)]
pub struct SampleNode {
    pub index: u32,
    /// The pixel this sample belongs to (a neighbour's when the filter reaches across).
    pub pixel: [u32; 2],
    pub film: DVec2,
    /// Normalised filter weight of this sample in the explained pixel.
    pub weight: f64,
    pub color: DVec3,
    pub camera: CameraNode,
    pub ray: RayNode,
}

#[derive(Debug, Clone, Serialize)]
pub struct Explanation {
    pub pixel: [u32; 2],
    pub color: DVec3,
    pub encoded: [u8; 3],
    pub samples: Vec<SampleNode>,
}

/// Explains pixel (x, y): traces every sample that reaches it with a [`TreeRecorder`] and
/// reconstructs the pixel with the same filter code `render` uses.
pub fn explain(scene: &Scene, x: u32, y: u32) -> Explanation {
    let s = &scene.render;
    let (w, h) = (scene.camera.width, scene.camera.height);
    let traced: RefCell<BTreeMap<(u32, u32, u32), SampleNode>> = RefCell::new(BTreeMap::new());
    let filter = Filter::for_settings(s);
    let (color, weights) = crate::sampling::render_reconstruct(&filter, x, y, w, h, |qx, qy| {
        sample_pixel(s, w, h, qx, qy, |k, film| {
            let mut rec = TreeRecorder::new(scene);
            let r = trace_sample(scene, s, qx, qy, k, film, &mut rec);
            let color = if r.color.is_finite() {
                r.color
            } else {
                DVec3::ZERO
            };
            let g = r.generation;
            traced.borrow_mut().insert(
                (qy, qx, k),
                SampleNode {
                    index: k,
                    pixel: [qx, qy],
                    film,
                    weight: 0.0,
                    color,
                    camera: CameraNode {
                        ndc: g.ndc,
                        film_point: g.film_point,
                        world_point: g.world_point,
                    },
                    ray: rec.root.expect("a camera ray was traced"),
                },
            );
            color
        })
        .into_iter()
        .map(|p| (p.film, p.color, p.area))
        .collect()
    });
    let mut traced = traced.into_inner();
    let samples = weights
        .into_iter()
        .filter_map(|(qx, qy, k, wt)| {
            let mut node = traced.remove(&(qy, qx, k as u32))?;
            node.weight = wt;
            Some(node)
        })
        .collect();
    Explanation {
        pixel: [x, y],
        color,
        encoded: encode(color, s.encoding),
        samples,
    }
}

/// Parses and checks `--pixel X,Y` against the image size.
pub fn parse_pixel(s: &str, width: u32, height: u32) -> Result<(u32, u32)> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    let bad = || {
        Error::arg(
            "--pixel",
            format!("expected two whole numbers X,Y (e.g. --pixel 120,80), found \"{s}\""),
        )
    };
    if parts.len() != 2 {
        return Err(bad());
    }
    let x: i64 = parts[0].parse().map_err(|_| bad())?;
    let y: i64 = parts[1].parse().map_err(|_| bad())?;
    if x < 0 || y < 0 || x >= width as i64 || y >= height as i64 {
        return Err(Error::arg(
            "--pixel",
            format!(
                "({x}, {y}) is outside the {width}×{height} image (x must be 0..{}, y 0..{})",
                width - 1,
                height - 1
            ),
        ));
    }
    Ok((x as u32, y as u32))
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
    if let Some(d) = &args.diagram {
        crate::output::check_writable(d, "--diagram")?;
    }
    if let Some(d) = &args.bundle_diagram {
        crate::output::check_writable(d, "--bundle-diagram")?;
    }
    let scene = args.render.load(&args.scene)?;
    let (x, y) = parse_pixel(&args.pixel, scene.camera.width, scene.camera.height)?;
    if let Some(path) = &args.bundle_diagram {
        crate::viz::bundle::draw(&scene, x, y)
            .map_err(|m| Error::arg("--bundle-diagram", m))?
            .write_png(path)?;
    }
    let mut e = explain(&scene, x, y);
    if let Some(k) = args.sample {
        // The pixel's own samples (the adaptive sampler decides how many while tracing).
        let own = e.samples.iter().filter(|s| s.pixel == [x, y]).count() as u32;
        let own = own.max(
            crate::sampling::sample_pixel(
                &scene.render,
                scene.camera.width,
                scene.camera.height,
                x,
                y,
                |_, _| DVec3::ZERO,
            )
            .len() as u32,
        );
        if k >= own {
            return Err(Error::arg(
                "--sample",
                if own == 0 {
                    format!("pixel ({x}, {y}) traces no samples of its own (it is filled in by --subsample)")
                } else {
                    format!(
                        "sample {k} does not exist: pixel ({x}, {y}) has {own} sample(s), 0..{}",
                        own - 1
                    )
                },
            ));
        }
    }
    if let Some(k) = args.sample {
        e.samples.retain(|s| s.pixel == [x, y] && s.index == k);
    }
    if let Some(path) = &args.diagram {
        // The first sample of the pixel itself (the one --sample chose, if given).
        if let Some(s) = e.samples.iter().find(|s| s.pixel == [x, y]) {
            let opts = crate::viz::slice::SliceOptions {
                plane,
                caption: Some(format!("pixel ({x}, {y}), sample {}", s.index)),
                ..Default::default()
            };
            crate::viz::slice::draw(&scene, &s.ray, &opts)?.write_png(path)?;
        }
    }
    let text = match args.format.as_str() {
        "json" => serde_json::to_string_pretty(&e).expect("serialisable") + "\n",
        "yaml" => serde_yaml::to_string(&e).expect("serialisable"),
        _ => crate::cli::explain_text::text(&scene, &e),
    };
    super::emit(out, &text)
}

/// A copy of an explain document rounded for snapshot tests (DESIGN §5): colours to 3
/// decimals, everything else (positions, t, weights) to 4, and −0.0 written as 0.0.
pub fn rounded(value: &serde_json::Value) -> serde_json::Value {
    fn walk(v: &serde_json::Value, digits: i32) -> serde_json::Value {
        use serde_json::Value;
        match v {
            Value::Number(n) if n.is_f64() => {
                let x = n.as_f64().unwrap_or(0.0);
                let s = 10f64.powi(digits);
                let r = (x * s).round() / s;
                let r = if r == 0.0 { 0.0 } else { r };
                serde_json::json!(r)
            }
            Value::Array(a) => Value::Array(a.iter().map(|x| walk(x, digits)).collect()),
            Value::Object(m) => Value::Object(
                m.iter()
                    .map(|(k, x)| {
                        let d = match k.as_str() {
                            "color" | "ambient" | "diffuse" | "specular" | "reflected"
                            | "transmitted" => 3,
                            _ => digits,
                        };
                        (k.clone(), walk(x, d))
                    })
                    .collect(),
            ),
            other => other.clone(),
        }
    }
    walk(value, 4)
}
