//! `penumbra render`: one frame of a scene to an image (PNG or EXR), with AOVs, tone
//! mapping, statistics and metadata that `penumbra info` can replay.
//!
//! `frame_args` holds the options every rendering command shares ([`FrameArgs`]) and how they
//! change a scene, `flags` the parsers of their values, `summary` what a finished render prints
//! and writes beside the image.

mod flags;
mod frame_args;
mod summary;

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use clap::Args;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use penumbra::film::{prepare_output, AovSet, Aovs, Film};
use penumbra::scene::inputs::Inputs;
use penumbra::scene::{self, SceneDesc};
use penumbra::store::{AosStore, PrimitiveStore, SoaStore};
use penumbra::trace::{render_observed, RenderSettings, RenderStats};
use penumbra::world::SceneWorld;

pub use self::flags::{parse_shutter, ShutterFlag};
pub use self::frame_args::{apply_size, check_simd, FrameArgs};
pub use self::summary::say;
use self::summary::{report, Memory};
use super::estimate;
use super::{bad_input, meta};

#[derive(Args, Debug, Default)]
pub struct RenderArgs {
    /// Scene file (RON). Without one, the built-in default scene is rendered.
    pub scene: Option<PathBuf>,
    /// Output image: `.png` (8-bit sRGB, tone-mapped) or `.exr` (linear half float); see `--format`.
    #[arg(short, long, default_value = "penumbra.png")]
    pub output: PathBuf,
    /// Print detailed statistics and write them as JSON to this file.
    #[arg(long, value_name = "STATS.json")]
    stats: Option<PathBuf>,
    /// Memory layout of the primitives: structure of arrays or array of structures (the same
    /// image, bit for bit; for measuring what the layout is worth).
    #[arg(long, value_enum, default_value_t = Layout::Soa)]
    layout: Layout,
    /// No progress bar (it is drawn only when standard error is a terminal anyway).
    #[arg(long)]
    quiet: bool,
    /// How to render and encode the image.
    #[command(flatten)]
    pub frame: FrameArgs,
}

/// Primitive memory layout (`--layout`).
#[derive(clap::ValueEnum, Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Layout {
    /// Structure of arrays: one array per coordinate.
    #[default]
    Soa,
    /// Array of structures: one struct per primitive.
    Aos,
}

impl RenderArgs {
    /// `penumbra` without arguments: the built-in scene to `penumbra.png`.
    pub fn default_scene() -> Self {
        Self { output: PathBuf::from("penumbra.png"), ..Default::default() }
    }
}

/// Renders as `args` say; `replay` are the arguments that reproduce the image (stored in its
/// metadata).
pub fn run(args: &RenderArgs, replay: &[String]) -> anyhow::Result<()> {
    let name = args.scene.as_ref().map(|p| p.display().to_string());
    run_named(args, replay, name.as_deref())
}

