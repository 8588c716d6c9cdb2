//! What the handlers share: the scene path, the loader, a small cache of loaded scenes, the
//! render streams (a newer render on a stream cancels the one still running), the watcher's
//! last word and the event channel the page listens to.

use super::Options;
use crate::error::{Error, Result};
use crate::interrupt::Cancel;
use crate::scene::Scene;
use serde::Serialize;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::SystemTime;

/// Turns render-option words (`["--spp=4", "--no-shadows"]`) into the loaded scene with those
/// options applied on top of the server's own (the CLI's parser and `RenderArgs::load`).
pub type Loader = Arc<dyn Fn(&[String]) -> Result<Scene> + Send + Sync>;

/// Turns the same words into the render options as command-line flags (the server's own
/// first), for the `rtlab explain` commands a diff report prints.
pub type Flags = Arc<dyn Fn(&[String]) -> Result<String> + Send + Sync>;

/// One render option as the page shows it: a switch (a flag) or a field with a value.
#[derive(Debug, Clone, Serialize)]
pub struct OptionInfo {
    /// The option's long name without dashes (also its query key): `spp`, `no-shadows`.
    pub name: String,
    pub help: String,
    /// A switch (`--no-shadows`) rather than an option with a value.
    pub flag: bool,
    /// The values the page offers (empty: free text).
    pub choices: Vec<String>,
    /// For free text that takes known names (`mistake`, a comma-separated list of them): the
    /// names, which the page suggests as you type.
    pub suggestions: Vec<String>,
}

/// Scenes kept loaded, by option words and file stamp.
const CACHE: usize = 6;

/// The most samples one request may ask for (width × height × spp): a lab server answers in
/// seconds, not hours.
pub const MAX_SAMPLES: u64 = 1 << 26;

type Stamp = Option<(SystemTime, u64)>;

/// A loaded scene, by the option words it was loaded with and its file's stamp.
type Cached = (Vec<String>, Stamp, Arc<Scene>);

/// The frames of `steps` (caption, PNG bytes), in order.
pub type Frames = Arc<Vec<(String, Vec<u8>)>>;

/// What the watcher last saw.
#[derive(Debug, Clone, Serialize)]
pub struct Status {
    /// Counts the scene file's good versions since the server started.
    pub version: u64,
    /// The error of the newest version, when it does not load (the page keeps the last good
    /// image).
    pub error: Option<String>,
}

pub struct State {
    pub scene_path: PathBuf,
    pub loader: Loader,
    pub flags: Flags,
    pub options: Vec<OptionInfo>,
    /// `Host` header values this server answers to.
    pub allowed_hosts: Vec<String>,
    cache: Mutex<Vec<Cached>>,
    streams: Mutex<HashMap<String, Cancel>>,
    pub status: Mutex<Status>,
    pub events: tokio::sync::broadcast::Sender<String>,
    /// Heavy work (renders, explanations) at most this many at a time; the rest wait.
    pub jobs: Arc<tokio::sync::Semaphore>,
    /// The steps frames (caption, PNG) of the last scene asked for.
    pub steps: Mutex<Option<(Arc<Scene>, Frames)>>,
}

impl State {
    pub fn new(opts: &Options, host: &str, port: u16) -> Result<State> {
        let scene = (opts.loader)(&[])?;
        check_samples(&scene)?;
        let mut allowed = vec![
            format!("127.0.0.1:{port}"),
            format!("localhost:{port}"),
            format!("[::1]:{port}"),
        ];
        let h = if host.contains(':') && !host.starts_with('[') {
            format!("[{host}]:{port}")
        } else {
            format!("{host}:{port}")
        };
        if !allowed.contains(&h) {
            allowed.push(h);
        }
        let (events, _) = tokio::sync::broadcast::channel(16);
        Ok(State {
            scene_path: opts.scene.clone(),
            loader: opts.loader.clone(),
            flags: opts.flags.clone(),
            options: opts.options.clone(),
            allowed_hosts: allowed,
            cache: Mutex::new(vec![(Vec::new(), stamp(&opts.scene), Arc::new(scene))]),
            streams: Mutex::new(HashMap::new()),
            status: Mutex::new(Status {
                version: 1,
                error: None,
            }),
            events,
            jobs: Arc::new(tokio::sync::Semaphore::new(2)),
            steps: Mutex::new(None),
        })
    }

