//! The native rtlab scene format (DESIGN §4). Every key is optional except
//! `camera.position` and each object's `shape`; unknown keys are errors with a suggestion.

mod appearance;
mod objects;
mod settings;

use super::json::Node;
use super::{resolve, Global, Object, RenderSettings, Scene, SceneFormat};
use crate::accel::Accel;
use crate::error::{Error, Result};
use crate::shading::Material;
use appearance::{light, material};
use glam::DVec3;
pub use objects::matrix;
use objects::object;
use serde_json::Value;
use settings::{camera, render_settings};
use std::collections::HashMap;
use std::path::Path;

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

/// The scene in `value`, the JSON read from `path` (whose folder relative file names in it
/// are taken from).
pub fn load(path: &Path, value: &Value) -> Result<Scene> {
    let root = Node {
        v: value,
        path: "",
        file: path,
    };
    let top = root.object(TOP)?;
    top.check_keys()?;
    // Read by people, not by the renderer: still held to the schema (a string).
    top.opt("description", |n| n.str().map(|_| ()))?;
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
