//! The figure palette: one colour per kind of ray and per role, used by every figure so a
//! student learns them once.

use crate::trace::RayKind;
use tiny_skia::Color;

pub fn rgb(r: u8, g: u8, b: u8) -> Color {
    Color::from_rgba8(r, g, b, 255)
}

pub fn rgba(r: u8, g: u8, b: u8, a: u8) -> Color {
    Color::from_rgba8(r, g, b, a)
}

pub fn background() -> Color {
    rgb(255, 255, 255)
}
pub fn ink() -> Color {
    rgb(30, 30, 36)
}
pub fn muted() -> Color {
    rgb(150, 150, 158)
}
pub fn grid() -> Color {
    rgb(228, 228, 234)
}
/// A kept candidate / the winning hit.
pub fn hit() -> Color {
    rgb(214, 39, 40)
}
/// A tossed candidate.
pub fn tossed() -> Color {
    rgb(160, 160, 168)
}
pub fn shape_fill() -> Color {
    rgba(90, 140, 200, 46)
}
pub fn shape_stroke() -> Color {
    rgb(40, 90, 160)
}
/// Surface normals (not green: green is the reflection ray).
pub fn normal() -> Color {
    rgb(140, 86, 75)
}

/// The colour of a ray of each kind.
pub fn ray(kind: RayKind) -> Color {
    match kind {
        RayKind::Camera => rgb(31, 119, 180),
        RayKind::Shadow => rgb(230, 150, 20),
        RayKind::Reflection => rgb(44, 160, 44),
        RayKind::Refraction => rgb(148, 103, 189),
        RayKind::Transmission => rgb(23, 190, 207),
    }
}
