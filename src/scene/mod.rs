//! Scene files → one validated [`Scene`]. Both formats (native rtlab JSON and the CS1230
//! course scenefile) load into the same types; nothing downstream knows which one it was.

pub mod cs1230;
pub mod json;
mod native;
pub mod obj;
mod solids;

use crate::accel::{Accel, AccelKind};
use crate::camera::Camera;
use crate::error::{Error, Result};
use crate::math::Transform;
use crate::shading::{Light, Material};
use crate::shapes::{Aabb, Shape};
use glam::DVec3;
use std::path::{Path, PathBuf};

pub use cs1230::stage::{ignored_lights_note, CourseStage};
pub use native::NATIVE_KEYS;
pub use solids::load_solid;

/// The deepest recursion accepted from a scene or `--max-depth`.
pub fn native_max_depth() -> u32 {
    native::MAX_DEPTH_LIMIT
}

/// How samples are placed in a pixel (DESIGN §3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SamplerKind {
    Center,
    Grid,
    Corners,
    Jittered,
    Random,
    Adaptive,
}

impl SamplerKind {
    pub const NAMES: [&'static str; 6] = [
        "center", "grid", "corners", "jittered", "random", "adaptive",
    ];
    pub fn parse(s: &str) -> Option<SamplerKind> {
        Some(match s {
            "center" => SamplerKind::Center,
            "grid" => SamplerKind::Grid,
            "corners" => SamplerKind::Corners,
            "jittered" => SamplerKind::Jittered,
            "random" => SamplerKind::Random,
            "adaptive" => SamplerKind::Adaptive,
            _ => return None,
        })
    }
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// Reconstruction filter (DESIGN §3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FilterKind {
    Box,
    Tent,
    Gaussian,
    Mitchell,
}

impl FilterKind {
    pub const NAMES: [&'static str; 4] = ["box", "tent", "gaussian", "mitchell"];
    pub fn parse(s: &str) -> Option<FilterKind> {
        Some(match s {
            "box" => FilterKind::Box,
            "tent" => FilterKind::Tent,
            "gaussian" => FilterKind::Gaussian,
            "mitchell" => FilterKind::Mitchell,
            _ => return None,
        })
    }
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// How linear colour becomes bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Encoding {
    /// byte = floor(255 · clamp(c, 0, 1)): the course's reference images.
    Clamp,
    /// The sRGB transfer curve, rounded.
    Srgb,
}

/// Everything that decides how the scene is rendered; scene values, overridable from the CLI.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    pub spp: u32,
    pub sampler: SamplerKind,
    pub filter: FilterKind,
    pub max_depth: u32,
    pub min_contribution: f64,
    pub background: DVec3,
    pub seed: u64,
    pub encoding: Encoding,
    pub shadows: bool,
    pub reflections: bool,
    pub refractions: bool,
    pub textures: bool,
    pub depth_of_field: bool,
    /// Which local terms of the lighting equation are on (for `steps`, which builds the
    /// image up term by term with the one tracer).
    pub ambient: bool,
    pub diffuse: bool,
    pub specular: bool,
    pub accel: AccelKind,
    /// Clamp every traced colour to [0, 1] before it is used (the course's renderer does).
    pub clamp_each_ray: bool,
    /// Offset for spawned rays, along the surface normal (scaled by the scene's size).
    pub epsilon: f64,
    /// Subsampling: only every K-th pixel in x and y traces samples; the filter, stretched K
    /// times, reconstructs the rest (1: every pixel).
    pub subsample: u32,
    /// The adaptive sampler splits a cell when its samples differ by more than this (largest
    /// channel difference, linear colour).
    pub adaptive_threshold: f64,
    /// Light only by directional lights (the course's Intersect stage does): the others are
    /// still evaluated, unshadowed, and reported as ignored, but add nothing to the colour.
    pub directional_only: bool,
    /// The ray budget of one sample: once its tree has traced this many rays (every kind
    /// counted), no further reflection or refraction ray is spawned and the node that wanted
    /// one ends with [`crate::trace::End::RayBudget`] (`render.max_rays`, `--max-rays`).
    pub max_rays: u64,
    /// Stops a render early when cancelled (or on Ctrl-C); never changes a pixel.
    pub cancel: crate::interrupt::Cancel,
    /// How a texture is looked up: nearest texel (the course's requirement) or bilinear.
    pub texture_filter: crate::shading::TextureFilter,
    /// Refraction the course's way (FORMAT §8): bend in, trace to the exit on the same
    /// object, bend out; the inner surface is not shaded and total internal reflection adds
    /// nothing. Off: rtlab's general Whitted refraction. The CS1230 loader turns it on.
    pub course_refraction: bool,
    /// How camera rays walk the BVHs: one by one or in bundles of 16 (`--traversal`; the
    /// image is the same either way).
    pub traversal: crate::accel::Traversal,
    /// Deliberate mistakes of the catalogue (`--mistake`): switches of the one tracer that
    /// reproduce a student's wrong code (empty: the correct tracer).
    pub mistakes: crate::mistakes::Mistakes,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            spp: 1,
            sampler: SamplerKind::Center,
            filter: FilterKind::Box,
            max_depth: 5,
            min_contribution: 0.001,
            background: DVec3::ZERO,
            seed: 0,
            encoding: Encoding::Clamp,
            shadows: true,
            reflections: true,
            refractions: true,
            textures: true,
            depth_of_field: true,
            ambient: true,
            diffuse: true,
            specular: true,
            accel: AccelKind::Bvh,
            clamp_each_ray: false,
            epsilon: 1e-7,
            subsample: 1,
            adaptive_threshold: 0.1,
            directional_only: false,
            max_rays: crate::trace::DEFAULT_MAX_RAYS,
            cancel: crate::interrupt::Cancel::default(),
            texture_filter: crate::shading::TextureFilter::Nearest,
            course_refraction: false,
            traversal: crate::accel::Traversal::Bundle,
            mistakes: crate::mistakes::Mistakes::NONE,
        }
    }
}

