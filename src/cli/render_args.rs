//! The options every command that renders shares ([`RenderArgs`], flattened into each), and
//! how they apply to a loaded scene.

use crate::accel::{AccelKind, Traversal};
use crate::error::{Error, Result};
use crate::report::shell_word;
use crate::scene::{check_size, CourseStage, Encoding, FilterKind, Loaded, SamplerKind, Scene};
use crate::shading::TextureFilter;

/// Options that change what a pixel is (shared by render, explain, steps, compare).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct RenderArgs {
    /// Image width in pixels (overrides the scene).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene).
    #[arg(long)]
    pub height: Option<u32>,
    /// Samples per pixel.
    #[arg(long)]
    pub spp: Option<u32>,
    /// Sample placement: center, grid, corners, jittered, random, adaptive.
    #[arg(long, value_name = "KIND")]
    pub sampler: Option<String>,
    /// Reconstruction filter: box, tent, gaussian, mitchell.
    #[arg(long, value_name = "KIND")]
    pub filter: Option<String>,
    /// Subsampling: trace only every K-th pixel in x and y and let the (stretched) filter
    /// fill in the rest.
    #[arg(long, value_name = "K")]
    pub subsample: Option<u32>,
    /// Adaptive sampler: split a cell when its samples differ by more than this (default 0.1).
    #[arg(long, value_name = "T")]
    pub adaptive_threshold: Option<f64>,
    /// Maximum recursion depth (0: ray casting, no reflection or refraction).
    #[arg(long, value_name = "D")]
    pub max_depth: Option<u32>,
    /// Seed of every random choice (same seed, same image).
    #[arg(long, value_name = "S")]
    pub seed: Option<u64>,
    /// How colour becomes bytes: clamp (course reference images) or srgb.
    #[arg(long, value_name = "clamp|srgb")]
    pub encoding: Option<String>,
    /// Acceleration: linear (the lecture's loop over every object) or bvh.
    #[arg(long, value_name = "linear|bvh")]
    pub accel: Option<String>,
    /// How camera rays walk the BVH: bundle (4×4 neighbouring rays together; the default: on
    /// no scene measured slower by more than 2 %, on most faster) or single (one at a time).
    /// The same image either way; only the work differs, which --stats and --aov cost show.
    #[arg(long, value_name = "single|bundle")]
    pub traversal: Option<String>,
    /// Turn off shadow rays.
    #[arg(long)]
    pub no_shadows: bool,
    /// Turn off reflection rays.
    #[arg(long)]
    pub no_reflections: bool,
    /// Turn off refraction and transparency.
    #[arg(long)]
    pub no_refractions: bool,
    /// Ignore textures.
    #[arg(long)]
    pub no_textures: bool,
    /// Use a pinhole even if the camera has an aperture.
    #[arg(long)]
    pub no_depth_of_field: bool,
    /// Ray budget of one sample (default 10000): past it, the rest of the sample's ray tree
    /// is cut (explain shows `end: ray-budget`).
    #[arg(long, value_name = "N", allow_negative_numbers = true, value_parser = ray_budget)]
    pub max_rays: Option<u64>,
    /// The course's stage: its template ini switches and what its reference renderer does.
    /// intersect: directional lights only, no shadows/reflections/refractions/textures,
    /// depth 0, 1 spp; illuminate: shadows, reflections, textures, depth 4, 1 spp.
    /// Explicit switches override it (default for an ini: the stage its folder names).
    #[arg(long, value_name = "intersect|illuminate")]
    pub course_stage: Option<String>,
    /// Texture lookup: nearest (default) or bilinear.
    #[arg(long, value_name = "nearest|bilinear")]
    pub texture_filter: Option<String>,
    /// Turn on shadow rays (over a stage or ini that turns them off).
    #[arg(long, conflicts_with = "no_shadows")]
    pub shadows: bool,
    /// Turn on reflection rays.
    #[arg(long, conflicts_with = "no_reflections")]
    pub reflections: bool,
    /// Turn on refraction and transparency.
    #[arg(long, conflicts_with = "no_refractions")]
    pub refractions: bool,
    /// Turn on textures.
    #[arg(long, conflicts_with = "no_textures")]
    pub textures: bool,
    /// Turn on depth of field (when the camera has an aperture).
    #[arg(long, conflicts_with = "no_depth_of_field")]
    pub depth_of_field: bool,
    /// Set by commands that have --quiet: the load's warnings are not printed.
    #[arg(skip)]
    pub quiet: bool,
    /// Render with a deliberate mistake of the catalogue (`rtlab mistakes` lists them);
    /// repeatable and comma-separated.
    #[arg(long = "mistake", value_name = "NAME")]
    pub mistakes: Vec<String>,
}

