//! One integration test binary, organised by feature (the tiny-skia layout).

mod book;
mod common;
mod csg;
mod explain;
mod render;
mod shading;
mod shapes;
