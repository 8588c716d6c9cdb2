//! Where samples go in a pixel, how they are weighted back into pixels, and the film.

pub mod aov;
mod film;
mod filter;
mod sampler;

pub use film::{check_memory, memory_needed, row_major_order, tiles, Tile, MEMORY_BUDGET, TILE};
pub use film::{
    encode, reconstruct as render_reconstruct, render, render_cancellable, Image, RenderOutput, RenderStats,
};
pub use filter::Filter;
pub use sampler::{pixel_samples, sample_pixel, traces_samples, validate_spp, PixelSample};
