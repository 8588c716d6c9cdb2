//! `rtlab serve`'s API against the CLI, byte for byte, and the server against misuse: bad
//! parameters, traversal paths, huge requests, foreign Host headers, concurrency, superseded
//! renders, a scene file edited and broken while the server runs.

use crate::common::{path, rtlab, stderr, tmp, write_tmp};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::TcpStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A `rtlab serve` process on a free port, stopped when dropped.
pub struct Server {
    child: Child,
    pub addr: String,
    pub url: String,
}

impl Server {
    pub fn start(scene: &Path, args: &[&str]) -> Server {
        let mut child = Command::new(env!("CARGO_BIN_EXE_rtlab"))
            .arg("serve")
            .arg(scene)
            .args(["--port", "0"])
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("rtlab serve starts");
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let url = line
            .split_whitespace()
            .find(|w| w.starts_with("http://"))
            .unwrap_or_else(|| panic!("no URL printed: {line:?}"))
            .to_string();
        let addr = url
            .trim_start_matches("http://")
            .trim_end_matches('/')
            .to_string();
        Server { child, addr, url }
    }

    /// GET `target` with this server's own Host.
    pub fn get(&self, target: &str) -> Reply {
        let host = self.addr.clone();
        self.raw(&format!(
            "GET {target} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"
        ))
    }

    /// Sends `request` as it is and reads the whole answer.
    pub fn post(&self, target: &str, body: &[u8]) -> Reply {
        let host = self.addr.clone();
        let mut request = format!(
            "POST {target} HTTP/1.1\r\nHost: {host}\r\nContent-Type: image/png\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
            body.len()
        )
        .into_bytes();
        request.extend_from_slice(body);
        self.raw_bytes(&request)
    }

    pub fn raw(&self, request: &str) -> Reply {
        self.raw_bytes(request.as_bytes())
    }

    fn raw_bytes(&self, request: &[u8]) -> Reply {
        let mut s = TcpStream::connect(&self.addr).unwrap();
        s.set_read_timeout(Some(Duration::from_secs(300))).unwrap();
        let _ = s.write_all(request);
        let mut bytes = Vec::new();
        let _ = s.read_to_end(&mut bytes);
        Reply::parse(&bytes)
    }
}

