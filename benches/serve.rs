//! `rtlab serve` latency, server side: a request over loopback to an in-process server, timed
//! from the first byte sent to the last byte received.
//!
//! - click → explanation: `GET /api/explain?x&y` for pixels across the image (target < 50 ms);
//! - switch → first preview: what the page does after a switch, `GET /api/scene?<switches>`
//!   (the size under those options) then `GET /api/render.png?<switches>&width=W/8&height=H/8`,
//!   with a combination of switches not asked before, so the scene is loaded afresh
//!   (target < 100 ms);
//! - the old preview, `--subsample 8` at full size, for comparison (its reconstruction still
//!   visits every pixel's filter footprint);
//! - and the full image after the switch, for scale.
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
        get(&addr, "/api/render.png?subsample=8");

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
            let (pw, ph) = (w.div_ceil(8), h.div_ceil(8));
            let (st, _, b) = get(
                &addr,
                &format!("/api/render.png?{sw}&width={pw}&height={ph}&stream=bench"),
            );
            assert_eq!(st, 200);
            preview.push(a + b);
            let (st, _, ms) = get(
                &addr,
                &format!("/api/render.png?{sw}&subsample=8&stream=bench"),
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
        println!("  (--subsample 8 preview   {})", stats(&mut subsampled));
        println!("  switch → full image      {}", stats(&mut full));
        running.stop();
    }
}
