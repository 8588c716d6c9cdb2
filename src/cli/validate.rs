//! `rtlab validate`: load a scene and say whether it is valid.

use crate::error::Result;
use crate::scene::SceneFormat;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene file (or course .ini) to check.
    pub scene: PathBuf,
    /// Check it under a course stage (an ini's folder names one by default).
    #[arg(long, value_name = "intersect|illuminate")]
    pub course_stage: Option<String>,
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    let args_render = super::RenderArgs {
        course_stage: args.course_stage.clone(),
        ..super::RenderArgs::default()
    };
    let loaded = args_render.load_full(&args.scene)?;
    let scene = &loaded.scene;
    let format = match scene.format {
        SceneFormat::Native => "rtlab scene",
        SceneFormat::Cs1230 => "CS1230 scenefile",
    };
    let from = if scene.path != args.scene {
        format!(" {}", scene.path.display())
    } else {
        String::new()
    };
    let text = format!(
        "{}: valid {format}{from}: {} object(s), {} light(s), {} material(s), {}×{} pixels",
        args.scene.display(),
        scene.objects.len(),
        scene.lights.len(),
        scene.materials.len() - 1,
        scene.camera.width,
        scene.camera.height
    );
    let mut text = text + "\n";
    if let Some(w) = crate::trace::branching_warning(scene, &scene.render) {
        text += &format!("warning: {w}\n");
    }
    for w in &loaded.warnings {
        text += &format!("warning: {w}\n");
    }
    super::emit(out, &text)
}
