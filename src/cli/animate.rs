//! `penumbra animate SCENE SCRIPT --frames A..=B --fps N -o DIR [--video OUT.mp4]`: a frame
//! sequence driven by a Rhai script, optionally encoded to a video with ffmpeg.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use anyhow::{bail, Context};
use clap::Args;

use penumbra::film::{write_image, OutputFormat};
use penumbra::scene::{self, SceneDesc};
use penumbra::script::{Animation, FrameRange, Limits, Script};
use penumbra::trace::render_with_aovs;

use super::meta;
use super::render::{say, FrameArgs};

/// Arguments of `penumbra animate`.
#[derive(Args, Debug)]
pub struct AnimateArgs {
    /// Scene file (RON).
    pub scene: PathBuf,
    /// Rhai script defining `fn frame(t)` (and optionally `fn setup()`).
    pub script: PathBuf,
    /// Frames to render: `A..=B`, `A..B` or a single frame `A`. Frame n is at time n / fps.
    #[arg(long, value_name = "RANGE")]
    pub frames: FrameRange,
    /// Frames per second (the script's `t` advances by 1/fps per frame).
    #[arg(long, default_value_t = 24.0, value_parser = parse_fps)]
    pub fps: f64,
    /// Folder for the frames, `frame_0000.png` and so on (created if missing).
    #[arg(short, long, default_value = "frames")]
    pub output: PathBuf,
    /// Also encode the frames to this video with ffmpeg (which must be on PATH).
    #[arg(long, value_name = "OUT.mp4")]
    pub video: Option<PathBuf>,
    /// Print nothing but errors.
    #[arg(long)]
    pub quiet: bool,
    /// How to render and encode each frame.
    #[command(flatten)]
    pub frame: FrameArgs,
}

fn parse_fps(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(f) if f.is_finite() && f > 0.0 && f <= 1000.0 => Ok(f),
        _ => Err(format!("fps must be a number in (0, 1000], got `{s}`")),
    }
}

/// The file of frame `n` in `dir`: `frame_0042.png`, with at least four digits and as many
/// as the range's last frame needs.
pub fn frame_path(dir: &Path, frames: FrameRange, n: u32, extension: &str) -> PathBuf {
    let digits = frame_digits(frames);
    dir.join(format!("frame_{n:0digits$}.{extension}"))
}

fn frame_digits(frames: FrameRange) -> usize {
    frames.last.to_string().len().max(4)
}

fn extension(format: OutputFormat) -> &'static str {
    match format {
        OutputFormat::Png8 | OutputFormat::Png16 => "png",
        OutputFormat::ExrHalf | OutputFormat::ExrFloat => "exr",
    }
}

/// Renders the frames as `args` say; `argv` is the whole command line (for frame metadata).
pub fn run(args: &AnimateArgs, argv: &[String]) -> anyhow::Result<()> {
    let mut desc: SceneDesc = scene::load_scene(&args.scene)?;
    let scene_source =
        std::fs::read(&args.scene).with_context(|| format!("{}: cannot read scene", args.scene.display()))?;
    args.frame.apply(&mut desc);
    let script = Script::load(&args.script, Limits::default())?;
    let format = args.frame.format.unwrap_or(OutputFormat::Png8);
    let tone = args.frame.tone_mapping(&desc);
    let ffmpeg = match &args.video {
        Some(video) => Some(find_ffmpeg(video, format)?),
        None => None,
    };
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("{}: cannot create the frames folder", args.output.display()))?;

    let pool = args.frame.thread_pool()?;
    let wanted = args.frame.aov.unwrap_or_default();
    let origin = args.scene.display().to_string();
    let started = Instant::now();
    pool.install(|| -> anyhow::Result<()> {
        let mut animation: Animation = Animation::new(&desc, &script, args.fps)?;
        for n in args.frames.iter() {
            let frame_started = Instant::now();
            let rebuilds = animation.world().world().grid_rebuilds();
            let snapshot = animation.step_to(n)?;
            let rebuilt = animation.world().world().grid_rebuilds() > rebuilds;
            let settings = animation.world().world().render_settings();
            let (film, aovs, mut stats) = render_with_aovs(&snapshot, &settings, wanted);
            (stats.times.script, stats.times.world_update) = animation.last_timing();
            let replay = meta::animate_replay(argv, n);
            let mut metadata = meta::describe(&origin, &scene_source, &settings, &tone, &replay);
            meta::add_script(&mut metadata, &args.script, script.source().as_bytes());
            let path = frame_path(&args.output, args.frames, n, extension(format));
            write_image(&film, aovs.as_ref(), &path, format, &tone, &metadata)?;
            if !args.quiet {
                say(&format!(
                    "frame {n:>5}  {:>7.3} s  {:>6.2} Mrays/s  {}{}",
                    frame_started.elapsed().as_secs_f64(),
                    stats.mrays_per_s(),
                    path.display(),
                    if rebuilt { "  (grid rebuilt)" } else { "" }
                ))?;
            }
        }
        Ok(())
    })?;
    if !args.quiet {
        let seconds = started.elapsed().as_secs_f64();
        say(&format!(
            "{} frames in {seconds:.2} s ({:.3} s per frame)",
            args.frames.len(),
            seconds / args.frames.len() as f64
        ))?;
    }
    if let (Some(ffmpeg), Some(video)) = (ffmpeg, &args.video) {
        encode_video(&ffmpeg, args, video)?;
        if !args.quiet {
            say(&format!("wrote {}", video.display()))?;
        }
    }
    Ok(())
}

/// The ffmpeg executable on PATH, checked before any frame is rendered.
fn find_ffmpeg(video: &Path, format: OutputFormat) -> anyhow::Result<PathBuf> {
    if !matches!(format, OutputFormat::Png8 | OutputFormat::Png16) {
        bail!(
            "--video {}: encoding needs PNG frames; drop --format or choose png8 or png16",
            video.display()
        );
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
