//! Progressive rendering: `--passes K` and `--time-budget SECONDS` make the same bytes for
//! the same K, on any thread count; the library yields each pass and can be cancelled.

use super::common::*;
use rtlab::sampling::progressive::{pass_settings, progressive};
use rtlab::sampling::render;

fn render_args<'a>(scene: &'a str, out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec![
        "render", scene, "-o", out, "--width", "64", "--height", "48",
    ];
    v.extend_from_slice(extra);
    v
}

/// Renders `scene` to `out` with `extra` (a time budget), and returns the pass K it printed
/// (`the same image: --passes K`) and its stderr.
fn budgeted(scene: &str, out: &std::path::Path, extra: &[&str]) -> (String, String) {
    let o = rtlab(&render_args(scene, out.to_str().unwrap(), extra));
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    let k: String = err
        .split("the same image: --passes ")
        .nth(1)
        .unwrap_or_else(|| panic!("no pass count on stderr: {err}"))
        .chars()
        .take_while(|c| c.is_ascii_digit())
        .collect();
    (k, err)
}

#[test]
fn budgeted_render_equals_passes_k_on_any_thread_count() {
    let scene = path("scenes/whitted.json");
    let s = scene.to_str().unwrap();
    let budget = tmp("budget.png");
    let (k, err) = budgeted(s, &budget, &["--time-budget", "0.3"]);
    assert!(k.parse::<u32>().unwrap() >= 1, "{err}");
    let want = std::fs::read(&budget).unwrap();
    for threads in ["1", "2"] {
        let out = tmp(&format!("passes-{threads}.png"));
        let o = rtlab(&render_args(
            s,
            out.to_str().unwrap(),
            &["--passes", &k, "--threads", threads, "--quiet"],
        ));
        assert!(o.status.success(), "{}", stderr(&o));
        assert!(
            std::fs::read(&out).unwrap() == want,
            "--passes {k} --threads {threads}"
        );
    }
    // A budget with a cap stops at the cap, and is then --passes of the cap.
    let capped = tmp("capped.png");
    let o = rtlab(&render_args(
        s,
        capped.to_str().unwrap(),
        &["--time-budget", "100", "--passes", "2", "--threads", "2"],
    ));
    assert!(
        stderr(&o).contains("the same image: --passes 2"),
        "{}",
        stderr(&o)
    );
    assert!(!stderr(&o).contains("the passes end"), "{}", stderr(&o));
    let plain = tmp("plain.png");
    let o = rtlab(&render_args(s, plain.to_str().unwrap(), &["--quiet"]));
    assert!(o.status.success());
    // Pass 2 is the scene's own settings: the plain render.
    assert!(std::fs::read(&capped).unwrap() == std::fs::read(&plain).unwrap());
}

/// An AOV under a budget is made pass by pass as the colour is (and stopped at the deadline
/// as the colour is): the image written is `--aov NAME --passes K`'s, K printed.
#[test]
fn a_budgeted_aov_equals_its_passes_k() {
    let scene = path("scenes/whitted.json");
    let s = scene.to_str().unwrap();
    let budget = tmp("budget-aov.png");
    let (k, err) = budgeted(s, &budget, &["--time-budget", "0.3", "--aov", "normal"]);
    assert!(err.contains("pass 1: "), "{err}");
    assert!(err.contains("normal: world-space surface normal"), "{err}");
    let out = tmp("passes-aov.png");
    let o = rtlab(&render_args(
        s,
        out.to_str().unwrap(),
        &[
            "--passes",
            &k,
            "--aov",
            "normal",
            "--threads",
            "1",
            "--quiet",
        ],
    ));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        std::fs::read(&out).unwrap() == std::fs::read(&budget).unwrap(),
        "--aov normal --passes {k}"
    );
}

