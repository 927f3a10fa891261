//! Stopping a run: SIGINT, SIGTERM and SIGHUP cancel the render in
//! progress (which stops, removes its temporary files and ends with
//! status 128 + the signal), and the long stages look at one
//! process-wide cancel request where stopping is cheap and safe.

/// How a program answers signals: the grace a cancelled run has to stop,
/// and whether SIGINT ends the program or only cancels the run (the
/// prompt goes on, as a shell's does).
///
/// ```
/// use std::time::Duration;
/// use plytrace::api::program::control::Policy;
///
/// let policy = Policy {
///     grace: Duration::from_secs(2),
///     sigint_ends: false,
///     sigint_message: "^C: cancelling the render",
///     cleanup: || {},
/// };
/// assert!(!policy.sigint_ends && policy.grace.as_secs() == 2);
/// ```
#[doc(inline)]
pub use crate::signals::Policy;

/// Listens for SIGINT, SIGTERM and SIGHUP on a thread of its own, as
/// `policy` says.
///
/// ```
/// use std::time::Duration;
/// use plytrace::api::program::control::{ending, install_signals, Policy};
///
/// let policy = Policy { grace: Duration::from_secs(1), sigint_ends: true, sigint_message: "", cleanup: || {} };
/// assert!(install_signals(policy).is_ok());
/// assert_eq!(ending(), None, "no signal came");
/// ```
#[doc(inline)]
pub use crate::signals::install as install_signals;

/// Marks the start (`true`) and the end of a run: a signal in between
/// cancels the run rather than ending the program at once.
///
/// ```
/// use plytrace::api::program::control::{ending, rendering};
///
/// rendering(true);
/// rendering(false);
/// assert_eq!(ending(), None);
/// ```
#[doc(inline)]
pub use crate::signals::rendering;

/// The exit status (128 + the signal) that a signal ending the program
/// asked for, once the run it stopped has cleaned up; `None` without one.
///
/// ```
/// use plytrace::api::program::control::ending;
///
/// assert_eq!(ending(), None);
/// ```
#[doc(inline)]
pub use crate::signals::ending;

/// `Err(Error::Cancelled)` when a stop of the render was requested (a
/// row sink calls it between rows).
///
/// ```
/// use plytrace::api::program::control::{check_cancel, request_cancel, reset_cancel};
///
/// reset_cancel();
/// assert!(check_cancel().is_ok());
/// assert!(!request_cancel(), "the first request");
/// assert!(matches!(check_cancel(), Err(plytrace::Error::Cancelled)));
/// reset_cancel();
/// assert!(check_cancel().is_ok());
/// ```
#[doc(inline)]
pub use crate::cancel::check as check_cancel;

/// Asks the render in progress to stop (what Ctrl-C does); returns
/// whether a request was already pending.
///
/// ```
/// use plytrace::api::program::control::{request_cancel, reset_cancel};
///
/// reset_cancel();
/// assert!(!request_cancel());
/// assert!(request_cancel(), "a second request before the first was honoured");
/// reset_cancel();
/// ```
#[doc(inline)]
pub use crate::cancel::request as request_cancel;

/// Forgets a stop request, before the next render starts.
///
/// ```
/// use plytrace::api::program::control::{check_cancel, request_cancel, reset_cancel};
///
/// request_cancel();
/// reset_cancel();
/// assert!(check_cancel().is_ok());
/// ```
#[doc(inline)]
pub use crate::cancel::reset as reset_cancel;
