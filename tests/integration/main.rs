//! One integration test binary, organised by feature (the tiny-skia layout).

mod accel;
mod beam_figure;
mod book;
mod browser;
mod bundle;
mod bundle_diagram;
mod common;
mod course;
mod cs1230;
mod csg;
mod diff;
mod errors;
mod explain;
mod intersect;
mod interval_figure;
mod limits;
mod mistakes;
mod progressive;
mod props;
mod render;
mod robust;
mod sampling;
mod serve;
mod shading;
mod shapes;
mod steps;
