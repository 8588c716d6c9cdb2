//! The recorder behind `explain`: keeps the whole ray tree of a sample, in the JSON shape of
//! DESIGN §3 (`RAY`). Field names here *are* the contract; add, never rename.

use super::{End, HitInfo, RayKind, Recorder};
use crate::math::Ray;
use crate::scene::Scene;
use crate::shading::LightTerm;
use crate::shapes::{Barycentric, Quadratic, Working};
use glam::DVec3;
use serde::Serialize;

/// One ray of the tree.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RayNode {
    pub kind: RayKind,
    pub depth: u32,
    pub origin: DVec3,
    pub direction: DVec3,
    /// For dispersion: the one colour channel this refraction ray carries.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub channel: Option<&'static str>,
    /// What the parent multiplies this ray's colour by (ks·Or for reflection, kt·Ot for
    /// transmission, masked to one channel for dispersion); absent on camera and shadow rays.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub weight: Option<DVec3>,
    pub tests: Vec<TestNode>,
    /// BVH nodes visited (0 with the linear list).
    pub bvh_nodes: u32,
    pub hit: Option<HitNode>,
    pub shading: Option<ShadingNode>,
    pub color: DVec3,
    pub end: End,
    /// The colour was clamped to [0, 1] before the parent used it (course scenefiles).
    pub clamped: bool,
    pub children: Vec<RayNode>,
}

/// One object's intersection test and its working.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TestNode {
    pub object: String,
    pub shape: &'static str,
    pub t: Option<f64>,
    /// The ray in the object's own space (t is the same parameter there).
    pub object_space: ObjectRay,
    pub quadratic: Option<QuadraticNode>,
    pub candidates: Vec<crate::shapes::working::CandidateRecord>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub barycentric: Option<Barycentric>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub triangles_tested: Option<usize>,
    /// Nodes of the mesh's own BVH the ray visited (meshes only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh_bvh_nodes: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub triangle: Option<usize>,
    /// CSG objects: each child's intervals along the ray and their combination.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub csg: Option<crate::shapes::working::CsgWorking>,
    /// Blobs: the field samples, brackets and refinement steps of the root search.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub blob: Option<crate::shapes::working::BlobWorking>,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ObjectRay {
    pub origin: DVec3,
    pub direction: DVec3,
}