    /// The scene with these option words, from the cache while the file is unchanged.
    pub fn scene(&self, words: &[String]) -> Result<Arc<Scene>> {
        let now = stamp(&self.scene_path);
        {
            let cache = lock(&self.cache);
            if let Some((_, _, s)) = cache.iter().find(|(w, st, _)| w == words && *st == now) {
                return Ok(s.clone());
            }
        }
        let scene = Arc::new((self.loader)(words)?);
        check_samples(&scene)?;
        let mut cache = lock(&self.cache);
        cache.retain(|(w, _, _)| w != words);
        cache.insert(0, (words.to_vec(), now, scene.clone()));
        cache.truncate(CACHE);
        Ok(scene)
    }

    /// Starts a render on `stream`: cancels the one still running there and returns the new
    /// one's token (for its settings to watch). No stream: a render nobody supersedes.
    pub fn supersede(&self, stream: Option<&str>) -> Cancel {
        let token = Cancel::new();
        if let Some(name) = stream {
            if let Some(old) = lock(&self.streams).insert(name.to_string(), token.clone()) {
                old.cancel();
            }
        }
        token
    }

    /// Ends a render started by [`State::supersede`], however it ended (finished, superseded,
    /// or its client gone): its token is cancelled, so a render still running stops, and its stream
    /// forgets it unless a newer render took the stream over.
    pub fn release(&self, stream: Option<&str>, token: &Cancel) {
        token.cancel();
        if let Some(name) = stream {
            let mut streams = lock(&self.streams);
            if streams.get(name).is_some_and(|t| t.is(token)) {
                streams.remove(name);
            }
        }
    }

    /// How many streams have a render running (for the tests).
    pub fn streams(&self) -> usize {
        lock(&self.streams).len()
    }

    pub fn status(&self) -> Status {
        lock(&self.status).clone()
    }
}

/// A poisoned lock (a panic elsewhere) still holds usable data here.
pub fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// The file's modification time and size (changes on every save).
pub fn stamp(path: &std::path::Path) -> Stamp {
    let m = std::fs::metadata(path).ok()?;
    Some((m.modified().ok()?, m.len()))
}

fn check_samples(scene: &Scene) -> Result<()> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    check_count(
        samples(w, h, &scene.render),
        "--width/--height/--spp",
        &render_words(w, h, &scene.render),
        "rtlab render",
    )
}

/// The samples a render of `w` × `h` pixels with `r` traces and filters
/// ([`crate::sampling::samples_at_most`]: two a pixel and the right and bottom borders
/// under the corners sampler, each pixel's samples under every other, all the adaptive
/// sampler's levels counted). A subsampled render traces fewer pixels, but every pixel is
/// still filtered from a traced pixel's samples, so it is counted as if every pixel traced.
pub fn samples(w: u32, h: u32, r: &crate::scene::RenderSettings) -> u64 {
    crate::sampling::samples_at_most((w, h), r.sampler, r.spp, 1)
}

/// "1280×720 pixels × 64 spp (sampler adaptive: up to 4 + 16 + 64 = 84 a pixel)": the render
/// [`samples`] counts, for a refusal's message.
pub fn render_words(w: u32, h: u32, r: &crate::scene::RenderSettings) -> String {
    use crate::scene::SamplerKind;
    let most = crate::sampling::most_samples(r.sampler, r.spp);
    let note = match r.sampler {
        SamplerKind::Corners => {
            " (sampler corners: a centre and a corner a pixel, and the borders)".to_string()
        }
        SamplerKind::Adaptive if most > r.spp => {
            let levels: Vec<String> = std::iter::successors(Some(4u64), |l| Some(l * 4))
                .take_while(|&l| l <= r.spp as u64)
                .map(|l| l.to_string())
                .collect();
            format!(
                " (sampler adaptive: up to {} = {most} a pixel)",
                levels.join(" + ")
            )
        }
        _ => String::new(),
    };
    format!("{w}×{h} pixels × {} spp{note}", r.spp)
}

/// Refuses work of more than [`MAX_SAMPLES`] samples: `n` of them, described by `what`
/// (blamed on `arg`), for which `instead` is the command to run.
pub fn check_count(n: u64, arg: &str, what: &str, instead: &str) -> Result<()> {
    if n > MAX_SAMPLES {
        return Err(Error::arg(
            arg,
            format!(
                "{what} is {n} samples, more than the server traces for one request ({MAX_SAMPLES}); use {instead}"
            ),
        ));
    }
    Ok(())
}
