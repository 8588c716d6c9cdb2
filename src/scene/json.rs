//! Walking a parsed JSON document with a path, so that every error can say where it is
//! (`objects[2].radius`) and unknown keys can be caught with a "did you mean" hint.
//! Both scene formats (native and CS1230) read through this.

use crate::error::{number, suggest, Error, Result};
use glam::{DVec2, DVec3};
use serde_json::{Map, Value};
use std::path::Path;

/// The largest magnitude of any number in a scene. Intersection tests square coordinates
/// (and multiply the squares): 1e12 keeps every intermediate far from f64's 1.8e308.
pub const MAX_MAGNITUDE: f64 = 1e12;
/// The smallest size (radius, slope, ...) accepted: below it, squares fall towards f64's
/// subnormal range and the surface is lost in rounding.
pub const MIN_SIZE: f64 = 1e-12;

/// The deepest nesting of JSON objects and arrays a scene may have: serde_json's recursion
/// limit, which keeps parsing from overflowing the stack.
pub const MAX_NESTING: usize = 128;

/// A value in the document and where it sits.
#[derive(Clone, Copy)]
pub struct Node<'a> {
    pub v: &'a Value,
    pub path: &'a str,
    pub file: &'a Path,
}

/// Parses JSON text, turning a syntax error into `file: line L:C: ...` (the line and column
/// where the parser stopped, both counted from 1, as editors show them). A key written twice
/// in one object keeps its last value, as JSON readers do; [`parse_noting_twice`] says so.
pub fn parse(file: &Path, text: &str) -> Result<Value> {
    parse_noting_twice(file, text).map(|(value, _)| value)
}

/// [`parse`], and the first object that names a key twice, as an error at its second place: a
/// JSON reader keeps the last value silently, so a key written twice (a pasted "material",
/// say) would quietly replace the first. One pass over the text builds the value and watches
/// the keys; only a file that does repeat a key is read a second time, for the value with
/// the last of each.
pub fn parse_noting_twice(file: &Path, text: &str) -> Result<(Value, Option<Error>)> {
    let text = without_bom(text);
    if text.trim().is_empty() {
        return Err(Error::input(
            file,
            "",
            "the file is empty: expected a JSON scene",
        ));
    }
    let e = match serde_json::from_str::<KeysOnce>(text) {
        Ok(KeysOnce(value)) => return Ok((value, None)),
        Err(e) => e,
    };
    // The only data errors this reader raises are its own: a key written twice.
    if e.classify() == serde_json::error::Category::Data {
        let (at, what) = where_and_what(&e);
        let value = serde_json::from_str(text).map_err(|e| syntax_error(file, &e))?;
        return Ok((value, Some(Error::input(file, at, what))));
    }
    Err(syntax_error(file, &e))
}

/// A serde_json syntax error (or nesting too deep) as the scene reader reports it.
fn syntax_error(file: &Path, e: &serde_json::Error) -> Error {
    let (at, what) = where_and_what(e);
    if what == "recursion limit exceeded" {
        return Error::input(
            file,
            at,
            format!(
                "the JSON is nested more than {MAX_NESTING} levels deep (objects and arrays \
                 inside one another), the most the scene reader allows (it keeps the reader's \
                 stack bounded). Each CSG level takes two (the node and its \"children\" list), so a \
                 CSG tree can be about {} levels deep, and CS1230 groups the same. A csg node \
                 takes any number of children, folded left to right: write one union of many \
                 children (or one difference A − B − C − ...) instead of nesting pairs (in a CS1230 scenefile: many primitives in one group)",
                MAX_NESTING / 2 - 2
            ),
        );
    }
    Error::input(file, at, format!("invalid JSON: {what}"))
}

/// A byte-order mark, which some Windows editors write at the start of UTF-8 files, is not
/// JSON: it is skipped rather than reported as "expected value" at line 1:1.
fn without_bom(text: &str) -> &str {
    text.strip_prefix('\u{feff}').unwrap_or(text)
}

