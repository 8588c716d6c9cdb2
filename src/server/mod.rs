//! `rtlab serve`: the lab in a browser. A local HTTP server (axum on tokio) with one page
//! embedded in the binary and an API over the same library the CLI uses: `/api/explain` is
//! the document of `rtlab explain --format json`, `/api/render.png` the bytes `rtlab render`
//! writes.
//!
//! The server knows nothing of the command line: the CLI hands it a [`Loader`] that turns a
//! request's render options (as command-line words, `--spp=4`) into a loaded scene, so every
//! render option the CLI has, now or later, works on the API with the CLI's own messages.
//!
//! | module | what |
//! |---|---|
//! | [`params`] | query string → the server's own parameters + render-option words |
//! | [`state`] | shared state: the scene cache, render streams (cancellation), watch status |
//! | [`routes`] | the router, the running of work (slots, cancellation) and the smaller handlers |
//! | `render` | `/api/render.png`: passes, AOVs, streams a newer render supersedes |
//! | `explain` | `/api/explain`, `/api/diagram.png`: one pixel, within the server's bounds |
//! | [`diff`] | `/api/diff`: what is wrong with an uploaded image |
//! | `security` | Host-header check (DNS rebinding), methods, request sizes |
//! | [`assets`] | the embedded page |
//! | [`watch`] | live scene: polls the scene file and tells the page |

pub mod assets;
pub mod diff;
mod explain;
pub mod params;
mod render;
pub mod routes;
mod security;
pub mod state;
pub mod watch;

pub use state::{Flags, Loader, OptionInfo};

use crate::error::{Error, Result};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::Arc;

/// What `rtlab serve` was asked for.
pub struct Options {
    pub scene: PathBuf,
    /// The address to listen on; `None`: 127.0.0.1 (loopback only).
    pub host: Option<String>,
    /// 0: any free port.
    pub port: u16,
    /// Loads the scene with the given render-option words (base options already applied).
    pub loader: Loader,
    /// The words as command-line flags (for the explain commands of a diff report).
    pub flags: Flags,
    /// The render options, for the page's controls.
    pub options: Vec<OptionInfo>,
}

/// A server running on its own threads (see [`start`]).
pub struct Running {
    pub addr: SocketAddr,
    /// The page's address, e.g. `http://127.0.0.1:8230/`.
    pub url: String,
    shutdown: Option<tokio::sync::oneshot::Sender<()>>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Running {
    /// Stops the server and waits for it.
    pub fn stop(mut self) {
        self.shutdown_now();
    }

    fn shutdown_now(&mut self) {
        if let Some(tx) = self.shutdown.take() {
            let _ = tx.send(());
        }
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }

    /// Blocks until Ctrl-C ([`crate::interrupt`]), then stops.
    pub fn wait_for_ctrl_c(mut self) {
        while !crate::interrupt::requested() {
            std::thread::sleep(std::time::Duration::from_millis(200));
        }
        self.shutdown_now();
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        self.shutdown_now();
    }
}

/// Binds the address, loads the scene once (a scene that does not load is an error here, as
/// for every command) and serves on a background thread.
pub fn start(opts: Options) -> Result<Running> {
    let host = opts.host.clone().unwrap_or_else(|| "127.0.0.1".into());
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .map_err(|e| Error::Other(format!("cannot start the server's runtime: {e}")))?;
    let listener = rt
        .block_on(tokio::net::TcpListener::bind((host.as_str(), opts.port)))
        .map_err(|e| {
            Error::arg(
                "--host/--port",
                format!("cannot listen on {host}:{}: {e}", opts.port),
            )
        })?;
    let addr = listener
        .local_addr()
        .map_err(|e| Error::Other(format!("cannot read the server's address: {e}")))?;
    let state = Arc::new(state::State::new(&opts, &host, addr.port())?);
    let app = routes::router(state.clone());
    let (tx, rx) = tokio::sync::oneshot::channel::<()>();
    let url_host = if addr.ip().is_unspecified() || host.contains(':') && !host.starts_with('[') {
        if addr.is_ipv6() {
            format!("[{}]", addr.ip())
        } else {
            addr.ip().to_string()
        }
    } else {
        host.clone()
    };
    let url = format!("http://{url_host}:{}/", addr.port());
    let thread = std::thread::Builder::new()
        .name("rtlab-serve".into())
        .spawn(move || {
            rt.block_on(async move {
                tokio::spawn(watch::run(state.clone()));
                let _ = axum::serve(listener, app)
                    .with_graceful_shutdown(async {
                        let _ = rx.await;
                    })
                    .await;
            });
            // Blocking renders still running are abandoned, not awaited.
            rt.shutdown_timeout(std::time::Duration::from_millis(100));
        })
        .map_err(|e| Error::Other(format!("cannot start the server thread: {e}")))?;
    Ok(Running {
        addr,
        url,
        shutdown: Some(tx),
        thread: Some(thread),
    })
}
