//! What a render keeps of a tile's samples between tracing them and reconstructing the
//! image from them: every sample's film position, colour and area, or, when every pixel
//! traces exactly one sample at its centre, the colours alone.

use super::bundles::TilePlan;
use super::sampler::centre;
use super::PixelSample;
use glam::{DVec2, DVec3};

/// A tile's samples, pixel by pixel in the tile's row-major order.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum TileSamples {
    /// One sample per pixel, at its centre, of area 1 (the centre sampler without
    /// subsampling, [`super::sampler::only_centres`]): its colour is all that is not known
    /// already, 24 bytes a pixel rather than a sample record and a list end (60). A render
    /// writes every byte it keeps while its trace runs, into memory the system hands over
    /// page by page; keeping less made the default render's trace measurably faster. Kept
    /// as plain arrays so that a plan's room comes zeroed from the allocator
    /// (`vec![[0.0; 3]; n]` asks for zeroed memory, which fresh pages already are) instead
    /// of written with zeros colour by colour before the trace writes each colour again.
    Centres(Vec<[f64; 3]>),
    /// Every sample; pixel l's are `samples[ends[l - 1]..ends[l]]` (from 0 for l = 0).
    Listed {
        samples: Vec<PixelSample>,
        ends: Vec<u32>,
    },
}

/// What a tile that was skipped (its render stopped) holds: nothing. Such a render is
/// never reconstructed, so which kind it is does not matter.
impl Default for TileSamples {
    fn default() -> Self {
        TileSamples::Centres(Vec::new())
    }
}

impl TileSamples {
    /// Room for `pixels` pixels of `samples` samples in all; `centres`: one at each centre.
    pub(super) fn with_capacity(centres: bool, pixels: usize, samples: usize) -> Self {
        if centres {
            TileSamples::Centres(Vec::with_capacity(pixels))
        } else {
            TileSamples::Listed {
                samples: Vec::with_capacity(samples),
                ends: Vec::with_capacity(pixels),
            }
        }
    }

    /// The next pixel's samples, in index order: `fill` appends them to the list it is
    /// given (the tile's own, when whole records are kept; `scratch`, when only a colour is).
    pub(super) fn push_pixel_with(
        &mut self,
        scratch: &mut Vec<PixelSample>,
        fill: impl FnOnce(&mut Vec<PixelSample>),
    ) {
        match self {
            TileSamples::Centres(colors) => {
                scratch.clear();
                fill(scratch);
                debug_assert!(scratch.len() == 1, "a centre pixel traces one sample");
                colors.extend(scratch.iter().map(|s| s.color.to_array()));
            }
            TileSamples::Listed { samples, ends } => {
                fill(samples);
                ends.push(samples.len() as u32);
            }
        }
    }

    /// Room for the samples of `plan`, to be filled in by [`TileSamples::set`]: a colour for
    /// each pixel of a plan of centres, whole records for a listed one.
    pub(super) fn planned(plan: &TilePlan) -> Self {
        match plan {
            TilePlan::Centres { len } => TileSamples::Centres(vec![[0.0; 3]; *len]),
            TilePlan::Listed { films, starts } => TileSamples::Listed {
                samples: vec![PixelSample::UNTRACED; films.len()],
                ends: starts[1..].to_vec(),
            },
        }
    }

    /// Sample `i` of the tile (of all its samples, in order) is `s`.
    #[inline(always)]
    pub(super) fn set(&mut self, i: usize, s: PixelSample) {
        match self {
            TileSamples::Centres(colors) => colors[i] = s.color.to_array(),
            TileSamples::Listed { samples, .. } => samples[i] = s,
        }
    }

    /// How many samples pixel l owns.
    pub(super) fn count(&self, l: usize) -> u32 {
        match self {
            TileSamples::Centres(_) => 1,
            TileSamples::Listed { ends, .. } => ends[l] - if l == 0 { 0 } else { ends[l - 1] },
        }
    }

    /// Pixel l's samples, as (film position, colour, area), in index order; the pixel is at
    /// (x, y) on the image.
    #[inline]
    pub(super) fn of(
        &self,
        l: usize,
        (x, y): (u32, u32),
    ) -> impl Iterator<Item = (DVec2, DVec3, f64)> + '_ {
        let (one, list): (Option<(DVec2, DVec3, f64)>, &[PixelSample]) = match self {
            TileSamples::Centres(colors) => {
                (Some((centre(x, y), DVec3::from_array(colors[l]), 1.0)), &[])
            }
            TileSamples::Listed { samples, ends } => {
                let start = if l == 0 { 0 } else { ends[l - 1] as usize };
                (None, &samples[start..ends[l] as usize])
            }
        };
        one.into_iter()
            .chain(list.iter().map(|s| (s.film, s.color, s.area)))
    }
}
