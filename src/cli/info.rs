//! `penumbra info IMAGE [--rerender OUT]`: how an image was made, and making it again.

use std::path::{Path, PathBuf};

use anyhow::Context;
use clap::{Args, Parser};

use penumbra::film::{read_metadata, Metadata};
use penumbra::scene::{DEFAULT_SCENE_ORIGIN, DEFAULT_SCENE_SOURCE};

use super::meta::{self, sha256_hex};
use super::{animate, bad_input, render};

/// Arguments of `penumbra info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// An image written by `penumbra render` (PNG or EXR).
    pub image: PathBuf,
    /// Render the image again, with the same scene and arguments, to this path. Fails if the
    /// scene file changed since (its hash differs).
    #[arg(long, value_name = "OUT")]
    pub rerender: Option<PathBuf>,
}

/// Prints the metadata of an image and, with `--rerender`, renders it again.
pub fn run(args: &InfoArgs) -> anyhow::Result<()> {
    let metadata = read_metadata(&args.image)?;
    if metadata.get(meta::VERSION).is_none() {
        return Err(bad_input(format!(
            "{}: no Penumbra metadata (not written by `penumbra render`?)",
            args.image.display()
        )));
    }
    let width = metadata.entries.iter().map(|(k, _)| k.len()).max().unwrap_or(0);
    for (key, value) in &metadata.entries {
        println!("{key:<width$}  {value}");
    }
    let Some(out) = &args.rerender else { return Ok(()) };

    let field = |key: &str| {
        metadata
            .get(key)
            .ok_or_else(|| bad_input(format!("{}: metadata lacks `{key}`", args.image.display())))
    };
    let scene = field(meta::SCENE)?;
    let source = if scene == DEFAULT_SCENE_ORIGIN {
        DEFAULT_SCENE_SOURCE.as_bytes().to_vec()
    } else {
        std::fs::read(Path::new(scene))
            .with_context(|| format!("{scene}: cannot read the scene the image was made from"))?
    };
    let recorded = field(meta::SCENE_HASH)?;
    let current = sha256_hex(&source);
    if current != recorded {
        return Err(bad_input(format!(
            "{scene}: the scene changed since {} was made (sha256 {current}, recorded {recorded})",
            args.image.display()
        )));
    }
    let replay: Vec<String> = serde_json::from_str(field(meta::ARGS)?).map_err(|e| {
        bad_input(format!("{}: `{}` is not a JSON list of strings: {e}", args.image.display(), meta::ARGS))
    })?;
    if replay.first().is_some_and(|a| a == "animate") {
        return rerender_frame(&args.image, &metadata, &replay, out);
    }
    let argv = ["penumbra", "render"]
        .into_iter()
        .map(String::from)
        .chain(replay.iter().cloned())
        .chain(["-o".into(), out.display().to_string()]);
    let cli = super::Cli::try_parse_from(argv)
        .map_err(|e| bad_input(format!("the recorded arguments no longer parse: {e}")))?;
    match cli.command {
        Some(super::Command::Render(render_args)) => render::run(&render_args, &replay),
        _ => Err(bad_input("the recorded arguments do not describe a render")),
    }
}

/// Makes a frame of an animation again: checks the script is unchanged, runs the recorded
/// `animate` arguments (one frame) into a scratch folder beside `out` and moves the frame there.
fn rerender_frame(image: &Path, metadata: &Metadata, replay: &[String], out: &Path) -> anyhow::Result<()> {
    let field = |key: &str| {
        metadata.get(key).ok_or_else(|| bad_input(format!("{}: metadata lacks `{key}`", image.display())))
    };
    let script = field(meta::SCRIPT)?;
    let source = std::fs::read(script)
        .with_context(|| format!("{script}: cannot read the script the frame was made with"))?;
    let (recorded, current) = (field(meta::SCRIPT_HASH)?, sha256_hex(&source));
    if current != recorded {
        return Err(bad_input(format!(
            "{script}: the script changed since {} was made (sha256 {current}, recorded {recorded})",
            image.display()
        )));
    }
    let parent = out.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let scratch = tempfile::Builder::new()
        .prefix(".penumbra-rerender-")
        .tempdir_in(parent)
        .with_context(|| format!("{}: cannot make a scratch folder", parent.display()))?;
    let argv: Vec<String> = ["penumbra"]
        .into_iter()
        .map(String::from)
        .chain(replay.iter().cloned())
        .chain(["--quiet".into(), "-o".into(), scratch.path().display().to_string()])
        .collect();
    let cli = super::Cli::try_parse_from(&argv)
        .map_err(|e| bad_input(format!("the recorded arguments no longer parse: {e}")))?;
    let Some(super::Command::Animate(animate_args)) = cli.command else {
        return Err(bad_input("the recorded arguments do not describe an animation"));
    };
    animate::run(&animate_args, &argv)?;
    let frame = std::fs::read_dir(scratch.path())?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| p.file_name().is_some_and(|n| n.to_string_lossy().starts_with("frame_")))
        .context("the animation wrote no frame")?;
    std::fs::rename(&frame, out).with_context(|| format!("cannot move the frame to {}", out.display()))?;
    println!("wrote {}", out.display());
    Ok(())
}
