//! `rtlab lessons build|check [LESSON ...]`: make the book's figures, or check that the
//! committed ones are up to date.

use crate::error::{Error, Result};
use crate::lessons::{load_all, words, Figure};
use std::path::Path;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct Args {
    /// build: (re)make the figures; check: rebuild into a temporary folder and fail on any
    /// committed figure that differs.
    #[arg(value_parser = ["build", "check"])]
    pub action: String,
    /// Lessons to run (file stem like 03-implicit-surfaces, or its number 03); default all.
    pub lessons: Vec<String>,
    /// The repository root (default: the current folder).
    #[arg(long, default_value = ".")]
    pub root: PathBuf,
}

pub fn run(args: Args, out: &mut dyn std::io::Write) -> Result<()> {
    // Figures name paths relative to the repository root, so run from there.
    let root = args
        .root
        .canonicalize()
        .map_err(|e| Error::io(&args.root, e))?;
    std::env::set_current_dir(&root).map_err(|e| Error::io(&root, e))?;
    let lessons = load_all(&root, &args.lessons)?;
    let tmp = tempfile::tempdir()
        .map_err(|e| Error::Other(format!("cannot make a temporary folder: {e}")))?;
    let mut stale = Vec::new();
    let mut count = 0;
    for lesson in &lessons {
        for fig in &lesson.figures {
            count += 1;
            if args.action == "build" {
                build_figure(fig, &root.join(&fig.output))?;
                super::emit(out, &format!("built {}\n", fig.output))?;
            } else {
                let fresh = tmp.path().join(format!(
                    "{count}-{}",
                    PathBuf::from(&fig.output)
                        .file_name()
                        .and_then(|s| s.to_str())
                        .unwrap_or("figure")
                ));
                build_figure(fig, &fresh)?;
                let new = std::fs::read(&fresh).map_err(|e| Error::io(&fresh, e))?;
                match std::fs::read(root.join(&fig.output)) {
                    Ok(old) if old == new => {}
                    Ok(_) => stale.push(format!(
                        "{} ({}: {}) is stale",
                        fig.output,
                        lesson.file.display(),
                        fig.name
                    )),
                    Err(_) => stale.push(format!(
                        "{} ({}: {}) is missing",
                        fig.output,
                        lesson.file.display(),
                        fig.name
                    )),
                }
            }
        }
    }
    if !stale.is_empty() {
        return Err(Error::Other(format!(
            "{} of {count} figure(s) out of date: {}; run `rtlab lessons build` and commit the figures",
            stale.len(),
            stale.join("; ")
        )));
    }
    if args.action == "check" {
        super::emit(out, &format!("{count} figure(s) up to date\n"))?;
    }
    Ok(())
}

/// Runs one figure's command in-process (here, in `cli/`, since it runs the CLI; the
/// lesson files themselves are read by the library's [`crate::lessons`]), writing its output to `out_path`.
pub fn build_figure(fig: &Figure, out_path: &Path) -> Result<()> {
    use clap::Parser;
    let out_str = out_path.to_string_lossy().to_string();
    let argv: Vec<String> = words(&fig.command)
        .into_iter()
        .map(|w| w.replace("{out}", &out_str))
        .collect();
    let captures = !fig.command.contains("{out}");
    let cli = super::Cli::try_parse_from(&argv).map_err(|e| {
        Error::Other(format!(
            "figure {}: the command does not parse: {}",
            fig.name,
            e.to_string().lines().next().unwrap_or("")
        ))
    })?;
    if let Some(dir) = out_path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    }
    let mut buf: Vec<u8> = Vec::new();
    super::run(cli, &mut buf).map_err(|e| Error::Other(format!("figure {}: {e}", fig.name)))?;
    if captures {
        crate::output::write_atomic(out_path, &buf)?;
    }
    Ok(())
}
