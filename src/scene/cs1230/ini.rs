//! The course's `.ini` files (its project template's `template_inis/<stage>/<scene>.ini`):
//! which scenefile to render, where to write it, the canvas size and the feature switches.
//!
//! ```ini
//! [IO]
//!     scene = scenefiles/intersect/required/unit_cone.json
//!     output = student_outputs/intersect/required/unit_cone.png
//! [Canvas]
//!     width = 1024
//!     height = 768
//! [Feature]
//!     shadows = false
//!     texture-filter = "nearest"
//! [Settings]
//!     maximum-recursive-depth = 4
//! ```
//!
//! Every key the course's files hold is accepted; those rtlab has no use for are reported
//! when they ask for something (`post-process = true`). Relative paths are tried against the
//! current folder, then against the project root (the folder holding `template_inis/`).

use super::stage::CourseStage;
use crate::error::{suggest, Error, Result};
use crate::scene::{check_size, Loaded, SamplerKind, Scene};
use crate::shading::TextureFilter;
use std::path::{Path, PathBuf};

/// The sections and their keys, as the course's files write them.
const SECTIONS: &[(&str, &[&str])] = &[
    ("IO", &["scene", "output"]),
    ("Canvas", &["width", "height"]),
    (
        "Feature",
        &[
            "shadows",
            "reflect",
            "refract",
            "texture",
            "texture-filter",
            "parallel",
            "super-sample",
            "samples-per-pixel",
            "num-samples",
            "super-sampler-pattern",
            "post-process",
            "acceleration",
            "depthoffield",
            "mipmapping",
            "mip-debug-colors",
        ],
    ),
    (
        "Settings",
        &[
            "maximum-recursive-depth",
            "samples-per-pixel",
            "num-samples",
            "super-sampler-pattern",
        ],
    ),
];

/// Is this a course ini file (by its extension)?
pub fn is_ini(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("ini"))
}

/// One `key = value` line.
#[derive(Debug, Clone)]
pub struct Entry {
    pub section: &'static str,
    pub key: &'static str,
    pub value: String,
    pub line: usize,
    /// 1-based columns of the key and of the value.
    pub key_col: usize,
    pub value_col: usize,
}

/// A parsed ini file: its entries, every key checked against the course's.
#[derive(Debug, Clone)]
pub struct Ini {
    pub file: PathBuf,
    pub entries: Vec<Entry>,
    pub warnings: Vec<String>,
}

impl Ini {
    /// Reads and parses an ini file.
    pub fn read(path: &Path) -> Result<Ini> {
        if path.is_dir() {
            return Err(Error::io(
                path,
                "is a directory, expected a course .ini file",
            ));
        }
        let bytes = crate::input::read_limited(path, crate::input::TEXT_LIMIT).map_err(|e| {
            Error::io(
                path,
                format!("cannot read ini file: {}", crate::scene::io_reason(&e)),
            )
        })?;
        let text = String::from_utf8(bytes).map_err(|_| {
            Error::input(
                path,
                "",
                "not a text file (invalid UTF-8): expected a course .ini file",
            )
        })?;
        Ini::parse(path, &text)
    }

