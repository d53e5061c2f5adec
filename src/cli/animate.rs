//! `penumbra animate SCENE SCRIPT --frames A..=B --fps N -o DIR [--shard I/N] [--video OUT.mp4]`:
//! a frame sequence driven by a Rhai script, resumable and split into shards for job arrays,
//! optionally encoded to a video with ffmpeg.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use anyhow::{bail, Context};
use clap::Args;

use indicatif::{MultiProgress, ProgressBar, ProgressDrawTarget, ProgressStyle};

use penumbra::batch::manifest::frame_digits;
use penumbra::batch::{self, FrameEntry, FrameState, JobSpec, Manifest, Shard, Split};
use penumbra::film::OutputFormat;
use penumbra::scene::inputs::Inputs;
use penumbra::scene::{self, SceneDesc};
use penumbra::script::{Animation, FrameRange, Limits, Script};
use penumbra::trace::{render_observed, tile_count};

use super::render::{absolute, say, warn_ray_trees, FrameArgs};
use super::{bad_input, interrupt, meta};

/// Arguments of `penumbra animate`.
#[derive(Args, Debug)]
pub struct AnimateArgs {
    /// Scene file (RON).
    pub scene: PathBuf,
    /// Rhai script defining `fn frame(t)` (and optionally `fn setup()`).
    pub script: PathBuf,
    /// Frames to render: `A..=B`, `A..B` or a single frame `A`; `:S` after a range renders
    /// every S-th frame (`0..=119:5`, for previews). Frame n is at time n / fps.
    #[arg(long, value_name = "RANGE")]
    pub frames: FrameRange,
    /// Frames per second (the script's `t` advances by 1/fps per frame).
    #[arg(long, default_value_t = 24.0, value_parser = parse_fps)]
    pub fps: f64,
    /// Folder for the frames, `frame_0000.png` and so on (created if missing).
    #[arg(short, long, default_value = "frames")]
    pub output: PathBuf,
    /// Render only shard INDEX of COUNT (0-based, e.g. `2/4`). Default: from the job
    /// scheduler's environment (Slurm array or Kubernetes Indexed Job), else the whole range.
    #[arg(long, value_name = "INDEX/COUNT")]
    pub shard: Option<Shard>,
    /// How the range is split among shards: contiguous blocks or interleaved frames.
    #[arg(long, default_value_t = Split::Contiguous, value_name = "SPLIT")]
    pub split: Split,
    /// Shard count for a Kubernetes Indexed Job (`JOB_COMPLETION_INDEX` gives the index);
    /// default: `PENUMBRA_SHARD_COUNT`.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub shard_count: Option<u32>,
    /// Render every frame of the shard again, even those already done.
    #[arg(long)]
    pub force: bool,
    /// Also encode the frames to this video with ffmpeg (which must be on PATH).
    #[arg(long, value_name = "OUT.mp4")]
    pub video: Option<PathBuf>,
    /// No progress bars or per-frame lines; errors only (for batch logs). The script's own
    /// `print` output still shows, once per rendered frame.
    #[arg(long)]
    pub quiet: bool,
    /// How to render and encode each frame.
    #[command(flatten)]
    pub frame: FrameArgs,
}

/// Parses `--fps`: a number in (0, 1000].
pub fn parse_fps(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(f) if f.is_finite() && f > 0.0 && f <= 1000.0 => Ok(f),
        _ => Err(format!("fps must be a number in (0, 1000], got `{s}`")),
    }
}

fn extension(format: OutputFormat) -> &'static str {
    match format {
        OutputFormat::Png8 | OutputFormat::Png16 => "png",
        OutputFormat::ExrHalf | OutputFormat::ExrFloat => "exr",
    }
}

/// The host name, for the manifest.
fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .map(|h| h.trim().to_owned())
        .ok()
        .or_else(|| std::env::var("HOSTNAME").ok())
        .or_else(|| std::env::var("COMPUTERNAME").ok())
        .unwrap_or_else(|| "unknown".into())
}

