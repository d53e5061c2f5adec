//! Script errors: every failure names the script file, the line and column, and what went
//! wrong; a broken sandbox limit names the limit and its value. Rhai's own wording is
//! translated where it would talk about its internals: an unknown property names the object,
//! suggests the closest property and lists them ([`Properties`]); assigning to a property of a
//! call (`entity("ball").kd = …`) shows how to write it instead.

use std::fmt;

use rhai::{EvalAltResult, ParseError, ParseErrorType, Position};

use super::api::properties::Properties;
use super::engine::Limits;
use crate::scene::error::{escaped, one_line, MAX_LINE_CHARS};

/// A sandbox limit a script ran into.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// Operations per call (`max_operations`).
    Operations,
    /// Nested function calls (`max_call_levels`).
    CallLevels,
    /// Expression nesting (`max_expr_depth`).
    ExpressionDepth,
    /// Bytes in one string (`max_string_size`).
    StringSize,
    /// Elements in one array (`max_array_size`).
    ArraySize,
    /// Entries in one object map (`max_map_size`).
    MapSize,
    /// Variables alive at once (`max_variables`).
    Variables,
    /// Functions defined by the script (`max_functions`).
    Functions,
    /// Wall-clock seconds per call (`time_limit`).
    Time,
}

impl Limit {
    /// The limit's name, as [`Limits`] spells its field.
    pub fn name(self) -> &'static str {
        match self {
            Limit::Operations => "max_operations",
            Limit::CallLevels => "max_call_levels",
            Limit::ExpressionDepth => "max_expr_depth",
            Limit::StringSize => "max_string_size",
            Limit::ArraySize => "max_array_size",
            Limit::MapSize => "max_map_size",
            Limit::Variables => "max_variables",
            Limit::Functions => "max_functions",
            Limit::Time => "time_limit",
        }
    }

    /// What the limit bounds, with its value, e.g. `more than 1000000 operations in one call`.
    fn describe(self, limits: &Limits) -> String {
        match self {
            Limit::Operations => format!("more than {} operations in one call", limits.max_operations),
            Limit::CallLevels => format!("function calls nested deeper than {}", limits.max_call_levels),
            Limit::ExpressionDepth => format!(
                "an expression nested deeper than {} (inside functions: {})",
                limits.max_expr_depth, limits.max_function_expr_depth
            ),
            Limit::StringSize => format!("a string longer than {} bytes", limits.max_string_size),
            Limit::ArraySize => format!("an array of more than {} elements", limits.max_array_size),
            Limit::MapSize => format!("an object map of more than {} entries", limits.max_map_size),
            Limit::Variables => format!("more than {} variables", limits.max_variables),
            Limit::Functions => format!("more than {} functions", limits.max_functions),
            Limit::Time => format!("longer than {} s in one call", limits.time_limit.as_secs_f64()),
        }
    }
}

/// What kind of failure a [`ScriptError`] is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ErrorKind {
    /// The file could not be read.
    Read,
    /// The script does not parse.
    Syntax,
    /// A sandbox limit was exceeded.
    Limit(Limit),
    /// The script tried something the sandbox does not grant (importing modules, files).
    Sandbox,
    /// An error while running: a bad value, a missing entity, an unknown function.
    Runtime,
    /// A function the host calls (`frame`, `sweep`) is not defined.
    MissingFunction,
}

/// A script failure, located in the script.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScriptError {
    /// The script file as given.
    pub file: String,
    /// 1-based line, when known.
    pub line: Option<usize>,
    /// 1-based column, when known.
    pub column: Option<usize>,
    /// What kind of failure.
    pub kind: ErrorKind,
    /// What went wrong.
    pub message: String,
    /// The host call that failed, e.g. `frame(0.5) at frame 12`.
    pub context: Option<String>,
}

impl fmt::Display for ScriptError {
    /// One line: the file, message and context escaped ([`one_line`]), so that a name with a
    /// newline or a 200 KB string a script throws cannot spread over lines or screens.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", escaped(&self.file))?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.column {
                write!(f, ":{column}")?;
            }
        }
        let what = match &self.kind {
            ErrorKind::Read => "cannot read script".to_owned(),
            ErrorKind::Syntax => "syntax error".to_owned(),
            ErrorKind::Limit(limit) => format!("script limit `{}` exceeded", limit.name()),
            ErrorKind::Sandbox => "not allowed in scripts".to_owned(),
            ErrorKind::Runtime => "script error".to_owned(),
            ErrorKind::MissingFunction => "missing function".to_owned(),
        };
        write!(f, ": {what}: {}", one_line(&self.message, MAX_LINE_CHARS))?;
        if let Some(context) = &self.context {
            write!(f, " (in {})", one_line(context, MAX_LINE_CHARS))?;
        }
        Ok(())
    }
}