    /// Parses ini text (`path` names the file in messages).
    pub fn parse(path: &Path, text: &str) -> Result<Ini> {
        let mut section: Option<&'static str> = None;
        let mut entries: Vec<Entry> = Vec::new();
        let mut warnings = Vec::new();
        let at = |l: usize, c: usize| format!("line {l}:{c}");
        for (i, raw) in text.lines().enumerate() {
            let line = i + 1;
            let raw = raw.strip_prefix('\u{feff}').unwrap_or(raw);
            let trimmed = raw.trim_start();
            let col = raw.len() - trimmed.len() + 1;
            let content = trimmed.trim_end();
            if content.is_empty() || content.starts_with(';') || content.starts_with('#') {
                continue;
            }
            if let Some(rest) = content.strip_prefix('[') {
                let Some(name) = rest.strip_suffix(']') else {
                    return Err(Error::input(
                        path,
                        at(line, col),
                        format!("a section header needs a closing \"]\": found {content}"),
                    ));
                };
                let name = name.trim();
                let names: Vec<&str> = SECTIONS.iter().map(|(s, _)| *s).collect();
                match SECTIONS.iter().find(|(s, _)| s.eq_ignore_ascii_case(name)) {
                    Some((s, _)) => section = Some(s),
                    None => {
                        let hint = suggest(name, &names)
                            .map(|s| format!("did you mean [{s}]? "))
                            .unwrap_or_default();
                        return Err(Error::input(
                            path,
                            at(line, col + 1),
                            format!(
                                "unknown section [{name}] ({hint}the course's ini files have: {})",
                                names
                                    .iter()
                                    .map(|s| format!("[{s}]"))
                                    .collect::<Vec<_>>()
                                    .join(", ")
                            ),
                        ));
                    }
                }
                continue;
            }
            let Some(eq) = content.find('=') else {
                return Err(Error::input(
                    path,
                    at(line, col),
                    format!("expected \"key = value\" or a [Section], found \"{content}\""),
                ));
            };
            let key = content[..eq].trim();
            let after = &content[eq + 1..];
            let value_col = col + eq + 1 + (after.len() - after.trim_start().len());
            let value = unquote(after.trim()).map_err(|m| {
                Error::input(
                    path,
                    at(line, value_col),
                    format!("[{}] {key}: {m}", section.unwrap_or("?")),
                )
            })?;
            let Some(sec) = section else {
                return Err(Error::input(
                    path,
                    at(line, col),
                    format!("key \"{key}\" comes before any [Section] (expected [IO], [Canvas], [Feature] or [Settings] first)"),
                ));
            };
            let keys = SECTIONS.iter().find(|(s, _)| *s == sec).expect("known").1;
            let Some(k) = keys.iter().copied().find(|k| k.eq_ignore_ascii_case(key)) else {
                let hint = suggest(key, keys)
                    .map(|s| format!(" (did you mean \"{s}\"?)"))
                    .unwrap_or_else(|| format!(" (expected one of: {})", keys.join(", ")));
                return Err(Error::input(
                    path,
                    at(line, col),
                    format!("unknown key \"{key}\" in [{sec}]{hint}"),
                ));
            };
            if let Some(old) = entries.iter().find(|e| e.section == sec && e.key == k) {
                warnings.push(format!(
                    "{}: line {line}: [{sec}] {k} is set twice (first on line {}): the later value is used",
                    path.display(),
                    old.line
                ));
                entries.retain(|e| !(e.section == sec && e.key == k));
            }
            entries.push(Entry {
                section: sec,
                key: k,
                value: value.to_string(),
                line,
                key_col: col,
                value_col,
            });
        }
        Ok(Ini {
            file: path.to_path_buf(),
            entries,
            warnings,
        })
    }

    /// The entry of a key (in any of the sections that hold it; the last one given wins).
    pub fn get(&self, section: &str, key: &str) -> Option<&Entry> {
        self.entries
            .iter()
            .rev()
            .find(|e| e.section == section && e.key == key)
    }

    fn get_any(&self, key: &str) -> Option<&Entry> {
        self.entries.iter().rev().find(|e| e.key == key)
    }

    fn err(&self, e: &Entry, msg: impl Into<String>) -> Error {
        Error::input(
            &self.file,
            format!("line {}:{}", e.line, e.value_col),
            format!("[{}] {}: {}", e.section, e.key, msg.into()),
        )
    }

    fn bool(&self, e: &Entry) -> Result<bool> {
        match e.value.to_ascii_lowercase().as_str() {
            "true" | "1" | "yes" | "on" => Ok(true),
            "false" | "0" | "no" | "off" => Ok(false),
            _ => Err(self.err(
                e,
                format!("expected true or false, found {}", shown(&e.value)),
            )),
        }
    }

    fn flag(&self, section: &str, key: &str) -> Result<Option<bool>> {
        self.get(section, key).map(|e| self.bool(e)).transpose()
    }

    fn uint(&self, e: &Entry) -> Result<u32> {
        e.value.parse::<u32>().map_err(|_| {
            // A whole number too big is still a whole number: say what is wrong with it.
            let digits = !e.value.is_empty() && e.value.bytes().all(|c| c.is_ascii_digit());
            let msg = match digits {
                true => format!("{} is too large a number (more than {})", e.value, u32::MAX),
                false => format!("expected a whole number ≥ 0, found {}", shown(&e.value)),
            };
            self.err(e, msg)
        })
    }

