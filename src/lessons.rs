//! `lessons/NN-topic.json` → the book's figures under `book/src/figures/`.
//!
//! A lesson lists figures, each the rtlab command line that makes it and the file it makes:
//!
//! ```json
//! {"title": "Implicit surfaces", "chapter": "book/src/03-implicit-surfaces.md",
//!  "figures": [
//!    {"name": "circle", "caption": "...", "command": "rtlab intersect circle --origin -3,1 --dir 0.8,-0.6 -o {out}",
//!     "output": "book/src/figures/circle.png"},
//!    {"name": "circle-text", "command": "rtlab intersect circle --origin -3,1 --dir 0.8,-0.6",
//!     "output": "book/src/figures/circle.txt"}]}
//! ```
//!
//! `{out}` in a command stands for the output path; a command without it has its standard
//! output captured into the output file. Commands run in-process, from the repository root.

use crate::error::{Error, Result};
use crate::scene::json::{parse, Node};
use std::path::{Path, PathBuf};

#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub name: String,
    pub caption: String,
    pub command: String,
    /// Output path relative to the repository root.
    pub output: String,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Lesson {
    pub file: PathBuf,
    pub title: String,
    pub chapter: String,
    pub figures: Vec<Figure>,
}

/// Reads every `lessons/*.json` under `root` (sorted), or only those whose file stem or
/// number matches one of `only`.
pub fn load_all(root: &Path, only: &[String]) -> Result<Vec<Lesson>> {
    let dir = root.join("lessons");
    let entries = std::fs::read_dir(&dir)
        .map_err(|e| Error::io(&dir, format!("cannot list lessons: {e}")))?;
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    let mut lessons = Vec::new();
    for f in files {
        let stem = f
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("")
            .to_string();
        if !only.is_empty()
            && !only
                .iter()
                .any(|o| stem == *o || stem.starts_with(&format!("{o}-")))
        {
            continue;
        }
        lessons.push(load(&f)?);
    }
    if !only.is_empty() && lessons.is_empty() {
        return Err(Error::arg(
            "LESSON",
            format!("no lesson matches {} in {}", only.join(", "), dir.display()),
        ));
    }
    Ok(lessons)
}

pub fn load(file: &Path) -> Result<Lesson> {
    let text = std::fs::read_to_string(file).map_err(|e| Error::io(file, e))?;
    let v = parse(file, &text)?;
    let root = Node {
        v: &v,
        path: "",
        file,
    };
    let o = root.object(&["title", "chapter", "figures"])?;
    o.check_keys()?;
    let figures = o.each("figures", |n, _| {
        let f = n.object(&["name", "caption", "command", "output"])?;
        f.check_keys()?;
        let command: String = f.req("command", |n| n.str().map(String::from))?;
        if !command.starts_with("rtlab ") {
            return Err(n.err("a figure's command starts with \"rtlab \""));
        }
        let output: String = f.req("output", |n| n.str().map(String::from))?;
        if !output.starts_with("book/src/figures/") {
            return Err(n.err("a figure's output lives under book/src/figures/"));
        }
        Ok(Figure {
            name: f.req("name", |n| n.str().map(String::from))?,
            caption: f.or("caption", String::new(), |n| n.str().map(String::from))?,
            command,
            output,
        })
    })?;
    Ok(Lesson {
        file: file.to_path_buf(),
        title: o.req("title", |n| n.str().map(String::from))?,
        chapter: o.or("chapter", String::new(), |n| n.str().map(String::from))?,
        figures,
    })
}

/// Splits a command line into words: whitespace separates, double quotes group.
pub fn words(command: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let (mut quoted, mut any) = (false, false);
    for ch in command.chars() {
        match ch {
            '"' => {
                quoted = !quoted;
                any = true;
            }
            c if c.is_whitespace() && !quoted => {
                if any {
                    out.push(std::mem::take(&mut cur));
                    any = false;
                }
            }
            c => {
                cur.push(c);
                any = true;
            }
        }
    }
    if any {
        out.push(cur);
    }
    out
}