/// Renders the frames as `args` say; `argv` is the whole command line (for frame metadata).
pub fn run(args: &AnimateArgs, argv: &[String]) -> anyhow::Result<()> {
    run_named(args, argv, None)
}

/// [`run`], recording the scene and script under `names` (the names they were given when the
/// frame was first made; `info --rerender` reads them from wherever they are now).
pub fn run_named(args: &AnimateArgs, argv: &[String], names: Option<(&str, &str)>) -> anyhow::Result<()> {
    args.frame.check_simd()?;
    let mut desc: SceneDesc = scene::load_scene(&args.scene)?;
    let scene_source =
        std::fs::read(&args.scene).with_context(|| format!("{}: cannot read scene", args.scene.display()))?;
    let script = Script::load(&args.script, Limits::default())?;
    script.require("frame", 1, "`animate` calls once per frame with the time in seconds")?;
    let (scene_name, script_name) = match names {
        Some((scene, script)) => (scene.to_owned(), script.to_owned()),
        None => (args.scene.display().to_string(), args.script.display().to_string()),
    };
    let inputs = Inputs::of_scene(&scene_name, &absolute(&args.scene), &scene_source, &desc)
        .map_err(|e| bad_input(e.to_string()))?
        .with_script(&script_name, &absolute(&args.script), script.source().as_bytes());
    args.frame.apply_checked(&mut desc, &scene_source, &args.scene.display().to_string())?;
    warn_ray_trees(&desc);
    let format = args.frame.format.unwrap_or(OutputFormat::Png8);
    args.frame.check_memory(&desc, format)?;
    let tone = args.frame.tone_mapping(&desc);

    let shard = match args.shard {
        Some(shard) => shard,
        None => Shard::from_env(|k| std::env::var(k).ok(), args.shard_count)
            .map_err(|e| bad_input(format!("cannot tell this task's shard: {e}")))?
            .unwrap_or(Shard::ALL),
    };
    if args.video.is_some() && shard.count > 1 {
        return Err(bad_input(format!(
            "--video needs every frame; encode after all {} shards have finished",
            shard.count
        )));
    }
    if args.video.is_some() && args.frames.step > 1 {
        return Err(bad_input(format!(
            "--video needs consecutive frames, but --frames {} takes every {}th; drop the step or --video",
            args.frames, args.frames.step
        )));
    }
    let ffmpeg = match &args.video {
        Some(video) => Some(find_ffmpeg(video, format)?),
        None => None,
    };

    let absolute =
        |p: &Path| std::fs::canonicalize(p).with_context(|| format!("{}: cannot resolve", p.display()));
    let job = JobSpec {
        version: env!("CARGO_PKG_VERSION").to_owned(),
        scene: absolute(&args.scene)?,
        script: absolute(&args.script)?,
        frames: args.frames,
        fps: args.fps,
        options: args.frame.fingerprint(),
        extension: extension(format).to_owned(),
        inputs: inputs.files.clone(),
    };
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("{}: cannot create the frames folder", args.output.display()))?;
    let manifest = Manifest::create(&args.output)?;
    // Joined before anything is written, so a lone run may clear what killed runs left.
    let run_lock = manifest.join_runs()?;
    manifest.write_job(&job)?;

    let mine = shard.frames(args.frames, args.split);
    let mut todo = Vec::new();
    for &n in &mine {
        let hash = job.inputs_hash(&inputs, n);
        if args.force || manifest.frame_state(&job, n, &hash)? != FrameState::Done {
            todo.push((n, hash));
        }
    }
    let log = |text: String| if args.quiet { Ok(()) } else { say(&text) };
    if !run_lock.removed.is_empty() {
        log(format!(
            "removed {} temporary files of interrupted runs: {}",
            run_lock.removed.len(),
            run_lock.removed.join(", ")
        ))?;
    }
    log(format!(
        "shard {shard} ({}): {} frames ({}), {} done, {} to render",
        args.split,
        mine.len(),
        batch::manifest::ranges(&mine),
        mine.len() - todo.len(),
        todo.len()
    ))?;

    if !todo.is_empty() {
        interrupt::install()?;
        let bars = Bars::new(args.quiet, todo.len());
        let pool = args.frame.thread_pool()?;
        let wanted = args.frame.aov.unwrap_or_default();
        let host = host();
        let started = Instant::now();
        let mut elsewhere = Vec::new();
        pool.install(|| -> anyhow::Result<()> {
            let mut animation: Animation = Animation::new(&desc, &script, args.fps)?;
            for (n, hash) in &todo {
                // Another run (an overlapping shard, a second process) may be rendering this
                // frame, or may have finished it since the list was made.
                let Some(_claim) = manifest.claim(*n)? else {
                    elsewhere.push(*n);
                    bars.skip_frame();
                    continue;
                };
                if !args.force && manifest.frame_state(&job, *n, hash)? == FrameState::Done {
                    elsewhere.push(*n);
                    bars.skip_frame();
                    continue;
                }
                let frame_started = Instant::now();
                let rebuilds = animation.world().world().grid_rebuilds();
                let snapshot = animation.step_to(*n)?;
                let rebuilt = animation.world().world().grid_rebuilds() > rebuilds;
                let settings = args.frame.settings(animation.world().world().render_settings());
                bars.start_frame(*n, tile_count(settings.width, settings.height));
                let on_tile = |done: u32, total: u32| bars.tile(done, total);
                let (film, aovs, mut stats) = render_observed(&snapshot, &settings, wanted, &on_tile);
                (stats.times.script, stats.times.world_update) = animation.last_timing();
                args.frame.check_film(&stats, &format!("frame {n}: "))?;
                let (settings, replay) = meta::pin_rounds(&settings, &stats, &meta::animate_replay(argv, *n));
                let metadata = meta::describe(&inputs, &settings, &tone, &replay);
                let file = job.file_name(*n);
                {
                    let _writing = interrupt::writing();
                    args.frame.write(
                        (&film, aovs.as_ref()),
                        &args.output.join(&file),
                        format,
                        &tone,
                        &metadata,
                    )?;
                    manifest.write_entry(&FrameEntry {
                        frame: *n,
                        file: file.clone(),
                        inputs: hash.clone(),
                        seed: settings.seed,
                        settings: format!("{settings:?}"),
                        render_seconds: stats.times.trace,
                        total_seconds: frame_started.elapsed().as_secs_f64(),
                        rays: FrameEntry::rays_of(&stats),
                        mrays_per_s: stats.mrays_per_s(),
                        host: host.clone(),
                        simd: stats.simd.name().to_owned(),
                        shard: shard.to_string(),
                        files: inputs.files.clone(),
                    })?;
                }
                bars.finish_frame(&format!(
                    "frame {n:>5}  {:>7.3} s  {:>6.2} Mrays/s  {}{}",
                    frame_started.elapsed().as_secs_f64(),
                    stats.mrays_per_s(),
                    args.output.join(&file).display(),
                    if rebuilt { "  (grid rebuilt)" } else { "" }
                ))?;
            }
            Ok(())
        })?;
        bars.clear();
        let seconds = started.elapsed().as_secs_f64();
        let rendered = todo.len() - elsewhere.len();
        log(format!(
            "{rendered} frames in {seconds:.2} s ({:.3} s per frame)",
            seconds / rendered.max(1) as f64
        ))?;
        if !elsewhere.is_empty() {
            log(format!(
                "{} frames rendered by another run on this folder: {}",
                elsewhere.len(),
                batch::manifest::ranges(&elsewhere)
            ))?;
        }
    }
    if let (Some(ffmpeg), Some(video)) = (ffmpeg, &args.video) {
        encode_video(&ffmpeg, args, video)?;
        log(format!("wrote {}", video.display()))?;
    }
    Ok(())
}