    fn note(&self, e: &Entry, msg: &str) -> String {
        format!(
            "{}: line {}: [{}] {} = {}: {msg}",
            self.file.display(),
            e.line,
            e.section,
            e.key,
            clipped(&e.value)
        )
    }
}

/// `"x"` or `'x'` → `x`; a quote at one end only is a mistake.
fn unquote(v: &str) -> std::result::Result<&str, String> {
    for q in ['"', '\''] {
        if v.len() >= 2 && v.starts_with(q) && v.ends_with(q) {
            return Ok(&v[1..v.len() - 1]);
        }
        if v.starts_with(q) || v.ends_with(q) {
            return Err(format!("{} has a quote ({q}) at one end only", shown(v)));
        }
    }
    Ok(v)
}

/// A value as messages quote it: at most 60 characters (a value pasted by mistake may be
/// a page long).
fn shown(v: &str) -> String {
    format!("\"{}\"", clipped(v))
}

/// At most 60 characters of `v`, and how long it is when it is longer.
fn clipped(v: &str) -> String {
    const MOST: usize = 60;
    if v.chars().count() <= MOST {
        v.to_string()
    } else {
        let head: String = v.chars().take(MOST).collect();
        format!("{head}… ({} characters)", v.chars().count())
    }
}

/// The course project's root for an ini: the nearest folder above it that holds
/// `template_inis/`, if any.
pub fn project_root(ini: &Path) -> Option<PathBuf> {
    // The path as given first (messages then show relative paths), then the absolute one.
    let dir = ini.parent().unwrap_or(Path::new(""));
    if let Some(a) = dir.ancestors().find(|a| a.join("template_inis").is_dir()) {
        return Some(a.to_path_buf());
    }
    let abs = ini.canonicalize().ok()?;
    abs.parent()?
        .ancestors()
        .find(|a| a.join("template_inis").is_dir())
        .map(Path::to_path_buf)
}

/// The stage the ini's folder names: `template_inis/intersect/…` or `…/illuminate/…`.
pub fn folder_stage(ini: &Path) -> Option<CourseStage> {
    let abs = ini.canonicalize().unwrap_or_else(|_| ini.to_path_buf());
    let parts: Vec<String> = abs
        .parent()?
        .components()
        .map(|c| c.as_os_str().to_string_lossy().to_string())
        .collect();
    // The folder right under template_inis/, else the ini's own folder.
    let under = parts
        .iter()
        .position(|p| p == "template_inis")
        .and_then(|i| parts.get(i + 1));
    under
        .and_then(|p| CourseStage::parse(p))
        .or_else(|| parts.last().and_then(|p| CourseStage::parse(p)))
}

