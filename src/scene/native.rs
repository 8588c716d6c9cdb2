//! The native rtlab scene format (DESIGN §4). Every key is optional except
//! `camera.position` and each object's `shape`; unknown keys are errors with a suggestion.

use super::json::Node;
use super::{
    check_size, load_texture, resolve, world_bounds, Global, Object, RenderSettings, Scene,
    SceneFormat,
};
use super::{Encoding, FilterKind, SamplerKind};
use crate::accel::Accel;
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::math::Transform;
use crate::shading::{Light, LightKind, Material, Texture, TextureSource};
use crate::shapes::{Cone, Cuboid, Cylinder, Plane, Shape, Sphere, Triangle};
use glam::{DMat4, DVec2, DVec3};
use serde_json::Value;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// The keys each part of the format accepts (also the source of `rtlab schema`'s lists).
pub const NATIVE_KEYS: &[(&str, &[&str])] = &[
    ("scene", TOP),
    ("camera", CAMERA),
    ("render", RENDER),
    ("global", GLOBAL),
    ("light", LIGHT),
    ("material", MATERIAL),
    ("texture", TEXTURE),
    ("object", OBJECT),
];
const TOP: &[&str] = &[
    "name",
    "description",
    "camera",
    "render",
    "global",
    "ambient_light",
    "lights",
    "materials",
    "objects",
];
const CAMERA: &[&str] = &[
    "position",
    "look_at",
    "up",
    "fov_y",
    "width",
    "height",
    "aperture",
    "focal_distance",
];
const RENDER: &[&str] = &[
    "spp",
    "sampler",
    "filter",
    "max_depth",
    "min_contribution",
    "background",
    "seed",
    "encoding",
    "clamp_each_ray",
    "max_rays",
    "texture_filter",
    "course_refraction",
];
const GLOBAL: &[&str] = &["ka", "kd", "ks", "kt"];
const LIGHT: &[&str] = &[
    "name",
    "type",
    "position",
    "direction",
    "color",
    "attenuation",
    "angle",
    "penumbra",
    "corner",
    "edge_u",
    "edge_v",
    "samples",
];
const MATERIAL: &[&str] = &[
    "ambient",
    "diffuse",
    "specular",
    "shininess",
    "reflective",
    "transparent",
    "ior",
    "refract",
    "texture",
];
const TEXTURE: &[&str] = &["file", "checker", "colors", "blend", "repeat"];
const OBJECT: &[&str] = &[
    "name",
    "shape",
    "material",
    "transform",
    "center",
    "radius",
    "point",
    "normal",
    "min",
    "max",
    "y_min",
    "y_max",
    "capped",
    "slope",
    "vertices",
    "normals",
    "uvs",
    "file",
    "op",
    "children",
    "left",
    "right",
    "threshold",
    "falloff",
    "components",
];
/// Which object keys belong to which shape (beyond name, shape, material, transform).
const SHAPE_KEYS: &[(&str, &[&str])] = &[
    ("sphere", &["center", "radius"]),
    ("plane", &["point", "normal"]),
    ("box", &["min", "max"]),
    ("cylinder", &["radius", "y_min", "y_max", "capped"]),
    ("cone", &["slope", "y_min", "y_max", "capped"]),
    ("triangle", &["vertices", "normals", "uvs"]),
    ("mesh", &["file"]),
    ("csg", &["op", "children", "left", "right"]),
    ("blob", &["threshold", "falloff", "components"]),
];

/// Largest recursion depth accepted (each level can double the rays).
pub const MAX_DEPTH_LIMIT: u32 = 64;

