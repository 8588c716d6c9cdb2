//! The page of `rtlab serve` in a real browser: headless Chromium driven through chromedriver
//! (WebDriver, the `fantoccini` client). Fails, not skips, when Chromium is missing: `.ci/run`
//! installs Debian's `chromium` and `chromium-driver`.
//!
//! One session walks what a student does: load, click a pixel (the ledger's sum is explain's
//! colour), toggle shadows (the image changes exactly where `render --no-shadows` differs),
//! edit the scene (the page re-renders), break it (the error shows, the image stays).
//! Screenshots go to `target/serve-*.png`.

use super::serve::{scene_copy, Server};
use crate::common::{path, rtlab, stderr, tmp};
use fantoccini::actions::{InputSource, MouseActions, PointerAction, MOUSE_BUTTON_LEFT};
use fantoccini::{Client, ClientBuilder, Locator};
use serde_json::Value;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const CHROMIUM: [&str; 2] = ["/usr/bin/chromium", "/usr/bin/chromium-browser"];
const DRIVER: [&str; 1] = ["/usr/bin/chromedriver"];

fn find(candidates: &[&str], what: &str) -> PathBuf {
    candidates
        .iter()
        .map(PathBuf::from)
        .find(|p| p.exists())
        .unwrap_or_else(|| {
            panic!("{what} is not installed ({candidates:?}): apt-get install chromium chromium-driver (.ci/run does)")
        })
}

struct Driver {
    child: Child,
    url: String,
}

