//! Wavefront OBJ meshes: `v`, `vt`, `vn` and polygonal `f` lines (fanned into triangles).
//! Written here rather than taken from a crate so every error can name its line.

use crate::error::{Error, Result};
use crate::shapes::Mesh;
use glam::{DVec2, DVec3};
use std::collections::HashMap;
use std::path::Path;

/// Loads an OBJ file into a mesh with one index per corner (positions, normals and texture
/// coordinates re-indexed together).
pub fn load(path: &Path) -> Result<Mesh> {
    if path.is_dir() {
        return Err(Error::io(path, "is a directory, expected an OBJ mesh file"));
    }
    let bytes = crate::input::read_limited(path, crate::input::MESH_LIMIT)
        .map_err(|e| Error::io(path, format!("cannot read mesh: {}", super::io_reason(&e))))?;
    let text = String::from_utf8(bytes)
        .map_err(|_| Error::input(path, "", "not a text OBJ file (binary or invalid UTF-8)"))?;
    parse(path, &text)
}

pub fn parse(path: &Path, text: &str) -> Result<Mesh> {
    let (mut v, mut vt, mut vn) = (Vec::new(), Vec::new(), Vec::new());
    let mut poly: Vec<u32> = Vec::new();
    // Corner (position, uv, normal) -> mesh vertex. Most files use each position with one
    // uv and normal, so the first corner seen for a position is kept in a plain array and
    // only the others go through the hash map (the map was most of the load time).
    let mut first: Vec<Option<((u32, u32), u32)>> = Vec::new();
    let mut corners: HashMap<(u32, u32, u32), u32> = HashMap::new();
    let (mut positions, mut normals, mut uvs, mut faces) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut any_vt = false;
    let mut any_vn = false;
    for (ln, line) in text.lines().enumerate() {
        let at = |col: usize| format!("line {}:{}", ln + 1, col + 1);
        let line = line.split('#').next().unwrap_or("");
        let mut words = line.split_whitespace();
        let Some(tag) = words.next() else { continue };
        // The byte column of a word of this line (words are slices of it).
        let column = |w: &str| w.as_ptr() as usize - line.as_ptr() as usize;
        let nums = |n: usize, mut words: std::str::SplitWhitespace| -> Result<[f64; 3]> {
            let mut out = [0.0; 3];
            for (k, x) in out.iter_mut().enumerate().take(n) {
                let Some(w) = words.next() else {
                    return Err(Error::input(
                        path,
                        at(0),
                        format!("'{tag}' needs {n} numbers, found {k}"),
                    ));
                };
                *x = w
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        Error::input(
                            path,
                            at(column(w)),
                            format!("expected a finite number, found \"{w}\""),
                        )
                    })?;
            }
            Ok(out)
        };
        match tag {
            "v" => {
                let p = nums(3, words)?;
                // Positions are single precision (see `Mesh`): rounded here already, so that
                // the degenerate-face check below sees the values the mesh will hold.
                if let Some(w) = p.iter().find(|x| !(**x as f32).is_finite()) {
                    return Err(Error::input(
                        path,
                        at(0),
                        format!("vertex coordinate {w:e} is beyond single precision (±3.4e38)"),
                    ));
                }
                v.push(crate::shapes::single_precision(DVec3::new(
                    p[0], p[1], p[2],
                )));
                first.push(None);
            }
            "vt" => {
                let p = nums(2, words)?;
                vt.push(DVec2::new(p[0], p[1]));
            }
            "vn" => {
                let p = nums(3, words)?;
                vn.push(DVec3::new(p[0], p[1], p[2]));
            }
            "f" => {
                poly.clear();
                for w in words {
                    let col = column(w);
                    let mut parts = w.split('/');
                    let resolve = |s: Option<&str>,
                                   len: usize,
                                   what: &str|
                     -> Result<Option<u32>> {
                        match s {
                            None | Some("") => Ok(None),
                            Some(s) => {
                                let i: i64 = s.parse().map_err(|_| {
                                    Error::input(path, at(col), format!("bad {what} index \"{s}\""))
                                })?;
                                let idx = if i < 0 { len as i64 + i } else { i - 1 };
                                if i == 0 || idx < 0 || idx >= len as i64 {
                                    return Err(Error::input(
                                        path,
                                        at(col),
                                        format!("{what} index {i} is out of range (the file has {len} so far)"),
                                    ));
                                }
                                Ok(Some(idx as u32))
                            }
                        }
                    };
                    let pi = resolve(parts.next(), v.len(), "vertex")?.ok_or_else(|| {
                        Error::input(path, at(col), "a face corner needs a vertex index")
                    })?;
                    let ti = resolve(parts.next(), vt.len(), "texture coordinate")?;
                    let ni = resolve(parts.next(), vn.len(), "normal")?;
                    any_vt |= ti.is_some();
                    any_vn |= ni.is_some();
                    let rest = (ti.map_or(u32::MAX, |x| x), ni.map_or(u32::MAX, |x| x));
                    let mut new_vertex = || {
                        positions.push(v[pi as usize]);
                        uvs.push(ti.map_or(DVec2::ZERO, |i| vt[i as usize]));
                        normals.push(ni.map_or(DVec3::ZERO, |i| vn[i as usize]));
                        positions.len() as u32 - 1
                    };
                    let id = match first[pi as usize] {
                        Some((seen, id)) if seen == rest => id,
                        None => {
                            let id = new_vertex();
                            first[pi as usize] = Some((rest, id));
                            id
                        }
                        Some(_) => *corners
                            .entry((pi, rest.0, rest.1))
                            .or_insert_with(new_vertex),
                    };
                    poly.push(id);
                }
                if poly.len() < 3 {
                    return Err(Error::input(
                        path,
                        at(0),
                        format!("a face needs at least 3 corners, found {}", poly.len()),
                    ));
                }
                for k in 1..poly.len() - 1 {
                    faces.push([poly[0], poly[k], poly[k + 1]]);
                }
            }
            _ => {} // groups, materials, smoothing: not needed for geometry
        }
    }
    // Drop degenerate faces (zero area): they can never be hit and only cost time.
    faces.retain(|f: &[u32; 3]| {
        let [a, b, c] = f.map(|i| positions[i as usize]);
        (b - a).cross(c - a).length_squared() > 0.0
    });
    if faces.is_empty() {
        return Err(Error::input(
            path,
            "",
            "the mesh has no triangles (no usable 'f' lines)",
        ));
    }
    if !any_vn || normals.iter().any(|n| n.length_squared() == 0.0) {
        normals.clear();
    }
    if !any_vt {
        uvs.clear();
    }
    Ok(Mesh::new(positions, normals, uvs, faces))
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn quads_fan_and_errors_name_lines() {
        let m = parse(
            Path::new("q.obj"),
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n",
        )
        .unwrap();
        assert_eq!(m.faces.len(), 2);
        let e = parse(Path::new("q.obj"), "v 0 0 0\nf 1 2 3\n").unwrap_err();
        assert!(e.to_string().contains("line 2"), "{e}");
        let e = parse(Path::new("q.obj"), "v 0 0 zero\n").unwrap_err();
        assert!(e.to_string().contains("line 1:7"), "{e}");
        assert!(parse(Path::new("q.obj"), "").is_err());
    }

    /// A position used with one normal is one mesh vertex, shared by every face that uses it
    /// that way; used with a second normal (a crease) it becomes a second vertex, and coming
    /// back to the first normal finds the first vertex again.
    #[test]
    fn corners_are_shared_exactly_when_position_uv_and_normal_agree() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 1 0 0\n\
                    f 1//1 2//1 3//1\nf 2//1 4//1 3//1\nf 2//2 4//2 3//1\nf 1//1 2//2 3//1\n";
        let m = parse(Path::new("n.obj"), text).unwrap();
        // Vertices: 1/1, 2/1, 3/1, 4/1, then 2/2 and 4/2; 1/1 and 3/1 are found again.
        assert_eq!(m.positions.len(), 6);
        assert_eq!(m.faces, vec![[0, 1, 2], [1, 3, 2], [4, 5, 2], [0, 4, 2]]);
        assert_eq!(m.normals[4], DVec3::X);
        assert_eq!(m.normals[1], DVec3::Z);
        // The column of a bad index is where that word starts, even when an identical word
        // comes earlier on the line.
        let e = parse(Path::new("n.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 1 9\n").unwrap_err();
        assert!(e.to_string().contains("line 4:7"), "{e}");
    }
}
