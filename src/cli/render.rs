//! `penumbra render`: one frame of a scene to an image (PNG or EXR), with AOVs, tone
//! mapping, statistics and metadata that `penumbra info` can replay.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use clap::Args;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use penumbra::camera::Shutter;
use penumbra::film::{
    prepare_output, write_atomically, write_image, AovSet, Aovs, Film, OutputFormat, ToneMapping,
    ToneOperator,
};
use penumbra::sample::Pattern;
use penumbra::scene::inputs::Inputs;
use penumbra::scene::{self, AdaptiveDesc, LightDesc, SceneDesc};
use penumbra::simd::SimdLevel;
use penumbra::store::{AosStore, PrimitiveStore, SoaStore};
use penumbra::trace::{render_observed, RenderSettings, RenderStats};
use penumbra::world::SceneWorld;

use super::estimate::{self, MemoryEstimate};
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

/// The options every rendering command shares: image size, threads, sampling, encoding.
#[derive(Args, Debug, Default, Clone)]
pub struct FrameArgs {
    /// Image width in pixels (overrides the scene; alone, the height keeps the scene's aspect).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    width: Option<u32>,
    /// Image height in pixels (overrides the scene; alone, the width keeps the scene's aspect).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=16384))]
    height: Option<u32>,
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// How rays are traced: auto (the best level this CPU has), scalar (single rays, the
    /// reference), or packets compiled for baseline, avx2 or avx512. Every level gives the same
    /// image, bit for bit; a level this CPU lacks is refused.
    #[arg(long, value_name = "LEVEL", default_value_t = SimdLevel::Auto)]
    pub simd: SimdLevel,
    /// Sample count of an effect, e.g. `--samples aa=16` (aa, lens, area_light, glossy, time; repeatable).
    #[arg(long, value_name = "EFFECT=N", value_parser = parse_samples)]
    samples: Vec<(Effect, u32)>,
    /// Sample pattern of an effect, e.g. `--pattern lens=grid` (grid, random, jittered; repeatable).
    #[arg(long, value_name = "EFFECT=PATTERN", value_parser = parse_pattern)]
    pattern: Vec<(Effect, Pattern)>,
    /// Adaptive supersampling with this corner threshold (`T`, or `T:DEPTH`, depth 1..=6, default 3).
    #[arg(
        long,
        value_name = "T[:DEPTH]",
        allow_negative_numbers = true,
        value_parser = parse_adaptive,
        conflicts_with = "no_adaptive"
    )]
    adaptive: Option<(f32, u32)>,
    /// Turn off adaptive sampling set in the scene (corner subdivision or noise-driven).
    #[arg(long)]
    no_adaptive: bool,
    /// Noise-driven adaptive sampling: each pixel takes batches of its AA set (× lens × time
    /// samples) until the standard error of its mean on the display is at most E (0..1; 0.01
    /// is about 2.5/255). Replaces `settings.adaptive`; other noise settings from the scene's
    /// `settings.noise` or their defaults.
    #[arg(long, value_name = "E", value_parser = parse_target_error, conflicts_with_all = ["adaptive", "no_adaptive"])]
    target_error: Option<f32>,
    /// Noise-driven adaptive sampling with a time limit: no round starts that would end after
    /// SECONDS of tracing (the image is always complete).
    #[arg(long, value_name = "SECONDS", value_parser = parse_time_limit, conflicts_with_all = ["adaptive", "no_adaptive"])]
    time_limit: Option<f32>,
    /// Noise-driven adaptive sampling: at least MIN and at most MAX camera samples per pixel
    /// (each rounded up to whole batches of the AA set; 1 <= MIN <= MAX <= 65536).
    #[arg(long, value_name = "MIN:MAX", value_parser = parse_noise_samples, conflicts_with_all = ["adaptive", "no_adaptive"])]
    noise_samples: Option<(u32, u32)>,
    /// Lens radius (0 = pinhole).
    #[arg(long, value_name = "R", allow_negative_numbers = true, value_parser = parse_aperture)]
    aperture: Option<f32>,
    /// Motion blur: when the shutter is open, `OPEN:CLOSE` as fractions of the frame interval
    /// (`0:0.5` is a 180° shutter), or `none` (overrides the scene's `camera.shutter`). What
    /// moves comes from the script (`animate`).
    #[arg(long, value_name = "OPEN:CLOSE", value_parser = parse_shutter)]
    shutter: Option<ShutterFlag>,
    /// Refuse a render whose estimated memory exceeds this (e.g. `8G`, `512M`; default: the
    /// memory the machine has available).
    #[arg(long, value_name = "SIZE", value_parser = estimate::parse_size)]
    max_memory: Option<u64>,
    /// Output encoding (default: from the extension): png8, png16, exr-half, exr-float.
    #[arg(long, value_name = "FORMAT")]
    pub format: Option<OutputFormat>,
    /// AOVs to write beside the image (EXR: layers of the same file; PNG: `NAME.AOV.png`):
    /// any of depth, normal, albedo, object, cost, comma-separated.
    #[arg(long, value_name = "LIST", value_parser = AovSet::parse)]
    pub aov: Option<AovSet>,
    /// Tone-mapping operator of PNG output: clamp, reinhard or aces (overrides the scene).
    #[arg(long, value_name = "OPERATOR", value_parser = parse_operator)]
    tonemap: Option<ToneOperator>,
    /// Exposure in stops applied before tone mapping, in [-30, 30] (overrides the scene).
    #[arg(long, value_name = "STOPS", allow_negative_numbers = true, value_parser = parse_exposure)]
    exposure: Option<f32>,
    /// White point of the Reinhard operator, > 0 (overrides the scene).
    #[arg(long, value_name = "W", value_parser = parse_white)]
    white: Option<f32>,
    /// Fail (exit 1, nothing written) when a sample's radiance is not finite, instead of
    /// dropping the sample with a warning.
    #[arg(long)]
    pub strict: bool,
}