/// Opens an ini: its scenefile, with the stage and the ini's settings applied (see
/// [`crate::scene::open`] for the order).
pub fn open(path: &Path, stage: Option<CourseStage>) -> Result<Loaded> {
    let ini = Ini::read(path)?;
    // No template_inis/ above the ini: its own folder stands in for the project root.
    let (root, root_name) = match project_root(path) {
        Some(r) => (
            r,
            "from the project root, the folder holding template_inis/",
        ),
        None => (
            path.parent().unwrap_or(Path::new("")).to_path_buf(),
            "from the ini's folder: no template_inis/ folder above it",
        ),
    };
    let scene_entry = ini.get("IO", "scene").ok_or_else(|| {
        Error::input(
            path,
            "[IO]",
            "no scene: the ini needs \"scene = path/to/scenefile.json\" under [IO]",
        )
    })?;
    // Tried against the current folder first, then the project root; the folder that
    // found the scene is also where the output goes.
    if scene_entry.value.is_empty() {
        return Err(ini.err(
            scene_entry,
            "is empty: give the scenefile, e.g. scene = scenefiles/unit_sphere.json",
        ));
    }
    let rel = Path::new(&scene_entry.value);
    if let Some(dir) = [rel.to_path_buf(), root.join(rel)]
        .into_iter()
        .find(|p| p.is_dir())
    {
        return Err(ini.err(
            scene_entry,
            format!("{} is a folder, not a scenefile (.json)", dir.display()),
        ));
    }
    let (scene_path, base) = if rel.is_absolute() || rel.is_file() {
        (rel.to_path_buf(), PathBuf::new())
    } else if root.join(rel).is_file() {
        (root.join(rel), root.clone())
    } else {
        let also = if root.as_os_str().is_empty() {
            String::new()
        } else {
            format!(" and {} ({root_name})", root.join(rel).display())
        };
        return Err(ini.err(
            scene_entry,
            format!(
                "scenefile not found: tried {} (from the current folder){also}",
                rel.display(),
            ),
        ));
    };
    if is_ini(&scene_path) {
        return Err(ini.err(
            scene_entry,
            "the scene of an ini must be a scenefile (.json), not another ini",
        ));
    }
    let (mut scene, mut warnings) = Scene::load_reporting(&scene_path)?;
    warnings.extend(ini.warnings.iter().cloned());
    let stage = stage.or_else(|| folder_stage(path));
    if let Some(st) = stage {
        st.apply(&mut scene.render);
    }
    apply(&ini, &mut scene, &mut warnings)?;
    if let Some(e) = ini.get("IO", "output") {
        if let Some(msg) = crate::output::wrong_extension(Path::new(&e.value), "png", "images") {
            return Err(ini.err(e, msg));
        }
    }
    let output = ini.get("IO", "output").map(|e| {
        let p = Path::new(&e.value);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            base.join(p)
        }
    });
    Ok(Loaded {
        scene,
        warnings,
        stage,
        output,
    })
}

