//! Bad input never hurts (issue #10): every mistake a student is likely to make, run through
//! the real binary. Each case asserts exit status 2, a message that names the place (file and
//! JSON path, line:column, or argument) and what was expected, and that nothing was written:
//! a previous good output file is byte-for-byte untouched and no temporary file is left.
//!
//! The README's table of messages is generated from these cases: `RTLAB_BLESS=1 cargo test
//! --release --test integration errors` rewrites it; otherwise the test fails when the table
//! is stale.

use super::common::*;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// One kind of bad input.
struct Case {
    /// What the user did wrong (the README table's first column).
    kind: &'static str,
    /// Files to create in the case's fresh folder.
    files: Vec<(&'static str, Vec<u8>)>,
    /// The command line (run in that folder, so messages show short relative paths).
    args: Vec<&'static str>,
    /// Every one of these must appear in the message.
    expect: Vec<&'static str>,
}

/// A small valid scene with one material "red", a camera with extra keys, and `objects`.
fn scene(camera: &str, objects: &str) -> Vec<u8> {
    format!(
        r#"{{
  "camera": {{"position": [0, 0, 5], "width": 8, "height": 6{camera}}},
  "lights": [{{"type": "point", "position": [2, 2, 5]}}],
  "materials": {{"red": {{"diffuse": [0.8, 0.1, 0.1]}}}},
  "objects": [{objects}]
}}"#
    )
    .into_bytes()
}

fn obj(o: &str) -> Vec<u8> {
    scene("", o)
}