/// An effect whose sampling the command line can set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effect {
    Aa,
    Lens,
    Shadow,
    Glossy,
    Time,
}

fn split_effect(s: &str) -> Result<(Effect, &str), String> {
    let (effect, value) = s.split_once('=').ok_or_else(|| format!("expected EFFECT=VALUE, got `{s}`"))?;
    let effect = match effect {
        "aa" => Effect::Aa,
        "lens" => Effect::Lens,
        // `area_light` as in reports and sweep files; `shadow` is its older spelling.
        "area_light" | "shadow" => Effect::Shadow,
        "glossy" => Effect::Glossy,
        "time" => Effect::Time,
        other => {
            return Err(format!("unknown effect `{other}`; expected aa, lens, area_light, glossy or time"))
        }
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

/// `--shutter`: a shutter interval, or `none` for an instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShutterFlag(pub Option<(f32, f32)>);

/// Parses `--shutter OPEN:CLOSE|none`.
pub fn parse_shutter(s: &str) -> Result<ShutterFlag, String> {
    if s == "none" {
        return Ok(ShutterFlag(None));
    }
    let number = |t: &str| t.trim().parse::<f32>().ok().filter(|x| x.is_finite());
    let Some((open, close)) = s.split_once(':').and_then(|(a, b)| Some((number(a)?, number(b)?))) else {
        return Err(format!(
            "expected OPEN:CLOSE (fractions of the frame interval, e.g. `0:0.5`) or `none`, got `{s}`"
        ));
    };
    Shutter::new(open, close).map(|_| ShutterFlag(Some((open, close))))
}

fn parse_target_error(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(e) if (0.0..=1.0).contains(&e) => Ok(e),
        _ => Err(format!(
            "expected a target error in [0, 1] (display units; 0.01 is about 2.5/255), got `{s}`"
        )),
    }
}

fn parse_time_limit(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(t),
        _ => Err(format!("expected a time limit in seconds, finite and > 0, got `{s}`")),
    }
}

