//! Where two images differ: the differing pixels grouped into regions (connected after a
//! light dilation, then split by the object under them).

use image::RgbImage;

/// How far (pixels, in x and y) differing pixels reach to join a neighbour's region: specks
/// of shadow acne a pixel or two apart become one region, separate highlights stay apart.
pub const MERGE_REACH: i64 = 2;

/// A group of differing pixels above one object (or the background).
#[derive(Debug, Clone, PartialEq)]
pub struct PixelGroup {
    /// The object the camera ray meets under most of these pixels (`None`: the background).
    pub object: Option<usize>,
    /// Row-major order.
    pub pixels: Vec<(u32, u32)>,
    /// [x0, y0, x1, y1], inclusive.
    pub bbox: [u32; 4],
}

/// Does any channel of pixel `i` differ by more than `tolerance` levels?
pub fn differs(a: &RgbImage, b: &RgbImage, x: u32, y: u32, tolerance: u8) -> bool {
    let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
    (0..3).any(|c| p[c].abs_diff(q[c]) > tolerance)
}

/// The mask of differing pixels, row-major.
pub fn mask(a: &RgbImage, b: &RgbImage, tolerance: u8) -> Vec<bool> {
    let (w, h) = a.dimensions();
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| differs(a, b, x, y, tolerance))
        .collect()
}

/// `mask` grown by `r` pixels in x and y (a square structuring element, done as a row pass
/// and a column pass).
fn dilate(mask: &[bool], w: usize, h: usize, r: i64) -> Vec<bool> {
    let grow = |get: &dyn Fn(usize) -> bool, n: usize| -> Vec<bool> {
        // Distance-limited running "any": prefix counts over the line.
        let mut prefix = vec![0u32; n + 1];
        for i in 0..n {
            prefix[i + 1] = prefix[i] + get(i) as u32;
        }
        (0..n)
            .map(|i| {
                let lo = (i as i64 - r).max(0) as usize;
                let hi = ((i as i64 + r) as usize).min(n - 1);
                prefix[hi + 1] > prefix[lo]
            })
            .collect()
    };
    let mut rows = vec![false; w * h];
    for y in 0..h {
        let line = grow(&|x| mask[y * w + x], w);
        rows[y * w..(y + 1) * w].copy_from_slice(&line);
    }
    let mut out = vec![false; w * h];
    for x in 0..w {
        let line = grow(&|y| rows[y * w + x], h);
        for y in 0..h {
            out[y * w + x] = line[y];
        }
    }
    out
}

/// Connected components (8-neighbours) of `mask`: a label per pixel, `u32::MAX` outside.
/// Labels count up in reading order of each component's first pixel.
fn components(mask: &[bool], w: usize, h: usize) -> (Vec<u32>, u32) {
    let mut label = vec![u32::MAX; w * h];
    let mut next = 0u32;
    let mut stack = Vec::new();
    for start in 0..w * h {
        if !mask[start] || label[start] != u32::MAX {
            continue;
        }
        label[start] = next;
        stack.push(start);
        while let Some(i) = stack.pop() {
            let (x, y) = ((i % w) as i64, (i / w) as i64);
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                        continue;
                    }
                    let j = ny as usize * w + nx as usize;
                    if mask[j] && label[j] == u32::MAX {
                        label[j] = next;
                        stack.push(j);
                    }
                }
            }
        }
        next += 1;
    }
    (label, next)
}

/// One object's pixels within a component (`None`: the background).
type ObjectPixels = (Option<usize>, Vec<(u32, u32)>);

