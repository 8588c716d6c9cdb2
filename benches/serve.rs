//! `rtlab serve` latency, server side: a request over loopback to an in-process server, timed
//! from the first byte sent to the last byte received.
//!
//! - click → explanation: `GET /api/explain?x&y` for pixels across the image (target < 50 ms);
//! - switch → first preview: what the page does after a switch, `GET /api/scene?<switches>`
//!   (the size under those options) then `GET /api/render.png?<switches>&pass=1`, pass 1 of
//!   the progressive render (`--passes 1`: one pixel in 4×4 traced), with a combination of
//!   switches not asked before, so the scene is loaded afresh (target < 100 ms);
//! - the page's old preview, the scene at 1/8 of its width and height, for comparison;
//! - and the full image after the switch, for scale.
//!
//! - in the browser (headless Chromium through chromedriver, when installed): a click on a
//!   pixel until its explanation is on the page, timed inside the page with
//!   `performance.now()` (target < 50 ms).
//!
//! `cargo bench --bench serve` (short: a few dozen requests per scene).

use rtlab::cli::serve::{loader, option_infos};
use rtlab::cli::RenderArgs;
use std::io::{Read, Write};
use std::net::TcpStream;
use std::path::PathBuf;
use std::time::Instant;

fn get(addr: &str, target: &str) -> (u16, usize, f64) {
    let t0 = Instant::now();
    let mut s = TcpStream::connect(addr).unwrap();
    write!(
        s,
        "GET {target} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut b = Vec::new();
    s.read_to_end(&mut b).unwrap();
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let status = String::from_utf8_lossy(&b[9..12]).parse().unwrap_or(0);
    (status, b.len(), ms)
}

fn stats(v: &mut [f64]) -> String {
    v.sort_by(|a, b| a.total_cmp(b));
    format!(
        "median {:7.1} ms   min {:7.1}   max {:7.1}   (n = {})",
        v[v.len() / 2],
        v[0],
        v[v.len() - 1],
        v.len()
    )
}

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    println!(
        "rtlab serve, server side (loopback round trip, {} threads)",
        rayon::current_num_threads()
    );
    for rel in ["scenes/spheres.json", "scenes/glass.json"] {
        let scene = root.join(rel);
        let running = rtlab::server::start(rtlab::server::Options {
            loader: loader(scene.clone(), RenderArgs::default()),
            flags: rtlab::cli::serve::flags(RenderArgs::default()),
            options: option_infos(),
            scene: scene.clone(),
            host: None,
            port: 0,
        })
        .expect("server starts");
        let addr = running.addr.to_string();
        let s = rtlab::scene::Scene::load(&scene).unwrap();
        let (w, h) = (s.camera.width, s.camera.height);

        // Warm up (first load, page assets).
        get(&addr, "/");
        get(&addr, "/api/render.png?pass=1");

        let mut explain = Vec::new();
        for i in 0..24u32 {
            let (x, y) = ((i * 37 + 11) % w, (i * 53 + 7) % h);
            let (st, _, ms) = get(&addr, &format!("/api/explain?x={x}&y={y}"));
            assert_eq!(st, 200);
            explain.push(ms);
        }

        let switches = [
            "no-shadows",
            "no-reflections",
            "no-refractions",
            "no-textures",
            "max-depth=1",
            "max-depth=2",
            "spp=2",
            "sampler=jittered&spp=4",
            "filter=tent",
            "no-shadows&no-reflections",
        ];
        let (mut preview, mut subsampled, mut full) = (Vec::new(), Vec::new(), Vec::new());
        for sw in switches {
            let (st, _, a) = get(&addr, &format!("/api/scene?{sw}"));
            assert_eq!(st, 200);
            let (st, _, b) = get(&addr, &format!("/api/render.png?{sw}&pass=1&stream=bench"));
            assert_eq!(st, 200);
            preview.push(a + b);
            let (pw, ph) = (w.div_ceil(8), h.div_ceil(8));
            let (st, _, ms) = get(
                &addr,
                &format!("/api/render.png?{sw}&width={pw}&height={ph}&stream=bench"),
            );
            assert_eq!(st, 200);
            subsampled.push(ms);
            let (st, _, ms) = get(&addr, &format!("/api/render.png?{sw}&stream=bench"));
            assert_eq!(st, 200);
            full.push(ms);
        }
        println!("\n{rel} ({w}×{h}, {} spp)", s.render.spp);
        println!("  click → explanation      {}", stats(&mut explain));
        println!("  switch → first preview   {}", stats(&mut preview));
        println!("  (1/8-size preview        {})", stats(&mut subsampled));
        println!("  switch → full image      {}", stats(&mut full));
        match browser_clicks(&running.url, w, h) {
            Ok(mut v) => println!("  click → explanation, in the browser  {}", stats(&mut v)),
            Err(why) => println!("  in the browser: not measured ({why})"),
        }
        running.stop();
    }
}

/// Clicks 12 pixels in the page and times each until its explanation is shown, in the page.
fn browser_clicks(url: &str, w: u32, h: u32) -> Result<Vec<f64>, String> {
    use std::process::{Command, Stdio};
    let driver = "/usr/bin/chromedriver";
    if !std::path::Path::new(driver).exists() {
        return Err("no chromedriver; bash .ci/deps installs it".into());
    }
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map_err(|e| e.to_string())?
        .port();
    let mut child = Command::new(driver)
        .arg(format!("--port={port}"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| e.to_string())?;
    let t0 = Instant::now();
    while TcpStream::connect(("127.0.0.1", port)).is_err() && t0.elapsed().as_secs() < 30 {
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    let profile = std::env::temp_dir().join(format!("rtlab-bench-chromium-{}", std::process::id()));
    let rt = tokio::runtime::Runtime::new().map_err(|e| e.to_string())?;
    let result = rt.block_on(async {
        let mut caps = serde_json::Map::new();
        caps.insert(
            "goog:chromeOptions".into(),
            serde_json::json!({
                "binary": "/usr/bin/chromium",
                "args": ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                         "--no-first-run", "--disable-background-networking",
                         "--disable-component-update", "--disable-sync",
                         "--disable-dev-shm-usage", "--window-size=1500,1250",
                         format!("--user-data-dir={}", profile.display())],
            }),
        );
        let connector = hyper_util::client::legacy::connect::HttpConnector::new();
        let c = fantoccini::ClientBuilder::new(connector)
            .capabilities(caps)
            .connect(&format!("http://127.0.0.1:{port}"))
            .await
            .map_err(|e| e.to_string())?;
        c.goto(url).await.map_err(|e| e.to_string())?;
        let mut times = Vec::new();
        for i in 0..13u32 {
            let (x, y) = ((i * 41 + 5) % w, (i * 29 + 3) % h);
            let script = format!(
                "return (async () => {{
                   while (!window.rtlab || !window.rtlab.state.pixels) await new Promise((r) => setTimeout(r, 20));
                   const t0 = performance.now();
                   select({x}, {y});
                   const shown = () => !document.getElementById('explanation').hidden
                     && document.getElementById('px-title').textContent.includes('({x}, {y})');
                   while (!shown()) await new Promise((r) => requestAnimationFrame(r));
                   return performance.now() - t0;
                 }})();"
            );
            let v = c.execute(&script, vec![]).await.map_err(|e| e.to_string())?;
            if i > 0 {
                times.push(v.as_f64().unwrap_or(f64::NAN)); // the first click warms the page up
            }
        }
        let _ = c.close().await;
        Ok::<_, String>(times)
    });
    let _ = child.kill();
    let _ = child.wait();
    let _ = std::fs::remove_dir_all(&profile);
    result
}