/// The ini's keys over the scene's (and the stage's) settings.
fn apply(ini: &Ini, scene: &mut Scene, warnings: &mut Vec<String>) -> Result<()> {
    let r = &mut scene.render;
    if let Some(v) = ini.flag("Feature", "shadows")? {
        r.shadows = v;
    }
    if let Some(v) = ini.flag("Feature", "reflect")? {
        r.reflections = v;
    }
    if let Some(v) = ini.flag("Feature", "refract")? {
        r.refractions = v;
    }
    if let Some(v) = ini.flag("Feature", "texture")? {
        r.textures = v;
    }
    if let Some(v) = ini.flag("Feature", "depthoffield")? {
        r.depth_of_field = v;
    }
    if let Some(e) = ini.get("Feature", "texture-filter") {
        match e.value.to_ascii_lowercase().as_str() {
            "nearest" => r.texture_filter = TextureFilter::Nearest,
            "bilinear" => r.texture_filter = TextureFilter::Bilinear,
            "trilinear" => {
                r.texture_filter = TextureFilter::Bilinear;
                warnings.push(ini.note(
                    e,
                    "rtlab has no mipmaps: bilinear filtering is used instead",
                ));
            }
            _ => warnings.push(ini.note(
                e,
                "not a filter name (nearest, bilinear or trilinear): the scene's filter is kept",
            )),
        }
    }
    if let Some(e) = ini.get("Settings", "maximum-recursive-depth") {
        let d = ini.uint(e)?;
        if d > crate::scene::native_max_depth() {
            return Err(ini.err(
                e,
                format!(
                    "{d} is too deep (at most {})",
                    crate::scene::native_max_depth()
                ),
            ));
        }
        r.max_depth = d;
    }
    if ini.flag("Feature", "super-sample")? == Some(true) {
        let n = ini
            .get_any("samples-per-pixel")
            .or_else(|| ini.get_any("num-samples"));
        let spp = match n {
            Some(e) => ini.uint(e)?,
            None => 1,
        };
        let pattern = ini.get_any("super-sampler-pattern");
        let square = ((spp as f64).sqrt().round() as u32).pow(2) == spp;
        let name = pattern.map(|e| e.value.to_ascii_lowercase());
        let sampler = match name.as_deref() {
            Some("random") => SamplerKind::Random,
            Some("jittered" | "stratified") => SamplerKind::Jittered,
            _ if square => SamplerKind::Grid,
            _ => SamplerKind::Random,
        };
        // Say so when the pattern named is not the one used.
        if let Some(e) = pattern {
            match name.as_deref() {
                Some("random" | "jittered" | "stratified") => {}
                Some("grid") if square => {}
                Some("grid") => warnings.push(ini.note(
                    e,
                    &format!("{spp} samples make no square grid: random samples are used"),
                )),
                _ => warnings.push(ini.note(
                    e,
                    &format!(
                        "not a pattern rtlab knows (grid, jittered or random): {} samples are used",
                        sampler.name()
                    ),
                )),
            }
        }
        if let Some(e) = n {
            crate::sampling::validate_spp(sampler, spp).map_err(|m| ini.err(e, m))?;
        }
        r.spp = spp;
        r.sampler = sampler;
    }
    for (key, why) in [
        (
            "post-process",
            "rtlab has no post-processing filter: no effect",
        ),
        ("mipmapping", "rtlab has no mipmaps: no effect"),
        ("mip-debug-colors", "rtlab has no mipmaps: no effect"),
    ] {
        if let Some(e) = ini.get("Feature", key) {
            if ini.bool(e)? {
                warnings.push(ini.note(e, why));
            }
        }
    }
    // `parallel` and `acceleration` change how fast, not what: rtlab always renders on
    // every core, with the BVH unless --accel linear; checked, nothing to say.
    for key in ["parallel", "acceleration"] {
        if let Some(e) = ini.get("Feature", key) {
            ini.bool(e)?;
        }
    }
    let (w, h) = (scene.camera.width, scene.camera.height);
    let width = ini
        .get("Canvas", "width")
        .map(|e| ini.uint(e).map(|v| (v, e)))
        .transpose()?;
    let height = ini
        .get("Canvas", "height")
        .map(|e| ini.uint(e).map(|v| (v, e)))
        .transpose()?;
    let (nw, nh) = (width.map_or(w, |x| x.0), height.map_or(h, |x| x.0));
    if let Err(m) = check_size(nw, nh) {
        let e = width.or(height).expect("size changed").1;
        return Err(ini.err(e, m));
    }
    if (nw, nh) != (w, h) {
        scene.camera.update_size(nw, nh);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Ini> {
        Ini::parse(Path::new("x.ini"), text)
    }

    #[test]
    fn a_byte_order_mark_is_skipped() {
        let ini = parse("\u{feff}[IO]\n    scene = a.json\n").unwrap();
        assert_eq!(ini.get("IO", "scene").unwrap().value, "a.json");
    }

    #[test]
    fn reads_the_course_layout() {
        let ini = parse(
            "[IO]\n    scene = a/b.json\n    output = \"out/b.png\"\n\n[Feature]\n  shadows = false\n  texture-filter = 'bilinear'\n; a comment\n[Settings]\n  maximum-recursive-depth = 4\n",
        )
        .unwrap();
        assert_eq!(ini.get("IO", "scene").unwrap().value, "a/b.json");
        assert_eq!(ini.get("IO", "output").unwrap().value, "out/b.png");
        assert_eq!(
            ini.get("Feature", "texture-filter").unwrap().value,
            "bilinear"
        );
        let e = ini.get("Settings", "maximum-recursive-depth").unwrap();
        assert_eq!((e.line, e.key_col, e.value_col), (10, 3, 29));
    }

    #[test]
    fn errors_name_line_column_and_the_nearest_key() {
        let e = parse("[Feature]\n  shadow = true\n")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "x.ini: line 2:3: unknown key \"shadow\" in [Feature] (did you mean \"shadows\"?)"
        );
        let e = parse("[Featur]\n").unwrap_err().to_string();
        assert!(
            e.starts_with("x.ini: line 1:2: unknown section [Featur] (did you mean [Feature]?"),
            "{e}"
        );
        let e = parse("shadows = true\n").unwrap_err().to_string();
        assert!(
            e.contains("line 1:1: key \"shadows\" comes before any [Section]"),
            "{e}"
        );
        let e = parse("[IO]\n scene\n").unwrap_err().to_string();
        assert!(e.contains("line 2:2: expected \"key = value\""), "{e}");
        let ini = parse("[Feature]\n shadows = maybe\n").unwrap();
        let e = ini
            .bool(ini.get("Feature", "shadows").unwrap())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "x.ini: line 2:12: [Feature] shadows: expected true or false, found \"maybe\""
        );
    }
}
