//! Arbitrary output variables (AOVs): instead of the colour, one quantity per pixel (how far,
//! which way the surface faces, which object, one term of the lighting equation, how much
//! work). Every AOV comes from the one tracer: an [`AovRecorder`] watches each camera sample
//! and keeps what the camera ray's own hit saw; `depth`, `normal` and `object-id` run it with
//! render settings that cast camera rays only (ray casting).
//!
//! Adding an AOV: one variant, one row in [`Aov::ALL`], one arm in `Aov::shown` (and, for
//! one coloured by an image-wide range, as depth and cost are, its colouring in
//! [`render_aov`]).

mod samples;

pub use samples::{trace_aov_samples, trace_kept, AovHit, AovRecorder, AovSample, AovSamples};

use super::reconstruct::{reconstruct_color, Kernel};
use super::sampler::standing_for;
use super::Filter;
use crate::scene::{Encoding, RenderSettings, Scene};
use glam::{DVec2, DVec3};

/// One arbitrary output variable (DESIGN §3 `--aov`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Aov {
    Depth,
    Normal,
    Albedo,
    ObjectId,
    Ambient,
    Diffuse,
    Specular,
    Reflection,
    Transmission,
    Shadow,
    RayDepth,
    Cost,
    /// Samples the sampler spent per pixel (the adaptive sampler's map).
    Spp,
}

impl Aov {
    /// Every AOV: its command-line name and what its picture shows.
    pub const ALL: &'static [(Aov, &'static str, &'static str)] = &[
        (
            Aov::Depth,
            "depth",
            "distance t along the camera ray (near white, far dark, by 1/t)",
        ),
        (
            Aov::Normal,
            "normal",
            "world-space surface normal n shown as 0.5 + 0.5·n",
        ),
        (
            Aov::Albedo,
            "albedo",
            "the diffuse colour kd·Od at the first hit (textures applied)",
        ),
        (
            Aov::ObjectId,
            "object-id",
            "which object the camera ray hits, one colour each",
        ),
        (Aov::Ambient, "ambient", "ka·La·Oa at the first hit"),
        (
            Aov::Diffuse,
            "diffuse",
            "Σ f_att·L·kd·Od·(n·l) at the first hit (shadows applied)",
        ),
        (
            Aov::Specular,
            "specular",
            "Σ f_att·L·ks·Os·(r·v)^n at the first hit (shadows applied)",
        ),
        (
            Aov::Reflection,
            "reflection",
            "ks·Or·I_r: what the reflection ray brings back",
        ),
        (
            Aov::Transmission,
            "transmission",
            "kt·Ot·I_t: what the refraction/transmission ray brings back",
        ),
        (
            Aov::Shadow,
            "shadow",
            "fraction of the first hit's shadow rays that reach their light",
        ),
        (
            Aov::RayDepth,
            "ray-depth",
            "deepest reflection/refraction level the sample reached",
        ),
        (
            Aov::Cost,
            "cost",
            "intersection tests + BVH nodes visited per pixel",
        ),
        (
            Aov::Spp,
            "spp",
            "samples traced per pixel (the adaptive sampler spends more on edges)",
        ),
    ];

    pub fn parse(s: &str) -> Option<Aov> {
        Self::ALL.iter().find(|r| r.1 == s).map(|r| r.0)
    }
    /// [`Aov::parse`] with the message of a bad `--aov NAME`.
    pub fn parse_arg(name: &str) -> crate::Result<Aov> {
        Aov::parse(name).ok_or_else(|| {
            crate::Error::arg(
                "--aov",
                format!(
                    "unknown AOV \"{name}\" (expected one of: {})",
                    Aov::names().join(", ")
                ),
            )
        })
    }

    pub fn name(self) -> &'static str {
        Self::row(self).1
    }
    pub fn describe(self) -> &'static str {
        Self::row(self).2
    }
    fn row(self) -> &'static (Aov, &'static str, &'static str) {
        Self::ALL
            .iter()
            .find(|r| r.0 == self)
            .expect("every AOV has a row")
    }
    pub fn names() -> Vec<&'static str> {
        Self::ALL.iter().map(|r| r.1).collect()
    }

    /// Traced with camera rays only (no lights, no secondary rays): pure visibility.
    pub fn camera_only(self) -> bool {
        matches!(self, Aov::Depth | Aov::Normal | Aov::ObjectId)
    }

    /// A radiance (a term of the lighting equation) encoded like the image, rather than a
    /// false-colour picture of some other quantity.
    pub fn is_radiance(self) -> bool {
        matches!(
            self,
            Aov::Albedo
                | Aov::Ambient
                | Aov::Diffuse
                | Aov::Specular
                | Aov::Reflection
                | Aov::Transmission
        )
    }

    /// The render settings this AOV is traced with.
    pub fn settings(self, base: &RenderSettings) -> RenderSettings {
        let mut s = base.clone();
        if self.camera_only() {
            // Ray casting: the camera ray's closest hit and nothing else.
            s.max_depth = 0;
            s.shadows = false;
            s.diffuse = false;
            s.specular = false;
            s.reflections = false;
            s.refractions = false;
        }
        s
    }

    /// What the image keeps of one sample while the others are traced: its displayed
    /// colour, for every AOV whose colour needs no image-wide range (the ray depth's is
    /// `max_depth`, known before), or the number its colour will be scaled from once every
    /// sample is in (the depth's `t`, the cost).
    fn shown(self, s: &AovSample, max_depth: u32) -> Shown {
        match self {
            Aov::Depth => return Shown::Depth(s.hit.map(|h| h.t)),
            Aov::Cost => return Shown::Cost(s.cost),
            _ => {}
        }
        let Some(hit) = s.hit else {
            return Shown::Colour(DVec3::ZERO);
        };
        Shown::Colour(match self {
            Aov::Normal => 0.5 + 0.5 * hit.normal,
            Aov::ObjectId => object_color(hit.object),
            Aov::Albedo => s.albedo,
            Aov::Ambient => s.ambient,
            Aov::Diffuse => s.diffuse,
            Aov::Specular => s.specular,
            Aov::Reflection => s.reflection,
            Aov::Transmission => s.transmission,
            Aov::Shadow => match s.shadow_rays {
                0 => DVec3::new(0.08, 0.1, 0.3),
                n => DVec3::splat(s.shadow_reached as f64 / n as f64),
            },
            Aov::RayDepth => heat(s.ray_depth as f64 / max_depth.max(1) as f64),
            // Coloured above (depth, cost), or from the render's own count (see `render_aov`).
            Aov::Depth | Aov::Cost | Aov::Spp => DVec3::ZERO,
        })
    }
}