/// The global weights of the lighting equation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Global {
    pub ka: f64,
    pub kd: f64,
    pub ks: f64,
    pub kt: f64,
}

/// An object: a shape in its own space, placed in the world by a transform.
#[derive(Debug, Clone)]
pub struct Object {
    pub name: String,
    pub shape: Shape,
    pub transform: Transform,
    pub material: usize,
    /// World-space bounds; `None` for unbounded shapes.
    pub bounds: Option<Aabb>,
}

/// The source a scene came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneFormat {
    Native,
    Cs1230,
}

/// A validated scene: every value here has been checked; nothing downstream re-validates.
#[derive(Debug, Clone)]
pub struct Scene {
    pub path: PathBuf,
    pub format: SceneFormat,
    pub camera: Camera,
    pub render: RenderSettings,
    pub global: Global,
    pub ambient_light: DVec3,
    pub lights: Vec<Light>,
    pub materials: Vec<Material>,
    pub objects: Vec<Object>,
    pub accel: Accel,
}

impl Scene {
    /// Loads a scene file of either format, recognised by its keys.
    pub fn load(path: &Path) -> Result<Scene> {
        Scene::load_reporting(path).map(|(s, _)| s)
    }

    /// [`Scene::load`], with what a student should hear about the file (a texture found
    /// somewhere else, a duplicate template name): one sentence each, file and place named.
    pub fn load_reporting(path: &Path) -> Result<(Scene, Vec<String>)> {
        let text = read_scene_text(path)?;
        let (value, twice) = json::parse_noting_twice(path, &text)?;
        let (mut scene, warnings) = if crate::scene::is_cs1230(&value) {
            // The course's own reader takes the last silently too: a warning, not a refusal.
            let (scene, mut warnings) = cs1230::load_reporting(path, &value)?;
            warnings.extend(twice.map(|e| e.to_string()));
            (scene, warnings)
        } else if let Some(e) = twice {
            return Err(e);
        } else {
            (native::load(path, &value)?, Vec::new())
        };
        scene.rebuild_accel();
        Ok((scene, warnings))
    }

    /// (Re)builds the accelerator after objects or `render.accel` changed.
    pub fn rebuild_accel(&mut self) {
        self.accel = Accel::build(self.render.accel, &self.objects);
        let size = self
            .objects
            .iter()
            .filter_map(|o| o.bounds)
            .fold(Aabb::EMPTY, |a, b| a.union(b));
        let extent = if size.is_empty() {
            1.0
        } else {
            (size.max - size.min)
                .max_element()
                .max(size.max.abs().max_element())
        };
        self.render.epsilon = 1e-7 * extent.clamp(1e-9, 1e12);
    }

    /// The material of an object.
    pub fn material_of(&self, object: usize) -> &Material {
        &self.materials[self.objects[object].material]
    }

    /// The name an object is shown by: its scene name or `#index`.
    pub fn object_name(&self, object: usize) -> &str {
        &self.objects[object].name
    }
}

/// The text of a scene file (either format), or the error that names why there is none: a
/// folder, unreadable, larger than [`crate::input::TEXT_LIMIT`], not UTF-8.
pub(crate) fn read_scene_text(path: &Path) -> Result<String> {
    read_json_text(path, "scene")
}

