//! Which SIMD width the bundle walks run at, chosen once at run time, and the sixteen-lane
//! operations they are written in.
//!
//! rtlab is compiled for plain x86-64 (SSE2: four `f32` lanes per instruction). The bundle
//! kernels ([`Kernel`]) are written once, against [`Wide`]: sixteen lanes, one per ray of a
//! bundle, with the handful of operations a slab test and a face test need. [`run`] calls
//! the kernel compiled for the widest level the processor has, with that level's `Wide`:
//! AVX-512 holds sixteen `f32` lanes in one register, AVX2 in two, and the portable level
//! ([`Portable`], plain arrays) leaves the vectors to the compiler. Every lane is computed
//! with the same IEEE operation whatever the level (minimum and maximum as `minps`/`maxps`
//! define them, comparisons ordered), so all levels give the same bits.
//!
//! The compiler's own vectorizer was tried first (plain loops over sixteen lanes, compiled
//! with AVX2 or AVX-512 enabled): it split the sixteen lanes into pieces of eight, four, two
//! and one, and the walk ran no faster than at SSE2. Hence explicit types per level. (Straight
//! line arithmetic over lanes with no masks does vectorize well: a block's camera rays,
//! plain arrays of `f64` (`crate::trace::camera_rays`), are made through [`run`] with no
//! `Wide` at all, and take two thirds of the instructions they take at SSE2.)
//!
//! The submodule `x86` holds the crate's `unsafe` code (but for one `madvise` call in
//! [`crate::accel::pages`]): the intrinsics of AVX2 and
//! AVX-512, and the calls into functions compiled for them, made only after
//! `is_x86_feature_detected!` has said the instructions are there (the tokens that prove it
//! cannot be made otherwise).

mod portable;
#[cfg(target_arch = "x86_64")]
mod x86;

pub use portable::Portable;

use super::lanes::{F32s, F64s};

/// Work compiled at every SIMD level: `run` must be `#[inline(always)]`, so that its body,
/// and everything it inlines, is compiled inside each of [`run`]'s entry points.
pub trait Kernel {
    type Output;
    fn run<W: Wide>(self, w: W) -> Self::Output;
}

/// Asks the processor to start bringing `x` into the cache (a hint: nothing else changes).
/// The walks give it the children they will open later. Every x86-64 has the instruction
/// (SSE); elsewhere it does nothing.
#[inline(always)]
pub fn prefetch<T>(x: &[T]) {
    #[cfg(target_arch = "x86_64")]
    x86::prefetch(x);
    #[cfg(not(target_arch = "x86_64"))]
    let _ = x;
}

/// Runs `k` compiled for the widest SIMD this processor has.
#[inline]
pub fn run<K: Kernel>(k: K) -> K::Output {
    #[cfg(target_arch = "x86_64")]
    {
        match level() {
            Level::Avx512 => return x86::avx512(k),
            Level::Avx2 => return x86::avx2(k),
            Level::Base => {}
        }
    }
    k.run(Portable)
}

// ANCHOR: wide
/// Sixteen lanes, one per ray of a bundle, and what the walks do with them. `F` holds
/// sixteen `f32`, `D` sixteen `f64`; comparisons return a bit mask (bit i: lane i). Every
/// operation is the IEEE one, lane by lane: `min(a, b)` is `a < b ? a : b` and `max(a, b)`
/// is `a > b ? a : b` (so a NaN in `a` gives `b`, as `minps` and `maxps` do), and the
/// comparisons are false for NaN.
pub trait Wide: Copy {
    type F: Copy;
    type D: Copy;
    /// The level, to choose between one pass over all lanes and a loop over a few.
    const LEVEL: Level;