impl Server {
    /// Stops the server and returns all it wrote on stderr.
    pub fn stop_for_stderr(mut self) -> String {
        let _ = self.child.kill();
        let mut text = String::new();
        let _ = self.child.stderr.take().unwrap().read_to_string(&mut text);
        text
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[derive(Debug)]
pub struct Reply {
    pub status: u16,
    pub headers: String,
    pub body: Vec<u8>,
}

impl Reply {
    fn parse(bytes: &[u8]) -> Reply {
        let split = bytes
            .windows(4)
            .position(|w| w == b"\r\n\r\n")
            .unwrap_or_else(|| panic!("no HTTP answer: {:?}", String::from_utf8_lossy(bytes)));
        let headers = String::from_utf8_lossy(&bytes[..split]).into_owned();
        let status = headers
            .split_whitespace()
            .nth(1)
            .and_then(|s| s.parse().ok())
            .unwrap();
        let mut body = bytes[split + 4..].to_vec();
        if headers
            .to_ascii_lowercase()
            .contains("transfer-encoding: chunked")
        {
            body = dechunk(&body);
        }
        Reply {
            status,
            headers,
            body,
        }
    }

    pub fn text(&self) -> String {
        String::from_utf8_lossy(&self.body).into_owned()
    }
}

fn dechunk(mut b: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let Some(eol) = b.windows(2).position(|w| w == b"\r\n") else {
            return out;
        };
        let n = usize::from_str_radix(String::from_utf8_lossy(&b[..eol]).trim(), 16).unwrap_or(0);
        if n == 0 || b.len() < eol + 2 + n {
            return out;
        }
        out.extend_from_slice(&b[eol + 2..eol + 2 + n]);
        b = &b[eol + 4 + n..];
    }
}

/// A copy of a repository scene in a fresh folder (the live-scene tests edit it).
pub fn scene_copy(rel: &str, name: &str) -> PathBuf {
    let p = tmp(name);
    std::fs::copy(path(rel), &p).unwrap();
    p
}

/// What the CLI prints on stderr for these arguments (its one line).
fn cli_error(args: &[&str]) -> String {
    let o = rtlab(args);
    assert_eq!(o.status.code(), Some(2), "{args:?} should fail");
    stderr(&o).lines().next().unwrap().to_string()
}

#[test]
fn render_and_explain_are_the_clis_bytes() {
    let s = Server::start(&path("scenes/spheres.json"), &["--max-depth", "2"]);
    let out = tmp("serve-render.png");
    let o = rtlab(&[
        "render",
        "scenes/spheres.json",
        "--max-depth",
        "2",
        "--spp",
        "2",
        "--sampler",
        "random",
        "--no-shadows",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let r = s.get("/api/render.png?spp=2&sampler=random&no-shadows");
    assert_eq!(r.status, 200, "{}", r.text());
    assert!(r.headers.contains("image/png"));
    assert_eq!(
        r.body,
        std::fs::read(&out).unwrap(),
        "render.png differs from rtlab render"
    );

    // An AOV is `render --aov`.
    let o = rtlab(&[
        "render",
        "scenes/spheres.json",
        "--max-depth",
        "2",
        "--aov",
        "normal",
        "-q",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    let r = s.get("/api/render.png?aov=normal");
    assert_eq!(r.body, std::fs::read(&out).unwrap());
    // Its legend, the line render --aov prints, comes in a header (form-encoded).
    let legend = r
        .headers
        .lines()
        .find_map(|l| l.strip_prefix("x-rtlab-aov-legend: "))
        .unwrap_or_else(|| panic!("{}", r.headers));
    assert!(legend.starts_with("normal%3A+"), "{legend}");

    // The page's preview and full image are passes 1 and 2 of `render --passes K`.
    for k in ["1", "2", "3"] {
        let o = rtlab(&[
            "render",
            "scenes/spheres.json",
            "--max-depth",
            "2",
            "--passes",
            k,
            "-q",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let r = s.get(&format!("/api/render.png?pass={k}"));
        assert_eq!(r.status, 200, "pass {k}: {}", r.text());
        // The options that make pass K's settings, to explain its pixels with.
        let options = r
            .headers
            .lines()
            .find_map(|l| l.strip_prefix("x-rtlab-pass-options: "))
            .map(|v| v.trim_end());
        let want = match k {
            "1" => "subsample%3D4",
            "2" => "",
            _ => "sampler%3Dgrid%26spp%3D4",
        };
        assert_eq!(options, Some(want), "pass {k}: {}", r.headers);
        assert_eq!(
            r.body,
            std::fs::read(&out).unwrap(),
            "pass {k} differs from --passes {k}"
        );
    }
    let plain = s.get("/api/render.png").body;
    assert_eq!(
        s.get("/api/render.png?pass=2").body,
        plain,
        "pass 2 is the scene's own image"
    );
    assert_ne!(
        s.get("/api/render.png?pass=1").body,
        plain,
        "pass 1 is a preview"
    );

    for (q, flags) in [
        ("x=160&y=120", vec![]),
        (
            "x=10&y=300&sampler=jittered&spp=4",
            vec!["--sampler", "jittered", "--spp", "4"],
        ),
        ("x=200&y=150&no-reflections", vec!["--no-reflections"]),
        // With a mistake, explain adds what differs from the correct run: so does the API.
        (
            "x=200&y=150&mistake=blinn-phong",
            vec!["--mistake", "blinn-phong"],
        ),
        (
            "x=160&y=120&course-stage=intersect",
            vec!["--course-stage", "intersect"],
        ),
    ] {
        let r = s.get(&format!("/api/explain?{q}"));
        assert_eq!(r.status, 200, "{q}: {}", r.text());
        let (x, y) = {
            let v: Vec<&str> = q.split('&').take(2).map(|p| &p[2..]).collect();
            (v[0].to_string(), v[1].to_string())
        };
        let pixel = format!("{x},{y}");
        let mut args = vec![
            "explain",
            "scenes/spheres.json",
            "--max-depth",
            "2",
            "--pixel",
            &pixel,
            "--format",
            "json",
        ];
        args.extend(flags.iter().copied());
        let o = rtlab(&args);
        assert!(o.status.success());
        assert_eq!(r.text(), String::from_utf8_lossy(&o.stdout), "explain {q}");
    }

    // The diagram is `explain --diagram`'s figure.
    let cli_diagram = |name: &str, extra: &[&str]| {
        let fig = tmp(name);
        let mut args = vec!["explain", "scenes/spheres.json", "--max-depth", "2"];
        args.extend(["--pixel", "200,150", "--diagram", fig.to_str().unwrap()]);
        args.extend(extra);
        let o = rtlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(&fig).unwrap()
    };
    let fig = cli_diagram("serve-diagram.png", &[]);
    let r = s.get("/api/diagram.png?x=200&y=150");
    assert_eq!(r.status, 200);
    assert_eq!(r.body, fig, "diagram differs from explain --diagram");
    // With a ray highlighted it is a different figure of the same size.
    let h = s.get("/api/diagram.png?x=200&y=150&highlight=1");
    assert_eq!(h.status, 200);
    assert_ne!(h.body, r.body);
    // `sample=I` draws the sample the page selected, as `explain --sample I --diagram` does
    // (under the box filter a pixel's samples are its own, in order); `sample=0` is the
    // default figure.
    let q = "x=200&y=150&spp=4&sampler=jittered";
    let first = s.get(&format!("/api/diagram.png?{q}"));
    assert_eq!(
        first.body,
        s.get(&format!("/api/diagram.png?{q}&sample=0")).body
    );
    let third = s.get(&format!("/api/diagram.png?{q}&sample=2"));
    assert_eq!(third.status, 200, "{}", third.text());
    let fig = cli_diagram(
        "serve-diagram-sample.png",
        &["--spp", "4", "--sampler", "jittered", "--sample", "2"],
    );
    assert_eq!(third.body, fig, "sample=2 vs explain --sample 2");
    assert_ne!(third.body, first.body);
}

#[test]
fn scene_steps_options_and_events() {
    let s = Server::start(&path("scenes/spheres.json"), &[]);
    let r = s.get("/api/scene");
    assert_eq!(r.status, 200);
    let v: serde_json::Value = serde_json::from_slice(&r.body).unwrap();
    let scene = rtlab::scene::Scene::load(&path("scenes/spheres.json")).unwrap();
    assert_eq!(v["width"], scene.camera.width);
    assert_eq!(v["height"], scene.camera.height);
    let names: Vec<&str> = v["objects"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["name"].as_str().unwrap())
        .collect();
    let expected: Vec<&str> = scene.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, expected);
    assert_eq!(v["lights"].as_array().unwrap().len(), scene.lights.len());
    assert_eq!(
        v["materials"].as_array().unwrap().len(),
        scene.materials.len()
    );
    // Options apply here too.
    let r = s.get("/api/scene?width=64&height=48");
    let v: serde_json::Value = serde_json::from_slice(&r.body).unwrap();
    assert_eq!(
        (v["width"].as_u64(), v["height"].as_u64()),
        (Some(64), Some(48))
    );

    // The controls come from the CLI's parser: every RenderArgs flag is there.
    let r = s.get("/api/options");
    let v: serde_json::Value = serde_json::from_slice(&r.body).unwrap();
    let names: Vec<&str> = v["render"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["name"].as_str().unwrap())
        .collect();
    for n in [
        "spp",
        "sampler",
        "filter",
        "max-depth",
        "no-shadows",
        "no-textures",
        "subsample",
    ] {
        assert!(names.contains(&n), "{n} missing from {names:?}");
    }
    assert!(v["aov"].as_array().unwrap().iter().any(|a| a == "depth"));
    // Every option that takes one of a few names offers them (the page shows a menu).
    let choices = |name: &str| -> Vec<String> {
        let o = v["render"].as_array().unwrap().iter();
        let o = o.clone().find(|o| o["name"] == name);
        let o = o.unwrap_or_else(|| panic!("{name} missing"));
        let c = o["choices"].as_array().unwrap().iter();
        c.map(|c| c.as_str().unwrap().to_string()).collect()
    };
    let mistake = v["render"]
        .as_array()
        .unwrap()
        .iter()
        .find(|o| o["name"] == "mistake")
        .unwrap();
    let suggested = mistake["suggestions"].as_array().unwrap();
    assert_eq!(suggested.len(), rtlab::mistakes::Mistake::ALL.len());
    assert!(suggested.iter().any(|m| m == "shadow-acne"), "{mistake}");
    for (name, expected) in [
        ("traversal", &["single", "bundle"][..]),
        ("accel", &["linear", "bvh"]),
        ("course-stage", &["intersect", "illuminate"]),
        ("texture-filter", &["nearest", "bilinear"]),
        ("encoding", &["clamp", "srgb"]),
    ] {
        assert_eq!(choices(name), expected, "{name}");
    }

    // Steps: the captions, and each frame a PNG; past the end is a 400.
    let r = s.get("/api/steps?width=96&height=72");
    assert_eq!(r.status, 200, "{}", r.text());
    let list: serde_json::Value = serde_json::from_slice(&r.body).unwrap();
    let n = list.as_array().unwrap().len();
    assert!(n >= 3, "{list}");
    let f = s.get("/api/steps/frame.png?i=0&width=96&height=72");
    assert_eq!(f.status, 200);
    assert_eq!(&f.body[1..4], b"PNG");
    let f = s.get(&format!("/api/steps/frame.png?i={n}&width=96&height=72"));
    assert_eq!(f.status, 400);
    assert!(f.text().contains("does not exist"), "{}", f.text());

    let r = s.get("/api/status");
    assert!(r.text().contains("\"version\": 1"), "{}", r.text());

    // The event stream opens with the current status.
    let mut st = TcpStream::connect(&s.addr).unwrap();
    write!(st, "GET /api/events HTTP/1.1\r\nHost: {}\r\n\r\n", s.addr).unwrap();
    st.set_read_timeout(Some(Duration::from_secs(20))).unwrap();
    let mut got = String::new();
    let mut buf = [0u8; 1024];
    while !got.contains("data:") {
        let n = st.read(&mut buf).unwrap();
        assert!(n > 0);
        got += &String::from_utf8_lossy(&buf[..n]);
    }
    assert!(got.contains("text/event-stream"), "{got}");
    assert!(got.contains("event: scene"), "{got}");
}

#[test]
fn bad_parameters_get_the_clis_one_line_messages() {
    let s = Server::start(&path("scenes/spheres.json"), &[]);
    for (q, cli) in [
        ("spp=banana", vec!["--spp", "banana"]),
        ("sampler=nope", vec!["--sampler", "nope"]),
        ("max-depth=999", vec!["--max-depth", "999"]),
        ("bogus=1", vec!["--bogus", "1"]),
        ("no-shadows=yes", vec!["--no-shadows=yes"]),
        ("width=0&height=10", vec!["--width", "0", "--height", "10"]),
    ] {
        let r = s.get(&format!("/api/explain?x=1&y=1&{q}"));
        assert_eq!(r.status, 400, "{q}: {}", r.text());
        let mut args = vec!["explain", "scenes/spheres.json", "--pixel", "1,1"];
        args.extend(cli.iter().copied());
        assert_eq!(r.text().trim_end(), cli_error(&args), "{q}");
        // The same parameters fail the same way on every endpoint.
        let r2 = s.get(&format!("/api/render.png?{q}"));
        assert_eq!((r2.status, r2.text()), (400, r.text()), "{q}");
    }
    // One pixel's document is bounded: 4096 samples (that pixel's and its neighbours' the
    // filter reaches), refused before any is traced; the CLI explains one sample of them.
    let r =
        s.get("/api/explain?x=1&y=1&sampler=jittered&spp=1024&filter=gaussian&width=3&height=3");
    assert_eq!(r.status, 400, "{}", r.text());
    assert!(
        r.text().contains("9216 samples (1024 spp × 9 pixel(s)") && r.text().contains("--sample K"),
        "{}",
        r.text()
    );
    for q in ["x=0&y=0&spp=4096", "x=0&y=0&spp=1024&filter=gaussian"] {
        let r = s.get(&format!(
            "/api/explain?{q}&sampler=jittered&width=1&height=1"
        ));
        assert_eq!(r.status, 200, "{q}: {}", r.text());
        let r = s.get(&format!(
            "/api/diagram.png?{q}&sampler=jittered&width=1&height=1"
        ));
        assert_eq!(r.status, 200, "{q}: {}", r.text());
    }
    let r = s.get("/api/explain?x=9999&y=1");
    assert_eq!(r.status, 400);
    assert_eq!(
        r.text().trim_end(),
        cli_error(&["explain", "scenes/spheres.json", "--pixel", "9999,1"])
    );
    let r = s.get("/api/render.png?aov=shiny");
    assert_eq!(r.status, 400);
    assert_eq!(
        r.text().trim_end(),
        cli_error(&["render", "scenes/spheres.json", "--aov", "shiny"])
    );
    // What some of the refusals below say. Samples are counted as the render takes them:
    // the corners sampler traces two a pixel whatever the spp (6000×6000 is 72 million,
    // past the limit though 6000×6000 × 1 spp is not), the adaptive sampler every level (84
    // a pixel at spp 64), and a subsampled render traces few pixels but filters every pixel
    // from a traced pixel's samples, so it counts as if unsubsampled (under corners too).
    let says = [
        (
            "/api/render.png?width=160&height=120&pass=8",
            "pass 8, 160×120 pixels × 4096 spp, is",
        ),
        (
            "/api/render.png?width=160&height=120&pass=8",
            "use rtlab render --passes 8",
        ),
        (
            "/api/render.png?width=6000&height=6000&sampler=corners",
            "6000×6000 pixels × 1 spp (sampler corners: a centre and a corner a pixel, and the borders) is 72012001 samples",
        ),
        (
            "/api/render.png?width=2000&height=2000&subsample=16&sampler=grid&spp=64",
            "2000×2000 pixels × 64 spp is 256000000 samples",
        ),
        (
            "/api/render.png?width=6000&height=6000&subsample=64&sampler=corners",
            "is 72012001 samples",
        ),
        (
            "/api/render.png?width=1000&height=1000&sampler=adaptive&spp=64",
            "1000×1000 pixels × 64 spp (sampler adaptive: up to 4 + 16 + 64 = 84 a pixel) is 84000000 samples",
        ),
    ];
    let mut heard = 0;
    for q in [
        "/api/explain",
        "/api/explain?x=1",
        "/api/explain?x=-1&y=2",
        "/api/explain?x=1&y=1&x=2",
        "/api/explain?x=1&y=1&=3",
        "/api/explain?x=1&y=1&--spp=3",
        "/api/explain?x=1&y=1&sp%20p=3",
        "/api/diagram.png?x=1&y=1&plane=sideways",
        "/api/diagram.png?x=1&y=1&highlight=one",
        "/api/render.png?spp=100000",
        "/api/render.png?pass=0",
        "/api/render.png?pass=two",
        "/api/render.png?pass=40",
        // Pass 8 of 160×120 is 4096 spp: past the per-request limit, as spp=4096 is.
        "/api/render.png?width=160&height=120&pass=8",
        "/api/render.png?width=160&height=120&aov=depth&pass=8",
        "/api/diagram.png?x=1&y=1&highlight=999999",
        "/api/diagram.png?x=1&y=1&sample=4",
        "/api/diagram.png?x=1&y=1&sample=first",
        "/api/explain?x=1,2&y=3",
        "/api/explain?x=1&y=1&sampler=grid%0a",
        "/api/explain?x=1&y=1&sampler=%1b%5b31mred",
        "/api/render.png?width=6000&height=6000&sampler=corners",
        "/api/render.png?width=2000&height=2000&subsample=16&sampler=grid&spp=64",
        "/api/render.png?width=6000&height=6000&subsample=64&sampler=corners",
        "/api/render.png?width=1000&height=1000&sampler=adaptive&spp=64",
    ] {
        let r = s.get(q);
        assert_eq!(r.status, 400, "{q}: {}", r.text());
        let t = r.text();
        for (_, part) in says.iter().filter(|(asked, _)| *asked == q) {
            assert!(t.contains(part), "{q}: {t:?}");
            heard += 1;
        }
        assert!(
            t.starts_with("error: ") && t.ends_with('\n') && t.lines().count() == 1,
            "{q}: {t:?}"
        );
        assert!(
            !t.contains('\u{1b}'),
            "{q}: a terminal escape code echoed back: {t:?}"
        );
    }
    assert_eq!(heard, says.len(), "every message checked");
    let r = s.get("/api/explain?x=1,2&y=3");
    assert_eq!(
        r.text(),
        "error: argument x: expected a whole number, found \"1,2\"\n"
    );
    let r = s.get(&format!(
        "/api/render.png?subsample=8&stream={}",
        "s".repeat(65)
    ));
    assert_eq!(r.status, 400, "{}", r.text());
    // Options the command line takes twice may repeat in a query too; others get the
    // CLI's own message; an endpoint's own key is given once.
    let r = s.get("/api/explain?x=1&y=1&mistake=shadow-acne&mistake=normal-not-normalized");
    assert_eq!(r.status, 200, "{}", r.text());
    let r = s.get("/api/render.png?traversal=single&traversal=bundle");
    assert_eq!(r.status, 400);
    assert_eq!(
        r.text().trim_end(),
        cli_error(&[
            "render",
            "scenes/spheres.json",
            "--traversal",
            "single",
            "--traversal",
            "bundle"
        ])
    );
    let r = s.get("/api/render.png?pass=1&pass=2");
    assert_eq!(r.text(), "error: argument pass: is given twice\n");
    let r = s.get("/api/diagram.png?x=1&y=1&sample=99999999999");
    assert_eq!(
        r.text(),
        "error: argument sample: 99999999999 is not in 0..=4294967295\n"
    );
}

#[test]
fn hostile_requests_are_refused() {
    let s = Server::start(&path("scenes/spheres.json"), &[]);
    // Only the embedded page and the API: no path reaches the file system.
    for target in [
        "/../../../../etc/passwd",
        "/%2e%2e/%2e%2e/etc/passwd",
        "/..%2f..%2fetc%2fpasswd",
        "/scenes/spheres.json",
        "/Cargo.toml",
        "/api/../Cargo.toml",
        "/api/render.png/../../Cargo.toml",
        "//etc/passwd",
        "/page.js/..",
    ] {
        let r = s.get(target);
        assert!(r.status == 404 || r.status == 400, "{target}: {}", r.status);
        let t = r.text();
        assert!(
            !t.contains("root:") && !t.contains("[package]"),
            "{target}: {t}"
        );
    }
    let page = s.get("/");
    assert_eq!(page.status, 200);
    assert!(page.text().contains("<canvas id=\"view\""));
    assert!(
        !page.text().contains("http://") && !page.text().contains("https://"),
        "the page fetches nothing from elsewhere"
    );
    assert!(s.get("/page.js").text().contains("/api/explain"));

    // DNS rebinding: a page of another site reaching 127.0.0.1 sends its own Host.
    let port = s.addr.rsplit(':').next().unwrap();
    for host in [
        "evil.example",
        "evil.example:80",
        &format!("attacker.test:{port}"),
        "127.0.0.1:1",
    ] {
        let r = s.raw(&format!(
            "GET /api/scene HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n"
        ));
        assert_eq!(r.status, 403, "Host {host}");
        assert!(!r.text().contains("objects"));
    }
    for ok in [format!("localhost:{port}"), format!("127.0.0.1:{port}")] {
        let r = s.raw(&format!(
            "GET /api/status HTTP/1.1\r\nHost: {ok}\r\nConnection: close\r\n\r\n"
        ));
        assert_eq!(r.status, 200, "Host {ok}");
    }
    let r = s.raw("GET /api/scene HTTP/1.0\r\n\r\n");
    assert_eq!(r.status, 400, "no Host header");

    // Only GET.
    let r = s.raw(&format!(
        "POST /api/render.png HTTP/1.1\r\nHost: {}\r\nContent-Length: 5\r\nConnection: close\r\n\r\nhello",
        s.addr
    ));
    assert_eq!(r.status, 405);
    let r = s.get("/api/diff");
    assert_eq!(r.status, 405);
    assert_eq!(
        r.text(),
        "error: only GET requests (and POST /api/diff with a PNG)\n"
    );

    // A page of another site may make the browser send requests here: refused, by what the
    // browser says of where the request comes from. The page's own requests pass.
    for header in [
        "Sec-Fetch-Site: cross-site".to_string(),
        "Origin: https://evil.example".to_string(),
        "Origin: null".to_string(),
        format!("Origin: http://attacker.test:{port}"),
    ] {
        let r = s.raw(&format!(
            "GET /api/render.png?subsample=8 HTTP/1.1\r\nHost: {}\r\n{header}\r\nConnection: close\r\n\r\n",
            s.addr
        ));
        assert_eq!(r.status, 403, "{header}: {}", r.text());
        assert!(r.text().contains("other sites"), "{}", r.text());
    }
    let r = s.raw(&format!(
        "GET /api/status HTTP/1.1\r\nHost: {0}\r\nOrigin: http://{0}\r\nSec-Fetch-Site: same-origin\r\nConnection: close\r\n\r\n",
        s.addr
    ));
    assert_eq!(r.status, 200, "{}", r.text());
    let r = s.raw(&format!(
        "GET /api/status HTTP/1.1\r\nHost: {0}\r\nHost: evil.example\r\nConnection: close\r\n\r\n",
        s.addr
    ));
    assert_eq!(r.status, 400, "two Host headers: {}", r.text());

    // Huge requests: a long query, a long target, a huge header, a body announced as huge.
    let q = "spp=1&".repeat(2000);
    let r = s.get(&format!("/api/render.png?{q}"));
    assert!(r.status == 400 || r.status == 414, "{}", r.status);
    let r = s.get(&format!("/{}", "a".repeat(20_000)));
    assert_eq!(r.status, 414);
    let r = s.raw(&format!(
        "GET /api/status HTTP/1.1\r\nHost: {}\r\nX-Big: {}\r\nConnection: close\r\n\r\n",
        s.addr,
        "b".repeat(1_000_000)
    ));
    assert!(
        r.status == 431 || r.status == 400 || r.status == 413,
        "{}",
        r.status
    );
    let r = s.raw(&format!(
        "GET /api/status HTTP/1.1\r\nHost: {}\r\nContent-Length: 100000000000\r\nConnection: close\r\n\r\n",
        s.addr
    ));
    assert!(r.status < 500, "{}", r.status);
    let r = s.raw("NONSENSE\r\n\r\n");
    assert!(r.status == 400 || r.status == 0, "{}", r.status);

    // Still serving after all that.
    assert_eq!(s.get("/api/status").status, 200);
}

#[test]
fn concurrent_requests_and_superseded_renders() {
    let s = Server::start(&path("scenes/spheres.json"), &[]);
    let expected = {
        let o = rtlab(&[
            "explain",
            "scenes/spheres.json",
            "--pixel",
            "100,100",
            "--format",
            "json",
        ]);
        String::from_utf8_lossy(&o.stdout).into_owned()
    };
    std::thread::scope(|sc| {
        let hs: Vec<_> = (0..6)
            .map(|_| sc.spawn(|| s.get("/api/explain?x=100&y=100")))
            .collect();
        for h in hs {
            let r = h.join().unwrap();
            assert_eq!(r.status, 200);
            assert_eq!(r.text(), expected);
        }
    });
    // A long render on a stream, then a newer one on the same stream: the first is cancelled.
    std::thread::scope(|sc| {
        let slow = sc.spawn(|| s.get("/api/render.png?spp=256&sampler=random&stream=t"));
        let t0 = Instant::now();
        std::thread::sleep(Duration::from_millis(500));
        let fast = s.get("/api/render.png?subsample=8&stream=t");
        assert_eq!(fast.status, 200);
        let slow = slow.join().unwrap();
        assert_eq!(slow.status, 409, "{}", slow.text());
        assert!(slow.text().contains("superseded"));
        // Cancelled, not finished: a full 256-spp render takes far longer than this.
        assert!(t0.elapsed() < Duration::from_secs(120));
    });
    // Another stream's render is not affected.
    let r = s.get("/api/render.png?subsample=4&stream=other");
    assert_eq!(r.status, 200);
    // Renders whose clients went away stop: they do not keep the server's two work slots
    // busy (a page that drops its image loads would otherwise pile up renders).
    for _ in 0..2 {
        let mut c = TcpStream::connect(&s.addr).unwrap();
        write!(
            c,
            "GET /api/render.png?spp=4096&sampler=random HTTP/1.1\r\nHost: {}\r\n\r\n",
            s.addr
        )
        .unwrap();
        std::thread::sleep(Duration::from_millis(300));
        drop(c);
    }
    let t0 = Instant::now();
    let r = s.get("/api/explain?x=100&y=100");
    assert_eq!(r.status, 200);
    // Two 4096-spp renders of 480×360 take minutes on this machine; cancelled, seconds.
    assert!(t0.elapsed() < Duration::from_secs(60), "{:?}", t0.elapsed());
}

/// What `serve` was started with stays under every request: its switches (a request cannot
/// turn `--no-shadows` off, nor leave it out), its mistakes (a request's add to them), and a
/// mistake made in the bytes (`srgb-gamma`) shows in `render.png` as in `rtlab render`.
#[test]
fn the_servers_options_hold_under_every_request() {
    let s = Server::start(
        &path("scenes/spheres.json"),
        &["--no-shadows", "--mistake", "no-attenuation"],
    );
    let cli = |extra: &[&str]| {
        let out = tmp(&format!("serve-held-{}.png", extra.join("_")));
        let mut args = vec!["render", "scenes/spheres.json", "--no-shadows"];
        args.extend([
            "--mistake",
            "no-attenuation",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ]);
        args.extend(extra);
        let o = rtlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(&out).unwrap()
    };
    let plain = cli(&["--passes", "1"]);
    for target in [
        "/api/render.png?pass=1",
        "/api/render.png?pass=1&shadows",
        "/api/render.png?pass=1&mistake=no-attenuation",
    ] {
        let r = s.get(target);
        assert_eq!(r.status, 200, "{target}: {}", r.text());
        assert_eq!(
            r.body, plain,
            "{target}: not rtlab render --no-shadows --mistake …"
        );
    }
    let r = s.get("/api/render.png?pass=1&mistake=srgb-gamma");
    assert_eq!(r.status, 200, "{}", r.text());
    assert_eq!(r.body, cli(&["--passes", "1", "--mistake", "srgb-gamma"]));
    assert_ne!(r.body, plain, "srgb-gamma changes the bytes");
    let scene: serde_json::Value = serde_json::from_str(&s.get("/api/scene").text()).unwrap();
    assert_eq!(scene["render"]["shadows"], false, "{scene}");
}

/// Steps and diffs whose clients went away stop too, as renders do: they do not keep the
/// server's two work slots busy.
#[test]
fn abandoned_steps_and_diffs_stop() {
    let s = Server::start(&path("scenes/glass.json"), &[]);
    let png = {
        let out = tmp("serve-abandoned.png");
        let o = rtlab(&[
            "render",
            "scenes/glass.json",
            "-q",
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(&out).unwrap()
    };
    let steps = format!(
        "GET /api/steps?spp=9&sampler=grid HTTP/1.1\r\nHost: {}\r\n\r\n",
        s.addr
    );
    let diff = [
        format!(
            "POST /api/diff?spp=64&sampler=grid HTTP/1.1\r\nHost: {}\r\nContent-Type: image/png\r\nContent-Length: {}\r\n\r\n",
            s.addr,
            png.len()
        )
        .into_bytes(),
        png.clone(),
    ]
    .concat();
    // Both slots taken by abandoned work, then a preview: on two cores the glass's steps at
    // 9 spp take 19 s and its diff at 64 spp 100 s when nothing stops them.
    for (request, within) in [(steps.into_bytes(), 10), (diff, 45)] {
        for _ in 0..2 {
            let mut c = TcpStream::connect(&s.addr).unwrap();
            c.write_all(&request).unwrap();
            std::thread::sleep(Duration::from_millis(300));
            drop(c);
        }
        let t0 = Instant::now();
        let r = s.get("/api/render.png?pass=1");
        assert_eq!(r.status, 200);
        assert!(
            t0.elapsed() < Duration::from_secs(within),
            "{:?}",
            t0.elapsed()
        );
    }
}

/// A request refused for its parameters does not supersede the render running on its
/// stream; and an explanation that would keep too many rays is refused before it is made.
#[test]
fn refused_requests_leave_running_work_alone() {
    let s = Server::start(&path("scenes/spheres.json"), &[]);
    std::thread::scope(|sc| {
        // Pass 6 (256 spp) runs for seconds; the refusals come while it does.
        let running = sc.spawn(|| s.get("/api/render.png?pass=6&stream=r"));
        std::thread::sleep(Duration::from_millis(200));
        // Refused by the parser, by the scene's checks, by the pass's.
        for bad in [
            "spp=x",
            "pass=0",
            "aov=bogus",
            "sampler=bogus",
            "mistake=nosuch",
            "spp=3&sampler=grid",
            "pass=40",
        ] {
            let r = s.get(&format!("/api/render.png?stream=r&{bad}"));
            assert_eq!(r.status, 400, "{bad}: {}", r.text());
        }
        let running = running.join().unwrap();
        assert_eq!(running.status, 200, "{}", running.text());
    });
    let glass = Server::start(&path("scenes/glass.json"), &[]);
    let r = glass.get("/api/explain?x=48&y=10&width=64&height=40&spp=1024&sampler=random");
    assert_eq!(r.status, 400, "{}", r.text());
    assert!(r.text().contains("more than 16384 rays"), "{}", r.text());
    let r = glass.get("/api/explain?x=48&y=10&width=64&height=40&spp=16&sampler=random");
    assert_eq!(r.status, 200, "{}", r.text());
    // One sample alone cannot pass the bound either, whatever its own budget: nested mirror
    // glass to depth 64 with no ray budget would trace 2⁶⁵ rays.
    let deep = write_tmp(
        "serve-deep.json",
        r#"{"camera": {"position": [0, 0, 5], "look_at": [0, 0, 0], "width": 64, "height": 48},
  "render": {"max_depth": 64, "min_contribution": 0},
  "lights": [{"type": "point", "position": [3, 4, 5]}],
  "materials": {"glass": {"diffuse": [0.1, 0.1, 0.1], "reflective": [1, 1, 1],
                          "transparent": [1, 1, 1], "ior": 1.5}},
  "objects": [{"shape": "sphere", "radius": 1.5, "material": "glass"},
              {"shape": "sphere", "radius": 1.0, "material": "glass"}]}"#,
    );
    let deep = Server::start(&deep, &[]);
    let r = deep.get("/api/explain?x=32&y=24&max-rays=4294967295");
    assert_eq!(r.status, 400, "{}", r.text());
    assert!(r.text().contains("more than 16384 rays"), "{}", r.text());
}

/// An AOV on a stream is superseded as the colour image is: it stops (409) instead of
/// keeping its threads busy for a page that no longer wants it (the page's AOV refinement).
#[test]
fn a_superseded_aov_render_stops() {
    let s = Server::start(&path("scenes/blob.json"), &[]);
    std::thread::scope(|sc| {
        let t0 = Instant::now();
        let slow = sc.spawn(|| s.get("/api/render.png?aov=depth&spp=64&sampler=random&stream=a"));
        std::thread::sleep(Duration::from_millis(300));
        let fast = s.get("/api/render.png?aov=depth&subsample=8&stream=a");
        assert_eq!(fast.status, 200, "{}", fast.text());
        let slow = slow.join().unwrap();
        assert_eq!(slow.status, 409, "{}", slow.text());
        assert!(slow.text().contains("superseded"));
        // Stopped, not finished and thrown away: the whole AOV (16 million samples of the
        // blob's root finding) takes 16 s on two idle cores, the stopped one under a second.
        assert!(t0.elapsed() < Duration::from_secs(8), "{:?}", t0.elapsed());
    });
    assert_eq!(s.get("/api/status").status, 200);
}

#[test]
fn edited_and_broken_scenes_while_serving() {
    let scene = scene_copy("scenes/spheres.json", "serve-live.json");
    let s = Server::start(&scene, &[]);
    let before = s.get("/api/render.png?subsample=4").body;
    let text = std::fs::read_to_string(&scene).unwrap();
    let wait_for = |want: &dyn Fn(&serde_json::Value) -> bool| {
        let t0 = Instant::now();
        loop {
            let v: serde_json::Value = serde_json::from_slice(&s.get("/api/status").body).unwrap();
            if want(&v) {
                return v;
            }
            assert!(t0.elapsed() < Duration::from_secs(30), "status stayed {v}");
            std::thread::sleep(Duration::from_millis(100));
        }
    };
    // A valid edit: a new version, a new image.
    let edited = text.replacen("\"width\": 480", "\"width\": 240", 1);
    assert_ne!(edited, text, "the scene's width is written as expected");
    rtlab::output::write_atomic(&scene, edited.as_bytes()).unwrap();
    wait_for(&|v| v["version"] == 2 && v["error"].is_null());
    let after = s.get("/api/render.png?subsample=4");
    assert_eq!(after.status, 200);
    assert_ne!(after.body, before);
    // A broken edit: the error names the file and the JSON path; requests say so too.
    let broken = edited.replacen("\"width\": 240", "\"width\": -3", 1);
    rtlab::output::write_atomic(&scene, broken.as_bytes()).unwrap();
    let v = wait_for(&|v| !v["error"].is_null());
    let err = v["error"].as_str().unwrap();
    let cli = cli_error(&["validate", scene.to_str().unwrap()]);
    assert_eq!(err, cli, "the page shows what the CLI says");
    assert!(
        err.contains("serve-live.json") && err.contains("width"),
        "{err}"
    );
    assert_eq!(v["version"], 2);
    let r = s.get("/api/render.png");
    assert_eq!(r.status, 422);
    assert_eq!(r.text().trim_end(), cli);
    // Fixed again.
    rtlab::output::write_atomic(&scene, text.as_bytes()).unwrap();
    wait_for(&|v| v["version"] == 3 && v["error"].is_null());
}

#[test]
fn serve_refuses_what_cannot_be_served() {
    let o = rtlab(&["serve", "scenes/nope.json", "--port", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("nope.json"), "{}", stderr(&o));
    let o = rtlab(&["serve", "scenes/spheres.json", "--port", "0", "--spp", "0"]);
    assert_eq!(o.status.code(), Some(2));
    // A port already taken (no name lookup: nothing leaves this machine).
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let o = rtlab(&[
        "serve",
        "scenes/spheres.json",
        "--host",
        "127.0.0.1",
        "--port",
        &port,
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("cannot listen"), "{}", stderr(&o));
    assert!(
        !stderr(&o).contains("warning"),
        "an address that cannot be listened on is only an error: {}",
        stderr(&o)
    );
}

#[test]
fn serve_warns_once_of_other_machines_and_of_each_load_warning() {
    // Loopback, named or not, is this machine only: no warning.
    let s = Server::start(Path::new("scenes/spheres.json"), &["--host", "127.0.0.1"]);
    let err = s.stop_for_stderr();
    assert!(!err.contains("warning"), "{err}");
    // Every address: other machines can reach it.
    let s = Server::start(Path::new("scenes/spheres.json"), &["--host", "0.0.0.0"]);
    let err = s.stop_for_stderr();
    assert!(
        err.contains("warning: listening on 0.0.0.0: other machines"),
        "{err}"
    );
    // A load warning (an option that does nothing here), on stderr once, however many
    // times requests load the scene with it.
    let s = Server::start(
        Path::new("scenes/spheres.json"),
        &["--adaptive-threshold", "0.1"],
    );
    for w in [40, 41, 40, 42] {
        let r = s.get(&format!("/api/render.png?width={w}&height=30"));
        assert_eq!(r.status, 200, "{}", r.text());
    }
    let err = s.stop_for_stderr();
    assert_eq!(
        err.matches("--adaptive-threshold has no effect").count(),
        1,
        "{err}"
    );
}

/// `POST /api/diff` answers what `rtlab diff --format json` prints for the same image and
/// options (the explain commands included), the figure of `-o`, and the CLI's errors.
#[test]
fn diff_of_an_uploaded_image_is_the_clis() {
    let scene = path("scenes/spheres.json");
    let s = Server::start(&scene, &["--max-depth", "2"]);
    let yours = tmp("serve-diff-yours.png");
    let o = rtlab(&[
        "render",
        scene.to_str().unwrap(),
        "--max-depth",
        "2",
        "--no-shadows",
        "--mistake",
        "blinn-phong",
        "-q",
        "-o",
        yours.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let png = std::fs::read(&yours).unwrap();
    let r = s.post("/api/diff?no-shadows&tolerance=3", &png);
    assert_eq!(r.status, 200, "{}", r.text());
    let o = rtlab(&[
        "diff",
        scene.to_str().unwrap(),
        yours.to_str().unwrap(),
        "--max-depth",
        "2",
        "--no-shadows",
        "--tolerance",
        "3",
        "--format",
        "json",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert_eq!(r.text(), String::from_utf8_lossy(&o.stdout));
    assert!(r.text().contains("\"blinn-phong\""), "{}", r.text());
    assert!(
        r.text().contains("--max-depth 2 --no-shadows"),
        "{}",
        r.text()
    );

    let fig = tmp("serve-diff-fig.png");
    let o = rtlab(&[
        "diff",
        scene.to_str().unwrap(),
        yours.to_str().unwrap(),
        "--max-depth",
        "2",
        "--no-shadows",
        "--tolerance",
        "3",
        "-o",
        fig.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1));
    let r = s.post("/api/diff?no-shadows&tolerance=3&format=png", &png);
    assert_eq!(r.status, 200);
    assert_eq!(
        r.body,
        std::fs::read(&fig).unwrap(),
        "the figure differs from diff -o"
    );

    // Not a PNG, the wrong size, a bad option: 400 with one line, never a panic (a bad
    // upload is a bad request, as a bad option is: 422 is kept for a scene that does not load).
    let r = s.post("/api/diff", b"not an image");
    assert_eq!(r.status, 400, "{}", r.text());
    assert!(r.text().contains("your image"), "{}", r.text());
    let r = s.post("/api/diff?width=100", &png);
    assert_eq!(r.status, 400, "{}", r.text());
    assert!(
        r.text().contains("480×360") || r.text().contains("100×"),
        "{}",
        r.text()
    );
    let r = s.post("/api/diff?tolerance=300", &png);
    assert_eq!(r.status, 400, "{}", r.text());
    // Only /api/diff takes a body.
    let r = s.post("/api/explain?x=1&y=1", &png);
    assert_eq!(r.status, 405, "{}", r.text());
    // The upload is bounded.
    let big = vec![0u8; 17 << 20];
    let r = s.post("/api/diff", &big);
    assert_eq!(r.status, 413, "{}", r.text());
}

/// `GET /api/bundle.png` is `explain --bundle-diagram`'s figure, byte for byte (`index=K` is
/// its `--sample K`, with the render options of the query), and where the CLI refuses the
/// figure, or the sample, the server answers 400 with the CLI's one line.
#[test]
fn the_bundle_figure_is_the_clis() {
    let s = Server::start(&path("scenes/teapot.json"), &[]);
    let cli = |name: &str, extra: &[&str]| -> Vec<u8> {
        let fig = tmp(name);
        let mut args = vec!["explain", "scenes/teapot.json", "--pixel", "330,260"];
        args.extend_from_slice(extra);
        args.extend(["--bundle-diagram", fig.to_str().unwrap()]);
        let o = rtlab(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        std::fs::read(&fig).unwrap()
    };
    let r = s.get("/api/bundle.png?x=330&y=260");
    assert_eq!(r.status, 200, "{}", r.text());
    assert_eq!(r.body, cli("serve-bundle.png", &[]));
    let r = s.get("/api/bundle.png?x=330&y=260&spp=4&sampler=grid&index=3");
    assert_eq!(r.status, 200, "{}", r.text());
    let third = ["--spp", "4", "--sampler", "grid", "--sample", "3"];
    assert_eq!(r.body, cli("serve-bundle-3.png", &third));
    assert_ne!(
        r.body,
        cli("serve-bundle-0.png", &third[..4]),
        "sample 3 is not sample 0"
    );
    let fig = tmp("serve-bundle-refused.png");
    for (q, pixel, extra) in [
        ("traversal=single", "330,260", vec!["--traversal", "single"]),
        (
            "sampler=adaptive&spp=4",
            "330,260",
            vec!["--sampler", "adaptive", "--spp", "4"],
        ),
        // Under --subsample 4 pixel (331, 260) is filled in, not traced.
        ("subsample=4", "331,260", vec!["--subsample", "4"]),
        // Four samples: 0 to 3.
        (
            "spp=4&sampler=grid&index=4",
            "330,260",
            vec!["--spp", "4", "--sampler", "grid", "--sample", "4"],
        ),
        // Past the image.
        ("", "640,260", vec![]),
        // The adaptive sampler's pixel has no sample 99 (its count known once traced).
        (
            "sampler=adaptive&spp=4&index=99",
            "330,260",
            vec!["--sampler", "adaptive", "--spp", "4", "--sample", "99"],
        ),
        (
            "sampler=adaptive&spp=4&index=0",
            "330,260",
            vec!["--sampler", "adaptive", "--spp", "4", "--sample", "0"],
        ),
        // A pixel with more samples than the page explains: the figure's own refusal still.
        (
            "width=16&height=16&sampler=adaptive&spp=16384&index=3",
            "8,8",
            vec![
                "--width",
                "16",
                "--height",
                "16",
                "--sampler",
                "adaptive",
                "--spp",
                "16384",
                "--sample",
                "3",
            ],
        ),
    ] {
        let (x, y) = pixel.split_once(',').unwrap();
        let r = s.get(&format!("/api/bundle.png?x={x}&y={y}&{q}"));
        assert_eq!(r.status, 400, "{q}: {}", r.text());
        let mut args = vec!["explain", "scenes/teapot.json", "--pixel", pixel];
        args.extend(extra.iter().copied());
        args.extend(["--bundle-diagram", fig.to_str().unwrap()]);
        assert_eq!(r.text().trim_end(), cli_error(&args), "{q}");
    }
    for (q, says) in [
        (
            "index=first",
            "error: argument index: expected a whole number, found \"first\"",
        ),
        (
            "index=-1",
            "error: argument index: expected a whole number, found \"-1\"",
        ),
        ("index=1&index=2", "error: argument index: is given twice"),
        ("sample=1", "error: unexpected argument '--sample' found"),
    ] {
        let r = s.get(&format!("/api/bundle.png?x=330&y=260&{q}"));
        assert_eq!(r.status, 400, "{q}: {}", r.text());
        assert!(r.text().trim_end().starts_with(says), "{q}: {}", r.text());
    }
    // The figure plans the pixel's whole tile: past 2^20 samples the page does not ask. A
    // tile at the image's edge is smaller (pixel 16 of 17 columns: a tile 1 wide).
    let r = s.get("/api/bundle.png?x=0&y=0&width=16&height=16&spp=8192&sampler=random");
    assert_eq!(r.status, 400, "{}", r.text());
    let says = "plans pixel (0, 0)'s tile of 16×16 pixels";
    assert!(r.text().contains(says), "{}", r.text());
    let r = s.get("/api/bundle.png?x=16&y=0&width=17&height=16&spp=8192&sampler=random");
    assert!(!r.text().contains("plans pixel"), "{}", r.text());
    // Where the figure would not plan (single traversal), the CLI's refusal, not the cap.
    let r = s
        .get("/api/bundle.png?x=0&y=0&width=16&height=16&spp=8192&sampler=random&traversal=single");
    assert!(r.text().contains("--traversal single"), "{}", r.text());
}
