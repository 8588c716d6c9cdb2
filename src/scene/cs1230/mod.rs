//! The CS1230 course scenefile format (Brown CSCI 1230, JSON era), read into the same
//! validated [`Scene`] as the native format. The semantics follow
//! `../shared/CS1230_FORMAT.md` section by section; where that summary marks a convention
//! unconfirmed, the comment at the code says which reading was chosen.
//!
//! Loading is two steps so that `rtlab convert` can reuse the first one:
//! [`flatten`] walks the group tree (transforms, templates) into a flat list of primitives
//! and lights in world space ([`Flat`]), then [`Flat::into_scene`] builds the `Scene`.

mod group;
pub mod ini;
mod primitive;
pub mod stage;

use super::json::Node;
use super::{Global, Object, RenderSettings, Scene, SceneFormat};
use crate::accel::Accel;
use crate::camera::Camera;
use crate::error::Result;
use crate::math::Transform;
use crate::shading::{Light, LightKind, Material};
use crate::shapes::Shape;
use glam::{DMat4, DVec3};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The course renders every reference image at this size (FORMAT §10); a scenefile has no
/// size of its own, so this is the default (`--width`/`--height` override it).
pub const DEFAULT_WIDTH: u32 = 1024;
pub const DEFAULT_HEIGHT: u32 = 768;

/// Memory a scenefile may take once its templates are instantiated. Templates nest, so a
/// few lines can ask for 2^40 copies: the count is computed before anything is built, and a
/// scene whose estimate ([`bytes_per_primitive`]) is above this is refused with the JSON path
/// of the culprit, the way an image too large is refused ([`crate::scene::check_size`]).
/// The course's largest scene (`recursive_sphere_9`, 585 940 primitives and lights) needs
/// about a third of it.
pub const MAX_SCENE_BYTES: u64 = 3 << 30;

/// Estimated bytes one expanded primitive costs at the peak of loading: its flat record and
/// its object, its material (each primitive owns one), its name, and its share of the BVH
/// (a leaf slot, its bounds while building, and inner nodes). Measured peak of a 586k-sphere
/// scene: see the README's CS1230 section.
pub fn bytes_per_primitive() -> u64 {
    use std::mem::size_of;
    let names = 2 * 24; // the object's and its material's name ("sphere#123456")
    let bvh = 96; // build records and the nodes' share
    (size_of::<FlatObject>() + size_of::<Object>() + 2 * size_of::<Material>() + names + bvh) as u64
}

/// Most primitives and lights a scenefile may expand to: [`MAX_SCENE_BYTES`] at
/// [`bytes_per_primitive`].
pub fn max_expanded() -> u64 {
    MAX_SCENE_BYTES / bytes_per_primitive()
}

/// Maximum recursion of the course's reference renderer: `maximum-recursive-depth = 4` in every
/// Illuminate ini, i.e. up to 4 bounces after the primary hit (FORMAT §8). rtlab's
/// `max_depth` counts the same way (the camera ray is depth 0; rays of depth ≤ 4 are traced).
pub const COURSE_MAX_DEPTH: u32 = 4;

const TOP: &[&str] = &[
    "name",
    "globalData",
    "cameraData",
    "groups",
    "templateGroups",
];
const GLOBAL: &[&str] = &[
    "ambientCoeff",
    "diffuseCoeff",
    "specularCoeff",
    "transparentCoeff",
];
const CAMERA: &[&str] = &[
    "position",
    "up",
    "heightAngle",
    "look",
    "focus",
    "aperture",
    "focalLength",
];

/// A light in world space, kept in the terms the native format writes (degrees, the
/// direction before normalising) so that a converted scene builds the very same [`Light`].
#[derive(Debug, Clone)]
pub struct FlatLight {
    pub name: String,
    pub kind: &'static str,
    pub color: DVec3,
    pub attenuation: [f64; 3],
    pub position: DVec3,
    /// World direction, not normalised (normalised once, in [`FlatLight::to_light`]).
    pub direction: DVec3,
    pub angle_deg: f64,
    pub penumbra_deg: f64,
}

