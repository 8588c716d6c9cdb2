//! Ctrl-C. The binary installs a handler ([`install`]) that only sets a flag; long loops
//! (the rows of a render) check [`requested`] and stop early, and [`crate::output`] refuses to
//! write once it is set, so an interrupted command leaves no file behind and never replaces a
//! previous good one. `main.rs` turns it into exit status 130 (128 + SIGINT, as shells do).
//! A library user that never calls [`install`] sees the flag stay false.

use crate::error::{Error, Result};
use std::sync::atomic::{AtomicBool, Ordering};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Installs the Ctrl-C handler (once per process; later calls do nothing).
pub fn install() {
    // Fails only if another handler is already installed, which is then the caller's choice.
    let _ = ctrlc::set_handler(|| INTERRUPTED.store(true, Ordering::SeqCst));
}

/// Has the user pressed Ctrl-C?
pub fn requested() -> bool {
    INTERRUPTED.load(Ordering::Relaxed)
}

/// Fails with "interrupted" once Ctrl-C was pressed: call before anything that would write.
pub fn check() -> Result<()> {
    if requested() {
        Err(Error::Other(
            "interrupted (Ctrl-C): stopped, nothing was written".into(),
        ))
    } else {
        Ok(())
    }
}

/// A cancellation flag a caller owns: a render, an explain or a step sequence whose settings
/// carry it ([`crate::scene::RenderSettings::cancel`]) stops soon after [`Cancel::cancel`]
/// (the tracer looks every [`crate::trace::CHECK_EVERY`] rays, the renderer at every pixel),
/// and its result is then to be thrown away (`RenderOutput::cancelled`).
/// Every token also sees Ctrl-C, so the default token is the global flag alone.
///
/// Cloning shares the flag (cancel a clone, and the original is cancelled). Tokens compare
/// equal whatever their state: cancelling decides whether a render finishes, never its pixels.
#[derive(Clone, Default)]
pub struct Cancel {
    /// The flag [`Cancel::cancel`] sets (none for the default token and for [`Cancel::or`]'s).
    own: Option<std::sync::Arc<AtomicBool>>,
    /// Other tokens' flags this one also stops for ([`Cancel::or`]).
    watched: Vec<std::sync::Arc<AtomicBool>>,
}

impl Cancel {
    /// A fresh token of its own, not cancelled.
    pub fn new() -> Cancel {
        Cancel {
            own: Some(std::sync::Arc::new(AtomicBool::new(false))),
            watched: Vec::new(),
        }
    }

    /// A token cancelled when either this one or `other` is (a render that a caller may
    /// cancel and that a time budget also stops). It only watches their flags: cancelling it
    /// does nothing; cancel the tokens it was made from.
    pub fn or(&self, other: &Cancel) -> Cancel {
        let flags = |c: &Cancel| c.own.clone().into_iter().chain(c.watched.clone());
        Cancel {
            own: None,
            watched: flags(self).chain(flags(other)).collect(),
        }
    }

    /// Asks every render using this token (or a clone of it) to stop. A token without a flag
    /// of its own (the default, or one made by [`Cancel::or`]) is not changed: only Ctrl-C
    /// and the tokens it watches stop it.
    pub fn cancel(&self) {
        if let Some(f) = &self.own {
            f.store(true, Ordering::SeqCst);
        }
    }

    /// Is `other` this very token (a clone of it: the same flag of its own)? Tokens compare
    /// equal whatever they are (see above); a holder of many (the server's render streams)
    /// finds its own this way.
    pub fn is(&self, other: &Cancel) -> bool {
        match (&self.own, &other.own) {
            (Some(a), Some(b)) => std::sync::Arc::ptr_eq(a, b),
            _ => false,
        }
    }

    /// Has this token been cancelled (or one it watches), or Ctrl-C pressed?
    pub fn is_cancelled(&self) -> bool {
        let set = |f: &std::sync::Arc<AtomicBool>| f.load(Ordering::Relaxed);
        requested() || self.own.as_ref().is_some_and(set) || self.watched.iter().any(set)
    }
}

impl PartialEq for Cancel {
    fn eq(&self, _other: &Cancel) -> bool {
        true
    }
}

impl std::fmt::Debug for Cancel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "Cancel({})",
            if self.is_cancelled() {
                "cancelled"
            } else {
                "running"
            }
        )
    }
}

#[cfg(test)]
mod tests {
    use super::Cancel;

    #[test]
    fn a_combined_token_stops_for_either_part_and_cancels_neither() {
        let (caller, deadline) = (Cancel::new(), Cancel::new());
        let both = caller.or(&deadline);
        assert!(!both.is_cancelled());
        both.cancel(); // it has no flag of its own
        assert!(!both.is_cancelled() && !caller.is_cancelled() && !deadline.is_cancelled());
        deadline.cancel();
        assert!(both.is_cancelled() && !caller.is_cancelled());
        // Tokens made from combined ones watch everything underneath.
        let (a, b) = (Cancel::new(), Cancel::new());
        let deeper = Cancel::default().or(&a.or(&b));
        b.cancel();
        assert!(deeper.is_cancelled() && !a.is_cancelled());
    }
}
