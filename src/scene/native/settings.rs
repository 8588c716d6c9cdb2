//! The camera and the render settings of a native scene.

use super::{CAMERA, MAX_DEPTH_LIMIT, RENDER};
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::scene::json::Node;
use crate::scene::{check_size, Encoding, FilterKind, RenderSettings, SamplerKind};
use glam::DVec3;

pub(super) fn camera(n: &Node) -> Result<Camera> {
    let o = n.object(CAMERA)?;
    o.check_keys()?;
    let position = o.req("position", |n| n.vec3())?;
    let look_at = o.or("look_at", DVec3::ZERO, |n| n.vec3())?;
    let up = o.or("up", DVec3::Y, |n| n.vec3())?;
    let fov = o.or("fov_y", 45.0, |n| n.f64())?;
    let width = o.or("width", 640, |n| n.u32())?;
    let height = o.or("height", 480, |n| n.u32())?;
    check_size(width, height).map_err(|m| n.err(m))?;
    let mut cam = Camera::new(position, look_at, up, fov, width, height).map_err(|m| n.err(m))?;
    cam.aperture = o.or("aperture", 0.0, |n| n.non_negative())?;
    if let Some(f) = o.opt("focal_distance", |n| n.positive())? {
        cam.focal_distance = f;
    }
    Ok(cam)
}

pub(super) fn render_settings(n: &Node) -> Result<RenderSettings> {
    let o = n.object(RENDER)?;
    o.check_keys()?;
    let d = RenderSettings::default();
    let sampler = o.or("sampler", d.sampler, |n| {
        let s = n.str()?;
        SamplerKind::parse(s).ok_or_else(|| {
            n.err(format!(
                "unknown sampler \"{s}\" (expected one of: {})",
                SamplerKind::NAMES.join(", ")
            ))
        })
    })?;
    let spp = o.or("spp", d.spp, |n| n.u32())?;
    crate::sampling::validate_spp(sampler, spp)
        .map_err(|m| Error::input(n.file, o.child_path("spp"), m))?;
    Ok(RenderSettings {
        spp,
        sampler,
        filter: o.or("filter", d.filter, |n| {
            let s = n.str()?;
            FilterKind::parse(s).ok_or_else(|| {
                n.err(format!(
                    "unknown filter \"{s}\" (expected one of: {})",
                    FilterKind::NAMES.join(", ")
                ))
            })
        })?,
        max_depth: o.or("max_depth", d.max_depth, |n| {
            let v = n.u32()?;
            if v > MAX_DEPTH_LIMIT {
                return Err(n.err(format!(
                    "max_depth {v} is too deep (at most {MAX_DEPTH_LIMIT})"
                )));
            }
            Ok(v)
        })?,
        min_contribution: o.or("min_contribution", d.min_contribution, |n| n.non_negative())?,
        background: o.or("background", d.background, |n| n.color())?,
        seed: o.or("seed", 0, |n| n.u32().map(|s| s as u64))?,
        encoding: o.or("encoding", d.encoding, |n| match n.str()? {
            "clamp" => Ok(Encoding::Clamp),
            "srgb" => Ok(Encoding::Srgb),
            s => Err(n.err(format!("unknown encoding \"{s}\" (expected clamp or srgb)"))),
        })?,
        clamp_each_ray: o.or("clamp_each_ray", d.clamp_each_ray, |n| n.bool())?,
        max_rays: o.or("max_rays", d.max_rays, |n| match n.u32()? {
            0 => Err(n.err(
                "max_rays must be at least 1 (the camera ray): it is the most rays one sample may trace",
            )),
            v => Ok(v as u64),
        })?,
        texture_filter: o.or("texture_filter", d.texture_filter, |n| {
            let s = n.str()?;
            crate::shading::TextureFilter::parse(s).ok_or_else(|| {
                n.err(format!(
                    "unknown texture filter \"{s}\" (expected nearest or bilinear)"
                ))
            })
        })?,
        course_refraction: o.or("course_refraction", d.course_refraction, |n| n.bool())?,
        ..d
    })
}
