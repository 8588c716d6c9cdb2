//! The explanation of one pixel: every sample that reaches it, each with its ray-generation
//! walk and its ray tree, from the same tracer `render` runs. A library type, so that the CLI
//! (`rtlab explain`), the server (`/api/explain`), `steps` and the tests share one document.
//!
//! Output format (DESIGN §3, version 1): `{"pixel", "color", "encoded", "samples": [{"index",
//! "film", "weight", "color", "camera", "ray"}]}` with `ray` a [`RayNode`] tree.

use crate::error::{Error, Result};
use crate::sampling::{encode_as, sample_pixel, Filter};
use crate::scene::{RenderSettings, Scene};
use crate::trace::{camera_ray, trace_camera, RayNode, TreeRecorder};
use glam::{DVec2, DVec3};
use serde::Serialize;
use std::cell::RefCell;
use std::collections::BTreeMap;

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

impl Explanation {
    /// How many of the samples are the pixel's own (the rest are neighbours' that its filter
    /// reaches): under the adaptive sampler, which decides while it traces, the count
    /// [`check_sample`] needs.
    pub fn own_samples(&self) -> u32 {
        self.samples
            .iter()
            .filter(|s| s.pixel == self.pixel)
            .count() as u32
    }
}

/// Explains pixel (x, y): traces every sample that reaches it with a [`TreeRecorder`] and
/// reconstructs the pixel with the same filter code `render` uses.
pub fn explain(scene: &Scene, x: u32, y: u32) -> Explanation {
    explain_within(scene, x, y, u64::MAX).expect("no bound on the rays")
}

/// [`explain`], unless its samples trace more than `max_rays` rays between them (every ray is
/// kept, a few kilobytes each): `None` once they would, a sample traced then stopping one
/// ray past the bound, and no sample traced after it.
pub fn explain_within(scene: &Scene, x: u32, y: u32, max_rays: u64) -> Option<Explanation> {
    let s = &scene.render;
    let rays = std::cell::Cell::new(0u64);
    let (w, h) = (scene.camera.width, scene.camera.height);
    let traced: RefCell<BTreeMap<(u32, u32, u32), SampleNode>> = RefCell::new(BTreeMap::new());
    let filter = Filter::for_settings(s);
    let (color, weights) = crate::sampling::render_reconstruct(&filter, x, y, w, h, |qx, qy| {
        sample_pixel(s, w, h, qx, qy, |k, film| {
            if rays.get() > max_rays {
                return DVec3::ZERO; // the explanation is refused: the rest is not traced
            }
            // One sample may not go past the bound either: its own budget is lowered to one
            // ray more than is left, and a sample cut by that is one past the bound.
            let left = max_rays - rays.get();
            let lowered = (left < s.max_rays).then(|| RenderSettings {
                max_rays: left + 1,
                ..s.clone()
            });
            let mut rec = TreeRecorder::new(scene);
            let mut camera = camera_ray(scene, s, qx, qy, k, film);
            let r = trace_camera(
                scene,
                lowered.as_ref().unwrap_or(s),
                &mut camera,
                None,
                &mut rec,
            );
            rays.set(rays.get().saturating_add(r.rays));
            let color = if r.color.is_finite() {
                r.color
            } else {
                DVec3::ZERO
            };
            let g = camera.generation(scene, s);
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
    });
    if rays.get() > max_rays {
        return None;
    }
    let mut traced = traced.into_inner();
    let samples = weights
        .into_iter()
        .filter_map(|(qx, qy, k, wt)| {
            let mut node = traced.remove(&(qy, qx, k as u32))?;
            node.weight = wt;
            Some(node)
        })
        .collect();
    Some(Explanation {
        pixel: [x, y],
        color,
        encoded: encode_as(color, s.encoding, s.mistakes),
        samples,
    })
}

/// Why pixel (x, y) has no ray to show: `--subsample` fills it in from its neighbours.
pub fn not_traced(x: u32, y: u32) -> String {
    format!("pixel ({x}, {y}) traces no samples of its own (it is filled in by --subsample)")
}

/// Does pixel (x, y) have a sample `k` (`explain --sample K`)? Its samples are those the
/// sampler plans for it, or `traced` if more (the adaptive sampler decides while it traces:
/// an explanation's count of the pixel's own samples; 0 when there is none). Else the
/// message `--sample` is refused with.
pub fn check_sample(
    scene: &Scene,
    (x, y): (u32, u32),
    k: u32,
    traced: u32,
) -> std::result::Result<(), String> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let planned = sample_pixel(&scene.render, w, h, x, y, |_, _| DVec3::ZERO).len() as u32;
    let own = traced.max(planned);
    match own {
        _ if k < own => Ok(()),
        0 => Err(not_traced(x, y)),
        _ => Err(format!(
            "sample {k} does not exist: pixel ({x}, {y}) has {own} sample(s), 0..{}",
            own - 1
        )),
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
    // A whole number too long for i64 is still a whole number: far outside the image.
    let whole = |p: &str| -> Result<i64> {
        let digits = p.strip_prefix('-').unwrap_or(p);
        match p.parse::<i64>() {
            Ok(v) => Ok(v),
            Err(_) if !digits.is_empty() && digits.bytes().all(|c| c.is_ascii_digit()) => {
                Ok(if p.starts_with('-') {
                    i64::MIN
                } else {
                    i64::MAX
                })
            }
            Err(_) => Err(bad()),
        }
    };
    let (x, y) = (whole(parts[0])?, whole(parts[1])?);
    if x < 0 || y < 0 || x >= width as i64 || y >= height as i64 {
        let show = |v: i64, p: &str| match v {
            i64::MIN | i64::MAX => p.to_string(),
            v => v.to_string(),
        };
        let (x, y) = (show(x, parts[0]), show(y, parts[1]));
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
