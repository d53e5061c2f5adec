//! Clean stops on SIGINT and SIGTERM: the process exits at once, except while a frame is being
//! written, when it first lets the write finish (the image renamed into place and its manifest
//! entry recorded), so a stop never leaves a temporary or partial file behind.

use std::sync::{Mutex, MutexGuard, OnceLock, PoisonError};

use anyhow::Context;

/// Held while a frame's files are written; the signal handler takes it before exiting.
static WRITING: Mutex<()> = Mutex::new(());
static INSTALLED: OnceLock<()> = OnceLock::new();

/// Installs the handler (once per process).
pub fn install() -> anyhow::Result<()> {
    if INSTALLED.get().is_some() {
        return Ok(());
    }
    let mut signals =
        signal_hook::iterator::Signals::new([signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM])
            .context("cannot install the SIGINT/SIGTERM handler")?;
    std::thread::Builder::new()
        .name("penumbra-signals".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                // Wait for a write in progress; nothing else needs cleaning up.
                let _quiet = WRITING.lock().unwrap_or_else(PoisonError::into_inner);
                let name = if signal == signal_hook::consts::SIGINT { "SIGINT" } else { "SIGTERM" };
                eprintln!("penumbra: stopped by {name}; finished frames are kept, rerun to render the rest");
                std::process::exit(128 + signal);
            }
        })
        .context("cannot start the signal thread")?;
    let _ = INSTALLED.set(());
    Ok(())
}

/// Marks a write in progress until the guard is dropped.
pub fn writing() -> MutexGuard<'static, ()> {
    WRITING.lock().unwrap_or_else(PoisonError::into_inner)
}
