//! The `penumbra` command line: render a scene file (or the built-in default scene) to a PNG.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Context;
use clap::{Args, Parser, Subcommand};

use penumbra::film::{write_atomically, write_png};
use penumbra::sample::Pattern;
use penumbra::scene::{self, AdaptiveDesc, LightDesc, SceneDesc};
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
    /// Sample count of an effect, e.g. `--samples aa=16` (aa, lens, shadow, glossy; repeatable).
    #[arg(long, value_name = "EFFECT=N", value_parser = parse_samples)]
    samples: Vec<(Effect, u32)>,
    /// Sample pattern of an effect, e.g. `--pattern lens=grid` (grid, random, jittered; repeatable).
    #[arg(long, value_name = "EFFECT=PATTERN", value_parser = parse_pattern)]
    pattern: Vec<(Effect, Pattern)>,
    /// Adaptive supersampling with this corner threshold (`T`, or `T:DEPTH`, depth 1..=6, default 3).
    #[arg(long, value_name = "T[:DEPTH]", value_parser = parse_adaptive, conflicts_with = "no_adaptive")]
    adaptive: Option<(f32, u32)>,
    /// Turn off adaptive supersampling set in the scene.
    #[arg(long)]
    no_adaptive: bool,
    /// Lens radius (0 = pinhole).
    #[arg(long, value_name = "R", value_parser = parse_aperture)]
    aperture: Option<f32>,
}

/// An effect whose sampling the command line can set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Effect {
    Aa,
    Lens,
    Shadow,
    Glossy,
}

fn split_effect(s: &str) -> Result<(Effect, &str), String> {
    let (effect, value) = s.split_once('=').ok_or_else(|| format!("expected EFFECT=VALUE, got `{s}`"))?;
    let effect = match effect {
        "aa" => Effect::Aa,
        "lens" => Effect::Lens,
        "shadow" => Effect::Shadow,
        "glossy" => Effect::Glossy,
        other => return Err(format!("unknown effect `{other}`; expected aa, lens, shadow or glossy")),
    };
    Ok((effect, value))
}

fn parse_samples(s: &str) -> Result<(Effect, u32), String> {
    let (effect, value) = split_effect(s)?;
    match value.parse::<u32>() {
        Ok(n) if (1..=4096).contains(&n) => Ok((effect, n)),
        _ => Err(format!("sample count must be a whole number in 1..=4096, got `{value}`")),
    }
}

fn parse_pattern(s: &str) -> Result<(Effect, Pattern), String> {
    let (effect, value) = split_effect(s)?;
    let pattern = match value {
        "grid" => Pattern::Grid,
        "random" => Pattern::Random,
        "jittered" => Pattern::Jittered,
        other => return Err(format!("unknown pattern `{other}`; expected grid, random or jittered")),
    };
    Ok((effect, pattern))
}

fn parse_adaptive(s: &str) -> Result<(f32, u32), String> {
    let (threshold, depth) = s.split_once(':').unwrap_or((s, "3"));
    let threshold = threshold.parse::<f32>().ok().filter(|t| t.is_finite() && *t >= 0.0);
    let depth = depth.parse::<u32>().ok().filter(|d| (1..=6).contains(d));
    match (threshold, depth) {
        (Some(t), Some(d)) => Ok((t, d)),
        _ => Err(format!(
            "expected a threshold ≥ 0 and an optional depth in 1..=6 (`0.05` or `0.05:4`), got `{s}`"
        )),
    }
}

fn parse_aperture(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(r) if r.is_finite() && r >= 0.0 => Ok(r),
        _ => Err(format!("aperture must be a finite number ≥ 0, got `{s}`")),
    }
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
    apply_effects(&mut desc, args);
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

/// Applies the sampling overrides of the command line to the scene.
fn apply_effects(desc: &mut SceneDesc, args: &RenderArgs) {
    for &(effect, n) in &args.samples {
        match effect {
            Effect::Aa => desc.settings.aa.samples = n,
            Effect::Lens => desc.camera.lens.samples = n,
            Effect::Glossy => desc.settings.glossy.samples = n,
            Effect::Shadow => desc.lights.iter_mut().for_each(|l| {
                if let LightDesc::Rect { samples, .. } | LightDesc::Disk { samples, .. } = l {
                    *samples = n;
                }
            }),
        }
    }
    for &(effect, p) in &args.pattern {
        match effect {
            Effect::Aa => desc.settings.aa.pattern = p,
            Effect::Lens => desc.camera.lens.pattern = p,
            Effect::Glossy => desc.settings.glossy.pattern = p,
            Effect::Shadow => desc.lights.iter_mut().for_each(|l| {
                if let LightDesc::Rect { pattern, .. } | LightDesc::Disk { pattern, .. } = l {
                    *pattern = p;
                }
            }),
        }
    }
    if let Some((threshold, max_depth)) = args.adaptive {
        desc.settings.adaptive = Some(AdaptiveDesc { threshold, max_depth });
    }
    if args.no_adaptive {
        desc.settings.adaptive = None;
    }
    if let Some(r) = args.aperture {
        desc.camera.aperture = r;
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