/// A budget longer than the whole sequence (on a 2×2 image) stops at its last pass, and
/// says why rather than stopping silently early.
#[test]
fn a_budget_past_the_last_pass_says_where_the_passes_end() {
    let out = tmp("all-passes.png");
    let mut args = vec!["render", "scenes/spheres.json", "-o", out.to_str().unwrap()];
    args.extend(["--width", "2", "--height", "2", "--time-budget", "600"]);
    let o = rtlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("the passes end at pass 10 (pass 11: 262144 samples per pixel is more than the limit of 65536)"),
        "{err}"
    );
    assert!(err.contains("the same image: --passes 10"), "{err}");
}

#[test]
fn each_pass_is_the_render_of_its_settings_and_stop_cancels() {
    let mut scene = scene("scenes/spheres.json");
    scene.camera.update_size(40, 30);
    let mut seen = Vec::new();
    // Stop before pass 4 starts: three passes, the last returned.
    let last = progressive(&scene, &scene.render, false, None, &|k| k >= 4, |p| {
        seen.push((p.index, p.output.image.clone()))
    })
    .expect("a pass completed");
    assert_eq!(last.index, 3);
    assert_eq!(seen.iter().map(|s| s.0).collect::<Vec<_>>(), vec![1, 2, 3]);
    for (k, image) in &seen {
        let s = pass_settings(&scene.render, 40, 30, *k).unwrap();
        assert_eq!(*image, render(&scene, &s, false, None).image, "pass {k}");
    }
    // Passes differ: the preview is not the full image, and pass 3 has more samples.
    assert_ne!(seen[0].1, seen[1].1);
    assert_ne!(seen[1].1, seen[2].1);
    // Stopped during its first pass: nothing.
    assert!(progressive(&scene, &scene.render, false, None, &|_| true, |_| {}).is_none());
    // A cap of passes.
    let two = progressive(&scene, &scene.render, true, Some(2), &|_| false, |_| {}).unwrap();
    assert_eq!(two.index, 2);
    assert!(two.output.stats.is_some());
}

/// A pass is asked whether to stop inside a tile too (before each pixel, or each 4×4 block
/// with bundles), not only before each tile: on an 8×8 image, one tile, a stop that says
/// yes on its third question of pass 3 (the first is before the pass, the second before
/// the tile) abandons pass 3 there, and pass 2 is what remains.
#[test]
fn a_pass_stops_inside_a_tile() {
    use rtlab::accel::Traversal;
    use std::sync::atomic::{AtomicU32, Ordering};
    let mut scene = scene("scenes/spheres.json");
    scene.camera.update_size(8, 8);
    for traversal in [Traversal::Single, Traversal::Bundle] {
        let mut settings = scene.render.clone();
        settings.traversal = traversal;
        let asked = AtomicU32::new(0);
        let stop = |k: u32| k >= 3 && asked.fetch_add(1, Ordering::Relaxed) >= 2;
        let last = progressive(&scene, &settings, false, None, &stop, |_| {});
        assert_eq!(last.expect("passes 1 and 2").index, 2, "{traversal:?}");
    }
}

#[test]
fn bad_pass_arguments_are_refused() {
    let scene = path("scenes/spheres.json");
    let out = tmp("bad-pass.png");
    for (args, want) in [
        (vec!["--passes", "0"], "passes are numbered from 1"),
        (vec!["--passes", "-1"], "passes are numbered from 1"),
        (vec!["--passes", "30"], "argument --passes"),
        (vec!["--time-budget", "0"], "argument --time-budget"),
    ] {
        let o = rtlab(&render_args(
            scene.to_str().unwrap(),
            out.to_str().unwrap(),
            &args,
        ));
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{args:?}: {}", stderr(&o));
        assert!(!out.exists());
    }
}

