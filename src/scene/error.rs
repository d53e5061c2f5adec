//! The scene loader's error type: a file that cannot be read, or a scene that is invalid at
//! a known line, column and field.
//!
//! Every problem in a scene, from a RON syntax error to a material that is not defined, is
//! reported as [`SceneError::Invalid`] and displays as `file:line:col: field `path`: rule`:
//!
//! ```text
//! scenes/bad.ron:12:51: field `objects[0].shape.radius`: must be > 0, got -1
//! ```
//!
//! Every message is one line: names and values a user wrote are echoed through [`shown`]
//! (control characters escaped, long ones cut to [`SHOWN_CHARS`] characters), and the
//! message as a whole through [`one_line`] (escaped, at most [`MAX_LINE_CHARS`] characters).

use std::borrow::Cow;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Why a scene could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{}: cannot read scene: {source}", escaped_path(path))]
    Io {
        /// The path as given.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// The scene text is malformed or breaks a rule of the format.
    #[error("{}: field `{}`: {}", located(path, *line, *col), shown(field), one_line(rule, MAX_LINE_CHARS))]
    Invalid {
        /// Where the text came from: the file path as given, or `<built-in default scene>`.
        path: String,
        /// 1-based line of the offending value; 0 for a scene with no text (built in code by
        /// [`super::SceneBuilder`]), whose errors show no position.
        line: usize,
        /// 1-based column of the offending value, counted in characters.
        col: usize,
        /// The field, as a path from the scene root such as `objects[2].shape.radius`.
        field: String,
        /// What is wrong and what is allowed, e.g. `must be in [0, 1], got 1.2`.
        rule: String,
    },
}

/// `path:line:col`, or `path` alone where there is no text (`line` 0).
fn located(path: &str, line: usize, col: usize) -> String {
    match line {
        0 => escaped(path).into_owned(),
        _ => format!("{}:{line}:{col}", escaped(path)),
    }
}

/// How many characters of a name or value [`shown`] keeps.
pub const SHOWN_CHARS: usize = 60;
/// The longest message [`one_line`] keeps whole, in characters.
pub const MAX_LINE_CHARS: usize = 1000;

/// `text` with control characters (and the Unicode line and paragraph separators) written as
/// escapes: `\n`, `\r`, `\t`, `\0`, otherwise `\u{1b}`; borrowed when there are none.
///
/// # Examples
/// ```
/// use penumbra::scene::error::escaped;
/// assert_eq!(escaped("a\nb\0c\u{1b}"), "a\\nb\\0c\\u{1b}");
/// assert_eq!(escaped("plain é"), "plain é");
/// ```
pub fn escaped(text: &str) -> Cow<'_, str> {
    let needs = |c: char| c.is_control() || c == '\u{2028}' || c == '\u{2029}';
    if !text.chars().any(needs) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        match c {
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            '\0' => out.push_str("\\0"),
            c if needs(c) => {
                // Writing to a String cannot fail.
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

/// A path as [`escaped`] text.
pub fn escaped_path(path: &Path) -> String {
    escaped(&path.display().to_string()).into_owned()
}

/// A user-provided name or value for a message: [`escaped`], and cut to its first
/// [`SHOWN_CHARS`] characters plus `…` and the full length when longer.
///
/// # Examples
/// ```
/// use penumbra::scene::error::shown;
/// assert_eq!(shown("ball\nred"), "ball\\nred");
/// let long = shown(&"x".repeat(200_000));
/// assert_eq!(long, format!("{}… (200000 characters)", "x".repeat(60)));
/// ```
pub fn shown(text: &str) -> String {
    let count = text.chars().count();
    if count <= SHOWN_CHARS {
        return escaped(text).into_owned();
    }
    let head: String = text.chars().take(SHOWN_CHARS).collect();
    format!("{}… ({count} characters)", escaped(&head))
}

/// A whole message on one line: [`escaped`], and when longer than `max` characters its first
/// and last `max / 2` characters around `… (N characters left out) …`.
///
/// # Examples
/// ```
/// use penumbra::scene::error::one_line;
/// assert_eq!(one_line("two\nlines", 100), "two\\nlines");
/// let cut = one_line(&"ab".repeat(600), 100);
/// assert!(cut.starts_with("ababab") && cut.contains("… (1100 characters left out) …"));
/// ```
pub fn one_line(text: &str, max: usize) -> String {
    let text = escaped(text);
    let count = text.chars().count();
    if count <= max {
        return text.into_owned();
    }
    let keep = max / 2;
    let head: String = text.chars().take(keep).collect();
    let tail: String = text.chars().skip(count - keep).collect();
    format!("{head}… ({} characters left out) …{tail}", count - 2 * keep)
}

/// A number for a message: plain when moderate, in scientific notation when very large or
/// small (`0.9`, `1e29`, `3e-9`), to four significant digits there.
pub fn number(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || (1e-4..1e6).contains(&a) {
        // As the 32-bit value the scene holds: `0.1`, not `0.10000000149011612`.
        return format!("{}", x as f32);
    }
    let text = format!("{x:.3e}");
    match text.split_once('e') {
        Some((mantissa, exponent)) if mantissa.contains('.') => {
            format!("{}e{exponent}", mantissa.trim_end_matches('0').trim_end_matches('.'))
        }
        _ => text,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_with_control_characters_print_on_one_line() {
        let invalid = SceneError::Invalid {
            path: "a\nb.ron".into(),
            line: 1,
            col: 2,
            field: "objects[0].name".into(),
            rule: "duplicate object name `x\ny\0`".into(),
        };
        let text = invalid.to_string();
        assert_eq!(text, "a\\nb.ron:1:2: field `objects[0].name`: duplicate object name `x\\ny\\0`");
        assert_eq!(escaped("\u{1b}[31m\u{2028}"), "\\u{1b}[31m\\u{2028}");
    }

    #[test]
    fn long_values_are_cut_with_their_length() {
        let name = "é".repeat(61);
        assert_eq!(shown(&name), format!("{}… (61 characters)", "é".repeat(60)));
        assert_eq!(shown(&"é".repeat(60)), "é".repeat(60));
        let rule = format!("material `{}` is not defined", "n".repeat(5000));
        let invalid = SceneError::Invalid { path: "s.ron".into(), line: 1, col: 1, field: "f".into(), rule };
        let text = invalid.to_string();
        assert!(text.chars().count() < MAX_LINE_CHARS + 100, "{} characters", text.len());
        assert!(text.ends_with("n` is not defined"), "{text}");
    }

    #[test]
    fn messages_have_the_documented_shape() {
        let invalid = SceneError::Invalid {
            path: "bad.ron".into(),
            line: 3,
            col: 14,
            field: "materials[1].kd".into(),
            rule: "must be in [0, 1], got 1.2".into(),
        };
        assert_eq!(invalid.to_string(), "bad.ron:3:14: field `materials[1].kd`: must be in [0, 1], got 1.2");
        let io = SceneError::Io {
            path: "missing.ron".into(),
            source: std::io::Error::new(std::io::ErrorKind::NotFound, "not found"),
        };
        assert_eq!(io.to_string(), "missing.ron: cannot read scene: not found");
    }
}
