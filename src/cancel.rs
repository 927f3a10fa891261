//! Cancelling a render on the user's request (Ctrl-C at the terminal).
//!
//! The request is one process-wide flag, as the signal that sets it is
//! process-wide. The long stages look at it where stopping is cheap and
//! safe: the tree builder stops expanding branches and casting shadows,
//! [`crate::render::plan`] then returns [`Error::Cancelled`], the scan
//! converter stops between the records and rows of a band (and between
//! bands) and returns it, and a row sink may return it between rows. Nothing half-built is written: outputs
//! are staged and only committed by a run that finishes.

use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::{Error, Result};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks the render in progress to stop. Returns whether a request was
/// already pending (a second Ctrl-C before the first was honoured).
pub fn request() -> bool {
    REQUESTED.swap(true, Ordering::SeqCst)
}

/// Forgets a request (before the next render starts).
pub fn reset() {
    REQUESTED.store(false, Ordering::SeqCst);
}

/// Whether a stop was requested.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::Relaxed)
}

/// `Err(Error::Cancelled)` when a stop was requested.
pub fn check() -> Result<()> {
    if requested() {
        Err(Error::Cancelled)
    } else {
        Ok(())
    }
}