impl std::error::Error for ScriptError {}

impl ScriptError {
    /// An error about the whole script (no position).
    pub fn new(file: &str, kind: ErrorKind, message: impl Into<String>) -> Self {
        Self { file: file.to_owned(), line: None, column: None, kind, message: message.into(), context: None }
    }

    /// The same error, saying which host call failed.
    pub fn in_call(mut self, context: impl Into<String>) -> Self {
        self.context = Some(context.into());
        self
    }

    fn at(mut self, position: Position) -> Self {
        self.line = position.line();
        self.column = position.position();
        self
    }

    /// A parse failure of `source`: as [`Self::from_parse`], with an assignment to a property
    /// of a call explained from the text it quotes.
    pub fn from_parse_of(file: &str, error: &ParseError, limits: &Limits, source: &str) -> Self {
        let ParseError(kind, position) = error;
        match kind.as_ref() {
            ParseErrorType::AssignmentToInvalidLHS(text) if text.is_empty() => {
                let line = position.line().and_then(|l| source.lines().nth(l - 1));
                let at = line.zip(position.position()).and_then(|(line, column)| {
                    line.char_indices().nth(column - 1).map(|(byte, _)| &line[byte..])
                });
                Self::new(file, ErrorKind::Syntax, invalid_assignment(at.unwrap_or(""))).at(*position)
            }
            _ => Self::from_parse(file, error, limits),
        }
    }

    /// A parse failure.
    pub fn from_parse(file: &str, error: &ParseError, limits: &Limits) -> Self {
        let ParseError(kind, position) = error;
        let (kind, message) = match kind.as_ref() {
            ParseErrorType::ExprTooDeep => {
                (ErrorKind::Limit(Limit::ExpressionDepth), Limit::ExpressionDepth.describe(limits))
            }
            ParseErrorType::TooManyFunctions => {
                (ErrorKind::Limit(Limit::Functions), Limit::Functions.describe(limits))
            }
            ParseErrorType::LiteralTooLarge(what, _) => {
                let limit = size_limit(what);
                (ErrorKind::Limit(limit), limit.describe(limits))
            }
            other => (ErrorKind::Syntax, other.to_string()),
        };
        Self::new(file, kind, message).at(*position)
    }

    /// A failure while running, located at the innermost position Rhai reports (inside the
    /// function where it happened, not the host's call). A broken limit is located at
    /// `statement`, the statement that was running (Rhai reports it at the outermost call).
    pub fn from_eval(file: &str, error: &EvalAltResult, limits: &Limits, statement: Position) -> Self {
        let mut error = error;
        while let EvalAltResult::ErrorInFunctionCall(_, _, inner, _) = error {
            error = inner;
        }
        let unwound = error.is_system_exception() && !matches!(error, EvalAltResult::ErrorParsing(..));
        let position = match unwound && !statement.is_none() {
            true => statement,
            false => error.position(),
        };
        let limit = match error {
            EvalAltResult::ErrorTooManyOperations(_) => Some(Limit::Operations),
            EvalAltResult::ErrorStackOverflow(_) => Some(Limit::CallLevels),
            EvalAltResult::ErrorTooManyVariables(_) => Some(Limit::Variables),
            EvalAltResult::ErrorDataTooLarge(what, _) => Some(size_limit(what)),
            EvalAltResult::ErrorTerminated(..) => Some(Limit::Time),
            _ => None,
        };
        let (kind, message) = match (limit, error) {
            (Some(limit), _) => (ErrorKind::Limit(limit), limit.describe(limits)),
            (None, EvalAltResult::ErrorParsing(kind, _)) => {
                return Self::from_parse(file, &ParseError(Box::new(kind.clone()), position), limits)
            }
            (None, EvalAltResult::ErrorModuleNotFound(name, _)) => (
                ErrorKind::Sandbox,
                format!("`import \"{name}\"`: scripts cannot import modules or read files"),
            ),
            (None, EvalAltResult::ErrorRuntime(value, _)) => (ErrorKind::Runtime, value.to_string()),
            (None, other) => {
                let translated = match other {
                    EvalAltResult::ErrorDotExpr(text, _) => property_error(text),
                    _ => None,
                };
                // Rhai's text ends with the position, which the error carries separately.
                let text = other.to_string();
                let suffix = format!(" ({position})");
                let message =
                    translated.unwrap_or_else(|| text.strip_suffix(&suffix).unwrap_or(&text).to_owned());
                (ErrorKind::Runtime, message)
            }
        };
        Self::new(file, kind, message).at(position)
    }
}