/// Progress: frames of the shard with an ETA, and the tiles of the frame being rendered
/// (drawn on standard error only when it is a terminal); per-frame lines go to standard output.
struct Bars {
    quiet: bool,
    frames: ProgressBar,
    tiles: ProgressBar,
    tile_style: ProgressStyle,
    _multi: MultiProgress,
}

impl Bars {
    fn new(quiet: bool, frames: usize) -> Self {
        let multi = MultiProgress::with_draw_target(match quiet {
            true => ProgressDrawTarget::hidden(),
            false => ProgressDrawTarget::stderr(),
        });
        let frame_style = ProgressStyle::with_template(
            "{prefix:>6} [{bar:30}] {pos}/{len} frames, {elapsed} elapsed, eta {eta}",
        )
        .expect("a valid template")
        .progress_chars("=> ");
        let tile_style = ProgressStyle::with_template("{prefix:>6} [{bar:30}] {pos}/{len} tiles")
            .expect("a valid template")
            .progress_chars("=> ");
        let frames = multi.add(ProgressBar::new(frames as u64).with_style(frame_style).with_prefix("shard"));
        // Blank until the first frame starts: without a length it would draw "0/0 tiles".
        let blank = ProgressStyle::with_template("").expect("a valid template");
        let tiles = multi.add(ProgressBar::no_length().with_style(blank));
        Self { quiet, frames, tiles, tile_style, _multi: multi }
    }

