//! The Whitted recursion, generic over a [`Recorder`]: one tracer, observed.
//!
//! `render` runs it with [`NoRecorder`] (zero-sized, every call compiles away); `explain`
//! with [`TreeRecorder`] (keeps the whole ray tree), `--stats` and the `cost` map with
//! [`Counter`]. There is no second copy of the maths anywhere.

mod budget;
mod counter;
pub mod forward;
mod recorder;
mod tree;
mod whitted;
mod worst_case;

pub use budget::{CHECK_EVERY, DEFAULT_MAX_RAYS};
pub use counter::{CountObserver, Counter, RayCounts};
pub use recorder::{End, HitInfo, NoRecorder, RayKind, Recorder};
pub use tree::{HitNode, LightNode, RayNode, ShadingNode, TestNode, TreeRecorder};
pub use whitted::{
    camera_ray, camera_rays, trace_camera, trace_sample, CameraRay, Found, SampleResult, Tracer,
};
pub use worst_case::{branching_warning, worst_case, WorstCase};