impl RenderArgs {
    /// These options (a request's, on `rtlab serve`) over `base` (the options the server was
    /// started with): an option given here wins; a switch given to either is on, except
    /// that a request cannot turn off a switch `base` gives (its opposite is dropped);
    /// mistakes add up. (The struct literal names every field: a new option does not compile
    /// until it is merged here too.)
    pub fn over(self, base: &RenderArgs) -> RenderArgs {
        // (on, off) of one switch and its negation.
        let switch = |on: bool, off: bool, base_on: bool, base_off: bool| {
            ((on && !base_off) || base_on, (off && !base_on) || base_off)
        };
        let (shadows, no_shadows) =
            switch(self.shadows, self.no_shadows, base.shadows, base.no_shadows);
        let (reflections, no_reflections) = switch(
            self.reflections,
            self.no_reflections,
            base.reflections,
            base.no_reflections,
        );
        let (refractions, no_refractions) = switch(
            self.refractions,
            self.no_refractions,
            base.refractions,
            base.no_refractions,
        );
        let (textures, no_textures) = switch(
            self.textures,
            self.no_textures,
            base.textures,
            base.no_textures,
        );
        let (depth_of_field, no_depth_of_field) = switch(
            self.depth_of_field,
            self.no_depth_of_field,
            base.depth_of_field,
            base.no_depth_of_field,
        );
        let mut mistakes = base.mistakes.clone();
        for m in self.mistakes {
            if !mistakes.contains(&m) {
                mistakes.push(m);
            }
        }
        RenderArgs {
            width: self.width.or(base.width),
            height: self.height.or(base.height),
            spp: self.spp.or(base.spp),
            sampler: self.sampler.or_else(|| base.sampler.clone()),
            filter: self.filter.or_else(|| base.filter.clone()),
            subsample: self.subsample.or(base.subsample),
            adaptive_threshold: self.adaptive_threshold.or(base.adaptive_threshold),
            max_depth: self.max_depth.or(base.max_depth),
            seed: self.seed.or(base.seed),
            encoding: self.encoding.or_else(|| base.encoding.clone()),
            accel: self.accel.or_else(|| base.accel.clone()),
            traversal: self.traversal.or_else(|| base.traversal.clone()),
            no_shadows,
            no_reflections,
            no_refractions,
            no_textures,
            no_depth_of_field,
            max_rays: self.max_rays.or(base.max_rays),
            course_stage: self.course_stage.or_else(|| base.course_stage.clone()),
            texture_filter: self.texture_filter.or_else(|| base.texture_filter.clone()),
            shadows,
            reflections,
            refractions,
            textures,
            depth_of_field,
            quiet: self.quiet || base.quiet,
            mistakes,
        }
    }

