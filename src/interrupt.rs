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
