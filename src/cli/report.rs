//! `penumbra report SCENE [--sweep SWEEP.ron] [--reference REF.exr] -o reports/NAME/`: what
//! accuracy costs in time, as tables, plots and a static HTML page.

use std::path::PathBuf;

use anyhow::Context;
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use penumbra::film::write_atomically;
use penumbra::report::reference::{read_reference, ReferenceFile};
use penumbra::report::run::{
    csv, effects_of, render_count, run as run_report, Options, ScriptFrame, DEFAULT_RUNS,
};
use penumbra::report::sweep::SweepDesc;
use penumbra::report::{html, plot};
use penumbra::scene;
use penumbra::script::{Limits, Script};
use penumbra::simd::SimdLevel;

use super::animate::parse_fps;
use super::bad_input;
use super::meta::{sha256_hex, SCENE, SCENE_HASH};
use super::render::{apply_size, check_simd, parse_shutter, say, ShutterFlag};

/// Arguments of `penumbra report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// Scene file (RON).
    pub scene: PathBuf,
    /// Sweep file (RON; see `report::sweep`). Default: AA and adaptive, plus area-light,
    /// glossy and lens samples where the scene uses those effects.
    #[arg(long, value_name = "SWEEP.ron")]
    pub sweep: Option<PathBuf>,
    /// Use this image as the reference instead of rendering one: a linear EXR (preferred; e.g.
    /// `penumbra render --format exr-float`) or an 8/16-bit sRGB PNG (clamped and quantised).
    /// It must have been made from the same scene file unless `--force`.
    #[arg(long, value_name = "REF.exr|REF.png")]
    pub reference: Option<PathBuf>,
    /// Use a `--reference` that records another scene (a warning instead of an error).
    #[arg(long)]
    pub force: bool,
    /// Pose every render at a frame of this Rhai script (`fn frame(t)`, as `penumbra animate`
    /// runs it): what moves while the shutter is open is blurred, and the sweep gains a `time`
    /// axis. The script's output is dropped; a script that sets sample counts overrides the
    /// sweep's.
    #[arg(long, value_name = "SCRIPT.rhai")]
    pub script: Option<PathBuf>,
    /// The script frame to pose the scene at (time FRAME / fps).
    #[arg(long, default_value_t = 0, requires = "script")]
    pub frame: u32,
    /// Frames per second of the script's clock.
    #[arg(long, default_value_t = 24.0, value_parser = parse_fps, requires = "script")]
    pub fps: f64,
    /// Motion blur: `OPEN:CLOSE` as fractions of the frame interval, or `none` (overrides the
    /// scene's `camera.shutter`; `none` makes every render an instant).
    #[arg(long, value_name = "OPEN:CLOSE", value_parser = parse_shutter)]
    pub shutter: Option<ShutterFlag>,
    /// Report folder (created if missing).
    #[arg(short, long, default_value = "report")]
    pub output: PathBuf,
    /// Interleaved rounds: each renders every distinct configuration once; a point's time is
    /// the median over the rounds.
    #[arg(long, default_value_t = DEFAULT_RUNS as u32, value_parser = clap::value_parser!(u32).range(1..=99))]
    pub runs: u32,
    /// Image width in pixels (overrides the scene; alone, the height keeps the aspect).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub width: Option<u32>,
    /// Image height in pixels (overrides the scene; alone, the width keeps the aspect).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    pub height: Option<u32>,
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// How rays are traced: auto (the best level this CPU has), scalar (single rays, the
    /// reference), or packets compiled for baseline, avx2 or avx512. Every level gives the same
    /// images, bit for bit, so only the times depend on it; a level this CPU lacks is refused.
    #[arg(long, value_name = "LEVEL", default_value_t = SimdLevel::Auto)]
    pub simd: SimdLevel,
    /// No progress bar or summary.
    #[arg(long)]
    pub quiet: bool,
}

/// Prints `line` to stderr.
fn warn(line: &str) -> anyhow::Result<()> {
    use std::io::Write;
    writeln!(std::io::stderr(), "{line}").context("cannot write to stderr")
}

