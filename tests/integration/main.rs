//! One integration test binary, organised by feature (the tiny-skia layout).

mod accel;
mod book;
mod common;
mod cs1230;
mod explain;
mod render;
mod shading;
mod shapes;