    /// These options again as command-line flags (" --spp 4 --no-shadows"), so a printed
    /// `rtlab explain` command sees the same image. The destructuring is exhaustive: a new
    /// option does not compile until it is written back here too.
    pub fn to_flags(&self) -> String {
        let RenderArgs {
            width,
            height,
            spp,
            sampler,
            filter,
            subsample,
            adaptive_threshold,
            max_depth,
            seed,
            encoding,
            accel,
            traversal,
            no_shadows,
            no_reflections,
            no_refractions,
            no_textures,
            no_depth_of_field,
            max_rays,
            course_stage,
            texture_filter,
            shadows,
            reflections,
            refractions,
            textures,
            depth_of_field,
            quiet: _,
            mistakes,
        } = self;
        let mut f = String::new();
        let mut opt = |name: &str, v: Option<String>| {
            if let Some(v) = v {
                f += &format!(" --{name} {}", shell_word(&v));
            }
        };
        let text = |v: &Option<u32>| v.map(|v| v.to_string());
        opt("width", text(width));
        opt("height", text(height));
        opt("spp", text(spp));
        opt("sampler", sampler.clone());
        opt("filter", filter.clone());
        opt("subsample", text(subsample));
        opt(
            "adaptive-threshold",
            adaptive_threshold.map(|v| v.to_string()),
        );
        opt("max-depth", text(max_depth));
        opt("seed", seed.map(|v| v.to_string()));
        opt("encoding", encoding.clone());
        opt("accel", accel.clone());
        opt("traversal", traversal.clone());
        opt("max-rays", max_rays.map(|v| v.to_string()));
        opt("course-stage", course_stage.clone());
        opt("texture-filter", texture_filter.clone());
        for m in mistakes {
            opt("mistake", Some(m.clone()));
        }
        for (on, name) in [
            (*no_shadows, "no-shadows"),
            (*no_reflections, "no-reflections"),
            (*no_refractions, "no-refractions"),
            (*no_textures, "no-textures"),
            (*no_depth_of_field, "no-depth-of-field"),
            (*shadows, "shadows"),
            (*reflections, "reflections"),
            (*refractions, "refractions"),
            (*textures, "textures"),
            (*depth_of_field, "depth-of-field"),
        ] {
            if on {
                f += &format!(" --{name}");
            }
        }
        f
    }

    /// Refuses, before anything is allocated, a render of `spp` samples per pixel that would
    /// not fit in memory; the message names the arguments when they set the size.
    pub fn check_memory(&self, scene: &Scene, path: &std::path::Path, spp: u32) -> Result<()> {
        let (w, h) = (scene.camera.width, scene.camera.height);
        crate::sampling::check_memory(w, h, scene.render.sampler, spp, scene.render.subsample)
            .map_err(|m| self.memory_error(path, m))
    }

    /// [`RenderArgs::check_memory`] for an AOV of the scene rendered with `settings`.
    pub fn check_aov_memory(
        &self,
        scene: &Scene,
        path: &std::path::Path,
        settings: &crate::scene::RenderSettings,
    ) -> Result<()> {
        let (w, h) = (scene.camera.width, scene.camera.height);
        crate::sampling::aov::check_memory(w, h, settings).map_err(|m| self.memory_error(path, m))
    }

    /// Too much memory: the arguments' fault when they set the size, else the scene's.
    fn memory_error(&self, path: &std::path::Path, m: String) -> Error {
        if self.width.is_some() || self.height.is_some() || self.spp.is_some() {
            Error::arg("--width/--height/--spp", m)
        } else {
            Error::input(path, "camera", m)
        }
    }

    /// Loads the scene (a scene file or a course `.ini`) and applies these options to it;
    /// the load's warnings go to stderr once, unless `quiet`.
    pub fn load(&self, path: &std::path::Path) -> Result<Scene> {
        let loaded = self.load_full(path)?;
        self.warn(&loaded.warnings);
        Ok(loaded.scene)
    }

    /// Prints warnings on stderr unless `quiet`.
    pub fn warn(&self, warnings: &[String]) {
        if !self.quiet {
            for w in warnings {
                eprintln!("warning: {w}");
            }
        }
    }

