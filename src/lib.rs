//! # rtlab — a ray-tracing lab that shows its work
//!
//! The modules follow the pipeline of the lecture, in order:
//!
//! | stage | module |
//! |---|---|
//! | scene files → validated scene | [`scene`] (native JSON, CS1230 import, OBJ meshes) |
//! | pixel sample → film plane → world ray | [`camera`] |
//! | ray–shape intersection in object space | [`shapes`] (+ [`math`] for rays and transforms) |
//! | closest object along a ray | [`accel`] (the "for every object" loop, and a BVH) |
//! | the lighting equation, Snell's law | [`shading`] |
//! | the Whitted recursion, observed by recorders | [`trace`] |
//! | samplers, filters, film, encoding | [`sampling`] |
//! | reports (explain, intersect) | [`report`] |
//! | figures | [`viz`] |
//! | the lab in a browser (HTTP server and page) | [`server`] |
//! | subcommands | [`cli`] |
//!
//! One tracer, observed: [`trace::Tracer`] is generic over a [`trace::Recorder`]. `render`
//! passes a zero-sized no-op recorder; `explain`, `--stats` and the figures pass recorders that
//! keep what they need. There is no second copy of any intersection or shading formula.

#![deny(unsafe_code)]

pub mod accel;
pub mod camera;
pub mod cli;
pub mod diff;
pub mod error;
pub mod input;
pub mod interrupt;
pub mod lessons;
pub mod math;
pub mod mistakes;
pub mod output;
pub mod report;
pub mod sampling;
pub mod scene;
pub mod server;
pub mod shading;
pub mod shapes;
pub mod trace;
pub mod viz;

pub use error::{Error, Result};
