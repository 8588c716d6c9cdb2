//! `explain --mistake NAME`: where the mistake changes the numbers. The pixel is explained
//! twice by the one tracer, with the mistakes and without, and the two explanation trees are
//! compared value by value; what differs is listed (text) or added as `mistakes` and
//! `differences` (JSON, YAML: `[{"path", "json_path", "correct", "mistake"}]`).

use super::explain::{explain, Explanation};
use crate::mistakes::Mistakes;
use crate::scene::Scene;
use serde::Serialize;
use serde_json::Value;

/// At most this many differences are listed in text (JSON carries them all).
const TEXT_LIMIT: usize = 40;

/// One value that differs between the correct explanation and the one with the mistakes.
#[derive(Debug, Clone, Serialize)]
pub struct Difference {
    /// Readable: `sample 0 › camera ray › light key › specular`.
    pub path: String,
    /// The JSON path in the explanation document: `samples[0].ray.shading.lights[0].specular`.
    pub json_path: String,
    pub correct: Value,
    pub mistake: Value,
}

/// The differences of an explanation made with mistakes from the correct one.
#[derive(Debug, Clone)]
pub struct Differences {
    pub mistakes: Mistakes,
    pub list: Vec<Difference>,
}

/// The explanation with its differences, for JSON and YAML (the explanation's keys first).
#[derive(Serialize)]
pub struct Annotated<'a> {
    #[serde(flatten)]
    pub explanation: &'a Explanation,
    pub mistakes: Vec<&'static str>,
    pub differences: &'a [Difference],
}

impl Differences {
    pub fn annotate<'a>(&'a self, e: &'a Explanation) -> Annotated<'a> {
        Annotated {
            explanation: e,
            mistakes: self.mistakes.iter().map(|m| m.name()).collect(),
            differences: &self.list,
        }
    }

    /// The text block appended to `explain`'s text output.
    pub fn text(&self) -> String {
        let names = self.mistakes.names();
        let mut t = format!(
            "\nWhere --mistake {names} changes the numbers (correct → with the mistake):\n"
        );
        if self.list.is_empty() {
            t += "  nowhere: this pixel is the same with and without the mistake\n";
        }
        for d in self.list.iter().take(TEXT_LIMIT) {
            t += &format!(
                "  ≠ {}: {} → {}\n",
                d.path,
                show(&d.correct),
                show(&d.mistake)
            );
        }
        if self.list.len() > TEXT_LIMIT {
            t += &format!(
                "  … and {} more (--format json lists them all)\n",
                self.list.len() - TEXT_LIMIT
            );
        }
        t
    }
}

/// Explains pixel (x, y) of `scene` again without its mistakes and compares the trees;
/// `None` when the scene has no mistakes. `sample` keeps one sample, as `--sample` does.
pub fn differences(
    scene: &Scene,
    x: u32,
    y: u32,
    sample: Option<u32>,
    with: &Explanation,
) -> Option<Differences> {
    let mistakes = scene.render.mistakes;
    if mistakes.is_empty() {
        return None;
    }
    let mut correct_scene = scene.clone();
    correct_scene.render.mistakes = Mistakes::NONE;
    let mut correct = explain(&correct_scene, x, y);
    if let Some(k) = sample {
        correct
            .samples
            .retain(|s| s.pixel == [x, y] && s.index == k);
    }
    let a = serde_json::to_value(&correct).expect("serialisable");
    let b = serde_json::to_value(with).expect("serialisable");
    let mut list = Vec::new();
    walk(&a, &b, &mut Vec::new(), &mut String::new(), &mut list);
    Some(Differences { mistakes, list })
}

/// Keys left out of the comparison: the intersection working and traversal counts differ
/// whenever a test does, and the hit, shading and colours already say what changed.
const SKIPPED: [&str; 2] = ["tests", "bvh_nodes"];