pub fn load(path: &Path, value: &Value) -> Result<Scene> {
    let root = Node {
        v: value,
        path: "",
        file: path,
    };
    let top = root.object(TOP)?;
    top.check_keys()?;
    let base = path.parent().unwrap_or(Path::new("."));

    let camera = top.req("camera", |n| camera(&n))?;
    let render = top.or("render", RenderSettings::default(), |n| render_settings(&n))?;
    let global = top.or(
        "global",
        Global {
            ka: 1.0,
            kd: 1.0,
            ks: 1.0,
            kt: 1.0,
        },
        |n| {
            let o = n.object(GLOBAL)?;
            o.check_keys()?;
            Ok(Global {
                ka: o.or("ka", 1.0, |n| n.non_negative())?,
                kd: o.or("kd", 1.0, |n| n.non_negative())?,
                ks: o.or("ks", 1.0, |n| n.non_negative())?,
                kt: o.or("kt", 1.0, |n| n.non_negative())?,
            })
        },
    )?;
    let ambient_light = top.or("ambient_light", DVec3::ONE, |n| n.color())?;
    let lights = top.each("lights", |n, i| light(&n, i))?;

    // Materials: a map from name to definition; index 0 is the default white diffuse.
    let mut materials = vec![Material::default()];
    let mut by_name: HashMap<String, usize> = HashMap::new();
    if let Some(v) = top.map.get("materials") {
        let p = "materials".to_string();
        let n = Node {
            v,
            path: &p,
            file: path,
        };
        let map = v
            .as_object()
            .ok_or_else(|| n.err("expected an object mapping material names to materials"))?;
        for (name, mv) in map {
            let mp = format!("materials.{name}");
            let m = material(
                &Node {
                    v: mv,
                    path: &mp,
                    file: path,
                },
                name,
                base,
            )?;
            by_name.insert(name.clone(), materials.len());
            materials.push(m);
        }
    }

    let objects = top.each("objects", |n, i| {
        let mut names: Vec<&str> = by_name.keys().map(|s| s.as_str()).collect();
        names.sort();
        object(&n, i, base, &by_name, &names, &mut materials)
    })?;

    Ok(Scene {
        path: path.to_path_buf(),
        format: SceneFormat::Native,
        camera,
        render,
        global,
        ambient_light,
        lights,
        materials,
        objects,
        accel: Accel::default(),
    })
}

fn camera(n: &Node) -> Result<Camera> {
    let o = n.object(CAMERA)?;
    o.check_keys()?;
    let position = o.req("position", |n| n.vec3())?;
    let look_at = o.or("look_at", DVec3::ZERO, |n| n.vec3())?;
    let up = o.or("up", DVec3::Y, |n| n.vec3())?;
    let fov = o.or("fov_y", 45.0, |n| n.f64())?;
    let width = o.or("width", 640, |n| n.u32())?;
    let height = o.or("height", 480, |n| n.u32())?;
    check_size(width, height).map_err(|m| n.err(m))?;
    let mut cam = Camera::new(position, look_at, up, fov, width, height).map_err(|m| n.err(m))?;
    cam.aperture = o.or("aperture", 0.0, |n| n.non_negative())?;
    if let Some(f) = o.opt("focal_distance", |n| n.positive())? {
        cam.focal_distance = f;
    }
    Ok(cam)
}

fn render_settings(n: &Node) -> Result<RenderSettings> {
    let o = n.object(RENDER)?;
    o.check_keys()?;
    let d = RenderSettings::default();
    let sampler = o.or("sampler", d.sampler, |n| {
        let s = n.str()?;
        SamplerKind::parse(s).ok_or_else(|| {
            n.err(format!(
                "unknown sampler \"{s}\" (expected one of: {})",
                SamplerKind::NAMES.join(", ")
            ))
        })
    })?;
    let spp = o.or("spp", d.spp, |n| n.u32())?;
    crate::sampling::validate_spp(sampler, spp)
        .map_err(|m| Error::input(n.file, o.child_path("spp"), m))?;
    Ok(RenderSettings {
        spp,
        sampler,
        filter: o.or("filter", d.filter, |n| {
            let s = n.str()?;
            FilterKind::parse(s).ok_or_else(|| {
                n.err(format!(
                    "unknown filter \"{s}\" (expected one of: {})",
                    FilterKind::NAMES.join(", ")
                ))
            })
        })?,
        max_depth: o.or("max_depth", d.max_depth, |n| {
            let v = n.u32()?;
            if v > MAX_DEPTH_LIMIT {
                return Err(n.err(format!(
                    "max_depth {v} is too deep (at most {MAX_DEPTH_LIMIT})"
                )));
            }
            Ok(v)
        })?,
        min_contribution: o.or("min_contribution", d.min_contribution, |n| n.non_negative())?,
        background: o.or("background", d.background, |n| n.color())?,
        seed: o.or("seed", 0, |n| n.u32().map(|s| s as u64))?,
        encoding: o.or("encoding", d.encoding, |n| match n.str()? {
            "clamp" => Ok(Encoding::Clamp),
            "srgb" => Ok(Encoding::Srgb),
            s => Err(n.err(format!("unknown encoding \"{s}\" (expected clamp or srgb)"))),
        })?,
        clamp_each_ray: o.or("clamp_each_ray", d.clamp_each_ray, |n| n.bool())?,
        max_rays: o.or("max_rays", d.max_rays, |n| match n.u32()? {
            0 => Err(n.err(
                "max_rays must be at least 1 (the camera ray): it is the most rays one sample may trace",
            )),
            v => Ok(v as u64),
        })?,
        texture_filter: o.or("texture_filter", d.texture_filter, |n| {
            let s = n.str()?;
            crate::shading::TextureFilter::parse(s).ok_or_else(|| {
                n.err(format!(
                    "unknown texture filter \"{s}\" (expected nearest or bilinear)"
                ))
            })
        })?,
        course_refraction: o.or("course_refraction", d.course_refraction, |n| n.bool())?,
        ..d
    })
}