/// A serde_json error as `line L:C` (counted from 1, as editors show them) and its message
/// without serde's own " at line … column …".
fn where_and_what(e: &serde_json::Error) -> (String, String) {
    let what = e.to_string();
    let what = what.split(" at line").next().unwrap_or(&what).to_string();
    (format!("line {}:{}", e.line(), e.column().max(1)), what)
}

/// A JSON value read as serde_json's own `Value` reads it (the same numbers, strings,
/// arrays and maps), but refusing, where it stands, a key its object already has.
struct KeysOnce(Value);

impl<'de> serde::Deserialize<'de> for KeysOnce {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        d.deserialize_any(KeysOnceVisitor)
    }
}

struct KeysOnceVisitor;

impl<'de> serde::de::Visitor<'de> for KeysOnceVisitor {
    type Value = KeysOnce;
    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("any JSON value")
    }
    fn visit_bool<E>(self, b: bool) -> std::result::Result<KeysOnce, E> {
        Ok(KeysOnce(Value::Bool(b)))
    }
    fn visit_i64<E>(self, i: i64) -> std::result::Result<KeysOnce, E> {
        Ok(KeysOnce(Value::Number(i.into())))
    }
    fn visit_u64<E>(self, u: u64) -> std::result::Result<KeysOnce, E> {
        Ok(KeysOnce(Value::Number(u.into())))
    }
    fn visit_f64<E>(self, x: f64) -> std::result::Result<KeysOnce, E> {
        // As `Value` does: a number JSON cannot hold becomes null.
        Ok(KeysOnce(
            serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number),
        ))
    }
    fn visit_str<E>(self, s: &str) -> std::result::Result<KeysOnce, E> {
        Ok(KeysOnce(Value::String(s.to_owned())))
    }
    fn visit_string<E>(self, s: String) -> std::result::Result<KeysOnce, E> {
        Ok(KeysOnce(Value::String(s)))
    }
    fn visit_unit<E>(self) -> std::result::Result<KeysOnce, E> {
        Ok(KeysOnce(Value::Null))
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(
        self,
        mut seq: A,
    ) -> std::result::Result<KeysOnce, A::Error> {
        let mut items = Vec::new();
        while let Some(KeysOnce(v)) = seq.next_element()? {
            items.push(v);
        }
        Ok(KeysOnce(Value::Array(items)))
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(
        self,
        mut map: A,
    ) -> std::result::Result<KeysOnce, A::Error> {
        let mut object = serde_json::Map::new();
        while let Some(key) = map.next_key::<String>()? {
            if object.contains_key(&key) {
                return Err(serde::de::Error::custom(format!(
                    "key \"{key}\" appears twice in one object (the second would silently \
                     replace the first)"
                )));
            }
            let KeysOnce(v) = map.next_value()?;
            object.insert(key, v);
        }
        Ok(KeysOnce(Value::Object(object)))
    }
}

fn type_name(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

impl<'a> Node<'a> {
    pub fn err(&self, msg: impl Into<String>) -> Error {
        Error::input(
            self.file,
            if self.path.is_empty() {
                "(top level)".to_string()
            } else {
                self.path.to_string()
            },
            msg,
        )
    }

    fn expected(&self, what: &str) -> Error {
        self.err(format!("expected {what}, found {}", describe(self.v)))
    }

    /// A finite number no larger in magnitude than [`MAX_MAGNITUDE`] (squaring a larger one
    /// in an intersection test would overflow to infinity and then NaN).
    pub fn f64(&self) -> Result<f64> {
        let x = self.v.as_f64().ok_or_else(|| self.expected("a number"))?;
        if !x.is_finite() {
            return Err(self.err("expected a finite number"));
        }
        if x.abs() > MAX_MAGNITUDE {
            return Err(self.err(format!(
                "{x:e} is too large: numbers in a scene must lie between -{MAX_MAGNITUDE:e} and {MAX_MAGNITUDE:e}"
            )));
        }
        Ok(x)
    }
    /// A size (radius, slope, distance): greater than 0 and not below [`MIN_SIZE`].
    pub fn positive(&self) -> Result<f64> {
        let x = self.f64()?;
        if x <= 0.0 {
            return Err(self.err(format!("must be greater than 0, found {}", number(x))));
        }
        if x < MIN_SIZE {
            return Err(self.err(format!(
                "{x:e} is too small: sizes must be at least {MIN_SIZE:e}"
            )));
        }
        Ok(x)
    }
    pub fn non_negative(&self) -> Result<f64> {
        let x = self.f64()?;
        if x < 0.0 {
            return Err(self.err(format!("must not be negative, found {}", number(x))));
        }
        Ok(x)
    }
    pub fn u32(&self) -> Result<u32> {
        let x = self.f64()?;
        if x < 0.0 || x.fract() != 0.0 {
            return Err(self.err(format!("expected a whole number ≥ 0, found {}", number(x))));
        }
        if x > u32::MAX as f64 {
            return Err(self.err(format!(
                "{} is too large: at most {} here",
                number(x),
                u32::MAX
            )));
        }
        Ok(x as u32)
    }
    pub fn bool(&self) -> Result<bool> {
        self.v
            .as_bool()
            .ok_or_else(|| self.expected("true or false"))
    }
    pub fn str(&self) -> Result<&'a str> {
        self.v.as_str().ok_or_else(|| self.expected("a string"))
    }
    pub fn array(&self) -> Result<&'a Vec<Value>> {
        self.v.as_array().ok_or_else(|| self.expected("an array"))
    }
    /// Numbers of an array of exactly `n` numbers.
    pub fn numbers(&self, n: usize) -> Result<Vec<f64>> {
        let a = self
            .array()
            .map_err(|_| self.expected(&format!("an array of {n} numbers")))?;
        if a.len() != n {
            return Err(self.err(format!(
                "expected an array of {n} numbers, found {} element(s)",
                a.len()
            )));
        }
        a.iter()
            .enumerate()
            .map(|(i, v)| {
                let p = format!("{}[{i}]", self.path);
                Node {
                    v,
                    path: &p,
                    file: self.file,
                }
                .f64()
            })
            .collect()
    }
    pub fn vec3(&self) -> Result<DVec3> {
        let v = self.numbers(3)?;
        Ok(DVec3::new(v[0], v[1], v[2]))
    }
    pub fn vec2(&self) -> Result<DVec2> {
        let v = self.numbers(2)?;
        Ok(DVec2::new(v[0], v[1]))
    }
    /// A colour: three numbers, or one number meaning grey. Negative values are refused.
    pub fn color(&self) -> Result<DVec3> {
        let c = if self.v.is_number() {
            DVec3::splat(self.f64()?)
        } else {
            self.vec3()?
        };
        if c.min_element() < 0.0 {
            return Err(self.err("colour components must not be negative"));
        }
        Ok(c)
    }
    /// A direction: three numbers, not all zero.
    pub fn direction(&self) -> Result<DVec3> {
        let d = self.vec3()?;
        if d.length_squared() == 0.0 || !d.length_squared().is_finite() {
            return Err(self.err(format!(
                "a direction must not be the zero vector (nor so short that its length squares to 0), found [{}, {}, {}]",
                number(d.x),
                number(d.y),
                number(d.z)
            )));
        }
        Ok(d)
    }
    pub fn object(&self, allowed: &'static [&'static str]) -> Result<Obj<'a>> {
        let map = self
            .v
            .as_object()
            .ok_or_else(|| self.expected("an object"))?;
        Ok(Obj {
            map,
            path: self.path.to_string(),
            file: self.file,
            allowed,
        })
    }
}