fn walk(
    a: &Value,
    b: &Value,
    path: &mut Vec<String>,
    json: &mut String,
    out: &mut Vec<Difference>,
) {
    match (a, b) {
        (Value::Object(ma), Value::Object(mb)) => {
            let mut keys: Vec<&String> = ma.keys().chain(mb.keys()).collect();
            keys.sort();
            keys.dedup();
            for k in keys {
                if SKIPPED.contains(&k.as_str()) {
                    continue;
                }
                let (va, vb) = (
                    ma.get(k).unwrap_or(&Value::Null),
                    mb.get(k).unwrap_or(&Value::Null),
                );
                let label = match k.as_str() {
                    "ray" | "children" | "lights" | "samples" => None, // labelled per item
                    "shading" => None,
                    other => Some(other.to_string()),
                };
                let len = json.len();
                if !json.is_empty() {
                    json.push('.');
                }
                json.push_str(k);
                if let Some(l) = &label {
                    path.push(l.clone());
                }
                if k == "ray" {
                    path.push(item_label("ray", va, 0));
                    walk(va, vb, path, json, out);
                    path.pop();
                } else {
                    walk(va, vb, path, json, out);
                }
                if label.is_some() {
                    path.pop();
                }
                json.truncate(len);
            }
        }
        (Value::Array(xa), Value::Array(xb))
            if !(is_numbers(xa) && is_numbers(xb)) && xa.len() == xb.len() =>
        {
            let parent = json.rsplit('.').next().unwrap_or("").to_string();
            for (i, (va, vb)) in xa.iter().zip(xb).enumerate() {
                let len = json.len();
                json.push_str(&format!("[{i}]"));
                path.push(item_label(&parent, va, i));
                walk(va, vb, path, json, out);
                path.pop();
                json.truncate(len);
            }
        }
        _ => {
            if !same(a, b) {
                out.push(Difference {
                    path: path.join(" › "),
                    json_path: json.clone(),
                    correct: a.clone(),
                    mistake: b.clone(),
                });
            }
        }
    }
}

/// How an item of a list is named in a readable path.
fn item_label(list: &str, v: &Value, i: usize) -> String {
    match list {
        "samples" => format!(
            "sample {}",
            v.get("index").and_then(Value::as_u64).unwrap_or(i as u64)
        ),
        "ray" | "children" => {
            let kind = v.get("kind").and_then(Value::as_str).unwrap_or("child");
            let depth = v.get("depth").and_then(Value::as_u64).unwrap_or(0);
            if list == "ray" {
                format!("{kind} ray")
            } else {
                format!("{kind} ray (depth {depth})")
            }
        }
        "lights" | "ignored_lights" => format!(
            "light {}",
            v.get("light").and_then(Value::as_str).unwrap_or("?")
        ),
        other => format!("{other}[{i}]"),
    }
}

fn is_numbers(v: &[Value]) -> bool {
    v.iter().all(Value::is_number)
}

/// Equal, or numbers equal to about 1e-9 relative (vectors element by element).
fn same(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap_or(0.0), y.as_f64().unwrap_or(0.0));
            (x - y).abs() <= 1e-9 * x.abs().max(y.abs()).max(1.0)
        }
        (Value::Array(xa), Value::Array(xb)) => {
            xa.len() == xb.len() && xa.iter().zip(xb).all(|(x, y)| same(x, y))
        }
        _ => a == b,
    }
}

/// A value as the text shows it: numbers to 4 decimals.
fn show(v: &Value) -> String {
    match v {
        Value::Number(n) => {
            let x = n.as_f64().unwrap_or(0.0);
            if x == x.trunc() && x.abs() < 1e15 {
                format!("{x}")
            } else {
                format!("{x:.4}")
            }
        }
        Value::Array(a) => format!("[{}]", a.iter().map(show).collect::<Vec<_>>().join(", ")),
        Value::Null => "none".into(),
        Value::Object(_) => "{…}".into(),
        other => other.to_string(),
    }
}

/// The explanation as `explain --format json` prints it: with `mistakes` and `differences`
/// added when the scene renders with mistakes. The CLI and the server both answer with this.
pub fn to_json(scene: &Scene, x: u32, y: u32, sample: Option<u32>, e: &Explanation) -> String {
    let text = match differences(scene, x, y, sample, e) {
        Some(d) => serde_json::to_string_pretty(&d.annotate(e)),
        None => serde_json::to_string_pretty(e),
    };
    text.expect("serialisable") + "\n"
}