fn light(n: &Node, i: usize) -> Result<Light> {
    let o = n.object(LIGHT)?;
    o.check_keys()?;
    let name = o.or("name", format!("#{i}"), |n| n.str().map(String::from))?;
    let ty = o.or("type", "point".to_string(), |n| n.str().map(String::from))?;
    let color = o.or("color", DVec3::ONE, |n| n.color())?;
    let attenuation = o.or("attenuation", [1.0, 0.0, 0.0], |n| {
        let a = n.numbers(3)?;
        if a.iter().any(|x| *x < 0.0) || a.iter().all(|x| *x == 0.0) {
            return Err(n.err("attenuation coefficients must be ≥ 0 and not all zero"));
        }
        Ok([a[0], a[1], a[2]])
    })?;
    let allowed: &[&str] = match ty.as_str() {
        "point" => &["position"],
        "directional" => &["direction"],
        "spot" => &["position", "direction", "angle", "penumbra"],
        "area" => &["corner", "edge_u", "edge_v", "samples"],
        other => {
            let hint = crate::error::suggest(other, &["point", "directional", "spot", "area"])
                .map(|s| format!(" (did you mean \"{s}\"?)"))
                .unwrap_or_default();
            return Err(Error::input(n.file, o.child_path("type"), format!("unknown light type \"{other}\"{hint}; expected point, directional, spot or area")));
        }
    };
    for key in [
        "position",
        "direction",
        "angle",
        "penumbra",
        "corner",
        "edge_u",
        "edge_v",
        "samples",
    ] {
        if o.has(key) && !allowed.contains(&key) {
            return Err(Error::input(
                n.file,
                o.child_path(key),
                format!(
                    "a {ty} light has no \"{key}\" (it takes: {})",
                    allowed.join(", ")
                ),
            ));
        }
    }
    let kind = match ty.as_str() {
        "point" => LightKind::Point {
            position: o.req("position", |n| n.vec3())?,
        },
        "directional" => LightKind::Directional {
            direction: o.req("direction", |n| n.direction())?.normalize(),
        },
        "spot" => {
            let angle = o.req("angle", |n| n.f64())?;
            if !(angle > 0.0 && angle < 180.0) {
                return Err(Error::input(
                    n.file,
                    o.child_path("angle"),
                    format!("spot angle must be between 0 and 180 degrees, found {angle}"),
                ));
            }
            LightKind::Spot {
                position: o.req("position", |n| n.vec3())?,
                direction: o.req("direction", |n| n.direction())?.normalize(),
                angle: angle.to_radians(),
                penumbra: o.or("penumbra", 0.0, |n| n.non_negative())?.to_radians(),
            }
        }
        _ => {
            let samples = o.or("samples", [4, 4], |n| {
                let s = n.numbers(2)?;
                if s.iter().any(|x| *x < 1.0 || x.fract() != 0.0 || *x > 64.0) {
                    return Err(n.err("samples must be two whole numbers from 1 to 64"));
                }
                Ok([s[0] as u32, s[1] as u32])
            })?;
            let edge_u = o.req("edge_u", |n| n.direction())?;
            let edge_v = o.req("edge_v", |n| n.direction())?;
            if edge_u.cross(edge_v).length() == 0.0 {
                return Err(Error::input(
                    n.file,
                    o.child_path("edge_v"),
                    "the area light's edges are parallel: it has no area",
                ));
            }
            LightKind::Area {
                corner: o.req("corner", |n| n.vec3())?,
                edge_u,
                edge_v,
                samples,
            }
        }
    };
    Ok(Light {
        name,
        kind,
        color,
        attenuation,
    })
}