/// Describes a value for "found ..." messages.
fn describe(v: &Value) -> String {
    match v {
        Value::String(s) if s.len() < 40 => format!("the string \"{s}\""),
        Value::Number(n) => format!("the number {n}"),
        other => type_name(other).to_string(),
    }
}

/// A JSON object being read, with the list of keys it may have.
pub struct Obj<'a> {
    pub map: &'a Map<String, Value>,
    pub path: String,
    pub file: &'a Path,
    pub allowed: &'static [&'static str],
}

impl<'a> Obj<'a> {
    pub fn child_path(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.path)
        }
    }

    /// Fails on the first key that is not allowed, suggesting the closest allowed one.
    pub fn check_keys(&self) -> Result<()> {
        for key in self.map.keys() {
            if !self.allowed.contains(&key.as_str()) {
                let hint = match suggest(key, self.allowed) {
                    Some(s) => format!(" (did you mean \"{s}\"?)"),
                    None => format!(" (expected one of: {})", self.allowed.join(", ")),
                };
                return Err(Error::input(
                    self.file,
                    self.child_path(key),
                    format!("unknown key \"{key}\"{hint}"),
                ));
            }
        }
        Ok(())
    }

    pub fn has(&self, key: &str) -> bool {
        self.map.contains_key(key)
    }

    /// Runs `f` on the value at `key` if present.
    pub fn opt<T>(&self, key: &str, f: impl FnOnce(Node) -> Result<T>) -> Result<Option<T>> {
        match self.map.get(key) {
            None => Ok(None),
            Some(v) => {
                let p = self.child_path(key);
                f(Node {
                    v,
                    path: &p,
                    file: self.file,
                })
                .map(Some)
            }
        }
    }
    pub fn or<T>(&self, key: &str, default: T, f: impl FnOnce(Node) -> Result<T>) -> Result<T> {
        Ok(self.opt(key, f)?.unwrap_or(default))
    }
    pub fn req<T>(&self, key: &str, f: impl FnOnce(Node) -> Result<T>) -> Result<T> {
        self.opt(key, f)?.ok_or_else(|| {
            let at = if self.path.is_empty() {
                "(top level)".to_string()
            } else {
                self.path.clone()
            };
            Error::input(self.file, at, format!("missing required key \"{key}\""))
        })
    }
    /// Each element of the array at `key` with its indexed path.
    pub fn each<T>(
        &self,
        key: &str,
        mut f: impl FnMut(Node, usize) -> Result<T>,
    ) -> Result<Vec<T>> {
        let Some(v) = self.map.get(key) else {
            return Ok(Vec::new());
        };
        let p = self.child_path(key);
        let arr = Node {
            v,
            path: &p,
            file: self.file,
        }
        .array()?;
        arr.iter()
            .enumerate()
            .map(|(i, v)| {
                let ip = format!("{p}[{i}]");
                f(
                    Node {
                        v,
                        path: &ip,
                        file: self.file,
                    },
                    i,
                )
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_key_written_twice_is_found_where_it_is_written_again() {
        let text = "{\"a\": 1,\n \"b\": {\"c\": 2, \"c\": 3}}";
        let (value, twice) = parse_noting_twice(Path::new("s.json"), text).unwrap();
        let e = twice.unwrap().to_string();
        assert!(
            e.contains("line 2:") && e.contains("key \"c\" appears twice"),
            "{e}"
        );
        // The value keeps the last, as serde_json's own reader does.
        assert_eq!(value, serde_json::from_str::<Value>(text).unwrap());
        assert_eq!(value["b"]["c"], 3);
        // The same key in two different objects is fine, and the value is the same as
        // serde_json's, numbers, strings, nulls and nesting included.
        let text = "[{\"a\": 1}, {\"a\": 2.5e-3, \"b\": [null, true, -7, 18446744073709551615, \"\\u00e9\"]}]";
        let (value, twice) = parse_noting_twice(Path::new("s.json"), text).unwrap();
        assert!(twice.is_none());
        assert_eq!(value, serde_json::from_str::<Value>(text).unwrap());
        // A syntax error is still one.
        assert!(parse_noting_twice(Path::new("s.json"), "{\"a\": 1,}").is_err());
    }

    #[test]
    fn a_byte_order_mark_is_skipped() {
        let v = parse(Path::new("s.json"), "\u{feff}{\"a\": 1}").unwrap();
        assert_eq!(v["a"], 1);
    }
}
