//! The book cannot drift from the code: every include and anchor resolves, every figure
//! exists, and every committed figure is what `rtlab lessons build` makes today.

use super::common::*;
use std::path::Path;

fn chapters() -> Vec<std::path::PathBuf> {
    let mut v: Vec<_> = std::fs::read_dir(path("book/src"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    v.sort();
    v
}

#[test]
fn summary_lists_existing_chapters() {
    let summary = std::fs::read_to_string(path("book/src/SUMMARY.md")).unwrap();
    for line in summary.lines() {
        if let (Some(a), Some(b)) = (line.find("]("), line.rfind(')')) {
            let file = &line[a + 2..b];
            assert!(
                path("book/src").join(file).exists(),
                "SUMMARY.md links to missing {file}"
            );
        }
    }
}

#[test]
fn includes_anchors_and_figures_resolve() {
    for ch in chapters() {
        let text = std::fs::read_to_string(&ch).unwrap();
        let dir = ch.parent().unwrap();
        for (i, _) in text.match_indices("{{#include ") {
            let rest = &text[i + 11..];
            let end = rest.find("}}").expect("closed include");
            let spec = rest[..end].trim();
            let (file, anchor) = match spec.rsplit_once(':') {
                Some((f, a)) if !a.chars().all(|c| c.is_ascii_digit()) => (f, Some(a)),
                _ => (spec, None),
            };
            let target = dir.join(file);
            let body = std::fs::read_to_string(&target)
                .unwrap_or_else(|_| panic!("{}: include of missing {file}", ch.display()));
            if let Some(a) = anchor {
                assert!(
                    body.contains(&format!("ANCHOR: {a}")),
                    "{}: anchor {a} not in {file}",
                    ch.display()
                );
                assert!(
                    body.contains(&format!("ANCHOR_END: {a}")),
                    "{}: anchor {a} not closed in {file}",
                    ch.display()
                );
            }
        }
        for (i, _) in text.match_indices("](figures/") {
            let rest = &text[i + 2..];
            let end = rest.find(')').unwrap();
            let fig = &rest[..end];
            assert!(
                dir.join(fig).exists(),
                "{}: missing figure {fig}",
                ch.display()
            );
        }
    }
}

#[test]
fn committed_figures_are_up_to_date() {
    assert!(Path::new(&path("lessons")).is_dir());
    let o = rtlab(&["lessons", "check"]);
    assert!(o.status.success(), "{}", stderr(&o));
}