    /// [`RenderArgs::load`] without printing: the scene, its warnings (the lights a course
    /// stage ignores among them), the stage and the ini's output path.
    pub fn load_full(&self, path: &std::path::Path) -> Result<Loaded> {
        // Cheap argument checks first, so a typo is reported before a long load.
        self.check()?;
        let mut loaded = crate::scene::open(path, self.stage())?;
        self.apply(&mut loaded.scene)?;
        if self.adaptive_threshold.is_some()
            && loaded.scene.render.sampler != crate::scene::SamplerKind::Adaptive
        {
            loaded.warnings.push(format!(
                "--adaptive-threshold has no effect: the sampler is {}, not adaptive",
                loaded.scene.render.sampler.name()
            ));
        }
        if loaded.stage == Some(CourseStage::Intersect) {
            loaded
                .warnings
                .extend(crate::scene::ignored_lights_note(&loaded.scene));
        }
        Ok(loaded)
    }

    fn stage(&self) -> Option<CourseStage> {
        self.course_stage
            .as_deref()
            .map(|s| CourseStage::parse(s).expect("checked"))
    }

    fn check(&self) -> Result<()> {
        if let Some(s) = &self.course_stage {
            CourseStage::parse(s).ok_or_else(|| {
                Error::arg(
                    "--course-stage",
                    format!("unknown course stage \"{s}\" (expected intersect or illuminate)"),
                )
            })?;
        }
        if let Some(s) = &self.texture_filter {
            TextureFilter::parse(s).ok_or_else(|| {
                Error::arg(
                    "--texture-filter",
                    format!("unknown texture filter \"{s}\" (expected nearest or bilinear)"),
                )
            })?;
        }
        if let Some(s) = &self.sampler {
            SamplerKind::parse(s).ok_or_else(|| {
                Error::arg(
                    "--sampler",
                    format!(
                        "unknown sampler \"{s}\" (expected one of: {})",
                        SamplerKind::NAMES.join(", ")
                    ),
                )
            })?;
        }
        if let Some(s) = &self.filter {
            FilterKind::parse(s).ok_or_else(|| {
                Error::arg(
                    "--filter",
                    format!(
                        "unknown filter \"{s}\" (expected one of: {})",
                        FilterKind::NAMES.join(", ")
                    ),
                )
            })?;
        }
        if let Some(k) = self.subsample {
            if !(1..=64).contains(&k) {
                return Err(Error::arg(
                    "--subsample",
                    format!("{k} is out of range (1 traces every pixel; at most 64)"),
                ));
            }
        }
        if let Some(t) = self.adaptive_threshold {
            if !(t.is_finite() && t >= 0.0) {
                return Err(Error::arg(
                    "--adaptive-threshold",
                    format!("{t} is not a colour difference (expected a number ≥ 0, e.g. 0.1)"),
                ));
            }
        }
        if let Some(e) = &self.encoding {
            if e != "clamp" && e != "srgb" {
                return Err(Error::arg(
                    "--encoding",
                    format!("unknown encoding \"{e}\" (expected clamp or srgb)"),
                ));
            }
        }
        if let Some(a) = &self.accel {
            AccelKind::parse(a).ok_or_else(|| {
                Error::arg(
                    "--accel",
                    format!("unknown accelerator \"{a}\" (expected linear or bvh)"),
                )
            })?;
        }
        if let Some(t) = &self.traversal {
            Traversal::parse(t).ok_or_else(|| {
                Error::arg(
                    "--traversal",
                    format!("unknown traversal \"{t}\" (expected single or bundle)"),
                )
            })?;
        }
        if let Some(d) = self.max_depth {
            if d > crate::scene::native_max_depth() {
                return Err(Error::arg(
                    "--max-depth",
                    format!(
                        "{d} is too deep (at most {})",
                        crate::scene::native_max_depth()
                    ),
                ));
            }
        }
        if let (Some(w), Some(h)) = (self.width, self.height) {
            check_size(w, h).map_err(|m| Error::arg("--width/--height", m))?;
        }
        self.mistake_set()?;
        Ok(())
    }

