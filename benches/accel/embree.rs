//! Embree's harness (`../shared/bench/embree`), run as a child process and read back.

use crate::{H, W};
use std::path::Path;
use std::process::Command;

#[derive(Default)]
pub struct EmbreeRun {
    pub build_ms: f64,
    pub single: f64,
    pub packet8: f64,
    pub packet16: f64,
    pub hits: u64,
    pub sum_t: f64,
    pub shadow: f64,
    pub shadow_rays: u64,
    pub occluded: u64,
    pub peak_mib: f64,
    /// Hit (true) or miss per pixel, from its depth image.
    pub mask: Vec<bool>,
}

/// One run of the harness over `modes`, each mode timed `passes` times (its `--runs`, each
/// run building the BVH again) and reported as the median of those: the same number of
/// passes rtlab's side of the round takes its median of. Its peak memory counts every
/// mode's buffers, so the memory column comes from a run of `single,shadow` alone (the
/// modes it had before the packet modes were added).
pub fn run_embree(
    bin: &Path,
    obj: &Path,
    ppm: &Path,
    modes: &str,
    passes: usize,
) -> Option<EmbreeRun> {
    let out = Command::new(bin)
        .arg(obj)
        .args(["--size", "1280x720", "--threads", "2", "--runs"])
        .arg(passes.to_string())
        .args(["--modes", modes, "--ppm"])
        .arg(ppm)
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    let mut r = EmbreeRun::default();
    let num = |s: &str| s.trim_end_matches(',').parse::<f64>().ok();
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        let after = |key: &str| w.iter().position(|x| *x == key).and_then(|i| num(w[i + 1]));
        if line.starts_with("build_ms") {
            r.build_ms = after("median")?;
        } else if line.starts_with("single") {
            r.single = after("median")?;
            r.hits = w[w.iter().position(|x| *x == "hits")? + 1]
                .split('/')
                .next()?
                .parse()
                .ok()?;
            r.sum_t = after("sum_t")?;
        } else if line.starts_with("packet8") {
            r.packet8 = after("median")?;
        } else if line.starts_with("packet16") {
            r.packet16 = after("median")?;
        } else if line.starts_with("shadow") {
            r.shadow = after("median")?;
            r.shadow_rays = after("rays")? as u64;
            r.occluded = after("occluded")? as u64;
        } else if line.starts_with("peak_rss_mib") {
            r.peak_mib = after("peak_rss_mib")?;
        }
    }
    let bytes = std::fs::read(ppm).ok()?;
    let header = format!("P5\n{W} {H}\n255\n");
    if !bytes.starts_with(header.as_bytes()) {
        return None;
    }
    r.mask = bytes[header.len()..].iter().map(|&g| g != 0).collect();
    (r.mask.len() == W * H).then_some(r)
}
