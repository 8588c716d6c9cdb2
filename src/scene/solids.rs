//! The `csg` and `blob` object kinds of the native format.
//!
//! ```json
//! {"shape": "csg", "op": "difference", "children": [
//!     {"shape": "box"},
//!     {"shape": "sphere", "radius": 1.3, "transform": [{"translate": [0, 0.5, 0]}]}]}
//! {"shape": "blob", "threshold": 0.5, "falloff": "wyvill",
//!  "components": [{"center": [0, 0, 0], "radius": 1, "strength": 1}]}
//! ```
//!
//! A CSG child is written like an object (shape, its keys, `transform`, an optional `name`)
//! but has no material: the whole solid wears the CSG object's. `"left"`/`"right"` may be
//! used instead of `"children"` for a binary node. Children must bound a solid.

use super::json::{Node, Obj};
use super::Object;
use crate::error::{Error, Result};
use crate::shapes::{Blob, Component, Csg, CsgChild, CsgOp, Falloff, Shape};
use glam::DVec3;
use std::sync::Arc;

/// Reads a CSG node; `child` parses one child written as an object (the loader's own
/// object reader, so every shape kind and transform is accepted at any depth).
pub fn csg(o: &Obj, child: &mut dyn FnMut(Node, usize) -> Result<Object>) -> Result<Shape> {
    let op = o.or("op", CsgOp::Union, |n| {
        let s = n.str()?;
        CsgOp::parse(s).ok_or_else(|| {
            let hint = crate::error::suggest(s, &CsgOp::NAMES)
                .map(|h| format!(" (did you mean \"{h}\"?)"))
                .unwrap_or_default();
            n.err(format!(
                "unknown CSG operation \"{s}\"{hint}; expected union, intersection or difference"
            ))
        })
    })?;
    let at = |key: &str| o.child_path(key);
    let mut read = |n: Node, i: usize| -> Result<CsgChild> {
        if n.v.get("material").is_some() {
            return Err(Error::input(
                n.file,
                format!("{}.material", n.path),
                "a CSG child has no material of its own: the CSG object's material covers the whole solid",
            ));
        }
        let obj = child(n, i)?;
        if !obj.shape.is_solid() {
            let why = match &obj.shape {
                Shape::Mesh(_) => {
                    "this mesh is not closed (some edge does not join exactly two faces)"
                }
                Shape::Cylinder(_) | Shape::Cone(_) => "an uncapped cylinder or cone has no inside",
                _ => "planes and triangles have no inside",
            };
            return Err(n.err(format!(
                "a CSG child must be a closed solid (sphere, box, capped cylinder or cone, closed mesh, blob or csg): {why}"
            )));
        }
        Ok(CsgChild::new(obj.name, obj.shape, obj.transform))
    };
    let children = match (o.has("children"), o.has("left") || o.has("right")) {
        (true, true) => {
            return Err(Error::input(
                o.file,
                at("left"),
                "a CSG node has either \"children\" or \"left\"/\"right\", not both",
            ))
        }
        (true, false) => o.each("children", &mut read)?,
        (false, _) => {
            let left = o.req("left", |n| read(n, 0))?;
            let right = o.req("right", |n| read(n, 1))?;
            vec![left, right]
        }
    };
    if children.is_empty() {
        return Err(Error::input(
            o.file,
            at("children"),
            "a CSG node needs at least one child",
        ));
    }
    Ok(Shape::Csg(Arc::new(Csg { op, children })))
}

/// Reads a blob: a threshold, a falloff and a list of components.
pub fn blob(o: &Obj) -> Result<Shape> {
    let threshold = o.or("threshold", 0.5, |n| n.positive())?;
    let falloff = o.or("falloff", Falloff::Wyvill, |n| {
        let s = n.str()?;
        Falloff::parse(s).ok_or_else(|| {
            n.err(format!(
                "unknown falloff \"{s}\"; expected wyvill or gaussian"
            ))
        })
    })?;
    let components = o.each("components", |n, _| {
        let c = n.object(&["center", "radius", "strength"])?;
        c.check_keys()?;
        Ok(Component {
            center: c.or("center", DVec3::ZERO, |n| n.vec3())?,
            radius: c.or("radius", 1.0, |n| n.positive())?,
            strength: c.or("strength", 1.0, |n| n.f64())?,
        })
    })?;
    if !components.iter().any(|c| c.strength > 0.0) {
        return Err(Error::input(
            o.file,
            o.child_path("components"),
            "a blob needs at least one component with a positive strength",
        ));
    }
    Ok(Shape::Blob(Arc::new(Blob {
        threshold,
        falloff,
        components,
    })))
}

/// Reads a standalone solid from a small JSON file written like a scene object (`"shape"`
/// may be left out: `kind` supplies it). For `intersect csg|blob --spec FILE`.
pub fn load_solid(path: &std::path::Path, kind: &str) -> Result<Object> {
    let text = super::read_json_text(path, "spec")?;
    let (mut value, twice) = super::json::parse_noting_twice(path, &text)?;
    // Written like a scene's object, so refused like one's: a key given twice.
    if let Some(e) = twice {
        return Err(e);
    }
    let root = Node {
        v: &value,
        path: "",
        file: path,
    };
    let map = root.object(&[])?.map;
    match map.get("shape").and_then(|s| s.as_str()) {
        None if map.contains_key("shape") => {
            return Err(Error::input(path, "shape", "expected a string"))
        }
        None => {
            if let Some(o) = value.as_object_mut() {
                o.insert("shape".into(), serde_json::Value::String(kind.into()));
            }
        }
        Some(s) if s != kind => {
            return Err(Error::input(
                path,
                "shape",
                format!("the spec describes a {s}, but a {kind} was asked for"),
            ))
        }
        Some(_) => {}
    }
    super::native::standalone_object(path, &value)
}
