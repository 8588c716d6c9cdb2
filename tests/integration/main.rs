//! One integration test binary, organised by feature (the tiny-skia layout).

mod book;
mod common;
mod errors;
mod explain;
mod props;
mod render;
mod robust;
mod shading;
mod shapes;
