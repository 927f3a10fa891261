//! The anti-aliasing polygon tilers rftb1-4 and getrgb as programs (Garcia
//! 1986, 004 appendix: the rftb and getrgb manual pages; chapter 5 for the
//! methods). Each binary in `src/bin` is a few lines over this module.
//!
//! ```text
//! rftbN <input> [output] [hres] [vres] [act-lines] [-flags]
//! getrgb NAME [hres vres] [-p | --png FILE]
//! ```
//!
//! Both take plytrace's budgets `--max-pixels N` and `--max-frame-memory
//! MiB`, with its defaults ([`Budgets::default`]): the resolution, the
//! bands of `act-lines` rows and the input files are checked against them
//! before anything is allocated or written, and an output that would pass
//! the file size limit (`ulimit -f`) is refused before it is started.
//! Inputs are read only from regular files, and no output may be an
//! input, another output or the program's log. SIGINT, SIGTERM and SIGHUP
//! stop a run within a second, remove its temporary files and end the
//! program with status 130, 143 or 129.
//!
//! rftbN reads `<input>.out` (a virtual image tree file, [`crate::tree`];
//! an input given as `X.out` is taken as `X`),
//! refuses a tree made for another method (back to front, or, with a
//! record below level 1, the other blending mode; both read from its
//! background record, see [`check_tree`]), blends transparency by
//! [`Program::transparency`] (section 5.6 for rftb1 and rftb3), and
//! writes, under the output seed (default: the input name):
//!
//! - rftb1 (method 1, area coverage): `OUTPUT.r .g .b .a`;
//! - rftb2 (method 2, pixel masks): `OUTPUT.r .g .b .m` (the manual's
//!   FILES section; its example says `.a`, but a mask tiler has masks);
//! - rftb3 (method 3, both): `OUTPUT.r .g .b .a .m`;
//! - rftb4 (method 4, pixel-structs): the pixel-struct file `OUTPUT`,
//!   exactly `hres x vres` 8-byte structs as getrgb's manual page says,
//!   and beside it `OUTPUT.frag`, the resolution and the fragment lists
//!   that the structs' `flist` fields point into.
//!
//! getrgb, like the manual's (`getrgb [fname]`), needs no resolution: it
//! writes the colours of the linear list of structs to `NAME.r .g .b`.
//! The PNG (`-p`, `--png`), an extension, needs the width: from the
//! optional `hres vres`, or else from `NAME.frag`.
//!
//! Layouts are in [`crate::output`]. With a display flag (`-a BITS`, `-r`,
//! `-g`, `-b`, `-y`, `-c`) the image is also written as `OUTPUT.png` in
//! that mode; there is no graphics screen, so `-Y` is accepted and
//! explained. All outputs appear together when the run succeeds and none
//! when it fails. Each run appends a line of statistics to `rftbN.log`
//! (`getrgb.log`) in the working directory.

use std::ffi::OsString;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Instant, SystemTime};

use crate::budget::Budgets;
use crate::error::{Error, Result};
use crate::output::{
    DisplayMode, PixelStructSink, Planes, PngSink, SeparationSink, Staged, commit_all, with_suffix,
};
use crate::raster::scan::{Method, Row, RowSink, ScanOptions, ScanStats, TransparencyRule};
use crate::tree::RecordStream;

mod args;
mod getrgb;
mod limits;
mod program;
mod run;

pub use args::*;
pub use getrgb::*;
pub use limits::*;
pub use program::*;
pub use run::*;
/// One of the four tilers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Program {
    /// Pixel coverage (method 1).
    Rftb1,
    /// Pixel masks (method 2).
    Rftb2,
    /// Coverage and masks (method 3).
    Rftb3,
    /// Pixel-structs (method 4).
    Rftb4,
}

