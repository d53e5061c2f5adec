//! The command line (clap): `render` (the default), `animate`, `sweep`, `status`, `report` and
//! `info`, one module each, with the size and memory estimate shown before a render
//! ([`estimate`]), Ctrl-C handling ([`interrupt`]) and the provenance every output carries
//! ([`meta`]). Only the binary uses this module (feature `cli`); everything it calls is the
//! library's public API.

pub mod animate;
pub mod estimate;
pub mod info;
pub mod interrupt;
pub mod meta;
pub mod render;
pub mod report;
pub mod status;
pub mod sweep;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

use penumbra::batch::ManifestError;
use penumbra::film::OutputError;
use penumbra::report::run::ReportError;
use penumbra::report::sweep::SweepError;
use penumbra::scene::obj::ObjError;
use penumbra::scene::SceneError;
use penumbra::script::ScriptError;

/// Penumbra: a data-oriented CPU ray tracer.
#[derive(Parser, Debug)]
#[command(version, about, long_about = None)]
pub struct Cli {
    /// What to do (default: render the built-in scene to penumbra.png).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Render one frame of a scene to an image (the default command).
    Render(render::RenderArgs),
    /// Print how an image was made; `--rerender` makes it again.
    Info(info::InfoArgs),
    /// Render a frame sequence driven by a Rhai script (`fn frame(t)`).
    Animate(animate::AnimateArgs),
    /// Render one image per parameter set a Rhai script declares (`fn sweep()`), with a table
    /// of render times and ray counts.
    Sweep(sweep::SweepArgs),
    /// Tell which frames of an animation folder are done, missing or stale.
    Status(status::StatusArgs),
    /// Measure what accuracy costs in time: error against a reference for each effect's
    /// sample count, with tables, plots and an HTML page.
    Report(report::ReportArgs),
}

/// The error and its causes on one line, `outer: cause: cause`, leaving out a cause whose text
/// the line already holds (errors that print their source in their own message). The last line
/// of defence for one-line errors: control characters are escaped and a line longer than
/// 2000 characters keeps its start and end (see [`penumbra::scene::error::one_line`]).
pub fn error_line(error: &anyhow::Error) -> String {
    let mut line = error.to_string();
    for cause in error.chain().skip(1) {
        let cause = cause.to_string();
        if !line.contains(&cause) {
            line.push_str(": ");
            line.push_str(&cause);
        }
    }
    penumbra::scene::error::one_line(&line, 2 * penumbra::scene::error::MAX_LINE_CHARS)
}

/// A bad combination or value of command-line arguments (or of a file they name) that clap
/// cannot check by itself; the message names the argument and the rule.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct BadInput(pub String);

/// A [`BadInput`] as an `anyhow::Error`, for `return Err(bad_input(...))` and `ok_or_else`.
pub fn bad_input(message: impl Into<String>) -> anyhow::Error {
    BadInput(message.into()).into()
}

/// The exit status for an error `main` reports:
///
/// - `2`: bad input: a scene ([`SceneError`], meshes included), an OBJ file ([`ObjError`]), a
///   script ([`ScriptError`]), a sweep file ([`SweepError`]), a file that cannot be read as an
///   image ([`OutputError::Read`]), a reference image of the wrong size
///   ([`ReportError::ReferenceSize`]), a frames folder that does not exist
///   ([`ManifestError::NoFolder`]) or a command-line argument ([`BadInput`]; clap's own parse
///   errors exit 2 before this is reached);
/// - `1`: anything else: the render or a write failed (e.g. an unwritable output path).
///
/// Success is `0`; a stop by SIGINT or SIGTERM exits `128 + N` (see [`interrupt`]).
pub fn exit_code(error: &anyhow::Error) -> ExitCode {
    let bad_input = error.chain().any(|e| {
        e.is::<SceneError>()
            || e.is::<ObjError>()
            || e.is::<ScriptError>()
            || e.is::<SweepError>()
            || e.is::<BadInput>()
            || matches!(e.downcast_ref::<OutputError>(), Some(OutputError::Read { .. }))
            || matches!(
                e.downcast_ref::<ReportError>(),
                Some(ReportError::ReferenceSize { .. } | ReportError::Point { .. } | ReportError::Script(_))
            )
            || matches!(e.downcast_ref::<ManifestError>(), Some(ManifestError::NoFolder { .. }))
    });
    ExitCode::from(if bad_input { 2 } else { 1 })
}
