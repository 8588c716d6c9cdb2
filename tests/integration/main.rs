//! One integration test binary, organised by feature (the tiny-skia layout).

mod book;
mod common;
mod cs1230;
mod explain;
mod render;
mod sampling;
mod shading;
mod shapes;
