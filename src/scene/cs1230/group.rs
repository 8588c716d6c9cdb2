//! The group tree: transforms in the format's fixed order, nested groups, template groups
//! (shared subtrees referenced by name), and the walk that instantiates it all in world space.

use super::primitive::{self, LightDef, Prim};
use super::{bytes_per_primitive, compose, max_expanded, FlatLight, FlatObject, MAX_SCENE_BYTES};
use crate::error::{suggest, Error, Result};
use crate::math::Transform;
use crate::scene::json::Node;
use crate::shading::TextureSource;
use crate::shapes::Mesh;
use glam::{DMat4, DVec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

const GROUP: &[&str] = &[
    "name",
    "translate",
    "rotate",
    "scale",
    "matrix",
    "lights",
    "primitives",
    "groups",
];

/// A parsed group: its own transform and contents, not yet placed in the world.
pub struct Group {
    /// JSON path of the group, for errors.
    path: String,
    /// T · R · S · M of this group.
    local: DMat4,
    lights: Vec<LightDef>,
    prims: Vec<Prim>,
    children: Vec<Child>,
    /// Primitives and lights once every template inside is expanded (saturating).
    count: u64,
}

/// An entry of a `groups` array: a group of its own, or a reference to a template.
pub enum Child {
    Inline(Group),
    Template {
        index: usize,
        name: String,
        /// JSON path of the referencing entry.
        path: String,
    },
}

/// What the parser keeps while it reads: templates registered so far, caches, warnings.
pub struct Ctx<'a> {
    pub file: &'a Path,
    pub base: PathBuf,
    templates: Vec<Option<Group>>,
    by_name: HashMap<String, usize>,
    /// Templates whose definition is being read (a reference to one of them is a cycle).
    parsing: Vec<usize>,
    /// Every name in `templateGroups` with its path, for "defined later" and "did you
    /// mean" errors.
    pub all_names: Vec<(String, String)>,
    pub textures: HashMap<PathBuf, TextureSource>,
    pub meshes: HashMap<PathBuf, Arc<Mesh>>,
    pub warnings: Vec<String>,
    /// Missing texture paths already reported (one warning per path, not per primitive).
    pub reported: std::collections::HashSet<PathBuf>,
}

