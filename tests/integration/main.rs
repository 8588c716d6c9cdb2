//! One integration test binary, organised by feature (the tiny-skia layout).

mod book;
mod common;
mod cs1230;
mod csg;
mod explain;
mod intersect;
mod render;
mod shading;
mod shapes;
mod steps;
