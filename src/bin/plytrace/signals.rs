//! Signals: Ctrl-C (SIGINT) cancels the render in progress and the
//! session goes on; SIGTERM and SIGHUP end the program as a shell expects
//! (status 143 and 129) after the render in progress has stopped and
//! removed its files. Outside a render, or asked a second time, the
//! program ends at once, removing the temporary files of its outputs
//! first: nothing of an unfinished run is left on disk either way.

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};

use crate::term::err;

/// Set while a run renders.
static RENDERING: AtomicBool = AtomicBool::new(false);

/// The signal that asked the program to end once its render has stopped.
static ENDING: AtomicI32 = AtomicI32::new(0);

/// Listens for SIGINT, SIGTERM and SIGHUP on a thread of its own.
pub fn install() -> std::io::Result<()> {
    let mut signals = signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP])?;
    std::thread::spawn(move || {
        for signal in signals.forever() {
            on_signal(signal);
        }
    });
    Ok(())
}

fn on_signal(signal: i32) {
    if RENDERING.load(Ordering::SeqCst) {
        let first = if signal == SIGINT {
            !plytrace::cancel::request()
        } else {
            let first = ENDING.compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst);
            plytrace::cancel::request();
            first.is_ok()
        };
        if first {
            if signal == SIGINT {
                err("^C: cancelling the render (press Ctrl-C again to quit)");
            } else {
                end_after_grace(signal);
            }
            return;
        }
    }
    plytrace::output::remove_temporaries();
    crate::stdout_image::cleanup();
    std::process::exit(128 + signal);
}

/// How long a render asked to end by SIGTERM or SIGHUP may take to stop
/// and clean up before the program ends without it.
const GRACE: std::time::Duration = std::time::Duration::from_secs(2);

/// Ends the program after [`GRACE`] if the render has not stopped by then
/// (a stage that does not look at the request): its temporary files are
/// removed all the same.
fn end_after_grace(signal: i32) {
    std::thread::spawn(move || {
        std::thread::sleep(GRACE);
        if RENDERING.load(Ordering::SeqCst) {
            plytrace::output::remove_temporaries();
            crate::stdout_image::cleanup();
            std::process::exit(128 + signal);
        }
    });
}

/// Marks the start and the end of a render.
pub fn rendering(on: bool) {
    RENDERING.store(on, Ordering::SeqCst);
}

/// The exit status a SIGTERM or SIGHUP asked for, once the render it
/// stopped has cleaned up.
pub fn ending() -> Option<u8> {
    match ENDING.load(Ordering::SeqCst) {
        0 => None,
        s => u8::try_from(128 + s).ok(),
    }
}
