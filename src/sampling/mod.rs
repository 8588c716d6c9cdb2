//! Where samples go in a pixel, how they are weighted back into pixels, and the film.

pub mod aov;
pub mod bundles;
mod film;
mod filter;
pub mod progressive;
mod sampler;

pub use film::{check_memory, memory_needed, row_major_order, tiles, Tile, MEMORY_BUDGET, TILE};
pub use film::{
    encode, encode_as, reconstruct as render_reconstruct, render, render_cancellable, render_until,
    Image, RenderOutput, RenderStats,
};
pub use filter::Filter;
pub use sampler::{
    pixel_samples, planned_films, sample_pixel, traces_samples, validate_spp, PixelSample,
};
