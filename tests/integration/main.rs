//! One integration test binary, organised by feature (the tiny-skia layout).

mod common;
mod explain;
mod render;
mod shading;
mod shapes;
