//! The `penumbra` command line: render a scene file (or the built-in default scene) to a PNG.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};

use penumbra::film::{write_atomically, write_png};
use penumbra::scene::{self, SceneDesc};
use penumbra::trace::{render, RenderStats};
use penumbra::world::SceneWorld;

/// Penumbra: a data-oriented CPU ray tracer.
#[derive(Parser, Debug)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render one frame of a scene to a PNG (the default command).
    Render(RenderArgs),
}

#[derive(Args, Debug, Default)]
struct RenderArgs {
    /// Scene file (RON). Without one, the built-in default scene is rendered.
    scene: Option<PathBuf>,
    /// Output PNG path.
    #[arg(short, long, default_value = "penumbra.png")]
    output: PathBuf,
    /// Image width in pixels (overrides the scene; alone, the height keeps the scene's aspect).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    width: Option<u32>,
    /// Image height in pixels (overrides the scene; alone, the width keeps the scene's aspect).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    height: Option<u32>,
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Print detailed statistics and write them as JSON to this file.
    #[arg(long, value_name = "STATS.json")]
    stats: Option<PathBuf>,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let args = match cli.command {
        Some(Command::Render(args)) => args,
        None => RenderArgs { output: PathBuf::from("penumbra.png"), ..Default::default() },
    };
    match run_render(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run_render(args: &RenderArgs) -> anyhow::Result<()> {
    let started = Instant::now();
    let mut desc: SceneDesc = match &args.scene {
        Some(path) => scene::load_scene(path)?,
        None => scene::default_scene(),
    };
    apply_size(&mut desc, args.width, args.height);
    let load = started.elapsed().as_secs_f64();

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0) as usize)
        .build()
        .context("cannot start worker threads")?;
    let (film, mut stats) = pool.install(|| {
        let started = Instant::now();
        let mut world: SceneWorld = scene::spawn_world(&desc);
        let spawn = started.elapsed().as_secs_f64();
        let snapshot = world.update();
        let settings = world.render_settings();
        let clock = world.stage_clock();
        let (film, mut stats) = render(&snapshot, &settings);
        stats.times.world_update = spawn + clock.bounds;
        stats.times.grid_build = clock.grid_build;
        stats.times.snapshot = clock.snapshot;
        (film, stats)
    });
    stats.times.load = load;

    let started = Instant::now();
    write_png(&film, &args.output)?;
    stats.times.write = started.elapsed().as_secs_f64();
    report(&stats, &args.output, args.stats.as_deref())
}

/// Applies `--width` / `--height`; one alone keeps the scene's aspect ratio.
fn apply_size(desc: &mut SceneDesc, width: Option<u32>, height: Option<u32>) {
    let (w0, h0) = (desc.camera.width as f64, desc.camera.height as f64);
    let scaled = |v: f64| (v.round() as u32).clamp(1, 16384);
    match (width, height) {
        (Some(w), Some(h)) => (desc.camera.width, desc.camera.height) = (w, h),
        (Some(w), None) => (desc.camera.width, desc.camera.height) = (w, scaled(w as f64 * h0 / w0)),
        (None, Some(h)) => (desc.camera.width, desc.camera.height) = (scaled(h as f64 * w0 / h0), h),
        (None, None) => {}
    }
}

fn report(stats: &RenderStats, output: &Path, stats_path: Option<&Path>) -> anyhow::Result<()> {
    let text = match stats_path {
        Some(path) => {
            let json = serde_json::to_vec_pretty(stats).context("cannot encode statistics")?;
            write_atomically(path, &json)?;
            format!("wrote {}\n{}\nstats      {}", output.display(), stats.summary(), path.display())
        }
        None => format!(
            "wrote {} ({}x{}, {} rays in {:.3} s, {:.2} Mrays/s)",
            output.display(),
            stats.width,
            stats.height,
            stats.rays.total(),
            stats.times.trace,
            stats.mrays_per_s()
        ),
    };
    // The files are written; a closed stdout (`penumbra ... | head`) is not an error.
    match writeln!(std::io::stdout().lock(), "{text}") {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e).context("cannot write to stdout"),
        _ => Ok(()),
    }
}