    /// The `--mistake` names as a set (unknown names: an argument error naming the nearest).
    pub fn mistake_set(&self) -> Result<crate::mistakes::Mistakes> {
        let mut set = crate::mistakes::Mistakes::NONE;
        for list in &self.mistakes {
            let more = crate::mistakes::Mistake::parse_list(list)
                .map_err(|m| Error::arg("--mistake", m))?;
            set = set.iter().chain(more.iter()).collect();
        }
        Ok(set)
    }

    pub fn apply(&self, scene: &mut Scene) -> Result<()> {
        let r = &mut scene.render;
        if let Some(s) = &self.sampler {
            r.sampler = SamplerKind::parse(s).expect("checked");
        }
        if let Some(s) = &self.filter {
            r.filter = FilterKind::parse(s).expect("checked");
        }
        if let Some(n) = self.spp {
            r.spp = n;
        }
        crate::sampling::validate_spp(r.sampler, r.spp).map_err(|m| match self.spp {
            Some(_) => Error::arg("--spp", m),
            // The count is the scene's: the sampler chosen here does not take it.
            None => Error::arg(
                "--sampler",
                format!(
                    "{m} (the {} is the scene's spp: give --spp with --sampler)",
                    r.spp
                ),
            ),
        })?;
        if let Some(d) = self.max_depth {
            r.max_depth = d;
        }
        if let Some(k) = self.subsample {
            r.subsample = k;
        }
        if let Some(t) = self.adaptive_threshold {
            r.adaptive_threshold = t;
        }
        if let Some(s) = self.seed {
            r.seed = s;
        }
        if let Some(n) = self.max_rays {
            r.max_rays = n;
        }
        if let Some(e) = &self.encoding {
            r.encoding = if e == "srgb" {
                Encoding::Srgb
            } else {
                Encoding::Clamp
            };
        }
        // Explicit switches win over the scene, the stage and the ini, in both directions
        // (clap refuses a switch given with its negation).
        let set = |v: &mut bool, on: bool, off: bool| {
            *v = (*v || on) && !off;
        };
        set(&mut r.shadows, self.shadows, self.no_shadows);
        set(&mut r.reflections, self.reflections, self.no_reflections);
        set(&mut r.refractions, self.refractions, self.no_refractions);
        set(&mut r.textures, self.textures, self.no_textures);
        set(
            &mut r.depth_of_field,
            self.depth_of_field,
            self.no_depth_of_field,
        );
        if let Some(f) = &self.texture_filter {
            r.texture_filter = TextureFilter::parse(f).expect("checked");
        }
        if let Some(t) = &self.traversal {
            r.traversal = Traversal::parse(t).expect("checked");
        }
        r.mistakes = r
            .mistakes
            .iter()
            .chain(self.mistake_set()?.iter())
            .collect();
        let (w, h) = (
            self.width.unwrap_or(scene.camera.width),
            self.height.unwrap_or(scene.camera.height),
        );
        check_size(w, h).map_err(|m| Error::arg("--width/--height", m))?;
        if (w, h) != (scene.camera.width, scene.camera.height) {
            scene.camera.update_size(w, h);
        }
        if let Some(a) = &self.accel {
            let kind = AccelKind::parse(a).expect("checked");
            if kind != scene.render.accel {
                scene.render.accel = kind;
                scene.rebuild_accel();
            }
        }
        Ok(())
    }
}

/// `--max-rays N`: 1 (the camera ray) to 4,294,967,295, the range a scene's `max_rays` takes.
fn ray_budget(s: &str) -> std::result::Result<u64, String> {
    match s.trim().parse::<i128>() {
        Ok(n) if n < 1 => Err(
            "must be at least 1 (the camera ray): it is the most rays one sample may trace".into(),
        ),
        Ok(n) if n > u32::MAX as i128 => Err(format!(
            "{n} is more than {}, the most a scene's max_rays takes",
            u32::MAX
        )),
        Ok(n) => Ok(n as u64),
        Err(_) => Err(format!("\"{s}\" is not a number of rays")),
    }
}