/// Checks that the reference was made from this scene file (the scene hash in its metadata):
/// another scene is refused (exit 2) unless `--force`, which warns instead; a file without the
/// hash is used with a warning that its scene cannot be checked.
fn check_provenance(args: &ReportArgs, path: &std::path::Path, file: &ReferenceFile) -> anyhow::Result<()> {
    let source =
        std::fs::read(&args.scene).with_context(|| format!("{}: cannot read scene", args.scene.display()))?;
    let ours = sha256_hex(&source);
    let Some(theirs) = file.meta.get(SCENE_HASH) else {
        return warn(&format!(
            "warning: {}: no Penumbra metadata ({SCENE_HASH}), so whether it was made from {} cannot be checked",
            path.display(),
            args.scene.display()
        ));
    };
    if theirs == ours {
        return Ok(());
    }
    let message = format!(
        "{}: the reference was made from scene {} (sha256 {theirs}), not from {} (sha256 {ours})",
        path.display(),
        file.meta.get(SCENE).unwrap_or("(unnamed)"),
        args.scene.display()
    );
    if args.force {
        warn(&format!("warning: {message}; used anyway (--force)"))
    } else {
        Err(bad_input(format!("{message}; pass --force to use it anyway")))
    }
}

/// Runs the report and writes its files.
pub fn run(args: &ReportArgs) -> anyhow::Result<()> {
    check_simd(args.simd)?;
    let mut desc = scene::load_scene(&args.scene)?;
    apply_size(&mut desc, args.width, args.height);
    if let Some(ShutterFlag(shutter)) = args.shutter {
        desc.camera.shutter = shutter;
    }
    let script = match &args.script {
        Some(path) => Some(ScriptFrame {
            script: Script::load(path, Limits::default())?,
            frame: args.frame,
            fps: args.fps,
        }),
        None => None,
    };
    let effects = effects_of(&desc, script.as_ref())?;
    let sweep = match &args.sweep {
        Some(path) => SweepDesc::load(path)?,
        None => SweepDesc::default_for(&effects),
    };
    let reference = match &args.reference {
        Some(path) => {
            let file = read_reference(path).map_err(|e| bad_input(e.to_string()))?;
            check_provenance(args, path, &file)?;
            if !args.quiet {
                file.notes.iter().try_for_each(|n| warn(&format!("note: {n}")))?;
            }
            Some((file.film, file.description))
        }
        None => None,
    };
    if args.output.is_file() {
        return Err(bad_input(format!("{}: is a file; the report needs a folder", args.output.display())));
    }
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("{}: cannot create the report folder", args.output.display()))?;
    let options = Options { runs: args.runs as usize, reference, simd: args.simd, script };

    let bar = ProgressBar::with_draw_target(
        Some(render_count(&desc, &effects, &sweep, &options) as u64),
        if args.quiet { ProgressDrawTarget::hidden() } else { ProgressDrawTarget::stderr() },
    );
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} renders, eta {eta}  {msg}")
            .expect("a valid template")
            .progress_chars("=> "),
    );
    let progress = |label: &str| {
        bar.set_message(label.to_owned());
        bar.inc(1);
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0) as usize)
        .build()
        .context("cannot start worker threads")?;
    let scene_name = args.scene.display().to_string();
    let report =
        pool.install(|| run_report(&desc, &scene_name, &sweep, &options, &args.output, &progress))?;
    bar.finish_and_clear();

    write_atomically(&args.output.join("results.csv"), csv(&report).as_bytes())?;
    let savings = report.savings();
    let mut json = serde_json::to_value(&report).context("cannot encode results.json")?;
    json["savings"] = serde_json::to_value(&savings).context("cannot encode results.json")?;
    let json = serde_json::to_vec_pretty(&json).context("cannot encode results.json")?;
    write_atomically(&args.output.join("results.json"), &json)?;
    plot::error_vs_time(&report, &args.output)?;
    plot::rays_vs_error(&report, &args.output)?;
    plot::effect_costs(&report, &args.output)?;
    plot::estimate_vs_error(&report, &args.output)?;
    let index = html::write_index(&report, &args.output)?;
    if !args.quiet {
        let front: Vec<&str> =
            report.pareto_front().iter().map(|&i| report.points[i].label.as_str()).collect();
        say(&format!(
            "{} points against the reference ({}, {:.2} s); Pareto front: {}\nwrote {}",
            report.points.len(),
            report.reference.description,
            report.reference.seconds,
            front.join(", "),
            index.display()
        ))?;
        for s in &savings {
            let at = |f: &Option<penumbra::report::FixedAt>, what: &str| match f {
                Some(f) => format!("{:.2}x the {what} (aa {})", f.ratio, f.pattern),
                None => format!("no fixed {what} to compare (RMSE outside the aa curves)"),
            };
            say(&format!(
                "equal error: {} (RMSE {:.3e}, {} rays, {:.3} s): best fixed needs {}, {}",
                s.label,
                s.rmse,
                s.rays,
                s.seconds,
                at(&s.fixed_rays, "rays"),
                at(&s.fixed_seconds, "time")
            ))?;
        }
    }
    Ok(())
}
