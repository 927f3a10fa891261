//! The arguments of a statement of the scene descriptor language (Garcia
//! 1986, 004 appendix B, the plytrace manual page): numbers, colours from
//! 0 to 1, whole numbers in a range, `on`/`off`, object references. Every
//! reader fails with a diagnostic that names the file, line and column of
//! the word and what was expected.

use std::path::{Path, PathBuf};

use glam::DVec3;

use super::commands::CommandSpec;
use super::lexer::Token;
use crate::error::{Diagnostic, Error, Location, MAX_SHOWN_TOKEN, Result, printable};

/// Where a statement came from, for diagnostics and relative paths.
pub(super) struct Context<'a> {
    /// The file (or `<stdin>`, `<command line>`) the text came from.
    pub file: &'a Path,
    /// The folder relative names are looked up in first.
    pub dir: PathBuf,
    /// The whole text, for the line a diagnostic quotes.
    pub source: &'a str,
}

impl Context<'_> {
    /// An error at `token`, quoting its line and underlining it.
    pub fn error(&self, token: &Token, message: impl Into<String>) -> Error {
        let line = self.source.lines().nth(token.line - 1).unwrap_or("");
        Diagnostic::new(Location::new(self.file, token.line, token.column), message)
            .with_source(line, token.text.chars().count())
            .into()
    }

    /// Where `token` is.
    pub fn location(&self, token: &Token) -> Location {
        Location::new(self.file, token.line, token.column)
    }
}

/// A value read from an argument, with the word it was read from (for the
/// errors found when the statement runs).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Spanned<T> {
    /// The value.
    pub value: T,
    /// The word as written.
    pub token: Token,
}

/// An object named by its number or (case-folded) name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum ObjectRef {
    /// `callobj 3`.
    Number(u32),
    /// `callobj cube`, folded to lower case.
    Name(String),
}

impl ObjectRef {
    /// Whether it names `o`.
    pub(super) fn names(&self, o: &crate::model::Object) -> bool {
        match self {
            ObjectRef::Number(n) => o.number == *n,
            ObjectRef::Name(name) => o.name == *name,
        }
    }
}

/// The arguments of one statement, with typed accessors that fail with a
/// located diagnostic.
pub(super) struct Args<'a> {
    pub ctx: &'a Context<'a>,
    /// The command word as written.
    pub cmd: &'a Token,
    pub args: &'a [Token],
    pub spec: &'static CommandSpec,
}

impl Args<'_> {
    /// Fails unless there are `min` to `max` arguments.
    pub fn count(&self, min: usize, max: usize) -> Result<()> {
        let n = self.args.len();
        if n >= min && n <= max {
            return Ok(());
        }
        let expected = if min == max {
            format!("{min} argument{}", if min == 1 { "" } else { "s" })
        } else if max == usize::MAX {
            format!("at least {min} argument{}", if min == 1 { "" } else { "s" })
        } else {
            format!("{min} to {max} arguments")
        };
        let usage = if self.spec.usage.is_empty() {
            String::new()
        } else {
            format!(" ({})", self.spec.usage)
        };
        let token = if n > max { &self.args[max] } else { self.cmd };
        Err(self.ctx.error(
            token,
            format!("`{}` expects {expected}{usage}, found {n}", self.spec.name),
        ))
    }

    /// Argument `i` as the word it is.
    pub fn text(&self, i: usize) -> String {
        self.args[i].text.clone()
    }

    /// Argument `i` with its word.
    pub fn spanned<T>(&self, i: usize, value: T) -> Spanned<T> {
        Spanned {
            value,
            token: self.args[i].clone(),
        }
    }

    /// Argument `i`, a finite number.
    pub fn number(&self, i: usize) -> Result<f64> {
        let t = &self.args[i];
        match t.text.parse::<f64>() {
            Ok(v) if v.is_finite() && !t.text.to_ascii_lowercase().contains("inf") => Ok(v),
            Ok(_) => Err(self.ctx.error(
                t,
                format!(
                    "expected a finite number, found `{}`",
                    printable(&t.text, MAX_SHOWN_TOKEN)
                ),
            )),
            Err(_) => Err(self.ctx.error(
                t,
                format!(
                    "expected a number, found `{}`",
                    printable(&t.text, MAX_SHOWN_TOKEN)
                ),
            )),
        }
    }

    /// The first `N` arguments, numbers.
    pub fn numbers<const N: usize>(&self) -> Result<[f64; N]> {
        let mut v = [0.0; N];
        for (i, x) in v.iter_mut().enumerate() {
            *x = self.number(i)?;
        }
        Ok(v)
    }

    /// Arguments `i` to `i + 2`, numbers.
    pub fn vec3(&self, i: usize) -> Result<DVec3> {
        Ok(DVec3::new(
            self.number(i)?,
            self.number(i + 1)?,
            self.number(i + 2)?,
        ))
    }

    /// Argument `i`, a number from 0 to 1.
    pub fn unit(&self, i: usize) -> Result<f64> {
        let v = self.number(i)?;
        if !(0.0..=1.0).contains(&v) {
            return Err(self.ctx.error(
                &self.args[i],
                format!("expected a value from 0 to 1, found {v}"),
            ));
        }
        Ok(v)
    }

    /// Arguments `i` to `i + 2`, a colour (components from 0 to 1).
    pub fn color(&self, i: usize) -> Result<DVec3> {
        Ok(DVec3::new(
            self.unit(i)?,
            self.unit(i + 1)?,
            self.unit(i + 2)?,
        ))
    }

    /// Argument `i`, a whole number from `min` to `max`.
    pub fn integer(&self, i: usize, min: i64, max: i64) -> Result<i64> {
        let t = &self.args[i];
        let v: i64 = t.text.parse().map_err(|_| {
            self.ctx.error(
                t,
                format!(
                    "expected a whole number, found `{}`",
                    printable(&t.text, MAX_SHOWN_TOKEN)
                ),
            )
        })?;
        if v < min || v > max {
            return Err(self.ctx.error(
                t,
                format!("expected a whole number from {min} to {max}, found {v}"),
            ));
        }
        Ok(v)
    }

    /// Argument `i`, an object number, or a name (case-folded).
    pub fn object_ref(&self, i: usize) -> Result<ObjectRef> {
        let t = &self.args[i];
        if t.text
            .starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+')
        {
            return Ok(ObjectRef::Number(
                self.integer(i, 0, u32::MAX as i64)? as u32
            ));
        }
        Ok(ObjectRef::Name(t.text.to_lowercase()))
    }

    /// Argument `i`, `on` or `off` (or `1`/`0`, `true`/`false`,
    /// `yes`/`no`).
    pub fn on_off(&self, i: usize) -> Result<bool> {
        let t = &self.args[i];
        match t.text.to_ascii_lowercase().as_str() {
            "on" | "1" | "true" | "yes" => Ok(true),
            "off" | "0" | "false" | "no" => Ok(false),
            _ => Err(self.ctx.error(
                t,
                format!(
                    "expected `on` or `off`, found `{}`",
                    printable(&t.text, MAX_SHOWN_TOKEN)
                ),
            )),
        }
    }

    /// For projections: left != right, bottom != top, near != far.
    pub fn distinct_pairs(&self, v: &[f64]) -> Result<()> {
        for pair in (0..v.len()).step_by(2) {
            if v[pair] == v[pair + 1] {
                return Err(self.ctx.error(
                    &self.args[pair + 1],
                    "expected different values for the two sides of the volume",
                ));
            }
        }
        Ok(())
    }
}
