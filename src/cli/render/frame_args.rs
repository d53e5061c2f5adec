//! [`FrameArgs`], the options every rendering command shares, and what they do: the size and
//! sampling overrides applied (and checked) on a scene, the `--simd` check, the output format,
//! tone mapping, memory check, thread pool and the fingerprint of what changes the pixels.

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::Args;

use penumbra::film::{
    write_image_with, AovSet, Aovs, Film, Metadata, OutputError, OutputFormat, PngCompression, ToneMapping,
    ToneOperator,
};
use penumbra::sample::Pattern;
use penumbra::scene::{self, AdaptiveSettings, LightDesc, SceneDesc};
use penumbra::simd::SimdLevel;
use penumbra::trace::{RenderSettings, RenderStats};

use super::flags::{
    parse_adaptive, parse_aperture, parse_exposure, parse_noise_samples, parse_operator, parse_pattern,
    parse_samples, parse_shutter, parse_target_error, parse_time_limit, parse_white, Effect, ShutterFlag,
};
use crate::cli::bad_input;
use crate::cli::estimate::{self, MemoryEstimate};

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
    /// Noise-driven adaptive sampling for at most N rounds (N >= 1), and no time limit: what a
    /// render stopped by its time limit records in its replay arguments, so that it renders
    /// again exactly, on any machine.
    #[arg(
        long,
        value_name = "N",
        value_parser = clap::value_parser!(u32).range(1..),
        conflicts_with_all = ["adaptive", "no_adaptive", "time_limit"]
    )]
    noise_rounds: Option<u32>,
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
    /// How hard PNG files are compressed: fast, balanced or high (smaller files, slower
    /// writes; the pixels are the same). EXR output ignores it.
    #[arg(long, value_name = "LEVEL", default_value_t = PngCompression::Fast)]
    pub png_compression: PngCompression,
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

    /// Writes a rendered frame (and its AOVs) to `path` in `format`, PNG data compressed as
    /// `--png-compression` says; every command's frames are written through here.
    pub fn write(
        &self,
        (film, aovs): (&Film, Option<&Aovs>),
        path: &Path,
        format: OutputFormat,
        tone: &ToneMapping,
        meta: &Metadata,
    ) -> Result<Vec<PathBuf>, OutputError> {
        write_image_with(film, aovs, path, (format, self.png_compression), tone, meta)
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
pub(super) fn simd_refusal(level: SimdLevel, has: impl Fn(SimdLevel) -> bool) -> Option<String> {
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
        desc.settings.adaptive = Some(AdaptiveSettings { threshold, max_depth });
        desc.settings.noise = None;
    }
    if args.no_adaptive {
        desc.settings.adaptive = None;
        desc.settings.noise = None;
    }
    if args.target_error.is_some()
        || args.time_limit.is_some()
        || args.noise_samples.is_some()
        || args.noise_rounds.is_some()
    {
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
        if let Some(n) = args.noise_rounds {
            (noise.rounds, noise.time_limit) = (Some(n), None);
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
