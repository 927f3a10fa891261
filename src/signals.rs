//! Signals, for every program of the system (plytrace and the manual's
//! rftb1-rftb4 and getrgb): SIGINT, SIGTERM and SIGHUP cancel the run in
//! progress ([`crate::cancel`]), which stops, removes its temporary files
//! and ends with status 128 + the signal. A run that has not stopped
//! within the policy's grace (a stage that does not look at the request),
//! a second signal, or a signal outside a run ends the program at once,
//! the temporary files removed first: nothing of an unfinished run is
//! left on disk.
//!
//! One difference, the [`Policy`]: at plytrace's prompt Ctrl-C (SIGINT)
//! only cancels the render and the session goes on, as a shell's Ctrl-C
//! does; a batch program ends on it. SIGXFSZ is caught, so a write past
//! the file size limit fails (and the run cleans up) rather than killing
//! the program.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::time::Duration;

use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM, SIGXFSZ};

/// How a program answers signals.
#[derive(Debug, Clone, Copy)]
pub struct Policy {
    /// How long a cancelled run may take to stop before the program ends
    /// without it.
    pub grace: Duration,
    /// Whether SIGINT ends the program (after the run stops), or only
    /// cancels the run (a session goes on).
    pub sigint_ends: bool,
    /// Said on standard error when SIGINT only cancels.
    pub sigint_message: &'static str,
    /// More to remove before the program ends (the program's own
    /// temporaries, beside [`crate::output::remove_temporaries`]).
    pub cleanup: fn(),
}

static RENDERING: AtomicBool = AtomicBool::new(false);
static ENDING: AtomicI32 = AtomicI32::new(0);

/// Listens for SIGINT, SIGTERM and SIGHUP on a thread of its own.
pub fn install(policy: Policy) -> std::io::Result<()> {
    signal_hook::flag::register(SIGXFSZ, Arc::new(AtomicBool::new(false)))?;
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    std::thread::spawn(move || {
        for signal in signals.forever() {
            on_signal(signal, policy);
        }
    });
    Ok(())
}

fn on_signal(signal: i32, policy: Policy) {
    if RENDERING.load(Ordering::SeqCst) {
        let first = if signal == SIGINT && !policy.sigint_ends {
            !crate::cancel::request()
        } else {
            let first = ENDING.compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst);
            crate::cancel::request();
            first.is_ok()
        };
        if first {
            if signal == SIGINT && !policy.sigint_ends {
                eprintln!("{}", policy.sigint_message);
            } else {
                end_after_grace(signal, policy);
            }
            return;
        }
    }
    end(signal, policy);
}

/// Ends the program after the grace if the run has not stopped by then.
fn end_after_grace(signal: i32, policy: Policy) {
    std::thread::spawn(move || {
        std::thread::sleep(policy.grace);
        if RENDERING.load(Ordering::SeqCst) {
            end(signal, policy);
        }
    });
}

/// Removes the temporaries and ends the program as `signal` asks.
fn end(signal: i32, policy: Policy) -> ! {
    crate::output::remove_temporaries();
    (policy.cleanup)();
    std::process::exit(128 + signal);
}

/// Marks the start and the end of a run (the time a signal cancels
/// rather than ends).
pub fn rendering(on: bool) {
    RENDERING.store(on, Ordering::SeqCst);
}

/// The exit status a signal that ends the program asked for, once the run
/// it stopped has cleaned up.
pub fn ending() -> Option<u8> {
    match ENDING.load(Ordering::SeqCst) {
        0 => None,
        s => u8::try_from(128 + s).ok(),
    }
}
