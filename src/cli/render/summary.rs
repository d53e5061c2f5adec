//! What a finished render prints and writes beside the image: the one-line summary, or with
//! `--stats` the detailed statistics (with the memory estimated and used) as text and JSON.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;

use penumbra::film::write_atomically;
use penumbra::trace::RenderStats;

use crate::cli::estimate::{self, MemoryEstimate};

/// The memory a render was estimated to need, and what it took.
pub(super) struct Memory {
    pub(super) estimate: MemoryEstimate,
    pub(super) peak_rss: Option<u64>,
}

/// Prints a line to stdout; a closed stdout (`penumbra ... | head`) is not an error.
pub fn say(text: &str) -> anyhow::Result<()> {
    match writeln!(std::io::stdout().lock(), "{text}") {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e).context("cannot write to stdout"),
        _ => Ok(()),
    }
}

/// Prints the summary of a render that wrote `written` (the image first, then its AOV files);
/// with `stats_path`, the detailed statistics, also written there as JSON.
pub(super) fn report(
    stats: &RenderStats,
    written: &[PathBuf],
    legend: Option<&[String]>,
    memory: &Memory,
    stats_path: Option<&Path>,
) -> anyhow::Result<()> {
    let output = written.first().map_or_else(String::new, |p| p.display().to_string());
    let output =
        if written.len() > 1 { format!("{output} (+{} AOV files)", written.len() - 1) } else { output };
    let text = match stats_path {
        Some(path) => {
            let mut json = serde_json::to_value(stats).context("cannot encode statistics")?;
            if let (Some(legend), Some(map)) = (legend, json.as_object_mut()) {
                let ids: serde_json::Map<String, serde_json::Value> = legend
                    .iter()
                    .enumerate()
                    .map(|(i, name)| ((i + 1).to_string(), name.clone().into()))
                    .collect();
                map.insert("object_ids".into(), ids.into());
            }
            if let Some(map) = json.as_object_mut() {
                let value = serde_json::json!({
                    "estimated_bytes": memory.estimate.peak(),
                    "peak_rss_bytes": memory.peak_rss,
                });
                map.insert("memory".into(), value);
            }
            let bytes = serde_json::to_vec_pretty(&json).context("cannot encode statistics")?;
            write_atomically(path, &bytes)?;
            let peak = memory.peak_rss.map_or_else(|| "unknown".into(), estimate::size);
            format!(
                "wrote {output}\n{}\nmemory     estimated {}, peak resident {peak}\nstats      {}",
                stats.summary(),
                estimate::size(memory.estimate.peak()),
                path.display()
            )
        }
        None => format!(
            "wrote {output} ({}x{}, {} rays in {:.3} s, {:.2} Mrays/s)",
            stats.width,
            stats.height,
            stats.rays.total(),
            stats.times.trace,
            stats.mrays_per_s()
        ),
    };
    say(&text)
}
