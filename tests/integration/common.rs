//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A path under the repository root.
pub fn path(rel: &str) -> PathBuf {
    root().join(rel)
}

/// Runs the rtlab binary with arguments.
pub fn rtlab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rtlab"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("rtlab runs")
}

/// Runs the rtlab binary with arguments, its SIMD level capped by `RTLAB_SIMD=level`.
pub fn rtlab_simd(level: &str, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rtlab"))
        .args(args)
        .current_dir(root())
        .env("RTLAB_SIMD", level)
        .output()
        .expect("rtlab runs")
}

/// Every sampler, with a sample count it takes (the corners sampler's 5: the centre and the
/// four corners).
pub const EVERY_SAMPLER: [(rtlab::scene::SamplerKind, u32); 6] = {
    use rtlab::scene::SamplerKind::*;
    [
        (Center, 1),
        (Grid, 4),
        (Corners, 5),
        (Jittered, 4),
        (Random, 3),
        (Adaptive, 16),
    ]
};

/// Loads a scene from the repository.
pub fn scene(rel: &str) -> rtlab::scene::Scene {
    rtlab::scene::Scene::load(&path(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

/// Every scene file in `scenes/`.
pub fn all_scenes() -> Vec<PathBuf> {
    json_files("scenes")
}

/// The `.json` files directly in the folder `rel` (relative to the crate), sorted.
pub fn json_files(rel: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(path(rel))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    v.sort();
    v
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rtlab-test-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// Writes a file under a fresh temporary folder and returns its path. Written under a name
/// of its own and renamed into place, so that two tests writing the same file in parallel
/// (the same scene, say) never let either read it half-written or truncated.
pub fn write_tmp(name: &str, text: &str) -> PathBuf {
    static WRITES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let p = tmp(name);
    if let Some(d) = p.parent() {
        std::fs::create_dir_all(d).unwrap();
    }
    let n = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let part = p.with_file_name(format!(".{n}.part"));
    std::fs::write(&part, text).unwrap();
    std::fs::rename(&part, &p).unwrap();
    p
}

pub fn exists(p: &Path) -> bool {
    p.exists()
}

/// A pinned pixel: scene, pixel, and what it teaches.
pub struct Case {
    pub name: &'static str,
    pub scene: &'static str,
    pub pixel: (u32, u32),
    /// A smaller max_depth than the scene's, to keep the snapshot readable.
    pub depth: Option<u32>,
    pub teaches: &'static str,
}

/// Explains the case's pixel in `scene` and pins the rounded JSON as a YAML snapshot named
/// `name` in `dir`, described by what the case teaches; `info` says where it comes from.
pub fn snapshot_explained(
    c: &Case,
    mut scene: rtlab::scene::Scene,
    dir: &str,
    name: &str,
    info: impl FnOnce(&rtlab::scene::Scene) -> serde_json::Value,
) {
    if let Some(d) = c.depth {
        scene.render.max_depth = d;
    }
    let e = rtlab::cli::explain::explain(&scene, c.pixel.0, c.pixel.1);
    let v = rtlab::cli::explain::rounded(&serde_json::to_value(&e).unwrap());
    let mut settings = insta::Settings::clone_current();
    settings.set_snapshot_path(dir);
    settings.set_prepend_module_to_snapshot(false);
    settings.set_description(c.teaches);
    settings.set_info(&info(&scene));
    settings.bind(|| insta::assert_yaml_snapshot!(name, v));
}

/// Chapter 13's culled bundle for `rtlab intersect box`: six rays passing beside the box.
pub const BOOK_CULLED: &[&str] = &[
    "--origin",
    "0,0,-5",
    "--dir",
    "0.3,0.05,1",
    "--bundle-to",
    "0.6,0.05,1",
    "--rays",
    "6",
];

/// Chapter 13's kept bundle for `rtlab intersect box`: sixteen rays, eight of which enter.
pub const BOOK_KEPT: &[&str] = &[
    "--origin",
    "0,0,-5",
    "--dir",
    "0.1,0.05,1",
    "--bundle-to",
    "0.4,0.05,1",
];

/// Each text a figure draws, in order: (text, where, size, anchor), for tests that measure
/// where labels went.
pub fn drawn_texts(c: &rtlab::viz::Canvas) -> Vec<(String, [f32; 2], f32, rtlab::viz::Anchor)> {
    c.display
        .iter()
        .filter_map(|p| match p {
            rtlab::viz::Prim::Text {
                at,
                text,
                size,
                anchor,
                ..
            } => Some((text.clone(), *at, *size, *anchor)),
            _ => None,
        })
        .collect()
}
