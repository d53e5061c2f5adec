//! `penumbra status DIR [--json]`: which frames of an animation folder are done, missing or
//! stale against the current scene and script.

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;

use penumbra::batch::manifest::ranges;
use penumbra::batch::status;

use super::render::say;

/// Arguments of `penumbra status`.
#[derive(Args, Debug)]
pub struct StatusArgs {
    /// A frames folder written by `penumbra animate`.
    pub dir: PathBuf,
    /// Print the status as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Prints the status; succeeds whatever the frames' state (the output says it).
pub fn run(args: &StatusArgs) -> anyhow::Result<()> {
    let s = status(&args.dir)?;
    if args.json {
        return say(&serde_json::to_string_pretty(&s).context("cannot encode the status")?);
    }
    let total = s.frames.len() as usize;
    let mut text = format!(
        "{}: frames {} ({total}): {} done, {} missing, {} stale\n  done     {}\n  missing  {}\n  stale    {}",
        args.dir.display(),
        s.frames,
        s.done.len(),
        s.missing.len(),
        s.stale.len(),
        ranges(&s.done),
        ranges(&s.missing),
        ranges(&s.stale)
    );
    if !s.changed.is_empty() {
        text += &format!("\n  changed  {} (since the stale frames were made)", s.changed.join(", "));
    }
    if !s.stray_temporaries.is_empty() {
        text += &format!(
            "\n  {} temporary files from interrupted writes (the next `animate` on this folder removes them): {}",
            s.stray_temporaries.len(),
            s.stray_temporaries.join(", ")
        );
    }
    say(&text)
}