/// What an AOV's image keeps of each sample until every sample is in (48 bytes with its film
/// position, against about 265 for the whole [`AovSample`]): see [`Aov::shown`].
#[derive(Debug, Clone, Copy)]
enum Shown {
    Colour(DVec3),
    /// The camera ray's hit distance (none: it hit nothing).
    Depth(Option<f64>),
    Cost(u64),
}

/// The depth's grey: scaled by 1/t (like a disparity map), for a floor running to the horizon
/// would otherwise leave everything near the camera the same white.
fn depth_grey(t: f64, r: &Ranges) -> DVec3 {
    let (a, b) = (1.0 / r.near.max(1e-9), 1.0 / r.far.max(1e-9));
    let x = ((1.0 / t.max(1e-9) - b) / (a - b).max(1e-12)).clamp(0.0, 1.0);
    DVec3::splat(0.2 + 0.8 * x)
}

/// Refuses, before anything is allocated, an AOV that would not fit in memory: as
/// [`super::check_memory`], but an AOV keeps each sample (what `Shown` holds of it) until
/// its image is made, where the render keeps each pixel's sums.
pub fn check_memory(width: u32, height: u32, settings: &RenderSettings) -> Result<(), String> {
    super::film::check_memory_kept(
        (width, height),
        settings.sampler,
        settings.spp,
        settings.subsample,
        {
            // And the depth's list of hit distances, sorted for its percentiles.
            let mut kept = super::film::Kept::of::<(DVec2, Shown)>();
            kept.sample += std::mem::size_of::<f64>() as u64;
            kept
        },
    )
    .map_err(|m| format!("{m} (an AOV keeps every sample until its image is made)"))
}

/// Image-wide values the false colours are scaled by.
#[derive(Debug, Clone, Copy)]
struct Ranges {
    near: f64,
    far: f64,
    max_depth: u32,
    max_cost: u64,
}