/// A quadratic with the name of the surface it came from (`sphere`, `body`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct QuadraticNode {
    pub surface: &'static str,
    #[serde(flatten)]
    pub q: Quadratic,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HitNode {
    pub object: String,
    pub t: f64,
    pub point: DVec3,
    pub normal: DVec3,
    pub surface: &'static str,
    pub uv: [f64; 2],
    pub object_space: HitObjectSpace,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub barycentric: Option<[f64; 3]>,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HitObjectSpace {
    pub origin: DVec3,
    pub direction: DVec3,
    pub point: DVec3,
    pub normal: DVec3,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShadingNode {
    pub ambient: DVec3,
    pub lights: Vec<LightNode>,
    /// Lights the settings leave out (the Intersect stage's point and spot lights), with the
    /// terms they would have added; not part of `color`. Absent when there are none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub ignored_lights: Vec<LightNode>,
    pub reflected: DVec3,
    pub transmitted: DVec3,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LightNode {
    pub light: String,
    pub visible: bool,
    pub visibility: f64,
    /// Distance to the light; `null` for directional lights.
    pub distance: Option<f64>,
    pub attenuation: f64,
    pub spot: f64,
    pub n_dot_l: f64,
    pub diffuse: DVec3,
    pub r_dot_v: f64,
    pub r_dot_v_pow: f64,
    pub specular: DVec3,
}

/// Builds the ray tree while the tracer runs.
pub struct TreeRecorder<'a> {
    scene: &'a Scene,
    working: Working,
    stack: Vec<RayNode>,
    pending_channel: Option<&'static str>,
    pending_weight: Option<DVec3>,
    /// The finished tree of the camera ray.
    pub root: Option<RayNode>,
}

impl<'a> TreeRecorder<'a> {
    pub fn new(scene: &'a Scene) -> Self {
        TreeRecorder {
            scene,
            working: Working::default(),
            stack: Vec::new(),
            pending_channel: None,
            pending_weight: None,
            root: None,
        }
    }
    fn top(&mut self) -> &mut RayNode {
        self.stack.last_mut().expect("a ray is being traced")
    }

    fn light_node(&self, t: &LightTerm) -> LightNode {
        LightNode {
            light: self.scene.lights[t.light].name.clone(),
            visible: t.visible,
            visibility: t.visibility,
            distance: t.distance.is_finite().then_some(t.distance),
            attenuation: t.attenuation,
            spot: t.spot,
            n_dot_l: t.n_dot_l,
            diffuse: t.diffuse,
            r_dot_v: t.r_dot_v,
            r_dot_v_pow: t.r_dot_v_pow,
            specular: t.specular,
        }
    }

    fn shading(&mut self) -> &mut ShadingNode {
        self.top().shading.get_or_insert_with(|| ShadingNode {
            ambient: DVec3::ZERO,
            lights: Vec::new(),
            ignored_lights: Vec::new(),
            reflected: DVec3::ZERO,
            transmitted: DVec3::ZERO,
        })
    }
}

impl Recorder for TreeRecorder<'_> {
    type Obs = Working;
    const ACTIVE: bool = true;

    fn observer(&mut self) -> &mut Working {
        &mut self.working
    }

    fn begin_ray(&mut self, kind: RayKind, depth: u32, ray: &Ray) {
        let channel = self.pending_channel.take();
        let weight = if kind == RayKind::Shadow {
            None
        } else {
            self.pending_weight.take()
        };
        self.stack.push(RayNode {
            kind,
            depth,
            origin: ray.origin,
            direction: ray.dir,
            channel,
            weight,
            tests: Vec::new(),
            bvh_nodes: 0,
            hit: None,
            shading: None,
            color: DVec3::ZERO,
            end: End::Miss,
            clamped: false,
            children: Vec::new(),
        });
    }

    fn tested(&mut self, object: usize, t: Option<f64>, t_max: f64, local_ray: &Ray) {
        let mut w = std::mem::take(&mut self.working);
        w.conclude(t, t_max);
        let o = &self.scene.objects[object];
        let node = TestNode {
            object: o.name.clone(),
            shape: o.shape.kind(),
            t,
            object_space: ObjectRay {
                origin: local_ray.origin,
                direction: local_ray.dir,
            },
            quadratic: w
                .quadratics
                .first()
                .map(|(s, q)| QuadraticNode { surface: s, q: *q }),
            candidates: w.candidates,
            barycentric: w.barycentric,
            triangles_tested: w.mesh.map(|m| m.0),
            mesh_bvh_nodes: w.bvh_nodes,
            triangle: w.mesh.and_then(|m| m.1),
            csg: w.csg,
            blob: w.blob,
        };
        self.top().tests.push(node);
    }

    fn nodes_visited(&mut self, n: u32) {
        self.top().bvh_nodes += n;
    }

    fn hit(&mut self, hit: &HitInfo) {
        let name = self.scene.objects[hit.object].name.clone();
        self.top().hit = Some(HitNode {
            object: name,
            t: hit.t,
            point: hit.point,
            normal: hit.normal,
            surface: hit.local.surface,
            uv: [hit.local.uv.x, hit.local.uv.y],
            object_space: HitObjectSpace {
                origin: hit.local_ray.origin,
                direction: hit.local_ray.dir,
                point: hit.local.point,
                normal: hit.local.normal,
            },
            barycentric: hit.local.barycentric,
        });
    }

    fn ambient(&mut self, c: DVec3) {
        self.shading().ambient = c;
    }

    fn light(&mut self, t: &LightTerm) {
        let node = self.light_node(t);
        self.shading().lights.push(node);
    }

    fn ignored_light(&mut self, t: &LightTerm) {
        let node = self.light_node(t);
        self.shading().ignored_lights.push(node);
    }

    fn reflected(&mut self, c: DVec3) {
        self.shading().reflected += c;
    }

    fn transmitted(&mut self, c: DVec3) {
        self.shading().transmitted += c;
    }

    fn channel(&mut self, channel: usize) {
        self.pending_channel = Some(["r", "g", "b"][channel]);
    }

    fn weight(&mut self, w: DVec3) {
        self.pending_weight = Some(w);
    }

    fn end_ray(&mut self, color: DVec3, end: End, clamped: bool) {
        let mut node = self.stack.pop().expect("end_ray after begin_ray");
        node.color = color;
        node.end = end;
        node.clamped = clamped;
        match self.stack.last_mut() {
            Some(parent) => parent.children.push(node),
            None => self.root = Some(node),
        }
    }
}