/// What to write instead of an assignment Rhai cannot make; `at` is the source from the
/// assigned expression on (`entity("ball").kd = …`, `texture("water").offset = …`).
fn invalid_assignment(at: &str) -> String {
    let opening = ["entity(", "texture("].into_iter().find(|f| at.starts_with(f));
    let call = opening.zip(at.find(')')).map(|(opening, end)| (opening, &at[..=end]));
    let Some((opening, call)) = call else {
        return "this expression cannot be assigned to: only a variable or a variable's property can \
                be (`x = …`, `x.position = …`); put the value in a variable first"
            .into();
    };
    let property: String = at[call.len()..]
        .strip_prefix('.')
        .unwrap_or("")
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect();
    let name = call[opening.len()..call.len() - 1].trim().trim_matches('"');
    let variable = match name.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_alphanumeric() || c == '_')
    {
        true => name.to_owned(),
        false => opening[..1].to_owned(),
    };
    let property = match (property.is_empty(), opening) {
        (false, _) => property,
        (true, "texture(") => "offset".to_owned(),
        (true, _) => "position".to_owned(),
    };
    format!(
        "`{call}.{property}` cannot be assigned to directly: Rhai writes only to a variable's \
         properties; write `let {variable} = {call}; {variable}.{property} = …;`"
    )
}

/// Our message for Rhai's "Unknown property 'p' - a getter is not registered for type 't'"
/// and "No writable property 'p' - a setter is not registered for type 't' to handle 'u'",
/// when `t` is a script type with known properties.
fn property_error(text: &str) -> Option<String> {
    let quoted = |from: &str| -> Option<&str> {
        let rest = &text[text.find(from)? + from.len()..];
        Some(&rest[..rest.find('\'')?])
    };
    let property = quoted("property '")?;
    let properties = Properties::of(quoted("for type '")?)?;
    let setting = text.starts_with("No writable property");
    Some(match setting && properties.read_only.contains(&property) {
        true => properties.read_only(property),
        false => properties.unknown(property),
    })
}

/// The size limit a Rhai "too large" message refers to.
fn size_limit(what: &str) -> Limit {
    let what = what.to_ascii_lowercase();
    if what.contains("string") {
        Limit::StringSize
    } else if what.contains("map") {
        Limit::MapSize
    } else {
        Limit::ArraySize
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_print_file_line_column_and_the_limit() {
        let e = ScriptError::new("fly.rhai", ErrorKind::Limit(Limit::Operations), "more than 10 operations")
            .at(Position::new(3, 7))
            .in_call("frame(0.5) at frame 12");
        assert_eq!(
            e.to_string(),
            "fly.rhai:3:7: script limit `max_operations` exceeded: more than 10 operations (in frame(0.5) at frame 12)"
        );
    }

    #[test]
    fn messages_print_on_one_line_and_long_ones_are_cut() {
        let e = ScriptError::new("a\nb.rhai", ErrorKind::Runtime, "no entity named `x\0y`")
            .at(Position::new(2, 5));
        assert_eq!(e.to_string(), "a\\nb.rhai:2:5: script error: no entity named `x\\0y`");
        let thrown = ScriptError::new("s.rhai", ErrorKind::Runtime, "z".repeat(200_000));
        let text = thrown.to_string();
        assert!(text.len() < 2 * MAX_LINE_CHARS && text.contains("characters left out"), "{}", text.len());
    }

    #[test]
    fn rhai_size_messages_map_to_their_limits() {
        assert_eq!(size_limit("Length of string"), Limit::StringSize);
        assert_eq!(size_limit("Size of array/BLOB"), Limit::ArraySize);
        assert_eq!(size_limit("Size of array literal"), Limit::ArraySize);
        assert_eq!(size_limit("Size of object map"), Limit::MapSize);
        assert_eq!(size_limit("Number of properties in object map literal"), Limit::MapSize);
    }
}