fn parse_noise_samples(s: &str) -> Result<(u32, u32), String> {
    let max = scene::validate::MAX_NOISE_SAMPLES;
    let parsed = s
        .split_once(':')
        .and_then(|(a, b)| Some((a.trim().parse::<u32>().ok()?, b.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((lo, hi)) if 1 <= lo && lo <= hi && hi <= max => Ok((lo, hi)),
        _ => {
            Err(format!("expected MIN:MAX camera samples per pixel with 1 <= MIN <= MAX <= {max}, got `{s}`"))
        }
    }
}

fn parse_aperture(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(r) if r.is_finite() && r >= 0.0 => Ok(r),
        _ => Err(format!("aperture must be a finite number ≥ 0, got `{s}`")),
    }
}

fn parse_operator(s: &str) -> Result<ToneOperator, String> {
    match s {
        "clamp" => Ok(ToneOperator::Clamp),
        "reinhard" => Ok(ToneOperator::Reinhard),
        "aces" => Ok(ToneOperator::Aces),
        other => Err(format!("unknown tone operator `{other}`; expected clamp, reinhard or aces")),
    }
}

fn parse_exposure(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(e) if e.is_finite() && e.abs() <= 30.0 => Ok(e),
        _ => Err(format!("exposure must be a number of stops in [-30, 30], got `{s}`")),
    }
}

fn parse_white(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(w) if w.is_finite() && w > 0.0 => Ok(w),
        _ => Err(format!("white point must be a finite number > 0, got `{s}`")),
    }
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
    stats.times.mesh_grid_build = desc.meshes.grid_build_seconds();
    stats.times.load = (load - stats.times.mesh_grid_build).max(0.0);

    args.frame.check_film(&stats, "")?;
    let metadata = meta::describe(&inputs, &settings, &tone, replay);
    let started = Instant::now();
    let written = write_image(&film, aovs.as_ref(), &args.output, format, &tone, &metadata)?;
    stats.times.write = started.elapsed().as_secs_f64();
    let memory = Memory { estimate: memory, peak_rss: estimate::peak_rss() };
    report(&stats, &written, aovs.as_ref().map(|a| a.object_names.as_slice()), &memory, args.stats.as_deref())
}

/// The memory a render was estimated to need, and what it took.
struct Memory {
    estimate: MemoryEstimate,
    peak_rss: Option<u64>,
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

/// Prints a line to stdout; a closed stdout (`penumbra ... | head`) is not an error.
pub fn say(text: &str) -> anyhow::Result<()> {
    match writeln!(std::io::stdout().lock(), "{text}") {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e).context("cannot write to stdout"),
        _ => Ok(()),
    }
}

impl FrameArgs {
    /// Applies the size and sampling overrides to the scene.
    pub fn apply(&self, desc: &mut SceneDesc) {
        apply_size(desc, self.width, self.height);
        apply_effects(desc, self);
    }

    /// [`Self::apply`], then the scene's combined rules on the result (`source` is the scene's
    /// text as loaded, named `origin` in errors): an override that makes them fail (`--samples
    /// aa=4096` on a bright light, `--aperture 1e30`) is an error at the scene field, naming the
    /// flag.
    pub fn apply_checked(&self, desc: &mut SceneDesc, source: &[u8], origin: &str) -> anyhow::Result<()> {
        self.apply(desc);
        let mut flags: Vec<(String, String)> = Vec::new();
        for &(effect, n) in &self.samples {
            let (field, name) = match effect {
                Effect::Aa => ("settings.aa.samples", "aa"),
                Effect::Lens => ("camera.lens.samples", "lens"),
                Effect::Glossy => ("settings.glossy.samples", "glossy"),
                Effect::Time => ("camera.time.samples", "time"),
                // Area-light samples each carry 1/samples of the light: no combined rule reads them.
                Effect::Shadow => continue,
            };
            flags.push((field.into(), format!("--samples {name}={n}")));
        }
        if let Some(r) = self.aperture {
            let r = scene::error::number(r.into());
            flags.push(("camera.aperture".into(), format!("--aperture {r}")));
        }
        if let Some((t, d)) = self.adaptive {
            flags.push(("settings.adaptive".into(), format!("--adaptive {t}:{d}")));
        }
        if let Some((lo, hi)) = self.noise_samples {
            flags.push(("settings.noise.max_samples".into(), format!("--noise-samples {lo}:{hi}")));
        }
        let text = String::from_utf8_lossy(source);
        scene::limits::check_overrides(desc, &text, origin, &flags)?;
        Ok(())
    }

