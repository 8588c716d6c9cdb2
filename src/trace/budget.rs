//! The ray budget of one sample. A surface that is both mirror and glass splits every ray in
//! two, so a tree of depth D can hold 2^(D+1) − 1 rays; with weights of 1 the
//! `min_contribution` cutoff never stops it. The budget does: it counts the rays a sample has
//! traced and refuses new reflection and refraction rays once the count reaches
//! `max_rays`. The count is per sample, so where a tree is cut depends on the sample alone,
//! not on the thread count or the order pixels are traced in.
//!
//! The same counter is where the tracer looks at the cancellation flag, every
//! [`CHECK_EVERY`] rays, so that even one huge tree stops soon after Ctrl-C.

use crate::interrupt::Cancel;
use std::cell::Cell;

/// The default ray budget of one sample. The shipped and course scenes stay far below it
/// (the most any of their samples traces is a few thousand rays, with area lights), and a
/// cut sample costs a few milliseconds.
pub const DEFAULT_MAX_RAYS: u64 = 10_000;

/// How many rays the tracer traces between two looks at the cancellation flag.
pub const CHECK_EVERY: u64 = 1024;

/// Rays one sample has traced, against its budget.
pub(crate) struct Budget<'a> {
    rays: Cell<u64>,
    /// The count at which [`Budget::allows`] next takes its slow path: the budget, or the
    /// next look at the cancellation flag, whichever comes first; 0 once refused for good.
    next_check: Cell<u64>,
    max: u64,
    cut: Cell<bool>,
    cancel: &'a Cancel,
}

impl<'a> Budget<'a> {
    pub(crate) fn new(max: u64, cancel: &'a Cancel) -> Budget<'a> {
        Budget {
            rays: Cell::new(0),
            next_check: Cell::new(max.min(CHECK_EVERY)),
            max,
            cut: Cell::new(false),
            cancel,
        }
    }

    /// One more ray traced (any kind).
    #[inline(always)]
    pub(crate) fn count(&self) {
        self.rays.set(self.rays.get() + 1);
    }

    /// May the tracer spawn one more reflection or refraction ray? On the hot path this is
    /// one integer compare; past the budget (or once cancelled) it stays false.
    #[inline(always)]
    pub(crate) fn allows(&self) -> bool {
        self.rays.get() < self.next_check.get() || self.check()
    }

    #[cold]
    #[inline(never)]
    fn check(&self) -> bool {
        let n = self.rays.get();
        if n >= self.max || self.cancel.is_cancelled() {
            self.next_check.set(0);
            self.cut.set(true);
            return false;
        }
        self.next_check.set(self.max.min(n + CHECK_EVERY));
        true
    }

    /// Rays traced so far.
    pub(crate) fn rays(&self) -> u64 {
        self.rays.get()
    }

    /// Was any ray refused?
    pub(crate) fn cut(&self) -> bool {
        self.cut.get()
    }
}