/// The text of a JSON file the user names, a `kind` of file ("scene", or "spec" for a
/// standalone solid), with the errors of [`read_scene_text`] in that kind's words.
pub(crate) fn read_json_text(path: &Path, kind: &str) -> Result<String> {
    if path.is_dir() {
        return Err(Error::io(
            path,
            format!("is a directory, expected a {kind} file (.json)"),
        ));
    }
    let bytes = crate::input::read_limited(path, crate::input::TEXT_LIMIT)
        .map_err(|e| Error::io(path, format!("cannot read {kind}: {}", io_reason(&e))))?;
    String::from_utf8(bytes).map_err(|_| {
        Error::input(
            path,
            "",
            format!("not a text file (invalid UTF-8): expected a JSON {kind}"),
        )
    })
}

/// A scene as every command that renders loads it: from a scene file or from a course
/// `.ini` file (which names the scenefile and its settings), with a course stage applied.
#[derive(Debug, Clone)]
pub struct Loaded {
    pub scene: Scene,
    /// Things to tell the user once, on stderr (or in `validate`'s report).
    pub warnings: Vec<String>,
    /// The course stage in force: `--course-stage`, else the ini's folder.
    pub stage: Option<CourseStage>,
    /// The ini's `[IO] output`, resolved (render writes there unless `-o` is given).
    pub output: Option<PathBuf>,
}

/// Opens a scene file or a course `.ini` (recognised by its extension). Settings apply in
/// this order: the scene's own, then the stage's preset (`stage`, else the stage the ini's
/// folder names), then the ini's keys; the caller's command-line switches come last.
pub fn open(path: &Path, stage: Option<CourseStage>) -> Result<Loaded> {
    if cs1230::ini::is_ini(path) {
        return cs1230::ini::open(path, stage);
    }
    let (mut scene, warnings) = Scene::load_reporting(path)?;
    if let Some(st) = stage {
        st.apply(&mut scene.render);
    }
    Ok(Loaded {
        scene,
        warnings,
        stage,
        output: None,
    })
}

/// A CS1230 scenefile has `globalData` and `cameraData` at the top level.
pub fn is_cs1230(v: &serde_json::Value) -> bool {
    v.get("globalData").is_some() || v.get("cameraData").is_some()
}

pub(crate) fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ => e.to_string(),
    }
}

/// Loads an image texture (PNG, JPEG, GIF) as linear values texel/255.
pub fn load_texture(path: &Path) -> Result<crate::shading::TextureSource> {
    if path.is_dir() {
        return Err(Error::io(path, "is a directory, expected a texture image"));
    }
    let bytes = crate::input::read_limited(path, crate::input::IMAGE_LIMIT)
        .map_err(|e| Error::io(path, format!("cannot read texture: {}", io_reason(&e))))?;
    if bytes.is_empty() {
        return Err(Error::io(
            path,
            "the texture file is empty: expected a PNG, JPEG or GIF image",
        ));
    }
    // The format comes from the file's first bytes, not its name.
    let img = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| Error::io(path, format!("cannot read texture: {e}")))?
        .decode()
        .map_err(|e| {
            let why = match e {
                image::ImageError::IoError(io)
                    if io.kind() == std::io::ErrorKind::UnexpectedEof =>
                {
                    "the file is truncated".to_string()
                }
                other => other.to_string(),
            };
            Error::io(
                path,
                format!("cannot decode texture image: {why} (expected a PNG, JPEG or GIF image)"),
            )
        })?;
    let rgb = img.to_rgb8();
    if rgb.width() == 0 || rgb.height() == 0 {
        return Err(Error::io(path, "the texture image is empty"));
    }
    let texels = rgb
        .pixels()
        .map(|p| DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64) / 255.0)
        .collect();
    Ok(crate::shading::TextureSource::Image {
        width: rgb.width(),
        height: rgb.height(),
        texels: std::sync::Arc::new(texels),
    })
}

/// Largest image rtlab will allocate (pixels); larger sizes are refused before any memory
/// is taken, with the size they would need.
pub const MAX_PIXELS: u64 = 1 << 27;

/// Checks an image size, naming what it would cost when it is refused.
pub fn check_size(width: u32, height: u32) -> std::result::Result<(), String> {
    if width == 0 || height == 0 {
        return Err(format!(
            "the image size must be at least 1×1, found {width}×{height}"
        ));
    }
    let n = width as u64 * height as u64;
    if n > MAX_PIXELS {
        return Err(format!(
            "{width}×{height} is {n} pixels, which would need about {:.1} GiB; the limit is {MAX_PIXELS} pixels",
            n as f64 * 64.0 / (1u64 << 30) as f64
        ));
    }
    Ok(())
}

/// Resolves a path written in a scene file against a base directory.
pub fn resolve(base: &Path, file: &str) -> PathBuf {
    let p = Path::new(file);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        base.join(p)
    }
}

/// World bounds of a shape under a transform.
pub fn world_bounds(shape: &Shape, t: &Transform) -> Option<Aabb> {
    shape.bounds().map(|b| b.transformed(&t.world_from_object))
}