    /// Warns on stderr (one line, after `context`) when samples were dropped as non-finite;
    /// under `--strict` that is an error instead (exit 1), before anything is written.
    pub fn check_film(&self, stats: &RenderStats, context: &str) -> anyhow::Result<()> {
        match stats.dropped.verdict(self.strict) {
            Ok(None) => Ok(()),
            Ok(Some(warning)) => {
                // A closed stderr cannot take a warning; the render goes on regardless.
                let _ = writeln!(std::io::stderr().lock(), "{context}{warning}");
                Ok(())
            }
            Err(e) if context.is_empty() => Err(e.into()),
            Err(e) => Err(anyhow::Error::new(e).context(context.trim_end_matches([':', ' ']).to_owned())),
        }
    }

    /// Refuses (exit 2) a `--simd` level this CPU lacks, naming the levels it has; called
    /// before any output is prepared or anything rendered.
    pub fn check_simd(&self) -> anyhow::Result<()> {
        check_simd(self.simd)
    }

    /// The World's render settings of a frame with the command line's engine options set
    /// (`--simd`; they choose how rays are traced, never the pixels). Every frame a command
    /// renders goes through here.
    pub fn settings(&self, settings: RenderSettings) -> RenderSettings {
        RenderSettings { simd: self.simd, ..settings }
    }

    /// The encoding of `output`: `--format`, else from its extension. A format that
    /// contradicts a known extension (`-o a.exr --format png16`) is refused.
    pub fn format_for(&self, output: &Path) -> anyhow::Result<OutputFormat> {
        let from_extension = OutputFormat::from_path(output);
        match (self.format, from_extension) {
            (Some(f), Some(e)) if f.is_exr() != e.is_exr() => Err(bad_input(format!(
                "--format {}: contradicts the extension of {} ({}); use a .{} file name or another --format",
                f.name(),
                output.display(),
                if e.is_exr() { "EXR" } else { "PNG" },
                if f.is_exr() { "exr" } else { "png" },
            ))),
            (Some(f), _) => Ok(f),
            (None, Some(e)) => Ok(e),
            (None, None) => Err(bad_input(format!(
                "{}: unknown output extension; use .png or .exr, or --format",
                output.display()
            ))),
        }
    }

    /// The scene's tone mapping with the command line's overrides.
    pub fn tone_mapping(&self, desc: &SceneDesc) -> ToneMapping {
        let t = &desc.settings.tonemap;
        ToneMapping {
            operator: self.tonemap.unwrap_or(t.operator),
            exposure: self.exposure.unwrap_or(t.exposure),
            white: self.white.unwrap_or(t.white),
        }
    }

    /// Every option that changes the pixels, as text (the thread count, the SIMD level, the
    /// memory limit and `--strict` never do). `animate` keys its frames on it, so a resumed
    /// run on another CPU (or with another `--simd`) skips the frames already done.
    pub fn fingerprint(&self) -> String {
        let pixels_only = FrameArgs {
            threads: None,
            simd: SimdLevel::Auto,
            max_memory: None,
            strict: false,
            ..self.clone()
        };
        // `--simd` is left out of the text altogether, so it is the text of the options before
        // `--simd` existed and frames folders made then still resume.
        format!("{pixels_only:?}").replacen(&format!("simd: {:?}, ", SimdLevel::Auto), "", 1)
    }

