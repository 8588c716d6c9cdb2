//! Materials, lights, textures and the lighting equation, term by term.

mod light;
mod lighting;
mod material;
pub mod optics;
mod texture;

pub use light::{Light, LightKind, LightSample};
pub use lighting::{LightTerm, Shading};
pub use material::Material;
pub use texture::{Texture, TextureFilter, TextureSource};