/// Groups the pixels of `mask` (a `w`×`h` row-major mask): connected after a dilation by
/// [`MERGE_REACH`], then split by `object_of` each pixel. A split-off group of fewer than
/// `min_pixels` pixels joins the largest group of its component (an edge's stray pixels are
/// not a region of their own). Largest first; ties in reading order.
pub fn group(
    mask: &[bool],
    w: u32,
    h: u32,
    object_of: impl Fn(u32, u32) -> Option<usize>,
    min_pixels: usize,
) -> Vec<PixelGroup> {
    let (wu, hu) = (w as usize, h as usize);
    let grown = dilate(mask, wu, hu, MERGE_REACH);
    let (label, n) = components(&grown, wu, hu);
    // Per component, its object groups in order of first appearance.
    let mut parts: Vec<Vec<ObjectPixels>> = vec![Vec::new(); n as usize];
    for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
        let (x, y) = ((i % wu) as u32, (i / wu) as u32);
        let o = object_of(x, y);
        let comp = &mut parts[label[i] as usize];
        match comp.iter_mut().find(|p| p.0 == o) {
            Some(p) => p.1.push((x, y)),
            None => comp.push((o, vec![(x, y)])),
        }
    }
    let mut out = Vec::new();
    for mut comp in parts {
        if comp.is_empty() {
            continue;
        }
        let big = (0..comp.len())
            .max_by_key(|&k| (comp[k].1.len(), usize::MAX - k))
            .unwrap();
        let mut strays = Vec::new();
        for (k, c) in comp.iter_mut().enumerate() {
            if k != big && c.1.len() < min_pixels {
                strays.append(&mut c.1);
            }
        }
        comp[big].1.append(&mut strays);
        for (object, mut pixels) in comp.into_iter().filter(|p| !p.1.is_empty()) {
            pixels.sort_unstable_by_key(|&(x, y)| (y, x));
            let bbox = pixels
                .iter()
                .fold([u32::MAX, u32::MAX, 0, 0], |b, &(x, y)| {
                    [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)]
                });
            out.push(PixelGroup {
                object,
                pixels,
                bbox,
            });
        }
    }
    out.sort_by_key(|g| {
        (
            std::cmp::Reverse(g.pixels.len()),
            (g.pixels[0].1, g.pixels[0].0),
        )
    });
    out
}

/// At most `cap` of `pixels`, evenly spread through the list (all of them when fewer).
pub fn spread(pixels: &[(u32, u32)], cap: usize) -> Vec<(u32, u32)> {
    if pixels.len() <= cap {
        return pixels.to_vec();
    }
    (0..cap).map(|k| pixels[k * pixels.len() / cap]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mask_of(rows: &[&str]) -> (Vec<bool>, u32, u32) {
        let w = rows[0].len() as u32;
        let m = rows
            .iter()
            .flat_map(|r| r.chars().map(|c| c != '.'))
            .collect();
        (m, w, rows.len() as u32)
    }

    #[test]
    fn specks_merge_far_blobs_do_not_and_objects_split() {
        let (m, w, h) = mask_of(&[
            "x.x.......",
            "..........",
            "x.........",
            "........xx",
            "........xx",
        ]);
        let g = group(&m, w, h, |_, _| Some(0), 1);
        assert_eq!(g.len(), 2, "{g:?}");
        assert_eq!(g[0].pixels.len(), 4);
        assert_eq!(g[0].bbox, [8, 3, 9, 4]);
        assert_eq!(g[1].pixels, vec![(0, 0), (2, 0), (0, 2)]);
        // Split by object: the right blob's left column is over another object.
        let g = group(&m, w, h, |x, _| Some((x == 8) as usize), 1);
        assert_eq!(g.len(), 3);
        // ... unless that part is too small to stand alone.
        let g = group(&m, w, h, |x, y| Some((x == 8 && y == 3) as usize), 2);
        assert_eq!(g.len(), 2);
        assert_eq!(g[0].object, Some(0));
    }

    #[test]
    fn spread_keeps_ends_and_count() {
        let p: Vec<(u32, u32)> = (0..10).map(|i| (i, 0)).collect();
        assert_eq!(spread(&p, 20).len(), 10);
        let s = spread(&p, 5);
        assert_eq!(s, vec![(0, 0), (2, 0), (4, 0), (6, 0), (8, 0)]);
    }
}
