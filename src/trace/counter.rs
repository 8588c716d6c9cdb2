use super::{RayKind, Recorder};
use crate::math::Ray;
use crate::shapes::Observer;
use serde::Serialize;

/// Rays traced, by kind (DESIGN §3 `--stats`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct RayCounts {
    pub camera: u64,
    pub shadow: u64,
    pub reflection: u64,
    pub refraction: u64,
    pub total: u64,
}

impl RayCounts {
    pub fn add(&mut self, o: &RayCounts) {
        self.camera += o.camera;
        self.shadow += o.shadow;
        self.reflection += o.reflection;
        self.refraction += o.refraction;
        self.total += o.total;
    }
}

/// Counts rays, intersection tests and BVH nodes: the numbers behind `--stats` and the
/// `cost` AOV, taken from the tracer itself rather than from hand-placed counters.
#[derive(Debug, Clone, Copy, Default)]
pub struct Counter {
    pub rays: RayCounts,
    /// Objects tested, plus the faces a mesh tested inside.
    pub tests: u64,
    /// BVH nodes visited: the scene's and the meshes' own.
    pub nodes: u64,
    obs: CountObserver,
}

/// Counts what a shape's own acceleration did (a mesh's faces and nodes); sees no working.
#[derive(Debug, Clone, Copy, Default)]
pub struct CountObserver {
    pub faces: u64,
    pub nodes: u64,
}

impl Observer for CountObserver {
    fn mesh(&mut self, tested: usize, _index: Option<usize>) {
        self.faces += tested as u64;
    }
    fn bvh_nodes(&mut self, n: u32) {
        self.nodes += n as u64;
    }
}

impl Counter {
    /// Intersection tests: objects, and each face a mesh tested.
    pub fn total_tests(&self) -> u64 {
        self.tests + self.obs.faces
    }
    /// BVH nodes visited, the scene's and the meshes'.
    pub fn total_nodes(&self) -> u64 {
        self.nodes + self.obs.nodes
    }
}

impl Recorder for Counter {
    type Obs = CountObserver;
    fn observer(&mut self) -> &mut CountObserver {
        &mut self.obs
    }
    fn begin_ray(&mut self, kind: RayKind, _depth: u32, _ray: &Ray) {
        match kind {
            RayKind::Camera => self.rays.camera += 1,
            RayKind::Shadow => self.rays.shadow += 1,
            RayKind::Reflection => self.rays.reflection += 1,
            RayKind::Refraction | RayKind::Transmission => self.rays.refraction += 1,
        }
        self.rays.total += 1;
    }
    fn tested(&mut self, _o: usize, _t: Option<f64>, _t_max: f64, _r: &Ray) {
        self.tests += 1;
    }
    fn nodes_visited(&mut self, n: u32) {
        self.nodes += n as u64;
    }
    fn bundled(&mut self, tests: u32, nodes: u32) {
        self.tests += tests as u64;
        self.nodes += nodes as u64;
    }
}
