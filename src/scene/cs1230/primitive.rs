//! Primitives (canonical shapes with a material) and lights, as the course defines them.

use super::group::Ctx;
use super::FlatLight;
use crate::error::{suggest, Error, Result};
use crate::scene::json::Node;
use crate::scene::{load_texture, resolve};
use crate::shading::{Material, Texture};
use crate::shapes::{Cone, Cuboid, Cylinder, Shape, Sphere};
use glam::{DMat4, DVec2, DVec3};
use std::path::{Path, PathBuf};
use std::sync::Arc;

const PRIMITIVE: &[&str] = &[
    "name",
    "type",
    "meshFile",
    "ambient",
    "diffuse",
    "specular",
    "reflective",
    "transparent",
    "shininess",
    "ior",
    "blend",
    "textureFile",
    "textureU",
    "textureV",
    "bumpMapFile",
    "bumpMapU",
    "bumpMapV",
];
const TYPES: &[&str] = &["cube", "sphere", "cylinder", "cone", "mesh"];
const LIGHT: &[&str] = &[
    "name",
    "type",
    "color",
    "attenuationCoeff",
    "direction",
    "penumbra",
    "angle",
];

/// A parsed primitive, ready to be placed once per group instance.
pub struct Prim {
    pub path: String,
    pub name: Option<String>,
    pub kind: &'static str,
    pub shape: Shape,
    /// From rtlab's shape to the course's canonical one (only the cone needs a shift).
    pub object_offset: DMat4,
    pub material: Material,
    pub texture_file: Option<PathBuf>,
    pub mesh_file: Option<PathBuf>,
}

/// The canonical shapes, all inside the cube [−0.5, 0.5]³ (FORMAT §6), as rtlab shapes.
/// Their texture coordinates are the course's already (rtlab's shapes follow FORMAT §9).
pub fn canonical(kind: &str) -> (Shape, DMat4) {
    match kind {
        "cube" => (
            Shape::Box(Cuboid {
                min: DVec3::splat(-0.5),
                max: DVec3::splat(0.5),
            }),
            DMat4::IDENTITY,
        ),
        "sphere" => (
            Shape::Sphere(Sphere {
                center: DVec3::ZERO,
                radius: 0.5,
            }),
            DMat4::IDENTITY,
        ),
        "cylinder" => (
            Shape::Cylinder(Cylinder {
                radius: 0.5,
                y_min: -0.5,
                y_max: 0.5,
                capped: true,
            }),
            DMat4::IDENTITY,
        ),
        // The course's cone has its base (radius 0.5) at y = −0.5 and its apex at y = +0.5:
        // x² + z² = ((0.5 − y)/2)². rtlab's cone has its apex at the origin, so it is the
        // cone of slope 0.5 on −1 ≤ y ≤ 0, shifted up by 0.5. Normals and uv agree.
        _ => (
            Shape::Cone(Cone {
                slope: 0.5,
                y_min: -1.0,
                y_max: 0.0,
                capped: true,
            }),
            DMat4::from_translation(DVec3::new(0.0, 0.5, 0.0)),
        ),
    }
}