    /// Refuses a frame of `desc` (sizes and overrides applied) that needs more memory than
    /// `--max-memory` or the machine has; the estimate otherwise.
    pub fn check_memory(&self, desc: &SceneDesc, format: OutputFormat) -> anyhow::Result<MemoryEstimate> {
        let estimate = MemoryEstimate::of(desc, self.aov.unwrap_or_default(), format);
        estimate::check_memory(&estimate, self.max_memory)?;
        Ok(estimate)
    }

    /// A rayon pool of `--threads` workers (default: one per core).
    pub fn thread_pool(&self) -> anyhow::Result<rayon::ThreadPool> {
        rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads.unwrap_or(0) as usize)
            .build()
            .context("cannot start worker threads")
    }
}

/// Refuses (exit 2) `--simd LEVEL` when this CPU lacks the level: the message names the
/// option, the level, what the CPU is missing and the levels it has.
pub fn check_simd(level: SimdLevel) -> anyhow::Result<()> {
    match simd_refusal(level, SimdLevel::available) {
        None => Ok(()),
        Some(message) => Err(bad_input(message)),
    }
}

/// Why `--simd level` cannot run on a CPU that has the levels `has` accepts, if it cannot.
fn simd_refusal(level: SimdLevel, has: impl Fn(SimdLevel) -> bool) -> Option<String> {
    if has(level) {
        return None;
    }
    let missing = match level {
        SimdLevel::Avx2 => "AVX2 and FMA (x86-64-v3)",
        SimdLevel::Avx512 => "AVX-512 F/BW/CD/DQ/VL (x86-64-v4)",
        // `auto`, `scalar` and `baseline` run everywhere.
        other => other.name(),
    };
    let available: Vec<&str> = SimdLevel::ALL.into_iter().filter(|&l| has(l)).map(SimdLevel::name).collect();
    Some(format!("--simd {level}: this CPU does not support {missing}; available: {}", available.join(", ")))
}

/// Applies `--width` / `--height`; one alone keeps the scene's aspect ratio.
pub fn apply_size(desc: &mut SceneDesc, width: Option<u32>, height: Option<u32>) {
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
fn apply_effects(desc: &mut SceneDesc, args: &FrameArgs) {
    for &(effect, n) in &args.samples {
        match effect {
            Effect::Aa => desc.settings.aa.samples = n,
            Effect::Lens => desc.camera.lens.samples = n,
            Effect::Glossy => desc.settings.glossy.samples = n,
            Effect::Time => desc.camera.time.samples = n,
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
            Effect::Time => desc.camera.time.pattern = p,
            Effect::Shadow => desc.lights.iter_mut().for_each(|l| {
                if let LightDesc::Rect { pattern, .. } | LightDesc::Disk { pattern, .. } = l {
                    *pattern = p;
                }
            }),
        }
    }
    if let Some((threshold, max_depth)) = args.adaptive {
        desc.settings.adaptive = Some(AdaptiveDesc { threshold, max_depth });
        desc.settings.noise = None;
    }
    if args.no_adaptive {
        desc.settings.adaptive = None;
        desc.settings.noise = None;
    }
    if args.target_error.is_some() || args.time_limit.is_some() || args.noise_samples.is_some() {
        let mut noise = desc.settings.noise.unwrap_or_default();
        if let Some(e) = args.target_error {
            noise.target_error = e;
        }
        if let Some(t) = args.time_limit {
            noise.time_limit = Some(t);
        }
        if let Some((lo, hi)) = args.noise_samples {
            (noise.min_samples, noise.max_samples) = (lo, hi);
        }
        desc.settings.noise = Some(noise);
        desc.settings.adaptive = None;
    }
    if let Some(r) = args.aperture {
        desc.camera.aperture = r;
    }
    if let Some(ShutterFlag(shutter)) = args.shutter {
        desc.camera.shutter = shutter;
    }
}

fn report(
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

#[cfg(test)]
mod tests;
