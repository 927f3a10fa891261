//! The `plytrace` program: the command interpreter and immediate mode of
//! Garcia 1986 (004 appendix B, the plytrace manual page), and its tools.
//! A thin layer over the library: the command line ([`args`]), the
//! session ([`session`]) and the side of a `run` that writes files and
//! prints ([`host`]).

use std::process::ExitCode;

mod args;
mod help;
mod host;
mod repl;
mod session;
mod stats;
mod stdout_image;
mod term;
mod tools;

use args::{Image, Request};
use plytrace::api::program::control::{Policy, install_signals};
use plytrace::api::program::files::check_target;
use term::{err, print_document, report};

/// jemalloc: the tree and the records are hundreds of thousands of small
/// blocks made and freed by several threads, where glibc's allocator spent
/// 15-25 % of the cycles (consolidating its fast bins on every large free).
#[global_allocator]
static ALLOCATOR: tikv_jemallocator::Jemalloc = tikv_jemallocator::Jemalloc;

/// jemalloc's options (its `malloc_conf`; `_RJEM_MALLOC_CONF` in the
/// environment still overrides them), chosen for peak memory (issue 10's
/// 64 MiB for office2), measured on office2 at 512x512:
/// - `dirty_decay_ms:10,muzzy_decay_ms:0`: pages freed for 10 ms go back
///   to the system. With the default 10 s, what the tree builder frees
///   stays resident to the end: 72 MB peak, against 58 MB.
/// - `thp:never`: huge pages cut the page faults (and a tenth of the
///   time) but hold 2 MB wherever any of it is used: 74-86 MB.
///
/// Not `percpu_arena:percpu` (one arena per CPU, 57 MB instead of 60): when
/// the process may run on fewer CPUs than the machine has (`taskset`, a
/// Slurm or Kubernetes cpuset), jemalloc then prints a warning on every
/// run.
#[unsafe(export_name = "_rjem_malloc_conf")]
static MALLOC_CONF: MallocConf =
    MallocConf(c"thp:never,dirty_decay_ms:10,muzzy_decay_ms:0".as_ptr());

/// A C string pointer jemalloc reads once at start-up.
#[repr(transparent)]
struct MallocConf(*const std::ffi::c_char);

// SAFETY: the pointer is to a string literal, never written.
unsafe impl Sync for MallocConf {}

fn main() -> ExitCode {
    let settings = match args::parse(std::env::args_os().skip(1).collect()) {
        Ok(Request::Run(s)) => s,
        Ok(Request::Tool(tool)) => return tools::run(tool),
        Ok(Request::Help) => {
            let help = args::command().render_long_help().to_string();
            return print_document(help.as_bytes());
        }
        Ok(Request::Version) => {
            return print_document(format!("plytrace {}\n", env!("CARGO_PKG_VERSION")).as_bytes());
        }
        Err(e) => {
            let _ = e.print();
            return ExitCode::from(2);
        }
    };
    // The command line's outputs are checked at once, before the scene is
    // read (and again when each run creates them).
    let named = match &settings.image {
        Image::File(p) => Some(p),
        _ => None,
    };
    for p in named.into_iter().chain(&settings.id_image) {
        if let Err(e) = check_target(p) {
            report(&e);
            return ExitCode::FAILURE;
        }
    }
    let policy = Policy {
        grace: std::time::Duration::from_secs(2),
        sigint_ends: false,
        sigint_message: "^C: cancelling the render (press Ctrl-C again to quit)",
        cleanup: stdout_image::cleanup,
    };
    if let Err(e) = install_signals(policy) {
        err(&format!("warning: signals cannot cancel a render: {e}"));
    }
    let output = match &settings.image {
        Image::Default => None,
        Image::File(p) => Some(p.clone()),
        Image::Stdout(format) => match stdout_image::prepare(format.extension()) {
            Ok(p) => Some(p),
            Err(e) => {
                report(&e);
                return ExitCode::FAILURE;
            }
        },
    };
    let mut host = host::CliHost::new(&settings, output);
    let code = session::run(&settings, &mut host);
    stdout_image::cleanup();
    code
}