fn material(n: &Node, name: &str, base: &Path) -> Result<Material> {
    let o = n.object(MATERIAL)?;
    o.check_keys()?;
    let d = Material::default();
    let ior = o.or("ior", d.ior, |n| {
        let v = if n.v.is_number() {
            DVec3::splat(n.f64()?)
        } else {
            n.vec3()?
        };
        if v.min_element() <= 0.0 {
            return Err(n.err("an index of refraction must be greater than 0"));
        }
        Ok(v)
    })?;
    Ok(Material {
        name: name.to_string(),
        ambient: o.or("ambient", d.ambient, |n| n.color())?,
        diffuse: o.or("diffuse", d.diffuse, |n| n.color())?,
        specular: o.or("specular", d.specular, |n| n.color())?,
        shininess: o.or("shininess", d.shininess, |n| n.non_negative())?,
        reflective: o.or("reflective", d.reflective, |n| n.color())?,
        transparent: o.or("transparent", d.transparent, |n| n.color())?,
        ior,
        refract: o.or("refract", true, |n| n.bool())?,
        texture: o.opt("texture", |n| texture(&n, base))?,
    })
}

fn texture(n: &Node, base: &Path) -> Result<Texture> {
    let o = n.object(TEXTURE)?;
    o.check_keys()?;
    let source = match (o.has("file"), o.has("checker")) {
        (true, true) => return Err(n.err("a texture has either \"file\" or \"checker\", not both")),
        (false, false) => {
            return Err(n.err(
                "a texture needs \"file\" (an image) or \"checker\" ([squares_u, squares_v])",
            ))
        }
        (true, false) => o.req("file", |n| referenced(&n, base, load_texture))?,
        (false, true) => {
            let squares = o.req("checker", |n| {
                let s = n.vec2()?;
                if s.min_element() <= 0.0 {
                    return Err(n.err("checker square counts must be greater than 0"));
                }
                Ok(s)
            })?;
            let colors = o.or("colors", [DVec3::ONE, DVec3::splat(0.1)], |n| {
                let a = n.array()?;
                if a.len() != 2 {
                    return Err(n.err("expected two colours"));
                }
                let p0 = format!("{}[0]", n.path);
                let p1 = format!("{}[1]", n.path);
                Ok([
                    Node {
                        v: &a[0],
                        path: &p0,
                        file: n.file,
                    }
                    .color()?,
                    Node {
                        v: &a[1],
                        path: &p1,
                        file: n.file,
                    }
                    .color()?,
                ])
            })?;
            TextureSource::Checker {
                squares,
                a: colors[0],
                b: colors[1],
            }
        }
    };
    if o.has("colors") && !o.has("checker") {
        return Err(Error::input(
            n.file,
            o.child_path("colors"),
            "\"colors\" belongs to a \"checker\" texture",
        ));
    }
    let blend = o.or("blend", 1.0, |n| {
        let b = n.f64()?;
        if !(0.0..=1.0).contains(&b) {
            return Err(n.err(format!("blend must be between 0 and 1, found {b}")));
        }
        Ok(b)
    })?;
    let repeat = o.or("repeat", DVec2::ONE, |n| {
        let r = n.vec2()?;
        if r.min_element() <= 0.0 {
            return Err(n.err("repeat counts must be greater than 0"));
        }
        Ok(r)
    })?;
    Ok(Texture {
        source,
        blend,
        repeat,
    })
}