/// A budgeted render's `--stats` says whose counts they are: the pass written, not the sum
/// of the passes; and they are exactly `--passes K`'s counts.
#[test]
fn budgeted_stats_are_the_written_pass() {
    let out = tmp("budget-stats.png");
    let o = out.to_str().unwrap();
    let args = [
        "render",
        "scenes/spheres.json",
        "--width",
        "40",
        "--height",
        "30",
    ];
    let budget = rtlab(
        &[
            &args[..],
            &["--time-budget", "0.2", "--passes", "3", "--stats", "-o", o],
        ]
        .concat(),
    );
    assert!(budget.status.success(), "{}", stderr(&budget));
    let text = stderr(&budget);
    let line = text
        .lines()
        .find(|l| l.contains("rays:"))
        .expect("a stats line");
    assert!(
        line.starts_with("pass 3 (the image written; earlier passes not counted): rays:"),
        "{line}"
    );
    let passes = rtlab(&[&args[..], &["--passes", "3", "--stats", "-o", o]].concat());
    let alone = stderr(&passes);
    let counts = |t: &str| {
        t.lines()
            .find(|l| l.contains("rays:"))
            .map(|l| l[l.find("rays:").unwrap()..].to_string())
    };
    assert_eq!(counts(&text), counts(&alone));
}

/// `RTLAB_SIMD` that names no level is ignored, with a warning (it once went unnoticed).
#[test]
fn an_unknown_simd_level_is_warned_of() {
    let o = tmp("simd-bogus.png");
    let run = rtlab_simd(
        "bogus",
        &[
            "render",
            "scenes/spheres.json",
            "--width",
            "16",
            "--height",
            "12",
            "-o",
            o.to_str().unwrap(),
        ],
    );
    assert!(run.status.success());
    assert!(
        stderr(&run).contains("warning: RTLAB_SIMD=bogus names no SIMD level"),
        "{}",
        stderr(&run)
    );
    // The name `--stats` gives the base level, in any case, is a level.
    let run = rtlab_simd(
        "PORTABLE",
        &[
            "render",
            "scenes/spheres.json",
            "--width",
            "16",
            "--height",
            "12",
            "--stats",
            "json",
            "-o",
            o.to_str().unwrap(),
        ],
    );
    assert!(run.status.success());
    assert!(!stderr(&run).contains("warning"), "{}", stderr(&run));
    assert!(String::from_utf8_lossy(&run.stdout).contains("\"simd\": \"portable\""));
}

/// A time budget stops a running pass within a few rays, not at the end of a 4×4 block,
/// which holds every sample of its sixteen pixels: here every sample traces its whole ray
/// budget (a glass ball inside a glass ball, depth 30, nothing cut for being faint), so a
/// block of pass 2 takes seconds, and the render must end soon after the budget (or after
/// pass 1, which always completes), either way; for the colour and for an AOV.
#[test]
fn a_budget_stops_a_pass_inside_a_block() {
    let scene = tmp("heavy_budget.json");
    std::fs::write(
        &scene,
        r#"{"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "width": 8, "height": 8, "fov_y": 30},
 "render": {"max_depth": 30, "min_contribution": 0, "max_rays": 100000, "spp": 64, "sampler": "grid"},
 "lights": [{"type": "point", "position": [3, 3, 3], "color": [1, 1, 1]}],
 "materials": {"glass": {"diffuse": [0.1, 0.1, 0.1], "reflective": [1, 1, 1], "transparent": [1, 1, 1], "ior": 1.5}},
 "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "glass"},
             {"shape": "sphere", "center": [0.3, 0.2, 0], "radius": 0.3, "material": "glass"}]}"#,
    )
    .unwrap();
    let out = tmp("heavy_budget.png");
    // The colour, and an AOV that traces the whole tree (its passes stop the same way).
    for (traversal, aov) in [
        ("bundle", &[][..]),
        ("single", &[]),
        ("bundle", &["--aov", "reflection"]),
        ("single", &["--aov", "reflection"]),
    ] {
        let start = std::time::Instant::now();
        let mut args = vec![
            "render",
            scene.to_str().unwrap(),
            "--time-budget",
            "0.5",
            "--traversal",
            traversal,
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(aov);
        let o = rtlab(&args);
        let took = start.elapsed().as_secs_f64();
        let err = stderr(&o);
        assert!(o.status.success(), "{err}");
        assert!(err.contains("passes: 1 "), "{traversal} {aov:?}: {err}");
        let first: f64 = err
            .split("pass 1: ")
            .nth(1)
            .and_then(|l| l.split(" done at ").nth(1))
            .and_then(|l| l.split(' ').next())
            .and_then(|t| t.parse().ok())
            .unwrap_or_else(|| panic!("{err}"));
        assert!(
            took < first.max(0.5) + 1.0,
            "{traversal} {aov:?}: pass 1 done at {first} s, the budget 0.5 s, the render ended at {took:.2} s"
        );
    }
}

