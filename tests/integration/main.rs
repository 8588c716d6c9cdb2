//! One integration test binary, organised by feature (the tiny-skia layout).

mod accel;
mod book;
mod course;
mod bundle;
mod browser;
mod common;
mod cs1230;
mod csg;
mod errors;
mod explain;
mod intersect;
mod progressive;
mod limits;
mod mistakes;
mod props;
mod render;
mod robust;
mod sampling;
mod serve;
mod shading;
mod shapes;
mod steps;