/// A transform: a list of operations applied in the order written (first op first).
pub fn transform(n: &Node) -> Result<Transform> {
    let mut m = DMat4::IDENTITY;
    let ops = n.array()?;
    for (i, v) in ops.iter().enumerate() {
        let p = format!("{}[{i}]", n.path);
        let node = Node {
            v,
            path: &p,
            file: n.file,
        };
        let o = node.object(&["scale", "rotate", "translate", "matrix"])?;
        o.check_keys()?;
        if o.map.len() != 1 {
            return Err(node
                .err("each transform step has exactly one of: scale, rotate, translate, matrix"));
        }
        let step = if let Some(s) = o.opt("scale", |n| {
            if n.v.is_number() {
                Ok(DVec3::splat(n.f64()?))
            } else {
                n.vec3()
            }
        })? {
            if s.x == 0.0 || s.y == 0.0 || s.z == 0.0 {
                return Err(Error::input(
                    n.file,
                    o.child_path("scale"),
                    "a scale of 0 flattens the object to nothing",
                ));
            }
            DMat4::from_scale(s)
        } else if let Some(t) = o.opt("translate", |n| n.vec3())? {
            DMat4::from_translation(t)
        } else if let Some(r) = o.opt("rotate", |n| {
            let r = n.object(&["axis", "degrees"])?;
            r.check_keys()?;
            Ok((
                r.req("axis", |n| n.direction())?,
                r.req("degrees", |n| n.f64())?,
            ))
        })? {
            DMat4::from_axis_angle(r.0.normalize(), r.1.to_radians())
        } else {
            o.req("matrix", |n| matrix(&n))?
        };
        m = step * m;
    }
    Transform::new(m).ok_or_else(|| n.err("the transform is singular (it cannot be inverted): check for zero scales or a degenerate matrix"))
}

/// A 4×4 matrix written as four rows.
pub fn matrix(n: &Node) -> Result<DMat4> {
    let rows = n.array()?;
    if rows.len() != 4 {
        return Err(n.err(format!(
            "a matrix is 4 rows of 4 numbers, found {} rows",
            rows.len()
        )));
    }
    let mut r = [[0.0; 4]; 4];
    for (i, row) in rows.iter().enumerate() {
        let p = format!("{}[{i}]", n.path);
        let v = Node {
            v: row,
            path: &p,
            file: n.file,
        }
        .numbers(4)?;
        r[i].copy_from_slice(&v);
    }
    Ok(DMat4::from_cols_array_2d(&r).transpose())
}