impl<'a> Ctx<'a> {
    pub fn new(file: &'a Path, base: PathBuf) -> Ctx<'a> {
        Ctx {
            file,
            base,
            templates: Vec::new(),
            by_name: HashMap::new(),
            parsing: Vec::new(),
            all_names: Vec::new(),
            textures: HashMap::new(),
            meshes: HashMap::new(),
            warnings: Vec::new(),
            reported: Default::default(),
        }
    }

    /// Reads one entry of `templateGroups`. The course's reader registers a template under
    /// its name before reading its contents, so a template may use itself (a cycle, refused
    /// here) or any template listed before it; a name used twice: the later one wins.
    pub fn template(&mut self, n: &Node) -> Result<()> {
        let o = n.object(GROUP)?;
        let name = o
            .req("name", |n| n.str().map(String::from))
            .map_err(|_| n.err("a template group needs a \"name\" (a string) to be used by"))?;
        let index = self.templates.len();
        if self.by_name.contains_key(&name) {
            self.warnings.push(format!(
                "{}: {}: a second template named \"{name}\": the later one wins (as in the course's reader)",
                self.file.display(),
                n.path
            ));
        }
        self.templates.push(None);
        self.by_name.insert(name, index);
        self.parsing.push(index);
        let g = self.group(n);
        self.parsing.pop();
        self.templates[index] = Some(g?);
        Ok(())
    }

    /// Reads one entry of a `groups` array: a template reference when its `name` is a
    /// registered template (every other key of the entry is then ignored, as the course's
    /// reader does), otherwise a group of its own.
    pub fn child(&mut self, n: &Node) -> Result<Child> {
        if let Some(name) = n.v.get("name").and_then(|v| v.as_str()) {
            if let Some(&index) = self.by_name.get(name) {
                if self.parsing.contains(&index) {
                    return Err(n.err(format!(
                        "template \"{name}\" is used inside its own definition: the group tree would never end"
                    )));
                }
                return Ok(Child::Template {
                    index,
                    name: name.to_string(),
                    path: n.path.to_string(),
                });
            }
            // An entry with nothing but a name is meant as a template reference. The course's
            // reader would quietly draw nothing for it; say why instead (only in files that
            // use templates, where such an entry can only be a slip).
            let only_name = n.v.as_object().is_some_and(|m| m.len() == 1);
            if only_name && !self.all_names.is_empty() {
                if let Some((_, at)) = self.all_names.iter().find(|(t, _)| t == name) {
                    return Err(n.err(format!(
                        "template \"{name}\" is used before it is defined (at {at}): a template can only use templates listed before it"
                    )));
                }
                let names: Vec<&str> = self.all_names.iter().map(|(t, _)| t.as_str()).collect();
                let hint = suggest(name, &names)
                    .map(|s| format!(" (did you mean \"{s}\"?)"))
                    .unwrap_or_else(|| format!(" (templates: {})", names.join(", ")));
                return Err(n.err(format!("no template named \"{name}\"{hint}")));
            }
        }
        Ok(Child::Inline(self.group(n)?))
    }

    fn group(&mut self, n: &Node) -> Result<Group> {
        let o = n.object(GROUP)?;
        o.check_keys()?;
        o.opt("name", |n| n.str().map(|_| ()))?;
        let local = local_transform(&o)?;
        let lights = o.each("lights", |n, _| primitive::light(&n))?;
        let prims = o.each("primitives", |n, _| primitive::parse(self, &n))?;
        let children = o.each("groups", |n, _| self.child(&n))?;
        let count = (prims.len() as u64 + lights.len() as u64).saturating_add(self.sum(&children));
        Ok(Group {
            path: n.path.to_string(),
            local,
            lights,
            prims,
            children,
            count,
        })
    }

    fn count_of(&self, c: &Child) -> u64 {
        match c {
            Child::Inline(g) => g.count,
            Child::Template { index, .. } => self.templates[*index].as_ref().map_or(0, |g| g.count),
        }
    }

    fn sum(&self, children: &[Child]) -> u64 {
        children
            .iter()
            .fold(0u64, |s, c| s.saturating_add(self.count_of(c)))
    }

    /// Refuses a scene that expands to more primitives and lights than fit in
    /// [`MAX_SCENE_BYTES`], naming the deepest group that alone is too large, and the template
    /// chain to it.
    pub fn check_size(&self, roots: &[Child]) -> Result<()> {
        let total = self.sum(roots);
        let max = max_expanded();
        if total <= max {
            return Ok(());
        }
        let mut at = "groups".to_string();
        let mut chain: Vec<String> = Vec::new();
        let mut children = roots;
        let mut count = total;
        while let Some(c) = children.iter().find(|c| self.count_of(c) > max) {
            count = self.count_of(c);
            match c {
                Child::Inline(g) => {
                    at = g.path.clone();
                    children = &g.children;
                }
                Child::Template { index, name, path } => {
                    at = path.clone();
                    chain.push(format!("{path} uses template \"{name}\""));
                    children = &self.templates[*index].as_ref().expect("parsed").children;
                }
            }
        }
        let via = if chain.is_empty() {
            String::new()
        } else {
            format!(" ({})", chain.join(", "))
        };
        Err(Error::input(
            self.file,
            at,
            format!(
                "expands to {} primitives and lights, which would need about {} GiB (about {} bytes each); the limit is {:.1} GiB, about {max} primitives: nested template references multiply{via}",
                if count == u64::MAX { "more than 2^64".to_string() } else { count.to_string() },
                if count == u64::MAX {
                    "more than 2^64".to_string()
                } else {
                    format!("{:.1}", count as f64 * bytes_per_primitive() as f64 / (1u64 << 30) as f64)
                },
                bytes_per_primitive(),
                MAX_SCENE_BYTES as f64 / (1u64 << 30) as f64,
            ),
        ))
    }

    /// Walks the tree from the roots: CTM_child = CTM_parent · T · R · S · M (FORMAT §4).
    pub fn instantiate(&self, roots: &[Child]) -> Result<(Vec<FlatLight>, Vec<FlatObject>)> {
        let mut lights = Vec::new();
        let mut objects = Vec::new();
        for c in roots {
            self.walk_child(c, DMat4::IDENTITY, &mut lights, &mut objects)?;
        }
        Ok((lights, objects))
    }

    fn walk_child(
        &self,
        c: &Child,
        ctm: DMat4,
        lights: &mut Vec<FlatLight>,
        objects: &mut Vec<FlatObject>,
    ) -> Result<()> {
        match c {
            Child::Inline(g) => self.walk(g, ctm, lights, objects),
            Child::Template { index, .. } => {
                let g = self.templates[*index].as_ref().expect("parsed before use");
                self.walk(g, ctm, lights, objects)
            }
        }
    }

    fn walk(
        &self,
        g: &Group,
        parent: DMat4,
        lights: &mut Vec<FlatLight>,
        objects: &mut Vec<FlatObject>,
    ) -> Result<()> {
        let ctm = parent * g.local;
        // Lights inside a template are placed once per reference (FORMAT §5, U: no reference
        // scene has one): it is what walking the tree gives.
        for l in &g.lights {
            lights.push(l.place(ctm, lights.len(), self.file)?);
        }
        for p in &g.prims {
            let world = ctm * p.object_offset;
            let transform = Transform::new(world).ok_or_else(|| {
                Error::input(
                    self.file,
                    p.path.clone(),
                    "this primitive's transform (its groups' translate/rotate/scale/matrix combined) is singular: it flattens the shape to nothing",
                )
            })?;
            let index = objects.len();
            let name = p
                .name
                .clone()
                .unwrap_or_else(|| format!("{}#{index}", p.kind));
            let mut material = p.material.clone();
            material.name = name.clone();
            objects.push(FlatObject {
                name,
                kind: p.kind,
                shape: p.shape.clone(),
                transform,
                material,
                texture_file: p.texture_file.clone(),
                mesh_file: p.mesh_file.clone(),
            });
        }
        for c in &g.children {
            self.walk_child(c, ctm, lights, objects)?;
        }
        Ok(())
    }
}

/// A group's own transform, T · R · S · M: the course's reader stores them in this fixed
/// order whatever the key order in the file, and right-multiplies them (FORMAT §4).
fn local_transform(o: &crate::scene::json::Obj) -> Result<DMat4> {
    let t = o.or("translate", DVec3::ZERO, |n| n.vec3())?;
    let r = o.opt("rotate", |n| {
        let v = n
            .numbers(4)
            .map_err(|_| n.err("rotate is [axis x, axis y, axis z, angle in degrees]"))?;
        let axis = DVec3::new(v[0], v[1], v[2]);
        // The axis is normalised by the rotation routine (glm::rotate); right-hand rule.
        let axis = axis
            .try_normalize()
            .ok_or_else(|| n.err("the rotation axis must not be the zero vector"))?;
        Ok(DMat4::from_axis_angle(axis, v[3].to_radians()))
    })?;
    let s = o.opt("scale", |n| {
        let s = n.vec3()?;
        if s.x == 0.0 || s.y == 0.0 || s.z == 0.0 {
            return Err(n.err("a scale of 0 flattens everything in the group to nothing"));
        }
        Ok(DMat4::from_scale(s))
    })?;
    let m = o.opt("matrix", |n| matrix(&n))?;
    let parts: Vec<DMat4> = [Some(DMat4::from_translation(t)), r, s, m]
        .into_iter()
        .flatten()
        .collect();
    Ok(compose(&parts))
}

/// `matrix`: 4 rows of 4 numbers, in ordinary (row-major) layout: translation is the last
/// column, and the last row must be 0 0 0 1 (an affine map; a projective one cannot place
/// an object).
fn matrix(n: &Node) -> Result<DMat4> {
    let m = crate::scene::native::matrix(n)?;
    let last = m.row(3);
    if last != glam::DVec4::W {
        return Err(Error::input(
            n.file,
            format!("{}[3]", n.path),
            format!(
                "the last row of a matrix must be [0, 0, 0, 1] (an affine transform), found [{}, {}, {}, {}]",
                last.x, last.y, last.z, last.w
            ),
        ));
    }
    if !crate::math::invertible(&m) {
        return Err(n.err(
            "the matrix is singular or nearly so (an axis of it zero, under 10^-12 of the longest, or in the plane of the other two): it flattens everything in the group to nothing",
        ));
    }
    Ok(m)
}
