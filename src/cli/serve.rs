//! `rtlab serve SCENE [--port P] [--host H] [--open] [render options]`: the lab in a browser
//! (the server itself is the library's [`crate::server`]). This face only hands the server a
//! loader that parses a request's render options with this CLI's own parser, so every render
//! option works on the API with the CLI's messages.

use super::RenderArgs;
use crate::error::{Error, Result};
use crate::server::{Flags, Loader, OptionInfo, Options};
use clap::{CommandFactory, Parser};
use std::collections::HashSet;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Scene file: native rtlab JSON or a CS1230 scenefile (watched: the page re-renders on save).
    pub scene: PathBuf,
    /// Port to listen on (0: any free port).
    #[arg(long, default_value_t = 8230)]
    pub port: u16,
    /// Address to listen on (default 127.0.0.1, this machine only). Anything else lets other
    /// machines reach the server: a warning is printed.
    #[arg(long)]
    pub host: Option<String>,
    /// Open the page in the default browser.
    #[arg(long)]
    pub open: bool,
    /// The server's render options: requests start from these and add their own.
    #[command(flatten)]
    pub render: RenderArgs,
}

/// The render options of one request, parsed as the CLI parses them.
#[derive(Debug, Parser)]
#[command(
    name = "rtlab",
    no_binary_name = true,
    disable_help_flag = true,
    disable_version_flag = true
)]
pub struct RequestArgs {
    #[command(flatten)]
    pub render: RenderArgs,
}

/// The loader of `rtlab serve`: `base` options, then a request's words (`--spp=4`). Each
/// load's warnings go to stderr the first time they are seen (the page loads the scene again
/// for every change of options, and on every save).
pub fn loader(scene: PathBuf, base: RenderArgs) -> Loader {
    let seen = Arc::new(Mutex::new(HashSet::<String>::new()));
    Arc::new(move |words: &[String]| {
        // The line the CLI prints, without its "error: ".
        let render = over(&base, words).map_err(|e| Error::Other(super::usage::usage_line(&e)))?;
        // The server reads its scene again whenever it changes: a pipe or a device there
        // would block the read (and the watcher behind it) until something writes to it.
        if std::fs::metadata(&scene).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
            return Err(Error::input(
                &scene,
                "",
                "is not a regular file (a pipe or a device): the server needs a scene file it can read again",
            ));
        }
        let loaded = render.load_full(&scene)?;
        let fresh: Vec<String> = {
            let mut seen = seen.lock().unwrap_or_else(|e| e.into_inner());
            if seen.len() > 1000 {
                seen.clear(); // a bound on what a long session keeps
            }
            loaded
                .warnings
                .into_iter()
                .filter(|w| seen.insert(w.clone()))
                .collect()
        };
        render.warn(&fresh);
        let s = loaded.scene;
        render.check_memory(&s, &scene, s.render.spp)?;
        Ok(s)
    })
}

/// The request's render options (over the server's) as command-line flags, as `rtlab diff`
/// writes them into its explain commands.
pub fn flags(base: RenderArgs) -> Flags {
    Arc::new(move |words: &[String]| {
        let a = over(&base, words).map_err(|e| Error::Other(super::usage::usage_line(&e)))?;
        Ok(a.to_flags())
    })
}

/// A request's words (`--spp=4`) parsed as the CLI parses them, over the server's options
/// ([`RenderArgs::over`]: a request cannot turn off a switch the server was started with).
fn over(base: &RenderArgs, words: &[String]) -> Result<RenderArgs, clap::Error> {
    Ok(RequestArgs::try_parse_from(words)?.render.over(base))
}

/// The render options as the page's controls, from the parser itself (a new option appears
/// on the page by itself).
pub fn option_infos() -> Vec<OptionInfo> {
    let cmd = RequestArgs::command();
    let choices = |name: &str| -> Vec<String> {
        let v: Vec<&str> = match name {
            "sampler" => crate::scene::SamplerKind::NAMES.to_vec(),
            "filter" => crate::scene::FilterKind::NAMES.to_vec(),
            "encoding" => vec!["clamp", "srgb"],
            "accel" => crate::accel::AccelKind::NAMES.to_vec(),
            "traversal" => crate::accel::Traversal::NAMES.to_vec(),
            "course-stage" => crate::scene::CourseStage::NAMES.to_vec(),
            "texture-filter" => crate::shading::TextureFilter::NAMES.to_vec(),
            _ => Vec::new(),
        };
        v.into_iter().map(String::from).collect()
    };
    cmd.get_arguments()
        .filter_map(|a| {
            let name = a.get_long()?.to_string();
            let flag = !a.get_action().takes_values();
            let mut c = choices(&name);
            if c.is_empty() {
                c = a
                    .get_possible_values()
                    .iter()
                    .map(|p| p.get_name().to_string())
                    .collect();
            }
            // `--mistake` takes a list (`a,b`) and repeats: free text, its names suggested.
            let suggestions = if name == "mistake" {
                crate::mistakes::Mistake::ALL
                    .iter()
                    .map(|m| m.name().to_string())
                    .collect()
            } else {
                Vec::new()
            };
            Some(OptionInfo {
                help: a.get_help().map(|h| h.to_string()).unwrap_or_default(),
                choices: if flag { Vec::new() } else { c },
                suggestions,
                name,
                flag,
            })
        })
        .collect()
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    let running = crate::server::start(Options {
        loader: loader(args.scene.clone(), args.render.clone()),
        flags: flags(args.render.clone()),
        options: option_infos(),
        scene: args.scene.clone(),
        host: args.host.clone(),
        port: args.port,
    })?;
    // Warned once the address is bound (an address that cannot be listened on is only an
    // error), and only when it is not loopback.
    if let Some(h) = args
        .host
        .as_ref()
        .filter(|_| !running.addr.ip().is_loopback())
    {
        eprintln!(
            "warning: listening on {h}: other machines that can reach this address can use the server \
             (it answers only requests addressed to {h} or to localhost)"
        );
    }
    super::emit(
        out,
        &format!("rtlab serve: {} (Ctrl-C to stop)\n", running.url),
    )?;
    let _ = out.flush();
    if args.open {
        // Best effort: the URL is printed either way.
        let _ = std::process::Command::new("xdg-open")
            .arg(&running.url)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn();
    }
    running.wait_for_ctrl_c();
    Ok(())
}
