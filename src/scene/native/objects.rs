//! A native scene's objects: their shapes (with each shape's keys), transforms and
//! materials.

use super::appearance::material;
use super::{referenced, OBJECT, SHAPE_KEYS};
use crate::error::{Error, Result};
use crate::math::Transform;
use crate::scene::json::Node;
use crate::scene::{world_bounds, Object};
use crate::shading::Material;
use crate::shapes::{Cone, Cuboid, Cylinder, Plane, Shape, Sphere, Triangle};
use glam::{DMat4, DVec2, DVec3};
use serde_json::Value;
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

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

pub(super) fn object(
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
        "csg" => crate::scene::solids::csg(&o, &mut |n, i| {
            object(&n, i, base, by_name, names, materials)
        })?,
        "blob" => crate::scene::solids::blob(&o)?,
        _ => Shape::Mesh(Arc::new(
            o.req("file", |n| referenced(&n, base, crate::scene::obj::load))?,
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