impl Driver {
    fn start() -> Driver {
        let bin = find(&DRIVER, "chromedriver");
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        // Its own process group, so that dropping the driver also ends the Chromium it
        // started, even when the test fails half-way.
        let child = Command::new(bin)
            .process_group(0)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("chromedriver starts");
        let t0 = Instant::now();
        while std::net::TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(
                t0.elapsed() < Duration::from_secs(30),
                "chromedriver did not listen"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
        Driver {
            child,
            url: format!("http://127.0.0.1:{port}"),
        }
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        // The whole process group (chromedriver and the Chromium it started). The `--` is
        // needed: procps' kill reads `-TERM -15637` as a signal to group -1, that is to every
        // process there is (seen here; it ended the test run and all beside it).
        let _ = Command::new("kill")
            .args(["-TERM", "--"])
            .arg(format!("-{}", self.child.id()))
            .status();
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

async fn browser(driver: &Driver) -> Client {
    let profile = tmp("chromium-profile");
    let _ = std::fs::remove_dir_all(&profile);
    let mut caps = serde_json::Map::new();
    caps.insert(
        "goog:chromeOptions".into(),
        serde_json::json!({
            "binary": find(&CHROMIUM, "chromium"),
            "args": ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                     "--no-first-run", "--disable-background-networking",
                     "--disable-component-update", "--disable-sync",
                     "--disable-dev-shm-usage", "--window-size=1500,1250",
                     "--force-device-scale-factor=1",
                     format!("--user-data-dir={}", profile.display())],
        }),
    );
    let connector = hyper_util::client::legacy::connect::HttpConnector::new();
    ClientBuilder::new(connector)
        .capabilities(caps)
        .connect(&driver.url)
        .await
        .expect("a Chromium session")
}

/// Polls `script` (a function body returning a value) until it returns something truthy.
async fn wait_js(c: &Client, script: &str, what: &str) -> Value {
    let t0 = Instant::now();
    loop {
        let v = c.execute(script, vec![]).await.unwrap_or(Value::Null);
        let truthy = match &v {
            Value::Null => false,
            Value::Bool(b) => *b,
            Value::String(s) => !s.is_empty(),
            _ => true,
        };
        if truthy {
            return v;
        }
        if t0.elapsed() > Duration::from_secs(120) {
            // What the page said last: usually why it never got there.
            let said = c
                .execute(
                    "return document.getElementById('render-state').textContent;",
                    vec![],
                )
                .await
                .unwrap_or(Value::Null);
            panic!("timed out waiting for {what}; the page's status: {said}");
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

/// The page's image as RGB bytes, once the full render with `query` is shown.
async fn page_image(c: &Client, query_has: &str) -> (u32, u32, Vec<u8>) {
    let js = format!(
        "const v = document.getElementById('view'); return v.dataset.state === 'full' && v.dataset.query.includes('{query_has}') && window.rtlab.state.pixels !== null;"
    );
    wait_js(c, &js, &format!("the full image with '{query_has}'")).await;
    let v = c
        .execute(
            "return [window.rtlab.state.width, window.rtlab.state.height, window.rtlab.rgbBase64()];",
            vec![],
        )
        .await
        .unwrap();
    let b = base64(v[2].as_str().unwrap());
    (
        v[0].as_u64().unwrap() as u32,
        v[1].as_u64().unwrap() as u32,
        b,
    )
}

fn base64(s: &str) -> Vec<u8> {
    let val = |c: u8| -> u32 {
        match c {
            b'A'..=b'Z' => (c - b'A') as u32,
            b'a'..=b'z' => (c - b'a' + 26) as u32,
            b'0'..=b'9' => (c - b'0' + 52) as u32,
            b'+' => 62,
            _ => 63,
        }
    };
    let bytes: Vec<u8> = s.bytes().filter(|&c| c != b'=').collect();
    let mut out = Vec::new();
    for chunk in bytes.chunks(4) {
        let mut n = 0u32;
        for (i, &c) in chunk.iter().enumerate() {
            n |= val(c) << (18 - 6 * i);
        }
        for i in 0..chunk.len().saturating_sub(1) {
            out.push((n >> (16 - 8 * i)) as u8);
        }
    }
    out
}

/// `rtlab render` of `scene` with `flags`, decoded.
fn cli_render(scene: &Path, flags: &[&str]) -> image::RgbImage {
    let out = tmp(&format!("browser-{}.png", flags.join("").replace('-', "")));
    let mut args = vec![
        "render",
        scene.to_str().unwrap(),
        "-q",
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend(flags);
    let o = rtlab(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    image::open(&out).unwrap().to_rgb8()
}

async fn click_pixel(c: &Client, x: u32, y: u32) {
    let p = c
        .execute(
            &format!("return window.rtlab.clientPoint({x}, {y});"),
            vec![],
        )
        .await
        .unwrap();
    let (px, py) = (p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
    let mouse = MouseActions::new("mouse".into())
        .then(PointerAction::MoveTo {
            duration: None,
            x: px.round(),
            y: py.round(),
        })
        .then(PointerAction::Down {
            button: MOUSE_BUTTON_LEFT,
        })
        .then(PointerAction::Up {
            button: MOUSE_BUTTON_LEFT,
        });
    c.perform_actions(mouse).await.unwrap();
}

fn rgb_attr(v: &Value) -> [f64; 3] {
    let s = v.as_str().unwrap();
    let p: Vec<f64> = s.split(',').map(|x| x.parse().unwrap()).collect();
    [p[0], p[1], p[2]]
}

async fn screenshot(c: &Client, name: &str) -> PathBuf {
    let png = c.screenshot().await.unwrap();
    let p = path("target").join(name);
    std::fs::write(&p, png).unwrap();
    p
}

/// Sets the page's control `id` to `value` as a user would: the value, then its change event.
async fn set_control(c: &Client, id: &str, value: &str) {
    let js = format!(
        "const e = document.getElementById('{id}'); e.value = '{value}'; e.dispatchEvent(new Event('change'));"
    );
    c.execute(&js, vec![]).await.unwrap();
}

/// Waits for the end of the page's refinement (refine (s) at 2) of the image that `rtlab
/// render{cli}` makes, and returns the pass K it stopped at: at least 3, and named in the
/// status as `rtlab render --passes K{cli}`.
async fn refined_pass(c: &Client, cli: &str) -> u32 {
    let js = format!(
        "const s = document.getElementById('render-state').textContent; return /^pass [0-9]+, .*\\(= rtlab render --passes [0-9]+{cli}\\), after [0-9]+ ms; (the 2 s were spent|pass [0-9]+ abandoned at the 2 s|no pass)/.test(s) ? s : '';"
    );
    let status = wait_js(c, &js, &format!("the refined passes' end ({cli})")).await;
    let status = status.as_str().unwrap().to_string();
    let k: u32 = status["pass ".len()..]
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(k >= 3, "{status}");
    assert!(
        status.contains(&format!("(= rtlab render --passes {k}{cli})")),
        "{status}"
    );
    k
}

/// The panels (`main` elements) the browser really displays: only the selected tab's.
async fn shown_panels(c: &Client) -> String {
    let v = c
        .execute(
            "return [...document.querySelectorAll('main')].filter((m) => getComputedStyle(m).display !== 'none').map((m) => m.id).join(',');",
            vec![],
        )
        .await
        .unwrap();
    v.as_str().unwrap().to_string()
}

#[test]
fn the_page_in_a_real_browser() {
    let driver = Driver::start();
    let scene = scene_copy("scenes/spheres.json", "browser-spheres.json");
    let server = Server::start(&scene, &[]);
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    rt.block_on(async {
        let c = browser(&driver).await;
        c.goto(&server.url).await.unwrap();

        // Load: the page shows `rtlab render`'s image, pixel for pixel.
        let (w, h, shown) = page_image(&c, "").await;
        let with = cli_render(&scene, &[]);
        assert_eq!((w, h), with.dimensions());
        assert_eq!(shown, with.as_raw().clone(), "the page shows render's bytes");

        assert_eq!(shown_panels(&c).await, "explore", "only Explore's panel shows");

        // Click a pixel on the lit sphere: the ledger sums to explain's colour.
        let (x, y) = (200, 150);
        click_pixel(&c, x, y).await;
        wait_js(&c, "return document.getElementById('pixel-sum') !== null && !document.getElementById('explanation').hidden;", "the explanation").await;
        let title = c.find(Locator::Id("px-title")).await.unwrap().text().await.unwrap();
        assert_eq!(title, format!("Pixel ({x}, {y})"), "the click landed on the pixel asked for");
        let pixel_sum = rgb_attr(&c.execute("return document.getElementById('pixel-sum').dataset.rgb;", vec![]).await.unwrap());
        let ledger_sum = rgb_attr(&c.execute("return document.getElementById('ledger-sum').dataset.rgb;", vec![]).await.unwrap());
        let o = rtlab(&["explain", scene.to_str().unwrap(), "--pixel", &format!("{x},{y}"), "--format", "json"]);
        let e: Value = serde_json::from_slice(&o.stdout).unwrap();
        for k in 0..3 {
            let want = e["color"][k].as_f64().unwrap();
            assert!((pixel_sum[k] - want).abs() < 1e-12, "pixel sum {pixel_sum:?} vs explain {}", e["color"]);
            let sample = e["samples"][0]["color"][k].as_f64().unwrap();
            assert!((ledger_sum[k] - sample).abs() < 1e-12, "ledger {ledger_sum:?} vs {}", e["samples"][0]["color"]);
        }
        // The ledger's lines are on the page.
        let ledger = c.find(Locator::Id("ledger")).await.unwrap().text().await.unwrap();
        assert!(ledger.contains("ambient") && ledger.contains("diffuse") && ledger.contains("sum"), "{ledger}");
        // The specular exponent is the hit material's (the mirror ball's shininess, 120).
        assert!(ledger.contains("^120 ="), "{ledger}");
        let tree = c
            .execute("return document.getElementById('tree').textContent;", vec![])
            .await
            .unwrap();
        let tree = tree.as_str().unwrap();
        assert!(tree.contains("camera ray") && tree.contains("D = b² − 4ac"), "{tree}");

        // Clicking a ray of the tree draws it in bold in the diagram.
        c.find(Locator::Css("[data-ray='1']")).await.unwrap().click().await.unwrap();
        let src = wait_js(&c, "const d = document.getElementById('diagram'); return d.complete && d.naturalWidth > 0 && d.src.includes('highlight=1') ? d.src : '';", "the highlighted diagram").await;
        assert!(src.as_str().unwrap().contains(&format!("x={x}&y={y}")));
        // The bundle figure needs a mesh: on the spheres the page says so, in the CLI's words.
        let why = wait_js(&c, "const w = document.getElementById('bundle-why'); return w.hidden ? '' : w.textContent;", "the bundle figure's refusal").await;
        assert!(why.as_str().unwrap().contains("needs a scene with a mesh"), "{why}");
        assert_eq!(c.execute("return document.getElementById('bundle').hidden;", vec![]).await.unwrap(), Value::Bool(true));
        // The screenshot (the book's figure) shows the explanation from its top.
        c.execute("document.getElementById('right').scrollTop = 0;", vec![])
            .await
            .unwrap();
        let shot = screenshot(&c, "serve-screenshot.png").await;
        assert!(std::fs::metadata(&shot).unwrap().len() > 10_000);

        // Shadows off: the image changes exactly where render --no-shadows differs.
        c.find(Locator::Id("opt-no-shadows")).await.unwrap().click().await.unwrap();
        let (_, _, without_page) = page_image(&c, "no-shadows").await;
        let without = cli_render(&scene, &["--no-shadows"]);
        let changed = |a: &[u8], b: &[u8]| -> Vec<usize> {
            (0..a.len() / 3).filter(|&i| a[3 * i..3 * i + 3] != b[3 * i..3 * i + 3]).collect()
        };
        let page_changed = changed(&shown, &without_page);
        let cli_changed = changed(with.as_raw(), without.as_raw());
        assert!(!cli_changed.is_empty(), "the scene has shadows to lose");
        assert_eq!(page_changed, cli_changed, "the page changed exactly where render --no-shadows differs");
        // The selected pixel's explanation followed the switch.
        wait_js(&c, "return document.getElementById('ledger').textContent.length > 0 && !document.getElementById('ledger').textContent.includes('in shadow');", "the explanation without shadows").await;

        // The cost AOV: the page shows render --aov's image and, under it, its legend.
        set_control(&c, "opt-aov", "cost").await;
        let legend = wait_js(
            &c,
            "const l = document.getElementById('aov-legend'); const s = document.getElementById('render-state').textContent; return !l.hidden && s.startsWith('pass 2') && s.includes('--aov cost') ? l.textContent : '';",
            "the cost AOV's full image and legend",
        )
        .await;
        let (_, _, cost_page) = page_image(&c, "no-shadows").await;
        let out = tmp("browser-cost.png");
        let o = rtlab(&["render", scene.to_str().unwrap(), "--no-shadows", "--aov", "cost", "-o", out.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        let cli_legend = stderr(&o).lines().next().unwrap().to_string();
        assert!(legend.as_str().unwrap().starts_with(&cli_legend), "page {legend} vs render {cli_legend}");
        assert_eq!(cost_page, image::open(&out).unwrap().to_rgb8().into_raw(), "the page shows render --aov cost");
        screenshot(&c, "serve-aov.png").await;
        set_control(&c, "opt-aov", "").await;
        wait_js(&c, "return document.getElementById('aov-legend').hidden && document.getElementById('render-state').textContent.startsWith('pass 2') && !document.getElementById('render-state').textContent.includes('--aov');", "the colour image again").await;

        // Refine: passes 3, 4, … while the seconds last; the last complete pass stays, and
        // it is `render --passes K`'s image, its pixels explained with that pass's settings.
        set_control(&c, "opt-refine", "2").await;
        let k = refined_pass(&c, "").await;
        let (_, _, refined) = page_image(&c, "no-shadows").await;
        let k_arg = k.to_string();
        assert_eq!(refined, cli_render(&scene, &["--no-shadows", "--passes", &k_arg]).into_raw(), "pass {k}");
        let pass_options: String = c
            .execute("return window.rtlab.state.passOptions;", vec![])
            .await
            .unwrap()
            .as_str()
            .unwrap()
            .to_string();
        click_pixel(&c, x, y).await;
        let sum = wait_js(
            &c,
            "const p = document.getElementById('pixel-sum'), e = document.getElementById('explanation'); const want = window.rtlab.state.passOptions.split('&').concat(['no-shadows']), have = (e.dataset.query || '').split('&'); return p !== null && !e.hidden && want.every((w) => have.includes(w)) ? p.dataset.rgb : '';",
            "the refined pixel's explanation",
        )
        .await;
        let mut args = vec!["explain".to_string(), scene.to_str().unwrap().to_string(), "--no-shadows".into(), "--pixel".into(), format!("{x},{y}"), "--format".into(), "json".into()];
        for kv in pass_options.split('&') {
            let (key, value) = kv.split_once('=').unwrap();
            args.extend([format!("--{key}"), value.to_string()]);
        }
        let o = rtlab(&args.iter().map(String::as_str).collect::<Vec<_>>());
        assert!(o.status.success(), "{}", stderr(&o));
        let e: Value = serde_json::from_slice(&o.stdout).unwrap();
        let sum = rgb_attr(&sum);
        for ch in 0..3 {
            assert!((sum[ch] - e["color"][ch].as_f64().unwrap()).abs() < 1e-12, "{sum:?} vs {} ({pass_options})", e["color"]);
        }
        screenshot(&c, "serve-refined.png").await;

        // An AOV refines as the colour does (the server stops an abandoned AOV pass as it
        // stops a colour one): its last complete pass is `render --aov normal --passes K`.
        set_control(&c, "opt-aov", "normal").await;
        let k = refined_pass(&c, " --aov normal").await;
        let (_, _, refined) = page_image(&c, "no-shadows").await;
        let k_arg = k.to_string();
        assert_eq!(
            refined,
            cli_render(&scene, &["--no-shadows", "--aov", "normal", "--passes", &k_arg]).into_raw(),
            "AOV pass {k}"
        );
        screenshot(&c, "serve-aov-refined.png").await;
        set_control(&c, "opt-refine", "").await;
        wait_js(&c, "return document.getElementById('render-state').textContent.startsWith('pass 2, the full image (= rtlab render --aov normal)');", "the AOV's full image").await;
        set_control(&c, "opt-aov", "").await;
        wait_js(&c, "return document.getElementById('render-state').textContent.startsWith('pass 2, the full image (= rtlab render)');", "the full image again").await;

        // Steps: the scrubber walks `rtlab steps`' frames.
        c.find(Locator::Css("nav button[data-mode='steps']"))
            .await
            .unwrap()
            .click()
            .await
            .unwrap();
        wait_js(
            &c,
            "const f = document.getElementById('steps-frame'); return f.complete && f.naturalWidth > 0 && Number(document.getElementById('steps-slider').max) >= 2;",
            "the first steps frame",
        )
        .await;
        c.execute(
            "const s = document.getElementById('steps-slider'); s.value = '2'; s.dispatchEvent(new Event('input'));",
            vec![],
        )
        .await
        .unwrap();
        let caption = wait_js(
            &c,
            "const f = document.getElementById('steps-frame'); return f.complete && f.src.includes('i=2') && f.naturalWidth > 0 ? document.getElementById('steps-caption').textContent : '';",
            "steps frame 3",
        )
        .await;
        let list: Value = serde_json::from_slice(&server.get("/api/steps?no-shadows").body).unwrap();
        assert_eq!(caption, list[2]["caption"], "the page shows frame 3's caption");
        assert_eq!(shown_panels(&c).await, "steps");
        screenshot(&c, "serve-steps.png").await;

        // Compare: two runs side by side and where they differ.
        c.find(Locator::Css("nav button[data-mode='compare']"))
            .await
            .unwrap()
            .click()
            .await
            .unwrap();
        let count = wait_js(
            &c,
            "return document.getElementById('cmp-count').textContent;",
            "the comparison",
        )
        .await;
        assert!(count.as_str().unwrap().contains("pixels differ"), "{count}");
        assert_eq!(shown_panels(&c).await, "compare");
        screenshot(&c, "serve-compare.png").await;

        // Diff: drop your image (here: the scene rendered with a mistake) → regions and
        // causes; a region's button shows its pixel in Explore.
        c.find(Locator::Css("nav button[data-mode='diff']"))
            .await
            .unwrap()
            .click()
            .await
            .unwrap();
        c.execute(
            "fetch('/api/render.png?' + join(renderQuery(), 'mistake=blinn-phong')).then((r) => r.blob()).then((b) => window.rtlabDiff(new File([b], 'yours.png', { type: 'image/png' })));",
            vec![],
        )
        .await
        .unwrap();
        let verdict = wait_js(
            &c,
            "const f = document.getElementById('diff-figure'); return !document.getElementById('diff-result').hidden && f.complete && f.naturalWidth > 0 ? document.getElementById('diff-verdict').textContent + ' | ' + document.getElementById('diff-diagnosis').textContent : '';",
            "the diff of an uploaded image",
        )
        .await;
        let verdict = verdict.as_str().unwrap().to_string();
        assert!(verdict.starts_with("different"), "{verdict}");
        assert!(verdict.contains("blinn-phong"), "{verdict}");
        assert_eq!(shown_panels(&c).await, "diff");
        screenshot(&c, "serve-diff.png").await;
        c.find(Locator::Css("button.diff-show"))
            .await
            .unwrap()
            .click()
            .await
            .unwrap();
        let title = wait_js(
            &c,
            "const e = document.getElementById('explanation'); return e.hidden ? '' : document.getElementById('px-title').textContent;",
            "the region's pixel explained",
        )
        .await;
        assert!(title.as_str().unwrap().starts_with("Pixel ("), "{title}");
        c.find(Locator::Css("nav button[data-mode='explore']"))
            .await
            .unwrap()
            .click()
            .await
            .unwrap();

        // Edit the scene file: the page re-renders on save.
        let text = std::fs::read_to_string(&scene).unwrap();
        let edited = text.replacen("\"width\": 480, \"height\": 360", "\"width\": 400, \"height\": 300", 1);
        assert_ne!(edited, text);
        rtlab::output::write_atomic(&scene, edited.as_bytes()).unwrap();
        wait_js(&c, "return document.body.dataset.version === '2';", "version 2 of the scene").await;
        let (w2, h2, edited_page) = page_image(&c, "no-shadows").await;
        let edited_cli = cli_render(&scene, &["--no-shadows"]);
        assert_eq!((w2, h2), (400, 300));
        assert_eq!(edited_page, edited_cli.as_raw().clone(), "the page shows the edited scene");

        // Break it: the error (file, JSON path, message) shows; the last good image stays.
        let broken = edited.replacen("\"fov_y\": 40", "\"fov_y\": \"wide\"", 1);
        assert_ne!(broken, edited);
        rtlab::output::write_atomic(&scene, broken.as_bytes()).unwrap();
        let banner = wait_js(&c, "const b = document.getElementById('scene-error'); return b.hidden ? '' : b.textContent;", "the scene error").await;
        let o = rtlab(&["validate", scene.to_str().unwrap()]);
        let cli = stderr(&o).lines().next().unwrap().to_string();
        assert!(cli.contains("fov_y"), "{cli}");
        assert!(banner.as_str().unwrap().starts_with(&cli), "banner {banner} vs {cli}");
        screenshot(&c, "serve-error.png").await;
        let (_, _, kept) = page_image(&c, "no-shadows").await;
        assert_eq!(kept, edited_page, "the last good image stays");

        // On a mesh, a clicked pixel shows the bundle its camera ray was traced in: the
        // figure of `explain --bundle-diagram`, 960×480.
        let teapot = Server::start(&path("scenes/teapot.json"), &[]);
        c.goto(&teapot.url).await.unwrap();
        page_image(&c, "").await;
        click_pixel(&c, 330, 260).await;
        let size = wait_js(&c, "const b = document.getElementById('bundle'); return !b.hidden && b.complete && b.naturalWidth > 0 ? b.naturalWidth + 'x' + b.naturalHeight : '';", "the bundle figure").await;
        assert_eq!(size.as_str().unwrap(), "960x480");
        c.execute("document.getElementById('bundle').scrollIntoView();", vec![]).await.unwrap();
        screenshot(&c, "serve-bundle.png").await;
        assert_eq!(c.execute("return document.getElementById('bundle-why').hidden;", vec![]).await.unwrap(), Value::Bool(true));

        c.close().await.unwrap();
    });
}
