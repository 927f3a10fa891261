//! rftbN as a program: the log line of a run, the signals that stop it
//! and the exit status (Garcia 1986, appendix B: the rftb manual page).

use super::*;

/// `t` as `YYYY-MM-DD HH:MM:SS UTC`.
pub fn utc_timestamp(t: SystemTime) -> String {
    let secs = t
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    // Howard Hinnant's civil_from_days.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02}:{:02} UTC",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

/// Appends `line` to `log` (created if missing).
pub fn append_log(log: &Path, line: &str) -> Result<()> {
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(log)
        .map_err(|e| Error::io(log, e))?;
    writeln!(f, "{line}").map_err(|e| Error::io(log, e))
}

/// The statistics line of an rftb run.
pub fn log_line(args: &Args, s: &Summary) -> String {
    let mut line = format!(
        "{}  input {}  output {}  {}x{}  act-lines {}  records {}  polygons tiled {}  \
         fragments peak {} total {}  {:.3} s",
        utc_timestamp(SystemTime::now()),
        args.input.display(),
        args.output.display(),
        args.hres,
        args.vres,
        args.act_lines,
        s.records,
        s.stats.polygons_tiled,
        s.stats.peak_fragments,
        s.stats.total_fragments,
        s.seconds
    );
    for n in &s.notes {
        line.push_str("  note: ");
        line.push_str(n);
    }
    line
}

/// The statistics log of program `name`, in the working directory.
pub fn log_path(name: &str) -> PathBuf {
    PathBuf::from(format!("{name}.log"))
}

/// Installs the signal handlers for program `name` ([`crate::signals`]:
/// every signal ends a batch program, after its run has stopped and
/// removed its temporaries, or after 600 ms), warning if it cannot.
pub(super) fn install_signals(name: &str) {
    let policy = crate::signals::Policy {
        grace: std::time::Duration::from_millis(600),
        sigint_ends: true,
        sigint_message: "",
        cleanup: || {},
    };
    if let Err(e) = crate::signals::install(policy) {
        eprintln!("{name}: warning: cannot handle signals: {e}");
    }
    crate::signals::rendering(true);
}

/// After a run: a signal received ends the program as it asks (the run
/// stopped, or finished, and either way its temporaries are gone).
pub(super) fn honour_signal() {
    if let Some(code) = crate::signals::ending() {
        crate::output::remove_temporaries();
        std::process::exit(i32::from(code));
    }
}

/// The whole of rftbN's `main`.
pub fn main(program: Program) -> ExitCode {
    let name = program.name();
    install_signals(name);
    let args = match parse_args(std::env::args_os().skip(1)) {
        Ok(Command::Run(a)) => a,
        Ok(Command::Help) => {
            println!("{}", program.usage());
            return ExitCode::SUCCESS;
        }
        Err(UsageError(msg)) => {
            eprintln!("{name}: {msg}\n{}", program.usage());
            return ExitCode::from(2);
        }
    };
    if args.screen {
        eprintln!(
            "{name}: -Y: there is no graphics display here; the image is not shown while \
             rendering (a display flag -a/-r/-g/-b/-y/-c writes OUTPUT.png instead)"
        );
    }
    let result = run(program, &args);
    honour_signal();
    match result {
        Ok(summary) => {
            for n in &summary.notes {
                eprintln!("{name}: {n}");
            }
            let line = log_line(&args, &summary);
            if args.debug > 0 {
                eprintln!("{name}: {line}");
            }
            finish_log(name, &line)
        }
        Err(e) => {
            eprintln!("{name}: {e}");
            ExitCode::from(1)
        }
    }
}

/// Appends to `NAME.log`; the outputs are written already, so a log that
/// cannot be written is a warning.
pub(super) fn finish_log(name: &str, line: &str) -> ExitCode {
    if let Err(e) = append_log(&log_path(name), line) {
        eprintln!("{name}: warning: {e}");
    }
    ExitCode::SUCCESS
}