/// A pass whose settings' token is cancelled while it runs is thrown away, not returned as
/// complete: cancelled once pass 2 is done, pass 3 stops at once and pass 2 is the last.
#[test]
fn a_cancelled_pass_is_not_a_completed_one() {
    let mut scene = scene("scenes/spheres.json");
    scene.camera.update_size(40, 30);
    let cancel = rtlab::interrupt::Cancel::new();
    let base = rtlab::scene::RenderSettings {
        cancel: scene.render.cancel.or(&cancel),
        ..scene.render.clone()
    };
    let mut seen = Vec::new();
    let last = progressive(&scene, &base, false, Some(4), &|_| false, |p| {
        seen.push(p.index);
        if p.index == 2 {
            cancel.cancel();
        }
    });
    assert_eq!(last.expect("passes 1 and 2").index, 2);
    assert_eq!(seen, vec![1, 2]);
}

/// An output folder that takes no files is found before the budget is spent, not after:
/// one line, exit 2, and no pass traced.
#[test]
fn an_unwritable_output_is_refused_before_the_budget_runs() {
    let o = rtlab(&[
        "render",
        path("scenes/spheres.json").to_str().unwrap(),
        "--time-budget",
        "30",
        "-o",
        "/proc/rtlab-budget.png",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(
        err.contains("argument -o") && err.contains("cannot write into the folder /proc"),
        "{err}"
    );
}

/// `--passes K --stats` names the pass it counts, as a budgeted render does; a budget that
/// wrote pass 1 does not speak of earlier passes.
#[test]
fn stats_name_the_pass() {
    let scene = path("scenes/spheres.json");
    let out = tmp("stats-pass.png");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "render",
            scene.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = rtlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        String::from_utf8_lossy(&o.stdout).to_string() + &stderr(&o)
    };
    let three = run(&[
        "--passes", "3", "--stats", "--width", "32", "--height", "24",
    ]);
    assert!(three.contains("pass 3: rays: "), "{three}");
    // A budget that wrote pass 1: capped there, so that it does not hang on timing.
    let one = run(&[
        "--time-budget",
        "100",
        "--passes",
        "1",
        "--stats",
        "--width",
        "32",
        "--height",
        "24",
    ]);
    assert!(one.contains("pass 1 (the image written): rays: "), "{one}");
    assert!(!one.contains("earlier passes"), "{one}");
}

/// A render stopped while its samples are being reconstructed gives no image, as one stopped
/// while tracing does: under `--subsample` the stretched filter can take longer than the
/// trace, and a time budget must not wait for it (it once wrote a pass that ended seconds
/// past the budget). `stop` is asked a fixed number of times while tracing (once per tile and
/// once per block or pixel), so counting the asks of a whole render tells when tracing ends.
#[test]
fn a_render_stopped_while_reconstructing_gives_no_image() {
    use rtlab::accel::Traversal;
    use rtlab::sampling::{render_until, Counting};
    use std::sync::atomic::{AtomicUsize, Ordering};
    let mut scene = scene("scenes/spheres.json");
    scene.camera.update_size(40, 30);
    for traversal in [Traversal::Bundle, Traversal::Single] {
        let settings = rtlab::scene::RenderSettings {
            subsample: 8,
            traversal,
            ..scene.render.clone()
        };
        let asked = AtomicUsize::new(0);
        let count = || {
            asked.fetch_add(1, Ordering::Relaxed);
            false
        };
        assert!(render_until(&scene, &settings, Counting::Off, None, &count).is_some());
        let rows = scene.camera.height as usize;
        let tracing = asked.load(Ordering::Relaxed) - rows;
        // Stopped at the first row of the reconstruction: nothing comes back.
        let asked = AtomicUsize::new(0);
        let stop_after_tracing = || asked.fetch_add(1, Ordering::Relaxed) >= tracing;
        assert!(
            render_until(&scene, &settings, Counting::Off, None, &stop_after_tracing).is_none(),
            "{traversal:?}"
        );
        // Stopped at the last row instead, the render is still thrown away; one ask later
        // is never made (the count is the same on every run, whatever the threads do).
        let asked = AtomicUsize::new(0);
        let stop_at_last_row = || asked.fetch_add(1, Ordering::Relaxed) + 1 >= tracing + rows;
        assert!(render_until(&scene, &settings, Counting::Off, None, &stop_at_last_row).is_none());
        let asked = AtomicUsize::new(0);
        let stop_past_the_end = || asked.fetch_add(1, Ordering::Relaxed) >= tracing + rows;
        assert!(render_until(&scene, &settings, Counting::Off, None, &stop_past_the_end).is_some());
    }
}

/// Pass 1 is a quarter of the width and height of the scene's render: `--passes 1` (and a
/// budget, whose pass 1 always completes) renders it where the scene's own render would not
/// fit in memory (both were refused with the full render's estimate).
#[test]
fn a_first_pass_renders_where_the_full_image_would_not_fit() {
    let scene = write_tmp(
        "one-sphere-big.json",
        r#"{"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0], "width": 1600, "height": 1600, "fov_y": 30},
 "render": {"spp": 64, "sampler": "grid"},
 "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1}]}"#,
    );
    let out = tmp("one-sphere-big.png");
    let run = |extra: &[&str]| {
        let mut args = vec!["render", scene.to_str().unwrap(), "--quiet", "-o"];
        args.push(out.to_str().unwrap());
        args.extend(extra);
        rtlab(&args)
    };
    let full = run(&[]);
    assert_eq!(full.status.code(), Some(2));
    assert!(stderr(&full).contains("GiB of memory"), "{}", stderr(&full));
    let first = run(&["--passes", "1"]);
    assert!(first.status.success(), "{}", stderr(&first));
    let one = std::fs::read(&out).unwrap();
    let budget = run(&["--time-budget", "0.01"]);
    assert!(budget.status.success(), "{}", stderr(&budget));
    assert_eq!(std::fs::read(&out).unwrap(), one, "the budget wrote pass 1");
}

/// On a terminal (a pseudo-terminal from util-linux's `script`, which every Debian has), a
/// budgeted render's progress bar counts each pass by name, the pass lines print above it,
/// and the bar moves: it once sat at 0 % for the whole budget, never handed to the passes.
#[test]
fn on_a_terminal_the_budgets_bar_counts_each_pass() {
    let out = tmp("bar.png");
    // Each path in single quotes for the shell `script` runs the command with.
    let quoted =
        |p: &std::path::Path| format!("'{}'", p.display().to_string().replace('\'', "'\\''"));
    let command = format!(
        "{} render {} -o {} --width 96 --height 72 --time-budget 2",
        quoted(std::path::Path::new(env!("CARGO_BIN_EXE_rtlab"))),
        quoted(&path("scenes/whitted.json")),
        quoted(&out)
    );
    let o = std::process::Command::new("script")
        .args(["-qec", &command, "/dev/null"])
        .current_dir(root())
        .output()
        .expect("`script` (util-linux) runs: the test needs a pseudo-terminal");
    let screen = String::from_utf8_lossy(&o.stdout).replace('\r', "\n");
    assert!(o.status.success(), "{screen}{}", stderr(&o));
    assert!(screen.contains("pass 1: "), "no line for pass 1: {screen}");
    assert!(screen.contains("the same image: --passes "), "{screen}");
    // Some frame of the bar names its pass and shows it under way (above 0 %).
    let moving = screen.lines().any(|line| {
        let Some(rest) = line.split("rendering pass ").nth(1) else {
            return false;
        };
        let percent = rest.split("] ").nth(1).and_then(|r| r.split('%').next());
        percent
            .and_then(|p| p.trim().parse::<u32>().ok())
            .is_some_and(|p| p > 0)
    });
    assert!(
        moving,
        "no frame of the bar shows a pass under way: {screen}"
    );
}