/// An AOV made visible, with the sentence that says how to read it.
pub struct AovImage {
    pub aov: Aov,
    pub image: image::RgbImage,
    /// How to read the colours, with the ranges actually used.
    pub legend: String,
}

/// Renders one AOV of the scene as an image. `None` when `base.cancel` was cancelled (or
/// Ctrl-C pressed) before it was complete: it stops within a few rays, as a render does,
/// and a partial image is never returned.
pub fn render_aov(scene: &Scene, base: &RenderSettings, aov: Aov) -> Option<AovImage> {
    let settings = aov.settings(base);
    if aov == Aov::Spp {
        // The real render: the count is a property of the sampler, not of one AOV sample.
        let out = super::render(scene, &settings, false, None);
        if out.cancelled {
            return None;
        }
        let (w, h) = (scene.camera.width, scene.camera.height);
        let spp = out
            .spp_map
            .unwrap_or_else(|| vec![settings.spp; (w * h) as usize]);
        let max = spp.iter().copied().max().unwrap_or(0);
        let image = crate::viz::heatmap::spp_heat_map(&spp, w, h, max);
        let legend = format!(
            "{}: {}\nheat map, dark purple: 0 to pale yellow: {} samples per pixel",
            aov.name(),
            aov.describe(),
            max
        );
        return Some(AovImage { aov, image, legend });
    }
    let samples = trace_kept(scene, &settings, |s| aov.shown(&s, settings.max_depth));
    if settings.cancel.is_cancelled() {
        return None;
    }
    let (w, h) = (samples.width, samples.height);

    let mut ts: Vec<f64> = samples
        .pixels
        .iter()
        .flatten()
        .filter_map(|(_, s)| match s {
            Shown::Depth(t) => *t,
            _ => None,
        })
        .collect();
    // The k-th smallest by selection, not a sort: linear, where sorting millions of hits on
    // one thread outlasted a time budget's deadline by half a second.
    let mut pct = |p: f64| -> f64 {
        if ts.is_empty() {
            0.0
        } else {
            let k = ((ts.len() - 1) as f64 * p).round() as usize;
            *ts.select_nth_unstable_by(k, f64::total_cmp).1
        }
    };
    let pixel_cost = |px: &Vec<(DVec2, Shown)>| {
        px.iter()
            .map(|(_, s)| match s {
                Shown::Cost(c) => *c,
                _ => 0,
            })
            .sum::<u64>()
    };
    // Percentiles, not min/max: one floor pixel at the horizon would squash the rest.
    let (near, far) = (pct(0.02), pct(0.98));
    if settings.cancel.is_cancelled() {
        return None;
    }
    let ranges = Ranges {
        near,
        far,
        max_depth: settings.max_depth,
        max_cost: samples.pixels.iter().map(pixel_cost).max().unwrap_or(0),
    };

    // The render's own filter: stretched under --subsample, and reaching the corners
    // sampler's shared corners.
    let filter = Filter::for_settings(&settings);
    let kernel = Kernel::new(&filter, settings.subsample);
    let given_up = || settings.cancel.is_cancelled();
    let colors = super::Image::from_fn_until(w, h, &given_up, |x, y| {
        if aov == Aov::Cost {
            // Per pixel, not filtered: the work this pixel's samples caused (under
            // --subsample, a pixel that traces nothing shows the one that stands for it).
            let (x, y) = standing_for(&settings, w, h, x, y);
            let c = pixel_cost(&samples.pixels[(y * w + x) as usize]);
            return heat(c as f64 / ranges.max_cost.max(1) as f64);
        }
        // As the film reconstructs (the same sums: under --subsample only the pixels that
        // trace are asked for samples).
        reconstruct_color(&kernel, (x, y), (w, h), |qx, qy| {
            samples.pixels[(qy * w + qx) as usize]
                .iter()
                .map(|(film, s)| {
                    let colour = match *s {
                        Shown::Colour(c) => c,
                        Shown::Depth(Some(t)) => depth_grey(t, &ranges),
                        Shown::Depth(None) | Shown::Cost(_) => DVec3::ZERO,
                    };
                    (*film, colour, 1.0)
                })
        })
    })?
    .pixels;
    let encoding = if aov.is_radiance() {
        settings.encoding
    } else {
        Encoding::Clamp
    };
    let mut image = image::RgbImage::new(w, h);
    for (p, c) in image.pixels_mut().zip(&colors) {
        *p = image::Rgb(super::encode(*c, encoding));
    }
    let legend = legend(aov, &ranges, scene);
    Some(AovImage { aov, image, legend })
}