impl Program {
    /// The program's name.
    pub fn name(self) -> &'static str {
        match self {
            Program::Rftb1 => "rftb1",
            Program::Rftb2 => "rftb2",
            Program::Rftb3 => "rftb3",
            Program::Rftb4 => "rftb4",
        }
    }

    /// Its scan conversion method.
    pub fn method(self) -> Method {
        match self {
            Program::Rftb1 => Method::Area,
            Program::Rftb2 => Method::Mask,
            Program::Rftb3 => Method::Hybrid,
            Program::Rftb4 => Method::Multilevel,
        }
    }

    /// The separation planes besides `.r .g .b`; `None` for rftb4's
    /// pixel-struct file.
    pub fn planes(self) -> Option<Planes> {
        let (coverage, mask) = match self {
            Program::Rftb1 => (true, false),
            Program::Rftb2 => (false, true),
            Program::Rftb3 => (true, true),
            Program::Rftb4 => return None,
        };
        Some(Planes { coverage, mask })
    }

    /// Whether it wants pre-blended shades (`setmode b on`): rftb1-3 do,
    /// rftb4 blends itself.
    pub fn wants_preblended(self) -> bool {
        self != Program::Rftb4
    }

    /// How it blends transparent surfaces: rftb1 "simulates linear and
    /// non-linear transparency using a pixel-coverage byte" and rftb3
    /// "combines the features of rftb1 and rftb2" (the rftb manual page),
    /// by section 5.6 (`Ā = A (1 - T)`, section 5.8 for rftb3). The manual
    /// gives rftb2 and rftb4 no transparency; they keep plytrace's
    /// section 4.9 rule (`I = I_cur + k_t I_behind`).
    pub fn transparency(self) -> TransparencyRule {
        match self {
            Program::Rftb1 | Program::Rftb3 => TransparencyRule::Coverage,
            Program::Rftb2 | Program::Rftb4 => TransparencyRule::Garcia,
        }
    }

    /// The usage line.
    pub fn usage(self) -> String {
        format!(
            "usage: {} <input> [output] [hres] [vres] [act-lines] [-0..-9] [-B] \
             [-a BITS | -r | -g | -b | -y | -c] [-Y] [--part I/N -o PART.png] {BUDGET_FLAGS}",
            self.name()
        )
    }
}

/// Checks that `stream` suits `program`: front to back, and pre-blended
/// for rftb1-3, post-blended for rftb4, unless the tree has only level-1
/// records. Pre-blending (`setmode b on`) blends "higher tree level parent
/// polygon intensities ... with each lower level children polygon" (004
/// appendix, SETMODE COMMANDS, `b`): with no record below level 1 there
/// is nothing to blend and both modes write the same shades, so either is
/// accepted (the manual's default, `setmode b off`, then works with every
/// tiler).
pub fn check_tree(program: Program, stream: &RecordStream, input: &Path) -> Result<()> {
    let mut wrong = Vec::new();
    if !stream.front_to_back {
        wrong.push("its polygons are back to front; write it with `sort ftb`".to_string());
    }
    let children = stream.records.iter().filter(|r| r.level > 1).count();
    let sub_level = |n: usize| {
        format!(
            "{n} of its records lie below level 1 (reflections or refractions), so the \
             blending mode matters"
        )
    };
    match (program.wants_preblended(), stream.blended) {
        (true, false) if children > 0 => wrong.push(format!(
            "its shades are post-blended and {}; {} blends nothing, so children would not \
             get their parents' shades: write it with `setmode b on` (or use rftb4)",
            sub_level(children),
            program.name()
        )),
        (false, true) if children > 0 => wrong.push(format!(
            "its shades are pre-blended and {}; rftb4 blends children with parents itself, \
             so parents would count twice: write it with `setmode b off`",
            sub_level(children)
        )),
        _ => {}
    }
    if wrong.is_empty() {
        return Ok(());
    }
    Err(Error::Invalid(format!(
        "{}: this tree is not for {}: {}",
        input.display(),
        program.name(),
        wrong.join("; ")
    )))
}

#[cfg(test)]
mod tests;