    fn load(self, a: &F32s) -> Self::F;
    fn store(self, v: Self::F) -> F32s;
    fn splat(self, x: f32) -> Self::F;
    fn sub(self, a: Self::F, b: Self::F) -> Self::F;
    fn mul(self, a: Self::F, b: Self::F) -> Self::F;
    fn min(self, a: Self::F, b: Self::F) -> Self::F;
    fn max(self, a: Self::F, b: Self::F) -> Self::F;
    /// Bit i: a_i ≤ b_i.
    fn le(self, a: Self::F, b: Self::F) -> u32;
    /// The smallest of the lanes set in `mask` (+∞ if none; lanes in `mask` are not NaN;
    /// between +0 and −0 either may be returned, as they compare equal).
    fn min_of(self, a: Self::F, mask: u32) -> f32;

    fn load_d(self, a: &F64s) -> Self::D;
    fn store_d(self, v: Self::D) -> F64s;
    fn splat_d(self, x: f64) -> Self::D;
    fn neg_d(self, a: Self::D) -> Self::D;
    fn add_d(self, a: Self::D, b: Self::D) -> Self::D;
    fn mul_d(self, a: Self::D, b: Self::D) -> Self::D;
    /// Bit i: a_i < b_i.
    fn lt_d(self, a: Self::D, b: Self::D) -> u32;
    /// Bit i: a_i ≤ b_i.
    fn le_d(self, a: Self::D, b: Self::D) -> u32;
}
// ANCHOR_END: wide

/// The SIMD widths [`run`] chooses between.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Level {
    /// The target's baseline (SSE2 on x86-64), through [`Portable`].
    Base,
    Avx2,
    Avx512,
}

/// The cap `RTLAB_SIMD` puts on the SIMD level: `Ok(None)` when unset, `Err` with the value
/// when it names no level (ignored by [`level`]; the CLI warns of it).
pub fn simd_cap() -> Result<Option<Level>, String> {
    match std::env::var("RTLAB_SIMD") {
        Err(std::env::VarError::NotPresent) => Ok(None),
        // `portable` is what `--stats` calls the base level.
        Ok(v) => match v.to_ascii_lowercase().as_str() {
            "base" | "portable" => Ok(Some(Level::Base)),
            "avx2" => Ok(Some(Level::Avx2)),
            "avx512" => Ok(Some(Level::Avx512)),
            _ => Err(v),
        },
        Err(std::env::VarError::NotUnicode(v)) => Err(v.to_string_lossy().into_owned()),
    }
}

/// The widest [`Level`] this processor supports, detected once. `RTLAB_SIMD=base|portable|avx2|avx512`
/// caps it (for comparing the levels; any other value is ignored: [`simd_cap`]).
pub fn level() -> Level {
    static LEVEL: std::sync::OnceLock<Level> = std::sync::OnceLock::new();
    *LEVEL.get_or_init(|| {
        let cap = simd_cap().ok().flatten().unwrap_or(Level::Avx512);
        let found = detected();
        if found.rank() <= cap.rank() {
            found
        } else {
            cap
        }
    })
}

impl Level {
    fn rank(self) -> u8 {
        match self {
            Level::Base => 0,
            Level::Avx2 => 1,
            Level::Avx512 => 2,
        }
    }

    /// From how many rays out of sixteen one pass over all the `f64` lanes (two, four or
    /// eight instructions per step) costs less than a loop over the rays one by one.
    #[inline(always)]
    pub fn lanes_from(self) -> u32 {
        match self {
            Level::Avx512 => 2,
            Level::Avx2 => 4,
            Level::Base => 7,
        }
    }

    /// Its name, as `--stats` prints it.
    pub fn name(self) -> &'static str {
        match self {
            Level::Base => "portable",
            Level::Avx2 => "avx2",
            Level::Avx512 => "avx512",
        }
    }
}

/// The levels this processor can run (for tests that compare them), narrowest first.
#[cfg(test)]
pub(crate) fn levels() -> Vec<Level> {
    [Level::Base, Level::Avx2, Level::Avx512]
        .into_iter()
        .filter(|l| l.rank() <= detected().rank())
        .collect()
}

/// Runs `k` compiled for `level`, which must be one of [`levels`] (for tests).
#[cfg(test)]
pub(crate) fn run_at<K: Kernel>(level: Level, k: K) -> K::Output {
    assert!(level.rank() <= detected().rank(), "{level:?} not available");
    match level {
        #[cfg(target_arch = "x86_64")]
        Level::Avx512 => x86::avx512(k),
        #[cfg(target_arch = "x86_64")]
        Level::Avx2 => x86::avx2(k),
        _ => k.run(Portable),
    }
}

