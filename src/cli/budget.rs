//! `rtlab render --time-budget` and `--passes`: the passes a budget runs, each pass's
//! settings, and what is said of the pass reached.

use crate::error::{Error, Result};
use crate::sampling::aov::Aov;
use crate::sampling::progressive::{describe, pass_settings, progressive_with, PassOf};

/// The settings of progressive pass `k`, or an argument error saying why it cannot be made.
pub(super) fn pass_of(scene: &crate::scene::Scene, k: u32) -> Result<crate::scene::RenderSettings> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    pass_settings(&scene.render, w, h, k).map_err(|m| Error::arg("--passes", m))
}

/// The pass a budget reached, for stderr once the image is written: why the sequence ended
/// when it ended before the budget or the cap (`max`), and the `--passes K` that gives the
/// same image.
pub(super) fn reached_lines<T>(
    scene: &crate::scene::Scene,
    pass: &PassOf<T>,
    max: Option<u32>,
    aov: Option<Aov>,
) -> Vec<String> {
    let mut lines = Vec::new();
    if max.is_none_or(|cap| pass.index < cap) {
        let (w, h) = (scene.camera.width, scene.camera.height);
        let k = pass.index + 1;
        let next = pass_settings(&scene.render, w, h, k);
        let next = match aov {
            Some(_) => next.and_then(|p| aov_fits(scene, &p).map_err(|m| format!("pass {k}: {m}"))),
            None => next.map(|_| ()),
        };
        if let Err(why) = next {
            lines.push(format!("the passes end at pass {} ({why})", pass.index));
        }
    }
    lines.push(format!(
        "passes: {k} ({}); the same image: --passes {k}",
        describe(&pass.settings),
        k = pass.index
    ));
    lines
}

/// Whether an AOV with `settings` fits in memory (an AOV keeps every sample).
pub(super) fn aov_fits(
    scene: &crate::scene::Scene,
    settings: &crate::scene::RenderSettings,
) -> std::result::Result<(), String> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    crate::sampling::aov::check_memory(w, h, settings)
}

/// Passes 1, 2, ... until `budget` seconds have gone (the first pass always completes) or
/// `max` passes are done, each made by `render` (the colour render, or an AOV's); says on
/// stderr when each pass is complete (unless quiet). `bar`, the terminal's progress bar
/// that `render` advances, starts again at each pass, named by it, and the pass lines are
/// printed above it.
pub(super) fn budgeted<T>(
    scene: &crate::scene::Scene,
    budget: f64,
    max: Option<u32>,
    quiet: bool,
    bar: Option<&indicatif::ProgressBar>,
    mut render: impl FnMut(&crate::scene::RenderSettings, &(dyn Fn() -> bool + Sync)) -> Option<T>,
) -> Option<PassOf<T>> {
    // The time is up when `deadline` is cancelled, by a timer thread: a flag is cheaper to
    // ask than the clock. Every pass's settings watch it, so a running pass stops within
    // a few rays (the tracer looks every CHECK_EVERY rays, the renderer at every pixel and
    // every sample of a bundle), as it does for Ctrl-C. The timer first waits for pass 1,
    // which always completes, then for what is left of the budget, and gives up when the
    // passes end first (`finished` dropped).
    let deadline = crate::interrupt::Cancel::new();
    let timer = deadline.clone();
    let budget = std::time::Duration::from_secs_f64(budget.min(1e9));
    let start = std::time::Instant::now();
    let (finished, done) = std::sync::mpsc::channel::<u32>();
    let timer = std::thread::spawn(move || {
        use std::sync::mpsc::RecvTimeoutError::{Disconnected, Timeout};
        if done.recv().is_err() {
            return; // no pass completed: Ctrl-C
        }
        loop {
            match done.recv_timeout(budget.saturating_sub(start.elapsed())) {
                Ok(_) => continue,
                Err(Timeout) => return timer.cancel(),
                Err(Disconnected) => return,
            }
        }
    });
    let base = crate::scene::RenderSettings {
        cancel: scene.render.cancel.or(&deadline),
        ..scene.render.clone()
    };
    // The passes come in order, 1, 2, ...: the bar names the one it counts.
    let mut pass = 0;
    let render = |settings: &crate::scene::RenderSettings, stop: &(dyn Fn() -> bool + Sync)| {
        pass += 1;
        if let Some(bar) = bar {
            bar.reset();
            bar.set_prefix(format!("rendering pass {pass}"));
        }
        render(settings, stop)
    };
    let last = progressive_with(
        scene,
        &base,
        max,
        &|k| k > 1 && deadline.is_cancelled(),
        render,
        |p| {
            if !quiet {
                let line = format!(
                    "pass {}: {} done at {:.2} s",
                    p.index,
                    describe(&p.settings),
                    p.finished
                );
                match bar {
                    Some(bar) => bar.println(line),
                    None => eprintln!("{line}"),
                }
            }
            let _ = finished.send(p.index);
            // Spent already (a pass that ended past the budget, pass 1 above all): stop here,
            // before the next pass starts, rather than whenever the timer thread runs.
            if start.elapsed() >= budget {
                deadline.cancel();
            }
        },
    );
    drop(finished);
    timer.join().expect("the budget's timer does not panic");
    last
}