fn cam(c: &str) -> Vec<u8> {
    scene(c, r#"{"shape": "sphere"}"#)
}

const GOOD: &[u8] = b"a previous good render";
const SPHERE: &str = r#"{"shape": "sphere", "material": "red"}"#;

fn render(scene: &'static str) -> Vec<&'static str> {
    vec!["render", scene, "-o", "good.png", "--quiet"]
}

fn cases() -> Vec<Case> {
    let c = |kind, files: Vec<(&'static str, Vec<u8>)>, args, expect| Case {
        kind,
        files,
        args,
        expect,
    };
    let s = |bytes: Vec<u8>| vec![("scene.json", bytes)];
    let r = || render("scene.json");
    let mesh = |text: &[u8]| {
        vec![
            ("scene.json", obj(r#"{"shape": "mesh", "file": "m.obj"}"#)),
            ("m.obj", text.to_vec()),
        ]
    };
    let texture = |bytes: &[u8]| {
        vec![
            (
                "scene.json",
                scene(
                    "",
                    r#"{"shape": "sphere", "material": {"texture": {"file": "t.png"}}}"#,
                ),
            ),
            ("t.png", bytes.to_vec()),
        ]
    };
    let png_header = b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\x08".to_vec();
    let one_texel = rtlab::output::png_bytes(&image::RgbImage::new(1, 1)).unwrap();
    vec![
        // ---- the scene file itself
        c("scene file missing", vec![], render("nope.json"), vec!["nope.json", "no such file"]),
        c(
            "scene path is a folder",
            vec![("folder/x", vec![])],
            render("folder"),
            vec!["folder", "is a directory"],
        ),
        c("empty scene file", s(vec![]), r(), vec!["scene.json", "the file is empty"]),
        c(
            "binary scene file",
            s(vec![0xff, 0xfe, 0, 1, 2]),
            r(),
            vec!["scene.json", "invalid UTF-8", "expected a JSON scene"],
        ),
        c(
            "malformed JSON (trailing comma)",
            s(br#"{"camera": {"position": [0, 0, 5],}}"#.to_vec()),
            r(),
            vec!["scene.json", "line 1:35", "trailing comma"],
        ),
        c(
            "NaN in JSON",
            s(br#"{"camera": {"position": [0, NaN, 5]}}"#.to_vec()),
            r(),
            vec!["scene.json", "line 1:29", "invalid JSON"],
        ),
        c(
            "number too large for f64 (1e999)",
            s(br#"{"camera": {"position": [0, 1e999, 5]}}"#.to_vec()),
            r(),
            vec!["scene.json", "line 1", "out of range"],
        ),
        c(
            "the scene is not an object",
            s(b"[1, 2, 3]".to_vec()),
            r(),
            vec!["scene.json", "(top level)", "expected an object, found an array"],
        ),
        // ---- keys and types
        c(
            "misspelled top-level key",
            s(br#"{"camera": {"position": [0, 0, 5]}, "objets": []}"#.to_vec()),
            r(),
            vec!["scene.json", "objets", "unknown key", "did you mean \"objects\""],
        ),
        c(
            "misspelled object key",
            s(obj(r#"{"shape": "sphere", "radus": 2}"#)),
            r(),
            vec!["objects[0].radus", "did you mean \"radius\""],
        ),
        c(
            "key of another shape",
            s(obj(r#"{"shape": "sphere", "normal": [0, 1, 0]}"#)),
            r(),
            vec!["objects[0].normal", "a sphere has no \"normal\""],
        ),
        c(
            "misspelled shape",
            s(obj(r#"{"shape": "sphre"}"#)),
            r(),
            vec!["objects[0].shape", "did you mean \"sphere\""],
        ),
        c(
            "wrong type (string for a number)",
            s(obj(r#"{"shape": "sphere", "radius": "big"}"#)),
            r(),
            vec!["objects[0].radius", "expected a number, found the string \"big\""],
        ),
        c(
            "wrong type (number for a vector)",
            s(cam(r#", "look_at": 3"#)),
            r(),
            vec!["camera.look_at", "expected an array of 3 numbers, found the number 3"],
        ),
        c(
            "vector of the wrong length",
            s(obj(r#"{"shape": "sphere", "center": [1, 2]}"#)),
            r(),
            vec!["objects[0].center", "expected an array of 3 numbers, found 2"],
        ),
        c(
            "missing required key",
            s(br#"{"camera": {"look_at": [0, 0, 0]}}"#.to_vec()),
            r(),
            vec!["scene.json", "camera", "missing required key \"position\""],
        ),
        c(
            "object without a shape",
            s(obj(r#"{"radius": 1}"#)),
            r(),
            vec!["objects[0]", "missing required key \"shape\""],
        ),
        c(
            "undefined material",
            s(obj(r#"{"shape": "sphere", "material": "rde"}"#)),
            r(),
            vec!["objects[0].material", "no material named \"rde\"", "did you mean \"red\""],
        ),
        c(
            "unknown light type",
            s(br#"{"camera": {"position": [0, 0, 5]}, "lights": [{"type": "pointy"}]}"#.to_vec()),
            r(),
            vec!["lights[0].type", "did you mean \"point\""],
        ),
        // ---- numbers
        c(
            "absurdly large number",
            s(obj(r#"{"shape": "sphere", "center": [1e300, 0, 0]}"#)),
            r(),
            vec!["objects[0].center[0]", "too large", "1e12"],
        ),
        c(
            "absurdly small size",
            s(obj(r#"{"shape": "sphere", "radius": 1e-200}"#)),
            r(),
            vec!["objects[0].radius", "too small", "1e-12"],
        ),
        c(
            "negative radius",
            s(obj(r#"{"shape": "sphere", "radius": -1}"#)),
            r(),
            vec!["objects[0].radius", "must be greater than 0, found -1"],
        ),
        c(
            "zero radius",
            s(obj(r#"{"shape": "cylinder", "radius": 0}"#)),
            r(),
            vec!["objects[0].radius", "must be greater than 0, found 0"],
        ),
        c(
            "negative colour",
            s(obj(r#"{"shape": "sphere", "material": {"diffuse": [1, -0.5, 0]}}"#)),
            r(),
            vec!["objects[0].material.diffuse", "must not be negative"],
        ),
        c(
            "box with min > max",
            s(obj(r#"{"shape": "box", "min": [1, 1, 1], "max": [0, 2, 2]}"#)),
            r(),
            vec!["objects[0].max", "max must be greater than min"],
        ),
        c(
            "cylinder with y_max <= y_min",
            s(obj(r#"{"shape": "cylinder", "y_min": 1, "y_max": 1}"#)),
            r(),
            vec!["objects[0].y_max", "must be greater than y_min"],
        ),
        // ---- transforms and geometry
        c(
            "scale 0",
            s(obj(r#"{"shape": "sphere", "transform": [{"scale": [1, 0, 1]}]}"#)),
            r(),
            vec!["objects[0].transform[0].scale", "a scale of 0"],
        ),
        c(
            "singular matrix",
            s(obj(
                r#"{"shape": "sphere", "transform": [{"matrix": [[1,0,0,0],[0,1,0,0],[1,1,0,0],[0,0,0,1]]}]}"#,
            )),
            r(),
            vec!["objects[0].transform", "singular"],
        ),
        c(
            "rotation about a zero axis",
            s(obj(
                r#"{"shape": "sphere", "transform": [{"rotate": {"axis": [0, 0, 0], "degrees": 30}}]}"#,
            )),
            r(),
            vec!["objects[0].transform[0].rotate.axis", "zero vector"],
        ),
        c(
            "degenerate triangle",
            s(obj(r#"{"shape": "triangle", "vertices": [[0, 0, 0], [1, 1, 1], [2, 2, 2]]}"#)),
            r(),
            vec!["objects[0].vertices", "degenerate", "collinear"],
        ),
        c(
            "zero-length direction",
            s(obj(r#"{"shape": "plane", "normal": [0, 0, 0]}"#)),
            r(),
            vec!["objects[0].normal", "must not be the zero vector"],
        ),
        c(
            "a direction too short to square",
            s(obj(r#"{"shape": "plane", "normal": [0, 1e-300, 0]}"#)),
            r(),
            vec!["objects[0].normal", "must not be the zero vector", "found [0, 1e-300, 0]"],
        ),
        c(
            "zero-length light direction",
            s(
                br#"{"camera": {"position": [0, 0, 5]}, "lights": [{"type": "directional", "direction": [0, 0, 0]}]}"#
                    .to_vec(),
            ),
            r(),
            vec!["lights[0].direction", "must not be the zero vector"],
        ),
        // ---- camera
        c(
            "up parallel to the view direction",
            s(cam(r#", "up": [0, 0, -2]"#)),
            r(),
            vec!["camera", "up vector is parallel to the view direction"],
        ),
        c(
            "camera looks at its own position",
            s(cam(r#", "look_at": [0, 0, 5]"#)),
            r(),
            vec!["camera", "view direction is zero"],
        ),
        c(
            "field of view 0",
            s(cam(r#", "fov_y": 0"#)),
            r(),
            vec!["camera", "field of view must be between 0 and 180", "found 0"],
        ),
        c(
            "field of view 180",
            s(cam(r#", "fov_y": 180"#)),
            r(),
            vec!["camera", "field of view", "found 180"],
        ),
        c(
            "image width 0",
            s(br#"{"camera": {"position": [0, 0, 5], "width": 0}}"#.to_vec()),
            r(),
            vec!["camera", "at least 1×1, found 0×480"],
        ),
        c(
            "image too large to allocate",
            s(br#"{"camera": {"position": [0, 0, 5], "width": 100000, "height": 100000}}"#.to_vec()),
            r(),
            vec!["camera", "100000×100000", "GiB", "the limit is"],
        ),
        c(
            "image × samples too large for memory",
            s(br#"{"camera": {"position": [0, 0, 5], "width": 10000, "height": 10000}, "render": {"spp": 16, "sampler": "random"}}"#.to_vec()),
            r(),
            vec!["scene.json", "camera", "10000×10000 pixels at 16 sample(s)", "GiB of memory"],
        ),
        c(
            "--spp too large for memory",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--width", "8000", "--height", "8000", "--spp", "64", "--sampler", "random"],
            vec!["argument --width/--height/--spp", "GiB of memory"],
        ),
        c(
            "fractional width",
            s(br#"{"camera": {"position": [0, 0, 5], "width": 10.5}}"#.to_vec()),
            r(),
            vec!["camera.width", "whole number"],
        ),
        // ---- render settings
        c(
            "spp 0 in the scene",
            s(br#"{"camera": {"position": [0, 0, 5]}, "render": {"spp": 0}}"#.to_vec()),
            r(),
            vec!["render.spp", "at least 1"],
        ),
        c(
            "absurd max_depth in the scene",
            s(br#"{"camera": {"position": [0, 0, 5]}, "render": {"max_depth": 100000}}"#.to_vec()),
            r(),
            vec!["render.max_depth", "too deep", "at most 64"],
        ),
        // ---- meshes
        c(
            "mesh file missing",
            vec![("scene.json", obj(r#"{"shape": "mesh", "file": "gone.obj"}"#))],
            r(),
            vec!["scene.json: objects[0].file: gone.obj", "cannot read mesh", "no such file"],
        ),
        c("empty OBJ file", mesh(b""), r(), vec!["m.obj", "no triangles"]),
        c(
            "binary OBJ file",
            mesh(&[0x00, 0xff, 0x80, 0x81]),
            r(),
            vec!["m.obj", "not a text OBJ file"],
        ),
        c(
            "malformed OBJ number",
            mesh(b"v 0 0 0\nv 1 0 0\nv 0 one 0\nf 1 2 3\n"),
            r(),
            vec!["m.obj", "line 3:5", "expected a finite number, found \"one\""],
        ),
        c(
            "OBJ coordinate beyond single precision",
            mesh(b"v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n"),
            r(),
            vec!["m.obj", "line 3", "vertex coordinate 1e39 is beyond single precision"],
        ),
        c(
            "OBJ face index out of range",
            mesh(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"),
            r(),
            vec!["m.obj", "line 4:7", "vertex index 4 is out of range", "has 3"],
        ),
        c(
            "OBJ with only degenerate faces",
            mesh(b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"),
            r(),
            vec!["m.obj", "no triangles"],
        ),
        c(
            "mesh path is a folder",
            vec![
                ("scene.json", obj(r#"{"shape": "mesh", "file": "meshes"}"#)),
                ("meshes/x", vec![]),
            ],
            r(),
            vec!["scene.json: objects[0].file: meshes", "is a directory, expected an OBJ mesh file"],
        ),
        // ---- textures
        c(
            "texture file missing",
            vec![(
                "scene.json",
                scene("", r#"{"shape": "sphere", "material": {"texture": {"file": "t.png"}}}"#),
            )],
            r(),
            vec!["scene.json: objects[0].material.texture.file: t.png", "cannot read texture", "no such file"],
        ),
        c(
            "empty texture file",
            texture(b""),
            r(),
            vec!["objects[0].material.texture.file: t.png", "the texture file is empty"],
        ),
        c(
            "empty file name",
            s(obj(r#"{"shape": "mesh", "file": ""}"#)),
            r(),
            vec!["scene.json: objects[0].file", "expected a file name, found an empty string"],
        ),
        c(
            "texture that is not an image",
            texture(b"hello, I am text"),
            r(),
            vec!["t.png", "cannot decode texture image"],
        ),
        c(
            "truncated PNG texture",
            texture(&png_header),
            r(),
            vec!["t.png", "cannot decode texture image: the file is truncated"],
        ),
        // ---- the output
        c(
            "output folder missing",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "missing/out.png", "--quiet"],
            vec!["argument -o", "missing/out.png", "the folder missing does not exist"],
        ),
        c(
            "output is a folder",
            vec![("scene.json", obj(SPHERE)), ("out.png/x", vec![])],
            vec!["render", "scene.json", "-o", "out.png", "--quiet"],
            vec!["argument -o", "out.png is a directory"],
        ),
        c(
            "output inside a file",
            vec![("scene.json", obj(SPHERE)), ("notes.txt", b"x".to_vec())],
            vec!["render", "scene.json", "-o", "notes.txt/out.png", "--quiet"],
            vec!["argument -o", "notes.txt", "not a folder"],
        ),
        c(
            "output folder that refuses new files",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "/proc/rtlab-test.png", "--quiet"],
            vec![
                "argument -o",
                "/proc/rtlab-test.png",
                "cannot write into the folder /proc: it does not take new files",
            ],
        ),
        c(
            "output is a texture the scene reads",
            texture(&one_texel),
            vec!["render", "scene.json", "-o", "./t.png", "--quiet"],
            vec!["argument -o", "./t.png is t.png, a file the scene reads", "would destroy it"],
        ),
        c(
            "steps' sheet is a texture the scene reads",
            texture(&one_texel),
            vec!["steps", "scene.json", "-o", "t.png", "--quiet"],
            vec!["argument -o", "t.png is a file the scene reads"],
        ),
        c(
            "two figures of explain named alike",
            s(obj(SPHERE)),
            vec!["explain", "scene.json", "--pixel", "1,1", "--diagram", "f.png", "--bundle-diagram", "./f.png"],
            vec!["argument --bundle-diagram", "./f.png is also --diagram's file"],
        ),
        c(
            "output format rtlab cannot write",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "out.jpg", "--quiet"],
            vec!["argument -o", "cannot write .jpg", "use a .png"],
        ),
        c(
            "output name that is only an extension",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", ".png", "--quiet"],
            vec!["argument -o", ".png is only an extension", "e.g. out.png"],
        ),
        c(
            "output name that begins with -",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "-x.png", "--quiet"],
            vec!["unexpected argument '-x'", "if -x.png is the value of -o, write -o=-x.png"],
        ),
        c(
            "output folder under a file",
            vec![("scene.json", obj(SPHERE)), ("notes.txt", b"x".to_vec())],
            vec!["steps", "scene.json", "-o", "notes.txt/steps", "--quiet"],
            vec!["notes.txt/steps", "cannot create the folder: not a directory"],
        ),
        c(
            "output over the scene itself",
            vec![("scene.png", obj(SPHERE))],
            vec!["render", "scene.png", "-o", "./scene.png", "--quiet"],
            vec!["argument -o", "scene.png is the scene", "choose another name"],
        ),
        c(
            "diff's figure over the image being diffed",
            vec![("scene.json", obj(SPHERE)), ("mine.png", GOOD.to_vec())],
            vec!["diff", "scene.json", "mine.png", "-o", "mine.png"],
            vec!["argument -o", "mine.png is your image", "choose another name"],
        ),
        c(
            "explain's diagram not a PNG",
            s(obj(SPHERE)),
            vec!["explain", "scene.json", "--pixel", "1,1", "--diagram", "scene.json"],
            vec!["argument --diagram", "cannot write .json images", "use a .png"],
        ),
        c(
            "diagram of a pixel --subsample fills in",
            s(obj(SPHERE)),
            vec!["explain", "scene.json", "--pixel", "1,1", "--subsample", "4", "--diagram", "d.png"],
            vec!["argument --diagram", "pixel (1, 1) traces no samples of its own", "pick a traced pixel"],
        ),
        c(
            "a control character in a value",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--sampler", "grid\u{1b}[31m"],
            vec!["argument --sampler", "grid\\u{1b}[31m"],
        ),
        c(
            "convert given a course .ini",
            vec![("x.ini", b"[IO]\nscene = scene.json\n".to_vec())],
            vec!["convert", "x.ini", "-o", "c.json"],
            vec!["x.ini", "is a course .ini, not a scenefile", "render and validate take the .ini itself"],
        ),
        c(
            "convert over its own input",
            s(obj(SPHERE)),
            vec!["convert", "scene.json", "-o", "scene.json"],
            vec!["argument -o", "scene.json is the scenefile being converted"],
        ),
        // ---- command-line values
        c(
            "--spp 0",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--spp", "0", "--quiet"],
            vec!["argument --spp", "at least 1"],
        ),
        c(
            "--spp for the one-sample sampler",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--spp", "16", "--quiet"],
            vec!["argument --spp", "the center sampler takes one sample per pixel, found 16", "grid, jittered, random or adaptive"],
        ),
        c(
            "--spp the corners sampler does not take",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--sampler", "corners", "--spp", "16", "--quiet"],
            vec!["argument --spp", "the corners sampler takes five samples per pixel", "found 16", "give 5"],
        ),
        c(
            "--width 0",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--width", "0", "--quiet"],
            vec!["argument --width/--height", "at least 1×1"],
        ),
        c(
            "--width/--height too large",
            s(obj(SPHERE)),
            vec![
                "render", "scene.json", "-o", "good.png", "--width", "200000", "--height", "200000",
            ],
            vec!["argument --width/--height", "GiB"],
        ),
        c(
            "--max-depth absurd",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--max-depth", "1000"],
            vec!["argument --max-depth", "too deep (at most 64)"],
        ),
        c(
            "--max-depth not a number",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--max-depth", "deep"],
            vec!["argument --max-depth", "\"deep\" is not a whole number"],
        ),
        c(
            "misspelled --sampler value",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--sampler", "jitterd"],
            vec!["argument --sampler", "unknown sampler \"jitterd\"", "jittered"],
        ),
        c(
            "misspelled option",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--sspp", "4"],
            vec!["--sspp", "--spp"],
        ),
        c(
            "a sampler that does not take the scene's spp",
            s(String::from_utf8(obj(SPHERE))
                .unwrap()
                .replace("\"objects\"", "\"render\": {\"spp\": 4, \"sampler\": \"grid\"}, \"objects\"")
                .into_bytes()),
            vec!["render", "scene.json", "-o", "good.png", "--sampler", "center"],
            vec!["argument --sampler", "found 4", "the scene's spp"],
        ),
        c(
            "a negative number of samples",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--spp", "-4"],
            vec!["'-4'", "no option here takes a negative number"],
        ),
        c(
            "one option given twice",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--traversal", "single", "--traversal", "bundle"],
            vec!["--traversal", "cannot be used multiple times"],
        ),
        c(
            "no scene",
            s(obj(SPHERE)),
            vec!["render"],
            vec!["required arguments were not provided: <SCENE>"],
        ),
        c(
            "--threads 0",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "-o", "good.png", "--threads", "0", "--quiet"],
            vec!["argument --threads", "at least 1"],
        ),
        c(
            "--pixel outside the image",
            s(obj(SPHERE)),
            vec!["explain", "scene.json", "--pixel", "8,2"],
            vec!["argument --pixel", "(8, 2) is outside the 8×6 image", "x must be 0..7"],
        ),
        c(
            "--pixel negative",
            s(obj(SPHERE)),
            vec!["explain", "scene.json", "--pixel", "-1,2"],
            vec!["argument --pixel", "outside the 8×6 image"],
        ),
        c(
            "--pixel malformed",
            s(obj(SPHERE)),
            vec!["explain", "scene.json", "--pixel", "3;4"],
            vec!["argument --pixel", "expected two whole numbers X,Y", "\"3;4\""],
        ),
        c(
            "--pixel with one number",
            s(obj(SPHERE)),
            vec!["explain", "scene.json", "--pixel", "3"],
            vec!["argument --pixel", "expected two whole numbers X,Y"],
        ),
        c(
            "--sample beyond the pixel's samples",
            s(obj(SPHERE)),
            vec!["explain", "scene.json", "--pixel", "3,3", "--sample", "5"],
            vec!["argument --sample", "sample 5 does not exist", "1 sample"],
        ),
        c(
            "a key written twice in one object",
            s(obj(r#"{"shape": "sphere", "radius": 1, "radius": 2}"#)),
            r(),
            vec!["scene.json: line", "key \"radius\" appears twice in one object"],
        ),
        c(
            "a key written twice in a solid's --spec",
            vec![(
                "spec.json",
                br#"{"shape": "blob", "threshold": 0.5, "threshold": 0.4, "spheres": []}"#.to_vec(),
            )],
            vec!["intersect", "blob", "--spec", "spec.json", "--origin", "0,0,5", "--dir", "0,0,-1"],
            vec!["spec.json: line 1:", "key \"threshold\" appears twice in one object"],
        ),
        c(
            "a bundle of rays against a sphere",
            vec![],
            vec!["intersect", "sphere", "--origin", "0,0,-5", "--dir", "0,0,1", "--bundle-to", "0.1,0,1"],
            vec!["--bundle-to", "only box takes a bundle of rays"],
        ),
        c(
            "a bundle of 17 rays",
            vec![],
            vec!["intersect", "box", "--origin", "0,0,-5", "--dir", "0,0,1", "--bundle-to", "0.1,0,1", "--rays", "17"],
            vec!["--rays", "\"17\" is not a number of rays", "a whole number from 2 to 16"],
        ),
        c(
            "--rays without a bundle",
            vec![],
            vec!["intersect", "box", "--origin", "0,0,-5", "--dir", "0,0,1", "--rays", "4"],
            vec!["--rays", "it goes with --bundle-to"],
        ),
        c(
            "a ray beyond a scene's range",
            vec![],
            vec!["intersect", "sphere", "--origin", "0,0,5", "--dir", "1e308,0,-1e308"],
            vec!["argument --dir", "1e308 is out of range: coordinates up to 1e12"],
        ),
        c(
            "a direction too short to square",
            vec![],
            vec!["intersect", "sphere", "--origin", "0,0,5", "--dir", "0,0,-1e-300"],
            vec!["argument --dir", "must not be zero (or shorter than 1e-12)"],
        ),
        c(
            "a radius below a scene's smallest size",
            vec![],
            vec!["intersect", "sphere", "--radius", "1e-320", "--origin", "0,0,5", "--dir", "0,0,-1"],
            vec!["argument --radius", "too small: sizes must be at least 1e-12"],
        ),
        c(
            "a bundle from beyond a scene's range",
            vec![],
            vec!["intersect", "box", "--origin", "0,0,-1e13", "--dir", "0,0,1", "--bundle-to", "0.1,0,1"],
            vec!["--origin", "is out of range: coordinates up to 1e12"],
        ),
        c(
            "a bundle whose directions pass through zero",
            vec![],
            vec!["intersect", "box", "--origin", "0,0,-5", "--dir", "0,0,1", "--bundle-to", "0,0,-1", "--rays", "3"],
            vec!["--bundle-to", "ray 1's direction, between --dir and --bundle-to, is shorter than"],
        ),
        c(
            "a solid's --spec that is a folder",
            vec![("specs/x", vec![])],
            vec!["intersect", "blob", "--spec", "specs", "--origin", "0,0,5", "--dir", "0,0,-1"],
            vec!["specs: is a directory, expected a spec file (.json)"],
        ),
        c(
            "a binary solid's --spec",
            vec![("spec.json", vec![0xff, 0xfe, 0, 1])],
            vec!["intersect", "csg", "--spec", "spec.json", "--origin", "0,0,5", "--dir", "0,0,-1"],
            vec!["spec.json", "invalid UTF-8", "expected a JSON spec"],
        ),
        c(
            "a misspelt key in a course .ini",
            vec![
                ("scene.json", obj(SPHERE)),
                ("x.ini", b"[IO]\n    scene = scene.json\n[Feature]\n    shadow = true\n".to_vec()),
            ],
            render("x.ini"),
            vec!["x.ini: line 4:5:", "unknown key \"shadow\" in [Feature]", "did you mean \"shadows\"?"],
        ),
        c(
            "a course .ini whose output is empty",
            vec![
                ("scene.json", obj(SPHERE)),
                ("x.ini", b"[IO]\n    scene = scene.json\n    output = \n".to_vec()),
            ],
            render("x.ini"),
            vec!["x.ini: line 3:13: [IO] output: no file name given: give one, e.g. out.png"],
        ),
        c(
            "a course .ini's whole number too large for any key",
            vec![
                ("scene.json", obj(SPHERE)),
                ("x.ini", b"[IO]\n    scene = scene.json\n[Settings]\n    maximum-recursive-depth = 99999999999\n".to_vec()),
            ],
            render("x.ini"),
            vec!["x.ini: line 4:31: [Settings] maximum-recursive-depth: 99999999999 is too large a number (more than 4294967295)"],
        ),
        c(
            "a course .ini whose scene is not there",
            vec![("x.ini", b"[IO]\n    scene = scenefiles/a.json\n".to_vec())],
            render("x.ini"),
            vec!["x.ini: line 2:13: [IO] scene: scenefile not found: tried scenefiles/a.json (from the current folder)"],
        ),
        c(
            "a scene path that never ends (a device)",
            vec![],
            render("/dev/zero"),
            vec!["/dev/zero: cannot read scene: larger than 64 MiB, the most such a file may hold"],
        ),
        c(
            "an image to compare that never ends (a device)",
            s(obj(SPHERE)),
            vec!["diff", "scene.json", "/dev/zero"],
            vec!["/dev/zero: is not an image; expected an 8-bit RGB PNG"],
        ),
        c(
            "a beam with no wall or mirror",
            vec![],
            vec!["beam", "--from", "-1,1", "--to", "1,1"],
            vec!["argument --wall/--mirror", "give at least one wall or mirror"],
        ),
        c(
            "a beam against walls that cross",
            vec![],
            vec!["beam", "--from", "-1,1", "--to", "1,1", "--wall", "-1,1,1,2", "--wall", "-1,2,1,1"],
            vec!["argument --wall/--mirror", "wall 1 and wall 2 cross or overlap"],
        ),
        c(
            "a mirror and a wall on one line, overlapping",
            vec![],
            vec!["beam", "--from", "0,1", "--to", "1,1", "--mirror", "0,2,2,2", "--wall", "-1,2,1,2"],
            vec!["argument --wall/--mirror", "wall 1 and mirror 1 cross or overlap"],
        ),
        c(
            "a beam half a turn wide",
            vec![],
            vec!["beam", "--from", "1,0", "--to", "-1,0", "--wall", "-1,1,1,1"],
            vec!["argument --from/--to", "180° apart", "less than 179.9999999° wide"],
        ),
        c(
            "an empty --mistake",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "--mistake="],
            vec!["argument --mistake", "no name given"],
        ),
        c(
            "more --threads than can be started",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "--threads", "100000"],
            vec!["argument --threads", "100000 is more than 1024"],
        ),
        c(
            "an unknown --traversal",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "--traversal", "zigzag"],
            vec!["argument --traversal", "unknown traversal \"zigzag\"", "single or bundle"],
        ),
        c(
            "a negative ray budget",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "--max-rays", "-1"],
            vec!["--max-rays", "must be at least 1 (the camera ray)"],
        ),
        c(
            "a ray budget past a scene's range",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "--max-rays", "5000000000"],
            vec!["--max-rays", "5000000000 is more than 4294967295"],
        ),
        c(
            "pass 0",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "--passes", "0"],
            vec!["--passes", "passes are numbered from 1"],
        ),
        c(
            "a last pass past the sample limit, beside a time budget",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "--spp", "64", "--sampler", "jittered", "--time-budget", "5", "--passes", "11"],
            vec!["argument --passes", "pass 11", "more than the limit of 65536"],
        ),
        c(
            "a pass past the sample limit, for a course .ini whose output folders do not exist",
            vec![
                ("scene.json", obj(SPHERE)),
                ("x.ini", b"[IO]\n    scene = scene.json\n    output = out/deep/x.png\n".to_vec()),
            ],
            vec!["render", "x.ini", "--passes", "11"],
            vec!["argument --passes", "pass 11", "more than the limit of 65536"],
        ),
        c(
            "a time budget of no time",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "--time-budget", "0"],
            vec!["argument --time-budget", "\"0\" is not a time", "seconds > 0"],
        ),
        c(
            "an AOV too big for memory (an AOV keeps every sample until its image is made)",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "--aov", "depth", "--width", "4000", "--height", "4000", "--spp", "16", "--sampler", "grid"],
            vec!["argument --width/--height/--spp", "GiB of memory"],
        ),
        c(
            "a time budget whose first pass is too big for memory",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "--time-budget", "1", "--width", "8000", "--height", "8000", "--spp", "256", "--sampler", "grid"],
            vec!["argument --time-budget", "pass 1:", "GiB of memory"],
        ),
        c(
            "an unknown --course-stage",
            s(obj(SPHERE)),
            vec!["render", "scene.json", "--course-stage", "raytrace"],
            vec!["argument --course-stage", "unknown course stage \"raytrace\"", "intersect or illuminate"],
        ),
    ]
}

fn case_dir(i: usize) -> PathBuf {
    let d = std::env::temp_dir().join(format!("rtlab-errors-{}-{i}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Every file under `dir` with its bytes, and every folder (`None`), sorted (to prove nothing
/// appeared or changed).
fn snapshot(dir: &Path) -> Vec<(PathBuf, Option<Vec<u8>>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                out.push((p.clone(), None));
                stack.push(p);
            } else {
                out.push((p.clone(), Some(std::fs::read(&p).unwrap())));
            }
        }
    }
    out.sort();
    out
}

fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rtlab"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("rtlab runs")
}

/// The one line the user sees, without the "error: " prefix.
fn message(o: &Output) -> String {
    stderr(o).trim().to_string()
}

/// Runs every case; returns the README rows (kind, command, message).
fn run_cases() -> Vec<(String, String, String)> {
    let mut rows = Vec::new();
    let mut failures = Vec::new();
    for (i, case) in cases().into_iter().enumerate() {
        let dir = case_dir(i);
        for (name, bytes) in &case.files {
            let p = dir.join(name);
            std::fs::create_dir_all(p.parent().unwrap()).unwrap();
            std::fs::write(&p, bytes).unwrap();
        }
        std::fs::write(dir.join("good.png"), GOOD).unwrap();
        let before = snapshot(&dir);
        let o = run_in(&dir, &case.args);
        let msg = message(&o);
        let mut problems = Vec::new();
        if o.status.code() != Some(2) {
            problems.push(format!("exit status {:?}, expected 2", o.status.code()));
        }
        for e in &case.expect {
            if !msg.contains(e) {
                problems.push(format!("message lacks {e:?}"));
            }
        }
        if msg.contains("panicked") || msg.contains("RUST_BACKTRACE") {
            problems.push("panicked".into());
        }
        if snapshot(&dir) != before {
            problems.push("files or folders changed: something was written".into());
        }
        if !problems.is_empty() {
            failures.push(format!(
                "{} (`rtlab {}`):\n    {}\n    message: {msg}",
                case.kind,
                case.args.join(" "),
                problems.join("; ")
            ));
        }
        let _ = std::fs::remove_dir_all(&dir);
        // Every message is one line, clap's usage errors too (the table shows it whole).
        if msg.trim_end().lines().count() != 1 {
            failures.push(format!(
                "{} (`rtlab {}`): not one line:\n{msg}",
                case.kind,
                case.args.join(" ")
            ));
        }
        let first = msg.lines().next().unwrap_or("").to_string();
        // A control character in an argument is shown as a shell writes it: $'…\e…'.
        let shown: Vec<String> = case
            .args
            .iter()
            .map(|a| match a.contains('\u{1b}') {
                true => format!("$'{}'", a.replace('\u{1b}', "\\e")),
                false => a.to_string(),
            })
            .collect();
        rows.push((case.kind.to_string(), shown.join(" "), first));
    }
    assert!(
        failures.is_empty(),
        "{} of {} bad-input cases failed:\n{}",
        failures.len(),
        rows.len(),
        failures.join("\n")
    );
    rows
}

/// A render big enough that it is still running when Ctrl-C arrives.
fn interrupted_render() -> (String, String, String) {
    let dir = case_dir(9999);
    let objects: Vec<String> = (0..40)
        .map(|i| {
            format!(
                r#"{{"shape": "sphere", "center": [{}, {}, 0], "radius": 0.3, "material": {{"reflective": [0.5, 0.5, 0.5]}}}}"#,
                (i % 8) as f64 - 3.5,
                (i / 8) as f64 - 2.0
            )
        })
        .collect();
    let text = format!(
        r#"{{"camera": {{"position": [0, 0, 8], "width": 2000, "height": 2000}},
            "render": {{"spp": 4, "sampler": "grid"}},
            "lights": [{{"type": "point", "position": [3, 3, 8]}}],
            "objects": [{}]}}"#,
        objects.join(", ")
    );
    std::fs::write(dir.join("big.json"), text).unwrap();
    std::fs::write(dir.join("good.png"), GOOD).unwrap();
    let before = snapshot(&dir);
    let args = ["render", "big.json", "-o", "good.png", "--quiet"];
    let child = Command::new(env!("CARGO_BIN_EXE_rtlab"))
        .args(args)
        .current_dir(&dir)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the process runs more than one thread: the Ctrl-C handler's thread exists
    // (it is installed first thing in main), so the signal reaches the handler.
    let status = format!("/proc/{}/status", child.id());
    for _ in 0..2000 {
        let threads = std::fs::read_to_string(&status)
            .ok()
            .and_then(|s| {
                s.lines()
                    .find_map(|l| l.strip_prefix("Threads:").map(|n| n.trim().to_string()))
            })
            .and_then(|n| n.parse::<u32>().ok())
            .unwrap_or(0);
        if threads > 1 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    let msg = message(&o);
    assert_eq!(o.status.code(), Some(130), "{msg}");
    assert!(msg.contains("interrupted"), "{msg}");
    assert_eq!(snapshot(&dir), before, "an interrupted render wrote a file");
    let _ = std::fs::remove_dir_all(&dir);
    (
        "Ctrl-C during a long render (exit status 130)".into(),
        args.join(" "),
        msg,
    )
}

const START: &str = "<!-- errors-table:start (generated by tests/integration/errors.rs) -->";
const END: &str = "<!-- errors-table:end -->";

fn table(rows: &[(String, String, String)]) -> String {
    let mut t =
        String::from("| Bad input | Command | What rtlab says (exit status 2) |\n|---|---|---|\n");
    for (kind, cmd, msg) in rows {
        let esc = |s: &str| s.replace('|', "\\|");
        // A message that quotes a command in backticks needs a longer fence.
        let code = |s: &str| match s.contains('`') {
            true => format!("`` {} ``", esc(s)),
            false => format!("`{}`", esc(s)),
        };
        t += &format!(
            "| {} | {} | {} |\n",
            esc(kind),
            code(&format!("rtlab {cmd}")),
            code(msg)
        );
    }
    t
}

#[test]
fn bad_inputs_exit_2_name_the_place_and_write_nothing() {
    let mut rows = run_cases();
    rows.push(interrupted_render());
    let readme_path = path("README.md");
    let readme = std::fs::read_to_string(&readme_path).unwrap();
    let (Some(a), Some(b)) = (readme.find(START), readme.find(END)) else {
        panic!("README.md lacks the markers {START} … {END}");
    };
    let fresh = format!("{}{START}\n{}{}", &readme[..a], table(&rows), &readme[b..]);
    if std::env::var("RTLAB_BLESS").is_ok_and(|v| v == "1") {
        std::fs::write(&readme_path, fresh).unwrap();
    } else {
        assert!(
            fresh == readme,
            "the README's table of error messages is stale: rerun with RTLAB_BLESS=1"
        );
    }
}

#[test]
fn good_output_is_replaced_only_by_a_complete_file() {
    // The success path through the same writer: the old file is replaced whole, and no
    // temporary file is left next to it.
    let dir = case_dir(10000);
    std::fs::write(dir.join("scene.json"), obj(SPHERE)).unwrap();
    std::fs::write(dir.join("good.png"), GOOD).unwrap();
    let o = run_in(&dir, &["render", "scene.json", "-o", "good.png", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let files = snapshot(&dir);
    assert_eq!(files.len(), 2, "{files:?}");
    let png = std::fs::read(dir.join("good.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let img = image::load_from_memory(&png).unwrap();
    assert_eq!((img.width(), img.height()), (8, 6));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every file rtlab writes goes through `src/output.rs` (temporary file + rename, refused
/// after Ctrl-C): no other module may open a file for writing.
#[test]
fn no_writer_bypasses_output_rs() {
    let mut stack = vec![path("src")];
    let mut offenders = Vec::new();
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|e| e == "rs") && !p.ends_with("src/output.rs") {
                let text = std::fs::read_to_string(&p).unwrap();
                for (n, line) in text.lines().enumerate() {
                    for bad in ["fs::write(", "File::create(", ".save(", "OpenOptions"] {
                        if line.contains(bad) {
                            offenders.push(format!("{}:{}: {}", p.display(), n + 1, line.trim()));
                        }
                    }
                }
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "write files through rtlab::output (atomic), not directly:\n{}",
        offenders.join("\n")
    );
}

#[test]
fn a_reader_that_stops_early_is_not_an_error() {
    // `rtlab explain … | head -2`: head exits, and the next write meets a closed pipe. The
    // pipe is closed here before rtlab has loaded the scene, so its first write meets it.
    let mut child = Command::new(env!("CARGO_BIN_EXE_rtlab"))
        .args(["explain", "scenes/textures.json", "--pixel", "100,100"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", message(&o));
    assert_eq!(message(&o), "", "nothing to say about a closed output");
}
