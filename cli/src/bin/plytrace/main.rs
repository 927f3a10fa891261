//! The `plytrace` program: the command interpreter and immediate mode of
//! Garcia 1986 (004 appendix B, the plytrace manual page), and its tools.
//! A thin layer over the library: the command line ([`args`]), the
//! session ([`session`]) and the side of a `run` that writes files and
//! prints ([`host`]).

use std::process::ExitCode;

mod allocator;
mod args;
mod help;
mod host;
mod repl;
mod session;
mod settings;
mod stats;
mod stdout_image;
mod term;
mod tools;

use args::Request;
use plytrace::api::program::control::{Policy, install_signals};
use plytrace::api::program::files::{check_target, on_lock_wait};
use settings::Image;
use term::{err, print_document, report};

fn main() -> ExitCode {
    on_lock_wait(|dir| {
        err(&format!(
            "waiting for another process writing into {} to finish",
            dir.display()
        ));
    });
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
    let stats = match &settings.stats {
        Some(settings::StatsTarget::File(p)) => Some(p),
        _ => None,
    };
    for p in named.into_iter().chain(&settings.id_image).chain(stats) {
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
