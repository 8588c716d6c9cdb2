//! `rtlab convert`: write the native rtlab equivalent of a CS1230 scenefile.
//!
//! The output is the flattened scene: every template instantiated, every primitive with its
//! full world transform as one `matrix` and its material inline, lights in world space, and
//! the course's render settings (`max_depth` 4, `clamp_each_ray`, no cutoff, 1024×768).
//! It loads into the same `Scene` and renders to the same bytes (a test checks this).
//! Texture and mesh paths are written relative to the output's folder.

use crate::error::{Error, Result};
use crate::output::{check_extension, check_not_input, write_atomic};
use crate::scene::cs1230::{self, Flat};
use crate::scene::Encoding;
use crate::shapes::Shape;
use glam::{DMat4, DVec3};
use serde_json::{json, Map, Value};
use std::path::{Component, Path, PathBuf};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// A CS1230 scenefile.
    pub scene: PathBuf,
    /// The native rtlab scene to write (.json).
    #[arg(short, long, value_name = "OUT.json")]
    pub output: PathBuf,
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    check_extension(&args.output, "-o", "json", "scenes")?;
    check_not_input(
        &args.output,
        "-o",
        &[(&args.scene, "the scenefile being converted")],
    )?;
    if crate::scene::cs1230::ini::is_ini(&args.scene) {
        return Err(Error::input(
            &args.scene,
            "",
            "is a course .ini, not a scenefile: convert the scenefile its [IO] scene names \
             (render and validate take the .ini itself)",
        ));
    }
    let value = cs1230::read(&args.scene)?;
    if !crate::scene::is_cs1230(&value) {
        return Err(Error::input(
            &args.scene,
            "",
            "this is already a native rtlab scene (no \"globalData\"/\"cameraData\"): nothing to convert",
        ));
    }
    let flat = cs1230::flatten(&args.scene, &value)?;
    let out_dir = match args.output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let doc = to_native(&flat, &args.scene, &out_dir);
    let mut text = serde_json::to_string_pretty(&doc).expect("a JSON value serialises");
    text.push('\n');
    write_atomic(&args.output, text.as_bytes())?;
    let mut msg = String::new();
    for w in &flat.warnings {
        msg += &format!("warning: {w}\n");
    }
    msg += &format!(
        "{}: wrote the native equivalent of {}: {} object(s), {} light(s)\n",
        args.output.display(),
        args.scene.display(),
        flat.objects.len(),
        flat.lights.len()
    );
    super::emit(out, &msg)
}

fn v3(v: DVec3) -> Value {
    json!([v.x, v.y, v.z])
}

/// A matrix as four rows (the native format's `matrix`).
fn rows(m: DMat4) -> Value {
    let r = |i: usize| {
        let r = m.row(i);
        json!([r.x, r.y, r.z, r.w])
    };
    json!([r(0), r(1), r(2), r(3)])
}

