//! One integration test binary, organised by feature (the tiny-skia layout).

mod common;
mod render;