pub fn parse(ctx: &mut Ctx, n: &Node) -> Result<Prim> {
    let o = n.object(PRIMITIVE)?;
    o.check_keys()?;
    let name = o.opt("name", |n| n.str().map(String::from))?;
    let ty = o.req("type", |n| n.str().map(String::from))?;
    let Some(kind) = TYPES.iter().copied().find(|t| *t == ty) else {
        let hint = suggest(&ty, TYPES)
            .map(|s| format!(" (did you mean \"{s}\"?)"))
            .unwrap_or_default();
        return Err(Error::input(
            n.file,
            o.child_path("type"),
            format!(
                "unknown primitive type \"{ty}\"{hint}; expected one of: {}",
                TYPES.join(", ")
            ),
        ));
    };

    let (shape, object_offset, mesh_file) = if kind == "mesh" {
        let file = o.req("meshFile", |n| n.str().map(String::from))?;
        let p = resolve(&ctx.base, &file);
        if !p.is_file() {
            let why = if p.is_dir() {
                "is a folder, not a mesh file"
            } else {
                "mesh file not found"
            };
            return Err(Error::input(
                n.file,
                o.child_path("meshFile"),
                format!(
                    "{why}: {} (paths are relative to the folder above the scene file's, as in the course's reader)",
                    p.display()
                ),
            ));
        }
        let mesh = match ctx.meshes.get(&p) {
            Some(m) => m.clone(),
            None => {
                // The OBJ's own error (file, line) behind the scenefile's JSON path.
                let m = crate::scene::obj::load(&p)
                    .map_err(|e| Error::input(n.file, o.child_path("meshFile"), e.to_string()))?;
                let m = Arc::new(m);
                ctx.meshes.insert(p.clone(), m.clone());
                m
            }
        };
        (Shape::Mesh(mesh), DMat4::IDENTITY, Some(p))
    } else {
        let (s, off) = canonical(kind);
        (s, off, None)
    };

    // Defaults of the course's reader (FORMAT §6): diffuse is WHITE when absent, everything
    // else 0.
    let ior = o.or("ior", 0.0, |n| n.non_negative())?;
    let (texture, texture_file) = texture(ctx, n, &o)?;
    let material = Material {
        name: String::new(),
        ambient: o.or("ambient", DVec3::ZERO, |n| n.color())?,
        diffuse: o.or("diffuse", DVec3::ONE, |n| n.color())?,
        specular: o.or("specular", DVec3::ZERO, |n| n.color())?,
        shininess: o.or("shininess", 0.0, |n| n.non_negative())?,
        reflective: o.or("reflective", DVec3::ZERO, |n| n.color())?,
        transparent: o.or("transparent", DVec3::ZERO, |n| n.color())?,
        // The reader's default ior is 0, which no refraction can use (η = 1/0): read as
        // 1, no bending. Files with transparent materials set an ior.
        ior: DVec3::splat(if ior == 0.0 { 1.0 } else { ior }),
        // The course refracts by Snell's law (extra credit): refractive transparency.
        refract: true,
        texture,
    };
    Ok(Prim {
        path: n.path.to_string(),
        name,
        kind,
        shape,
        object_offset,
        material,
        texture_file,
        mesh_file,
    })
}

/// `textureFile` with `blend` and the repeat counts `textureU`, `textureV` (default 1).
/// A texture file that does not exist acts as no texture, as in the course's renderer
/// (FORMAT §6, U: some published scenes point at files that are not there); it is reported
/// as a warning (`rtlab validate`, `rtlab convert`).
fn texture(
    ctx: &mut Ctx,
    n: &Node,
    o: &crate::scene::json::Obj,
) -> Result<(Option<Texture>, Option<PathBuf>)> {
    let blend = o.or("blend", 0.0, |n| {
        let b = n.f64()?;
        if !(0.0..=1.0).contains(&b) {
            return Err(n.err(format!("blend must be between 0 and 1, found {b}")));
        }
        Ok(b)
    })?;
    let repeat = DVec2::new(
        o.or("textureU", 1.0, |n| n.positive())?,
        o.or("textureV", 1.0, |n| n.positive())?,
    );
    let Some(file) = o.opt("textureFile", |n| n.str().map(String::from))? else {
        return Ok((None, None));
    };
    // `file:src/../x.png` (some course scenefiles): the prefix is a URL scheme, not a folder.
    let file = file.strip_prefix("file:").unwrap_or(&file);
    let mut p = resolve(&ctx.base, file);
    if !p.is_file() {
        let at = o.child_path("textureFile");
        match find_in_textures(n.file, &p) {
            Some(found) => {
                if ctx.reported.insert(p.clone()) {
                    ctx.warnings.push(format!(
                        "{}: {at}: texture not found at {}; using {} (the same name in a textures/ folder beside or above the scenefile)",
                        n.file.display(),
                        p.display(),
                        found.display()
                    ));
                }
                p = found;
            }
            None => {
                let why = if p.is_dir() {
                    "is a folder, not an image"
                } else {
                    "texture not found"
                };
                ctx.warnings.push(format!(
                    "{}: {at}: {why}: {} (nor in a textures/ folder beside or above the scenefile; drawn without it, as the course's renderer does)",
                    n.file.display(),
                    p.display()
                ));
                return Ok((None, None));
            }
        }
    }
    let source = match ctx.textures.get(&p) {
        Some(s) => s.clone(),
        None => {
            let s = load_texture(&p)
                .map_err(|e| Error::input(n.file, o.child_path("textureFile"), e.to_string()))?;
            ctx.textures.insert(p.clone(), s.clone());
            s
        }
    };
    Ok((
        Some(Texture {
            source,
            blend,
            repeat,
        }),
        Some(p),
    ))
}

