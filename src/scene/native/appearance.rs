//! What objects look like and what lights them: a native scene's lights, materials and
//! textures.

use super::{referenced, LIGHT, MATERIAL, TEXTURE};
use crate::error::{Error, Result};
use crate::scene::json::Node;
use crate::scene::load_texture;
use crate::shading::{Light, LightKind, Material, Texture, TextureSource};
use glam::{DVec2, DVec3};
use std::path::Path;

pub(super) fn light(n: &Node, i: usize) -> Result<Light> {
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

pub(super) fn material(n: &Node, name: &str, base: &Path) -> Result<Material> {
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