impl FlatLight {
    /// The light as the tracer uses it (the same arithmetic as the native loader).
    pub fn to_light(&self) -> Light {
        let kind = match self.kind {
            "point" => LightKind::Point {
                position: self.position,
            },
            "directional" => LightKind::Directional {
                direction: self.direction.normalize(),
            },
            _ => LightKind::Spot {
                position: self.position,
                direction: self.direction.normalize(),
                angle: self.angle_deg.to_radians(),
                penumbra: self.penumbra_deg.to_radians(),
            },
        };
        Light {
            name: self.name.clone(),
            kind,
            color: self.color,
            attenuation: self.attenuation,
        }
    }
}

/// One instantiated primitive: a canonical shape, placed by `world_from_object`.
#[derive(Debug, Clone)]
pub struct FlatObject {
    pub name: String,
    /// The course's primitive type (`cube`, `sphere`, `cylinder`, `cone`, `mesh`).
    pub kind: &'static str,
    pub shape: Shape,
    pub transform: Transform,
    pub material: Material,
    /// Resolved texture image, when the material has one that exists.
    pub texture_file: Option<PathBuf>,
    /// Resolved OBJ file of a mesh.
    pub mesh_file: Option<PathBuf>,
}

/// A scenefile with its group tree walked: everything in world space, in file order.
#[derive(Debug, Clone)]
pub struct Flat {
    pub name: Option<String>,
    pub camera: Camera,
    pub render: RenderSettings,
    pub global: Global,
    pub lights: Vec<FlatLight>,
    pub objects: Vec<FlatObject>,
    /// Things the course's reader accepts silently but a student should hear about
    /// (a texture that cannot be found, a duplicate template name).
    pub warnings: Vec<String>,
}

/// The render settings that reproduce the course's reference images (FORMAT §7, §8):
/// black background, at most 4 bounces, no contribution cutoff (the course has none), and
/// every traced colour clamped to [0, 1] before its parent uses it.
pub fn course_settings() -> RenderSettings {
    RenderSettings {
        max_depth: COURSE_MAX_DEPTH,
        min_contribution: 0.0,
        background: DVec3::ZERO,
        clamp_each_ray: true,
        // Refraction the course's way (FORMAT §8): two bends, no inner shading, no TIR.
        course_refraction: true,
        ..RenderSettings::default()
    }
}

/// Reads and parses a file as JSON (for `rtlab convert` and `validate`'s warnings).
pub fn read(path: &Path) -> Result<Value> {
    let text = super::read_scene_text(path)?;
    super::json::parse(path, &text)
}

/// Loads a parsed CS1230 scenefile into a [`Scene`] (called by [`Scene::load`]).
pub fn load(path: &Path, value: &Value) -> Result<Scene> {
    flatten(path, value)?.into_scene(path)
}

/// [`load`] with the scenefile's warnings.
pub fn load_reporting(path: &Path, value: &Value) -> Result<(Scene, Vec<String>)> {
    let mut flat = flatten(path, value)?;
    let warnings = std::mem::take(&mut flat.warnings);
    Ok((flat.into_scene(path)?, warnings))
}

/// Walks a parsed scenefile into a [`Flat`] list of world-space lights and primitives.
pub fn flatten(path: &Path, value: &Value) -> Result<Flat> {
    let root = Node {
        v: value,
        path: "",
        file: path,
    };
    let top = root.object(TOP)?;
    top.check_keys()?;
    let name = top.opt("name", |n| n.str().map(String::from))?;
    let global = top.req("globalData", |n| global(&n))?;
    let camera = top.req("cameraData", |n| camera(&n))?;

    // File paths are resolved against the PARENT of the scene file's folder: the course's
    // reader does `basepath = parent_path().parent_path()` (FORMAT §6).
    let dir = path.parent().unwrap_or(Path::new(""));
    let base = dir.join("..");
    let mut ctx = group::Ctx::new(path, base);
    if let Some(Value::Array(ts)) = value.get("templateGroups") {
        ctx.all_names = ts
            .iter()
            .enumerate()
            .filter_map(|(i, t)| {
                Some((
                    t.get("name")?.as_str()?.to_string(),
                    format!("templateGroups[{i}]"),
                ))
            })
            .collect();
    }
    // templateGroups is read before groups, whatever their order in the file (FORMAT §1).
    top.each("templateGroups", |n, _| ctx.template(&n))?;
    let roots = top.each("groups", |n, _| ctx.child(&n))?;
    ctx.check_size(&roots)?;
    let (lights, objects) = ctx.instantiate(&roots)?;
    Ok(Flat {
        name,
        camera,
        render: course_settings(),
        global,
        lights,
        objects,
        warnings: ctx.warnings,
    })
}