/// Looks for a texture's file name in `textures/` folders beside the scenefile and in each
/// folder above it, nearest first, up to the scenefile tree's root: a folder named
/// `scenefiles`, or one holding `.git` or `template_inis/` (at most 8 levels up). The
/// course's published files name textures by paths that only resolved in its old tree.
pub fn find_in_textures(scene: &Path, missing: &Path) -> Option<PathBuf> {
    let name = missing.file_name()?;
    let dir = scene.parent().unwrap_or(Path::new(""));
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    for a in dir.ancestors().take(8) {
        let candidate = a.join("textures").join(name);
        if candidate.is_file() {
            return Some(candidate);
        }
        let root = a.file_name().is_some_and(|n| n == "scenefiles")
            || a.join(".git").exists()
            || a.join("template_inis").is_dir();
        if root {
            break;
        }
    }
    None
}

/// A light as written in a group, before the group's transform is known.
pub struct LightDef {
    path: String,
    name: Option<String>,
    kind: &'static str,
    color: DVec3,
    attenuation: [f64; 3],
    direction: DVec3,
    angle: f64,
    penumbra: f64,
}

pub fn light(n: &Node) -> Result<LightDef> {
    let o = n.object(LIGHT)?;
    o.check_keys()?;
    let name = o.opt("name", |n| n.str().map(String::from))?;
    let ty = o.req("type", |n| n.str().map(String::from))?;
    let kinds = ["point", "directional", "spot"];
    let Some(kind) = kinds.iter().copied().find(|k| *k == ty) else {
        let hint = suggest(&ty, &kinds)
            .map(|s| format!(" (did you mean \"{s}\"?)"))
            .unwrap_or_default();
        return Err(Error::input(
            n.file,
            o.child_path("type"),
            format!("unknown light type \"{ty}\"{hint}; expected point, directional or spot"),
        ));
    };
    let color = o.req("color", |n| n.color())?;
    let att = |n: Node| -> Result<[f64; 3]> {
        let a = n.numbers(3)?;
        if a.iter().any(|x| *x < 0.0) {
            return Err(n.err("attenuation coefficients must not be negative"));
        }
        // All zero: f_att = min(1, 1/0) = 1, the same as [1, 0, 0] (which rtlab's light
        // model, and the native format, can hold).
        if a.iter().all(|x| *x == 0.0) {
            return Ok([1.0, 0.0, 0.0]);
        }
        Ok([a[0], a[1], a[2]])
    };
    // Which keys each type requires (FORMAT §5): directional lights may omit attenuation.
    let attenuation = if kind == "directional" {
        o.or("attenuationCoeff", [1.0, 0.0, 0.0], att)?
    } else {
        o.req("attenuationCoeff", att)?
    };
    let direction = if kind == "point" {
        DVec3::NEG_Y // unused
    } else {
        o.req("direction", |n| n.direction())?
    };
    let (angle, penumbra) = if kind == "spot" {
        let angle = o.req("angle", |n| n.f64())?;
        if !(angle > 0.0 && angle < 180.0) {
            return Err(Error::input(
                n.file,
                o.child_path("angle"),
                format!("a spot's angle (its half-angle, from the axis) must be between 0 and 180 degrees, found {angle}"),
            ));
        }
        // The course's spot light clamps the penumbra to [0, angle]; rtlab's falloff clamps
        // to at most `angle`, a negative one is read as 0 here.
        let penumbra = o.req("penumbra", |n| n.f64())?.max(0.0);
        (angle, penumbra)
    } else {
        (0.0, 0.0)
    };
    Ok(LightDef {
        path: n.path.to_string(),
        name,
        kind,
        color,
        attenuation,
        direction,
        angle,
        penumbra,
    })
}

impl LightDef {
    /// The light in world space: position = CTM · (0, 0, 0, 1), direction = CTM · (d, 0).
    /// (FORMAT §5: "with CTM applied", exact formula unconfirmed; the course's documentation
    /// says directional lights ignore translation, which this formula does too. The two
    /// readings differ only under rotated or scaled light groups, which no reference has.)
    pub fn place(&self, ctm: DMat4, index: usize, file: &std::path::Path) -> Result<FlatLight> {
        let position = ctm.transform_point3(DVec3::ZERO);
        let direction = ctm.transform_vector3(self.direction);
        if self.kind != "point" && direction.length_squared() == 0.0 {
            return Err(Error::input(
                file,
                self.path.clone(),
                "the light's groups squash its direction to zero",
            ));
        }
        Ok(FlatLight {
            name: self
                .name
                .clone()
                .unwrap_or_else(|| format!("{}#{index}", self.kind)),
            kind: self.kind,
            color: self.color,
            attenuation: self.attenuation,
            position,
            direction,
            angle_deg: self.angle,
            penumbra_deg: self.penumbra,
        })
    }
}
