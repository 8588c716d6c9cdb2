//! `rtlab validate`: load a scene and say whether it is valid.

use crate::error::Result;
use crate::scene::{Scene, SceneFormat};
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene file to check.
    pub scene: PathBuf,
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    let scene = Scene::load(&args.scene)?;
    let format = match scene.format {
        SceneFormat::Native => "rtlab scene",
        SceneFormat::Cs1230 => "CS1230 scenefile",
    };
    let text = format!(
        "{}: valid {format}: {} object(s), {} light(s), {} material(s), {}×{} pixels",
        args.scene.display(),
        scene.objects.len(),
        scene.lights.len(),
        scene.materials.len() - 1,
        scene.camera.width,
        scene.camera.height
    );
    let mut text = text + "\n";
    if let Some(w) = crate::trace::branching_warning(&scene, &scene.render) {
        text += &format!("warning: {w}\n");
    }
    if scene.format == SceneFormat::Cs1230 {
        for w in crate::scene::cs1230::warnings(&args.scene) {
            text += &format!("warning: {w}\n");
        }
    }
    super::emit(out, &text)
}
