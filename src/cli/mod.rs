//! The command line (clap): `render` (the default), `animate`, `sweep`, `status`, `report` and `info`. Only the binary uses this
//! module; everything it calls is the library's public API.

pub mod animate;
pub mod info;
pub mod interrupt;
pub mod meta;
pub mod render;
pub mod report;
pub mod status;
pub mod sweep;

use clap::{Parser, Subcommand};

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