/// [`run`], recording the scene under `scene_name` (the name it was given when the image was
/// first made: `info --rerender` reads the file from wherever it is now, but the image says
/// what the original said).
pub fn run_named(args: &RenderArgs, replay: &[String], scene_name: Option<&str>) -> anyhow::Result<()> {
    let started = Instant::now();
    // A level this CPU lacks, a wrong format or an unwritable folder fails before any work.
    args.frame.check_simd()?;
    let format = args.frame.format_for(&args.output)?;
    prepare_output(&args.output)?;
    if let Some(stats) = &args.stats {
        prepare_output(stats)?;
    }
    let (mut desc, inputs, source, origin) = match &args.scene {
        Some(path) => {
            let desc = scene::load_scene(path)?;
            // Read again for the hash: `load_scene` validated exactly these bytes or failed.
            let bytes =
                std::fs::read(path).with_context(|| format!("{}: cannot read scene", path.display()))?;
            let name = scene_name.map_or_else(|| path.display().to_string(), str::to_owned);
            let inputs = Inputs::of_scene(&name, &absolute(path), &bytes, &desc)
                .map_err(|e| bad_input(e.to_string()))?;
            (desc, inputs, bytes, path.display().to_string())
        }
        None => (
            scene::default_scene(),
            Inputs::builtin(),
            scene::DEFAULT_SCENE_SOURCE.as_bytes().to_vec(),
            scene::DEFAULT_SCENE_ORIGIN.to_owned(),
        ),
    };
    args.frame.apply_checked(&mut desc, &source, &origin)?;
    warn_ray_trees(&desc);
    let tone = args.frame.tone_mapping(&desc);
    let wanted = args.frame.aov.unwrap_or_default();
    let memory = args.frame.check_memory(&desc, format)?;
    let load = started.elapsed().as_secs_f64();

    let pool = args.frame.thread_pool()?;
    let bar = tile_bar(args.quiet);
    bar.set_message(estimate::work(&desc));
    let on_tile = |done: u32, total: u32| {
        bar.set_length(u64::from(total));
        bar.set_position(u64::from(done));
    };
    let (film, aovs, mut stats, settings) = pool.install(|| match args.layout {
        Layout::Soa => render_frame::<SoaStore>(&desc, &args.frame, wanted, &on_tile),
        Layout::Aos => render_frame::<AosStore>(&desc, &args.frame, wanted, &on_tile),
    });
    bar.finish_and_clear();
    stats.times.mesh_grid_build = desc.assets.meshes.grid_build_seconds();
    stats.times.load = (load - stats.times.mesh_grid_build).max(0.0);

    args.frame.check_film(&stats, "")?;
    let (settings, replay) = meta::pin_rounds(&settings, &stats, replay);
    let metadata = meta::describe(&inputs, &settings, &tone, &replay);
    let started = Instant::now();
    // In the render's pool: encoding is parallel, on the threads asked for.
    let written =
        pool.install(|| args.frame.write((&film, aovs.as_ref()), &args.output, format, &tone, &metadata))?;
    stats.times.write = started.elapsed().as_secs_f64();
    let memory = Memory { estimate: memory, peak_rss: estimate::peak_rss() };
    report(&stats, &written, aovs.as_ref().map(|a| a.object_names.as_slice()), &memory, args.stats.as_deref())
}

/// `path` made absolute without resolving links (kept as given if that fails).
pub fn absolute(path: &Path) -> PathBuf {
    std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
}

/// A progress bar of tiles with an ETA on standard error: drawn only when standard error is a
/// terminal and `quiet` is off, and empty until the first tile reports the total.
pub fn tile_bar(quiet: bool) -> ProgressBar {
    let target = match quiet {
        true => ProgressDrawTarget::hidden(),
        false => ProgressDrawTarget::stderr(),
    };
    let style = ProgressStyle::with_template(
        "render [{bar:30}] {pos}/{len} tiles, {elapsed} elapsed, eta {eta} ({msg})",
    )
    .expect("a valid template")
    .progress_chars("=> ");
    ProgressBar::with_draw_target(None, target).with_style(style)
}

/// Spawns, updates and renders one frame with primitive layout `S` and the engine options of
/// `frame` (`--simd`).
fn render_frame<S: PrimitiveStore>(
    desc: &SceneDesc,
    frame: &FrameArgs,
    wanted: AovSet,
    on_tile: &(dyn Fn(u32, u32) + Sync),
) -> (Film, Option<Aovs>, RenderStats, RenderSettings) {
    let started = Instant::now();
    let mut world: SceneWorld<S> = scene::spawn_world(desc);
    let spawn = started.elapsed().as_secs_f64();
    let snapshot = world.update();
    let settings = frame.settings(world.render_settings());
    let clock = world.stage_clock();
    let (film, aovs, mut stats) = render_observed(&snapshot, &settings, wanted, on_tile);
    stats.times.world_update = spawn + clock.bounds;
    stats.times.grid_build = clock.grid_build;
    stats.times.snapshot = clock.snapshot;
    (film, aovs, stats, settings)
}

/// Prints one `warning:` line on stderr for each material whose ray tree can outgrow the
/// budget of secondary rays (see [`scene::ray_tree`]), before any rendering.
pub fn warn_ray_trees(desc: &SceneDesc) {
    let mut stderr = std::io::stderr().lock();
    for warning in scene::ray_tree::ray_tree_warnings(desc) {
        // A closed stderr cannot take a warning; the render goes on regardless.
        let _ = writeln!(stderr, "warning: {warning}");
    }
}

#[cfg(test)]
mod tests;