/// The native scene document of a flattened scenefile. Every number is written with full
/// precision (serde_json writes the shortest string that reads back to the same f64).
pub fn to_native(flat: &Flat, source: &Path, out_dir: &Path) -> Value {
    let cam = &flat.camera;
    let r = &flat.render;
    let lights: Vec<Value> = flat
        .lights
        .iter()
        .map(|l| {
            let mut o = Map::new();
            o.insert("name".into(), json!(l.name));
            o.insert("type".into(), json!(l.kind));
            o.insert("color".into(), v3(l.color));
            o.insert("attenuation".into(), json!(l.attenuation));
            if l.kind != "directional" {
                o.insert("position".into(), v3(l.position));
            }
            if l.kind != "point" {
                o.insert("direction".into(), v3(l.direction));
            }
            if l.kind == "spot" {
                o.insert("angle".into(), json!(l.angle_deg));
                o.insert("penumbra".into(), json!(l.penumbra_deg));
            }
            Value::Object(o)
        })
        .collect();
    let objects: Vec<Value> = flat
        .objects
        .iter()
        .map(|ob| {
            let mut o = Map::new();
            o.insert("name".into(), json!(ob.name));
            match &ob.shape {
                Shape::Box(b) => {
                    o.insert("shape".into(), json!("box"));
                    o.insert("min".into(), v3(b.min));
                    o.insert("max".into(), v3(b.max));
                }
                Shape::Sphere(s) => {
                    o.insert("shape".into(), json!("sphere"));
                    o.insert("center".into(), v3(s.center));
                    o.insert("radius".into(), json!(s.radius));
                }
                Shape::Cylinder(c) => {
                    o.insert("shape".into(), json!("cylinder"));
                    o.insert("radius".into(), json!(c.radius));
                    o.insert("y_min".into(), json!(c.y_min));
                    o.insert("y_max".into(), json!(c.y_max));
                    o.insert("capped".into(), json!(c.capped));
                }
                Shape::Cone(c) => {
                    o.insert("shape".into(), json!("cone"));
                    o.insert("slope".into(), json!(c.slope));
                    o.insert("y_min".into(), json!(c.y_min));
                    o.insert("y_max".into(), json!(c.y_max));
                    o.insert("capped".into(), json!(c.capped));
                }
                _ => {
                    let file = ob.mesh_file.as_deref().expect("a mesh has its file");
                    o.insert("shape".into(), json!("mesh"));
                    o.insert("file".into(), json!(relative(file, out_dir)));
                }
            }
            let m = &ob.material;
            let mut mat = json!({
                "ambient": v3(m.ambient),
                "diffuse": v3(m.diffuse),
                "specular": v3(m.specular),
                "shininess": m.shininess,
                "reflective": v3(m.reflective),
                "transparent": v3(m.transparent),
                "ior": m.ior.x,
                "refract": m.refract,
            });
            if let (Some(t), Some(file)) = (&m.texture, &ob.texture_file) {
                mat["texture"] = json!({
                    "file": relative(file, out_dir),
                    "blend": t.blend,
                    "repeat": [t.repeat.x, t.repeat.y],
                });
            }
            o.insert("material".into(), mat);
            if !ob.transform.identity {
                o.insert(
                    "transform".into(),
                    json!([{ "matrix": rows(ob.transform.world_from_object) }]),
                );
            }
            Value::Object(o)
        })
        .collect();
    json!({
        "name": flat.name.clone().unwrap_or_else(|| source.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()),
        "description": format!("converted by `rtlab convert` from the CS1230 scenefile {}", source.display()),
        "camera": {
            "position": v3(cam.position),
            "look_at": v3(cam.look_at),
            "up": v3(cam.up),
            "fov_y": cam.fov_y,
            "width": cam.width,
            "height": cam.height,
            "aperture": cam.aperture,
            "focal_distance": cam.focal_distance,
        },
        "render": {
            "spp": r.spp,
            "sampler": r.sampler.name(),
            "filter": r.filter.name(),
            "max_depth": r.max_depth,
            "min_contribution": r.min_contribution,
            "background": v3(r.background),
            "seed": r.seed,
            "encoding": if r.encoding == Encoding::Srgb { "srgb" } else { "clamp" },
            "clamp_each_ray": r.clamp_each_ray,
            "course_refraction": r.course_refraction,
            "texture_filter": r.texture_filter.name(),
        },
        "global": {"ka": flat.global.ka, "kd": flat.global.kd, "ks": flat.global.ks, "kt": flat.global.kt},
        "ambient_light": [1.0, 1.0, 1.0],
        "lights": lights,
        "objects": objects,
    })
}

/// `file` relative to `dir` when both can be resolved (so the converted scene can move with
/// its folder), else `file` made absolute.
fn relative(file: &Path, dir: &Path) -> String {
    let (Ok(f), Ok(d)) = (file.canonicalize(), dir.canonicalize()) else {
        return std::path::absolute(file)
            .unwrap_or_else(|_| file.to_path_buf())
            .display()
            .to_string();
    };
    let fc: Vec<Component> = f.components().collect();
    let dc: Vec<Component> = d.components().collect();
    let common = fc.iter().zip(&dc).take_while(|(a, b)| a == b).count();
    let mut p = PathBuf::new();
    for _ in common..dc.len() {
        p.push("..");
    }
    for c in &fc[common..] {
        p.push(c);
    }
    p.display().to_string()
}