    fn start_frame(&self, n: u32, tiles: u32) {
        // Length first and the visible style last: every draw shows the frame's own tile count.
        self.tiles.set_length(u64::from(tiles));
        self.tiles.reset();
        self.tiles.set_prefix(format!("{n}"));
        self.tiles.set_style(self.tile_style.clone());
    }

    fn skip_frame(&self) {
        self.frames.inc(1);
    }

    fn tile(&self, done: u32, total: u32) {
        self.tiles.set_length(u64::from(total));
        self.tiles.set_position(u64::from(done));
    }

    fn finish_frame(&self, line: &str) -> anyhow::Result<()> {
        self.frames.inc(1);
        if !self.quiet {
            // Above the bars, and in the log when standard output is a file.
            self.frames.suspend(|| say(line))?;
        }
        Ok(())
    }

    fn clear(&self) {
        self.tiles.finish_and_clear();
        self.frames.finish_and_clear();
    }
}

/// The ffmpeg executable on PATH, checked before any frame is rendered.
fn find_ffmpeg(video: &Path, format: OutputFormat) -> anyhow::Result<PathBuf> {
    if !matches!(format, OutputFormat::Png8 | OutputFormat::Png16) {
        return Err(bad_input(format!(
            "--video {}: encoding needs PNG frames; drop --format or choose png8 or png16",
            video.display()
        )));
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    let found = std::env::split_paths(&path).map(|dir| dir.join("ffmpeg")).find(|p| p.is_file());
    match found {
        Some(ffmpeg) => Ok(ffmpeg),
        None => bail!(
            "--video {}: ffmpeg is not on PATH, so no video can be made; install ffmpeg, or drop --video \
             and encode the frames later with ffmpeg -framerate FPS -i DIR/frame_%04d.png OUT.mp4",
            video.display()
        ),
    }
}

/// Encodes the frames to H.264 (yuv420p, padded to even dimensions, which players need).
fn encode_video(ffmpeg: &Path, args: &AnimateArgs, video: &Path) -> anyhow::Result<()> {
    let pattern = args.output.join(format!("frame_%0{}d.png", frame_digits(args.frames)));
    let output = Command::new(ffmpeg)
        .args(["-y", "-loglevel", "error", "-framerate"])
        .arg(args.fps.to_string())
        .arg("-start_number")
        .arg(args.frames.first.to_string())
        .arg("-i")
        .arg(&pattern)
        .arg("-frames:v")
        .arg(args.frames.len().to_string())
        .args([
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
            "-c:v",
            "libx264",
            "-pix_fmt",
            "yuv420p",
            "-crf",
            "18",
        ])
        .arg(video)
        .output()
        .with_context(|| format!("cannot run {}", ffmpeg.display()))?;
    if !output.status.success() {
        bail!(
            "ffmpeg failed ({}) encoding {}: {}",
            output.status,
            video.display(),
            String::from_utf8_lossy(&output.stderr).trim()
        );
    }
    Ok(())
}