#[cfg(target_arch = "x86_64")]
fn detected() -> Level {
    x86::detected()
}

#[cfg(not(target_arch = "x86_64"))]
fn detected() -> Level {
    Level::Base
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rng;

    /// Every operation of [`Wide`] on one set of lanes.
    struct Ops {
        a: F32s,
        b: F32s,
        c: F64s,
        d: F64s,
        mask: u32,
    }

    #[derive(Debug, PartialEq)]
    struct Results {
        f: Vec<[u32; 16]>,
        d: Vec<[u64; 16]>,
        masks: Vec<u32>,
        /// By value: with +0 and −0 both in the mask either may come out (they are equal).
        min_of: f32,
    }

    impl Kernel for Ops {
        type Output = Results;
        #[inline(always)]
        fn run<W: Wide>(self, w: W) -> Results {
            let bits = |v: W::F| w.store(v).0.map(f32::to_bits);
            let bits_d = |v: W::D| w.store_d(v).0.map(f64::to_bits);
            let (a, b) = (w.load(&self.a), w.load(&self.b));
            let (c, d) = (w.load_d(&self.c), w.load_d(&self.d));
            Results {
                f: vec![
                    bits(w.sub(a, b)),
                    bits(w.mul(a, b)),
                    bits(w.min(a, b)),
                    bits(w.max(a, b)),
                    bits(w.splat(self.a.0[3])),
                ],
                d: vec![
                    bits_d(w.add_d(c, d)),
                    bits_d(w.mul_d(c, d)),
                    bits_d(w.neg_d(c)),
                    bits_d(w.splat_d(self.d.0[5])),
                ],
                masks: vec![
                    w.le(a, b),
                    w.le(b, a),
                    w.lt_d(c, d),
                    w.le_d(c, d),
                    w.lt_d(d, c),
                    w.le_d(d, c),
                ],
                min_of: w.min_of(a, self.mask),
            }
        }
    }

    fn lanes(rng: &mut Rng) -> (F32s, F32s, F64s, F64s) {
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            1e-40,
        ];
        let mut pick = |i: usize| {
            if rng.next_f64() < 0.3 {
                special[(rng.next_f64() * 8.0) as usize]
            } else {
                (rng.next_f64() - 0.5) * 10f64.powi((i % 9) as i32 - 4)
            }
        };
        let a = F32s(std::array::from_fn(|i| pick(i) as f32));
        let b = F32s(std::array::from_fn(|i| pick(i + 3) as f32));
        let c = F64s(std::array::from_fn(|i| pick(i + 5)));
        let d = F64s(std::array::from_fn(|i| pick(i + 1)));
        (a, b, c, d)
    }

    /// The x86 levels give the portable level's results, bit for bit, on ordinary numbers,
    /// zeros of both signs, infinities and NaN (the levels this processor has).
    #[test]
    fn every_level_gives_the_same_bits() {
        let mut rng = Rng::new(&[7, 7]);
        let mut checked = 0;
        for round in 0..3000 {
            let (a, b, c, d) = lanes(&mut rng);
            // min_of's lanes are never NaN (they are entries the slab test accepted).
            let not_nan = (0..16).fold(0, |m, i| m | ((!a.0[i].is_nan()) as u32) << i);
            let mask = (rng.next_f64() * 65536.0) as u32 & not_nan;
            let ops = || Ops { a, b, c, d, mask };
            let portable = ops().run(Portable);
            #[cfg(target_arch = "x86_64")]
            {
                if x86::detected() != Level::Base {
                    assert_eq!(x86::avx2(ops()), portable, "round {round}: avx2");
                    checked += 1;
                }
                if x86::detected() == Level::Avx512 {
                    assert_eq!(x86::avx512(ops()), portable, "round {round}: avx512");
                    checked += 1;
                }
            }
        }
        println!("{checked} comparisons with the portable level");
    }
}