impl Flat {
    /// Builds the validated scene. Material 0 is the unused default, as in the native loader.
    pub fn into_scene(self, path: &Path) -> Result<Scene> {
        let mut materials = vec![Material::default()];
        let mut objects = Vec::with_capacity(self.objects.len());
        for o in self.objects {
            let bounds = super::world_bounds(&o.shape, &o.transform);
            materials.push(o.material);
            objects.push(Object {
                name: o.name,
                shape: o.shape,
                transform: o.transform,
                material: materials.len() - 1,
                bounds,
            });
        }
        Ok(Scene {
            path: path.to_path_buf(),
            format: SceneFormat::Cs1230,
            camera: self.camera,
            render: self.render,
            global: self.global,
            // Ambient is ka·Oa, not multiplied by any light colour (FORMAT §7).
            ambient_light: DVec3::ONE,
            lights: self.lights.iter().map(FlatLight::to_light).collect(),
            materials,
            objects,
            accel: Accel::default(),
        })
    }
}

/// The warnings of a scenefile (empty for a native scene or one that fails to load).
pub fn warnings(path: &Path) -> Vec<String> {
    read(path)
        .ok()
        .filter(super::is_cs1230)
        .and_then(|v| flatten(path, &v).ok())
        .map(|f| f.warnings)
        .unwrap_or_default()
}

fn global(n: &Node) -> Result<Global> {
    let o = n.object(GLOBAL)?;
    o.check_keys()?;
    Ok(Global {
        ka: o.req("ambientCoeff", |n| n.non_negative())?,
        kd: o.req("diffuseCoeff", |n| n.non_negative())?,
        ks: o.req("specularCoeff", |n| n.non_negative())?,
        // Refraction is extra credit: kt is optional and 0 when absent (FORMAT §2).
        kt: o.or("transparentCoeff", 0.0, |n| n.non_negative())?,
    })
}

fn camera(n: &Node) -> Result<Camera> {
    let o = n.object(CAMERA)?;
    o.check_keys()?;
    let position = o.req("position", |n| n.vec3())?;
    let up = o.req("up", |n| n.vec3())?;
    let height_angle = o.req("heightAngle", |n| n.f64())?;
    // `look` is a direction, `focus` a point (look = focus − position); exactly one of them.
    let look =
        match (o.has("look"), o.has("focus")) {
            (true, true) => {
                return Err(n.err(
                    "the camera has both \"look\" (a direction) and \"focus\" (a point): keep one",
                ))
            }
            (false, false) => return Err(n.err(
                "the camera needs \"look\" (a view direction) or \"focus\" (a point to look at)",
            )),
            (true, false) => o.req("look", |n| n.vec3())?,
            (false, true) => o.req("focus", |n| n.vec3())? - position,
        };
    // Built through the look-at point so that the native equivalent written by
    // `rtlab convert` (which stores `look_at`) gives a bit-identical camera.
    let mut cam = Camera::new(
        position,
        position + look,
        up,
        height_angle,
        DEFAULT_WIDTH,
        DEFAULT_HEIGHT,
    )
    .map_err(|m| n.err(m))?;
    // Depth of field is extra credit and its lens model is not documented (FORMAT §3, U).
    // Chosen reading: `aperture` is the lens diameter and `focalLength` the distance to the
    // plane in focus, rtlab's thin lens; without `focalLength` the focus is |look|.
    cam.aperture = o.or("aperture", 0.0, |n| n.non_negative())?;
    if let Some(f) = o.opt("focalLength", |n| n.positive())? {
        cam.focal_distance = f;
    }
    Ok(cam)
}

/// `a · b` for the group transforms, spelled out where the order matters.
fn compose(parts: &[DMat4]) -> DMat4 {
    parts.iter().fold(DMat4::IDENTITY, |m, p| m * *p)
}
