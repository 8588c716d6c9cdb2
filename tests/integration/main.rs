//! One integration test binary, organised by feature (the tiny-skia layout).

mod accel;
mod book;
mod common;
mod cs1230;
mod csg;
mod diff;
mod errors;
mod explain;
mod intersect;
mod mistakes;
mod props;
mod render;
mod robust;
mod sampling;
mod shading;
mod shapes;
mod steps;
