//! Figures, drawn with tiny-skia and labelled with a font embedded in the binary, so that
//! every machine draws the same pixels. Every figure also keeps a display list (what was
//! drawn, in order, with rounded coordinates) for snapshot tests.

pub mod beam;
pub mod bundle;
pub mod canvas;
pub mod clip;
pub mod compare;
pub mod diff;
pub mod forward;
pub mod heatmap;
pub mod intersect;
pub mod interval;
pub mod labels;
pub mod samples;
mod section;
pub mod slice;
pub mod solids;
pub mod steps;
pub mod style;

pub use canvas::{Anchor, Canvas, Prim};