fn object(
    n: &Node,
    i: usize,
    base: &Path,
    by_name: &HashMap<String, usize>,
    names: &[&str],
    materials: &mut Vec<Material>,
) -> Result<Object> {
    let o = n.object(OBJECT)?;
    o.check_keys()?;
    let name = o.or("name", format!("#{i}"), |n| n.str().map(String::from))?;
    let kind = o.req("shape", |n| n.str().map(String::from))?;
    let Some((_, keys)) = SHAPE_KEYS.iter().find(|(k, _)| *k == kind) else {
        let all: Vec<&str> = SHAPE_KEYS.iter().map(|(k, _)| *k).collect();
        let hint = crate::error::suggest(&kind, &all)
            .map(|s| format!(" (did you mean \"{s}\"?)"))
            .unwrap_or_default();
        return Err(Error::input(
            n.file,
            o.child_path("shape"),
            format!(
                "unknown shape \"{kind}\"{hint}; expected one of: {}",
                all.join(", ")
            ),
        ));
    };
    for key in o.map.keys() {
        let common = ["name", "shape", "material", "transform"];
        if !common.contains(&key.as_str()) && !keys.contains(&key.as_str()) {
            return Err(Error::input(
                n.file,
                o.child_path(key),
                format!("a {kind} has no \"{key}\" (it takes: {})", keys.join(", ")),
            ));
        }
    }
    let material = match o.map.get("material") {
        None => 0,
        Some(Value::String(m)) => *by_name.get(m).ok_or_else(|| {
            let hint = crate::error::suggest(m, names)
                .map(|s| format!(" (did you mean \"{s}\"?)"))
                .unwrap_or_default();
            Error::input(
                n.file,
                o.child_path("material"),
                format!("no material named \"{m}\" in \"materials\"{hint}"),
            )
        })?,
        Some(v) => {
            let p = o.child_path("material");
            let m = material(
                &Node {
                    v,
                    path: &p,
                    file: n.file,
                },
                &name,
                base,
            )?;
            materials.push(m);
            materials.len() - 1
        }
    };
    let transform = o.or("transform", Transform::IDENTITY, |n| transform(&n))?;
    let positive = |key: &str, default: f64| o.or(key, default, |n| n.positive());
    let shape = match kind.as_str() {
        "sphere" => Shape::Sphere(Sphere {
            center: o.or("center", DVec3::ZERO, |n| n.vec3())?,
            radius: positive("radius", 1.0)?,
        }),
        "plane" => Shape::Plane(Plane {
            point: o.or("point", DVec3::ZERO, |n| n.vec3())?,
            normal: o.or("normal", DVec3::Y, |n| n.direction())?.normalize(),
        }),
        "box" => {
            let min = o.or("min", DVec3::splat(-1.0), |n| n.vec3())?;
            let max = o.or("max", DVec3::ONE, |n| n.vec3())?;
            if min.cmpge(max).any() {
                return Err(Error::input(
                    n.file,
                    o.child_path("max"),
                    format!("max must be greater than min in every axis (min {min}, max {max})"),
                ));
            }
            Shape::Box(Cuboid { min, max })
        }
        "cylinder" | "cone" => {
            let y_min = o.or("y_min", -1.0, |n| n.f64())?;
            let y_max = o.or("y_max", if kind == "cone" { 0.0 } else { 1.0 }, |n| n.f64())?;
            if y_max <= y_min {
                return Err(Error::input(
                    n.file,
                    o.child_path("y_max"),
                    format!("y_max ({y_max}) must be greater than y_min ({y_min})"),
                ));
            }
            let capped = o.or("capped", true, |n| n.bool())?;
            if kind == "cylinder" {
                Shape::Cylinder(Cylinder {
                    radius: positive("radius", 1.0)?,
                    y_min,
                    y_max,
                    capped,
                })
            } else {
                Shape::Cone(Cone {
                    slope: positive("slope", 1.0)?,
                    y_min,
                    y_max,
                    capped,
                })
            }
        }
        "triangle" => {
            let v = o.req("vertices", |n| points(&n, 3))?;
            let t = Triangle {
                v: [v[0], v[1], v[2]],
                normals: o.opt("normals", |n| points(&n, 3).map(|v| [v[0], v[1], v[2]]))?,
                uvs: o.opt("uvs", |n| {
                    let a = n.array()?;
                    if a.len() != 3 {
                        return Err(n.err("expected 3 texture coordinates"));
                    }
                    let mut out = [DVec2::ZERO; 3];
                    for (k, v) in a.iter().enumerate() {
                        let p = format!("{}[{k}]", n.path);
                        out[k] = Node {
                            v,
                            path: &p,
                            file: n.file,
                        }
                        .vec2()?;
                    }
                    Ok(out)
                })?,
            };
            if t.geometric_normal() == DVec3::ZERO {
                return Err(Error::input(
                    n.file,
                    o.child_path("vertices"),
                    "the triangle is degenerate (its corners are collinear): it has no area",
                ));
            }
            Shape::Triangle(t)
        }
        "csg" => super::solids::csg(&o, &mut |n, i| {
            object(&n, i, base, by_name, names, materials)
        })?,
        "blob" => super::solids::blob(&o)?,
        _ => Shape::Mesh(Arc::new(
            o.req("file", |n| referenced(&n, base, super::obj::load))?,
        )),
    };
    let bounds = world_bounds(&shape, &transform);
    Ok(Object {
        name,
        shape,
        transform,
        material,
        bounds,
    })
}

/// Reads one object written as in a scene's `"objects"`, alone (no named materials).
pub(super) fn standalone_object(path: &Path, value: &Value) -> Result<Object> {
    let node = Node {
        v: value,
        path: "",
        file: path,
    };
    let base = path.parent().unwrap_or(Path::new("."));
    let mut materials = vec![Material::default()];
    object(&node, 0, base, &HashMap::new(), &[], &mut materials)
}

/// Loads a file the scene names (a mesh, a texture). When it cannot be read, the error names
/// the scene's key as well as the file, so the student knows which line to fix; errors inside
/// the file (an OBJ's line:column) name that file.
fn referenced<T>(n: &Node, base: &Path, load: impl FnOnce(&Path) -> Result<T>) -> Result<T> {
    let file = n.str()?;
    if file.trim().is_empty() {
        return Err(n.err("expected a file name, found an empty string"));
    }
    load(&resolve(base, file)).map_err(|e| match e {
        Error::Io { path, msg } => n.err(format!("{}: {msg}", path.display())),
        other => other,
    })
}

fn points(n: &Node, count: usize) -> Result<Vec<DVec3>> {
    let a = n.array()?;
    if a.len() != count {
        return Err(n.err(format!(
            "expected {count} points of 3 numbers, found {}",
            a.len()
        )));
    }
    a.iter()
        .enumerate()
        .map(|(k, v)| {
            let p = format!("{}[{k}]", n.path);
            Node {
                v,
                path: &p,
                file: n.file,
            }
            .vec3()
        })
        .collect()
}
