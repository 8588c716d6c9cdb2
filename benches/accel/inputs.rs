//! What the bench reads: the shared meshes, the 1M-triangle terrain, Embree's harness.

use rtlab::scene::Scene;
use std::path::{Path, PathBuf};
use std::process::Command;

pub fn shared_meshes() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("RTLAB_MESHES") {
        return Some(PathBuf::from(p));
    }
    let here = Path::new(env!("CARGO_MANIFEST_DIR"));
    [
        here.join("../shared/meshes"),
        here.join("../../shared/meshes"),
        PathBuf::from("/work/shared/meshes"),
    ]
    .into_iter()
    .find(|p| p.join("bunny_56k.obj").exists())
}

pub fn meshes() -> Vec<(String, Option<PathBuf>)> {
    let dir = shared_meshes();
    let mut out: Vec<(String, Option<PathBuf>)> =
        ["teapot", "bunny", "bunny_56k", "samurai_monastry"]
            .iter()
            .map(|n| {
                let p = dir.as_ref().map(|d| d.join(format!("{n}.obj")));
                (n.to_string(), p.filter(|p| p.exists()))
            })
            .collect();
    out.push(("terrain_1m".into(), terrain(dir.as_deref())));
    out
}

pub fn terrain(dir: Option<&Path>) -> Option<PathBuf> {
    let path = PathBuf::from(
        std::env::var("RTLAB_TERRAIN").unwrap_or_else(|_| "/tmp/terrain_1m.obj".into()),
    );
    if path.exists() {
        return Some(path);
    }
    let tool = dir?.join("tools/gen_mesh.py");
    println!(
        "generating the 1M-triangle terrain: python3 {} terrain --tris 1000000 -o {}",
        tool.display(),
        path.display()
    );
    let ok = Command::new("python3")
        .arg(&tool)
        .args(["terrain", "--tris", "1000000", "-o"])
        .arg(&path)
        .status()
        .map(|s| s.success())
        .unwrap_or(false);
    ok.then_some(path)
}

/// The harness binary: $EMBREE_BENCH, or built into the target folder by its build.sh.
pub fn locate_embree() -> Option<PathBuf> {
    if let Ok(p) = std::env::var("EMBREE_BENCH") {
        return Some(PathBuf::from(p)).filter(|p| p.exists());
    }
    let target = std::env::var("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| Path::new(env!("CARGO_MANIFEST_DIR")).join("target"));
    let out = target.join("embree");
    let bin = out.join("embree_bench");
    if bin.exists() {
        return Some(bin);
    }
    let script = shared_meshes()?.join("../bench/embree/build.sh");
    if !script.exists() {
        println!(
            "Embree: no harness at {} (set EMBREE_BENCH)",
            script.display()
        );
        return None;
    }
    if !Path::new("/usr/include/embree3/rtcore.h").exists() {
        println!("Embree: headers missing (apt-get install -y libembree-dev g++), skipping the comparison");
        return None;
    }
    let ok = Command::new("bash")
        .arg(&script)
        .arg(&out)
        .status()
        .map(|s| s.success())
        .unwrap_or(false);
    if !ok {
        println!(
            "Embree: {} failed, skipping the comparison",
            script.display()
        );
    }
    (ok && bin.exists()).then_some(bin)
}

/// A scene holding only this mesh (loaded by rtlab's own scene and OBJ loaders).
pub fn mesh_scene(obj: &Path, dir: &Path) -> Scene {
    let file = dir.join(format!(
        "{}.json",
        obj.file_stem().unwrap().to_string_lossy()
    ));
    let json = serde_json::json!({
        "camera": {"position": [0, 0, 1]},
        "objects": [{"name": "mesh", "shape": "mesh", "file": obj.to_string_lossy()}]
    });
    std::fs::write(&file, json.to_string()).expect("writable temp folder");
    Scene::load(&file).expect("the mesh loads")
}
