//! Where samples go in a pixel, how they are weighted back into pixels, and the film.

pub mod aov;
pub mod bundles;
mod film;
mod filter;
mod image;
mod kept;
pub mod progressive;
mod reconstruct;
mod sampler;
mod tiles;

pub use film::{check_memory, memory_needed, samples_at_most, MEMORY_BUDGET};
pub use film::{
    render, render_counting, render_until, Counting, PixelWork, RenderOutput, RenderStats,
};
pub use filter::Filter;
pub use image::{encode, encode_as, Image};
pub use reconstruct::reconstruct as render_reconstruct;
pub use sampler::{
    filter_samples, most_samples, pixel_samples, planned_films, sample_pixel, samples_kept,
    traces_samples, validate_spp, PixelSample,
};
pub use tiles::{row_major_order, tile_of, tiles, Tile, TILE};