fn legend(aov: Aov, r: &Ranges, scene: &Scene) -> String {
    let head = format!("{}: {}", aov.name(), aov.describe());
    let how = match aov {
        Aov::Depth if r.far <= 0.0 => "black: no ray hits anything".into(),
        Aov::Depth => format!(
            "brightness 0.2 + 0.8·(1/t − 1/far)/(1/near − 1/far), white: t <= {:.3} (near), dark grey: t >= {:.3} (far; 2nd and 98th percentile of the hits), black: no hit",
            r.near, r.far
        ),
        Aov::Normal => "x → red, y → green, z → blue; black: no hit".into(),
        Aov::ObjectId => {
            let names: Vec<String> = (0..scene.objects.len())
                .map(|i| {
                    let c = super::encode(object_color(i), Encoding::Clamp);
                    format!(
                        "{} #{:02x}{:02x}{:02x}",
                        scene.object_name(i),
                        c[0],
                        c[1],
                        c[2]
                    )
                })
                .collect();
            format!("black: no hit; {}", names.join(", "))
        }
        Aov::Shadow => {
            "white: every shadow ray reached its light, black: all blocked, dark blue: faces away from every light (no shadow ray), black background: no hit".into()
        }
        Aov::RayDepth => format!(
            "heat map, dark purple: 0 (camera ray only) to pale yellow: {} (max depth)",
            r.max_depth
        ),
        Aov::Cost => format!("heat map, dark purple: 0 to pale yellow: {} per pixel", r.max_cost),
        _ => "linear radiance, encoded like the image".into(),
    };
    format!("{head}; {how}")
}

/// A distinct, stable colour for object `i`: hues spaced by the golden angle.
pub fn object_color(i: usize) -> DVec3 {
    let hue = (i as f64 * 0.618_033_988_749_895 + 0.1).fract();
    let (s, v) = if i & 1 == 0 {
        (0.7, 0.95)
    } else {
        (0.55, 0.75)
    };
    hsv(hue, s, v)
}

fn hsv(h: f64, s: f64, v: f64) -> DVec3 {
    let k = |n: f64| {
        let k = (n + h * 6.0) % 6.0;
        v - v * s * k.min(4.0 - k).clamp(0.0, 1.0)
    };
    DVec3::new(k(5.0), k(3.0), k(1.0))
}

/// The project's one heat scale (dark purple at 0 through red and orange to pale yellow at
/// 1), the same as the sampling figures' ([`crate::viz::heatmap::heat_colour`]).
pub fn heat(x: f64) -> DVec3 {
    let [r, g, b] = crate::viz::heatmap::heat_colour(x);
    DVec3::new(r as f64, g as f64, b as f64) / 255.0
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn names_round_trip() {
        for &(aov, name, _) in Aov::ALL {
            assert_eq!(Aov::parse(name), Some(aov));
            assert_eq!(aov.name(), name);
        }
        assert_eq!(Aov::parse("colour"), None);
    }
    #[test]
    fn object_colours_differ() {
        let c: Vec<[u8; 3]> = (0..12)
            .map(|i| super::super::encode(object_color(i), Encoding::Clamp))
            .collect();
        for i in 0..c.len() {
            for j in 0..i {
                assert_ne!(c[i], c[j], "objects {i} and {j}");
            }
        }
    }
    #[test]
    fn heat_ends() {
        // Encoded, the AOV's colours are the heat scale's (to the byte's rounding).
        for x in [0.0, 0.3, 0.7, 1.0] {
            let a = crate::sampling::encode(heat(x), Encoding::Clamp);
            let b = crate::viz::heatmap::heat_colour(x);
            assert!(
                (0..3).all(|c| a[c].abs_diff(b[c]) <= 1),
                "{x}: {a:?} vs {b:?}"
            );
        }
        assert!(heat(0.0).length() < 0.05 && heat(1.0).min_element() > 0.6);
    }
}
