//! Tokens of the scene descriptor language (Garcia 1986, 004 appendix):
//! `#` comments to the end of the line, `/* */` comments that may span
//! lines, arguments separated by white space or commas. One statement per
//! line; a statement is a command word followed by its arguments.
//! Parentheses count as separators too, so that the manual's
//! `lookat(vx, vy, vz, px, py, pz, twist)` reads as `lookat vx ... twist`.

use std::path::Path;

use crate::error::{Diagnostic, Location, Result};

/// A word of a statement with its 1-based position.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Token {
    /// The text as written.
    pub text: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column (in characters).
    pub column: usize,
}

/// The tokens of one line (never empty).
pub type Statement = Vec<Token>;

/// Splits `source` into statements. Fails only on an unterminated `/*`.
pub fn lex(source: &str, file: &Path) -> Result<Vec<Statement>> {
    let mut statements = Vec::new();
    let mut current: Statement = Vec::new();
    let mut word = String::new();
    let mut word_start = (0, 0);
    let mut in_block: Option<(usize, usize)> = None;
    let mut in_line_comment = false;

    let mut chars = source.chars().peekable();
    let (mut line, mut column) = (1usize, 0usize);

    fn flush(word: &mut String, start: (usize, usize), current: &mut Statement) {
        if !word.is_empty() {
            current.push(Token {
                text: std::mem::take(word),
                line: start.0,
                column: start.1,
            });
        }
    }

    while let Some(c) = chars.next() {
        column += 1;
        if c == '\n' {
            flush(&mut word, word_start, &mut current);
            if in_block.is_none() && !current.is_empty() {
                statements.push(std::mem::take(&mut current));
            }
            in_line_comment = false;
            line += 1;
            column = 0;
            continue;
        }
        if in_line_comment {
            continue;
        }
        if in_block.is_some() {
            if c == '*' && chars.peek() == Some(&'/') {
                chars.next();
                column += 1;
                in_block = None;
            }
            continue;
        }
        match c {
            '#' => {
                flush(&mut word, word_start, &mut current);
                in_line_comment = true;
            }
            '/' if chars.peek() == Some(&'*') => {
                flush(&mut word, word_start, &mut current);
                chars.next();
                in_block = Some((line, column));
                column += 1;
            }
            c if c.is_whitespace() || matches!(c, ',' | '(' | ')') => {
                flush(&mut word, word_start, &mut current);
            }
            c => {
                if word.is_empty() {
                    word_start = (line, column);
                }
                word.push(c);
            }
        }
    }
    if let Some((l, c)) = in_block {
        let text = source.lines().nth(l - 1).unwrap_or("");
        return Err(Diagnostic::new(
            Location::new(file, l, c),
            "unterminated comment: `/*` has no closing `*/`",
        )
        .with_source(text, 2)
        .into());
    }
    flush(&mut word, word_start, &mut current);
    if !current.is_empty() {
        statements.push(current);
    }
    Ok(statements)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(src: &str) -> Vec<Vec<String>> {
        lex(src, Path::new("t"))
            .unwrap()
            .into_iter()
            .map(|s| s.into_iter().map(|t| t.text).collect())
            .collect()
    }

    #[test]
    fn comments_and_commas() {
        let w = words("color 1,0.5 ,0 # red\n/* a\n b */ ident /* x */ \n\n  scale 1 2 3");
        assert_eq!(
            w,
            vec![
                vec!["color", "1", "0.5", "0"],
                vec!["ident"],
                vec!["scale", "1", "2", "3"]
            ]
        );
    }

    #[test]
    fn parentheses_separate_arguments() {
        assert_eq!(
            words("lookat(0, 0, 5, 0,0,0, 0)\nscale (1 2 3)"),
            vec![
                vec!["lookat", "0", "0", "5", "0", "0", "0", "0"],
                vec!["scale", "1", "2", "3"]
            ]
        );
    }

    #[test]
    fn positions_are_one_based() {
        let s = lex("# c\n  light 1 2", Path::new("t")).unwrap();
        assert_eq!((s[0][0].line, s[0][0].column), (2, 3));
        assert_eq!((s[0][2].line, s[0][2].column), (2, 11));
    }

    #[test]
    fn unterminated_block_comment_is_an_error_at_its_start() {
        let e = lex("ident\n  /* open", Path::new("f.des")).unwrap_err();
        let d = e.diagnostic().unwrap();
        assert_eq!((d.location.line, d.location.column), (2, 3));
        assert!(d.message.contains("unterminated"));
    }
}
