//! `penumbra info IMAGE [--rerender OUT]`: how an image was made, and making it again.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use clap::{Args, Parser};

use penumbra::film::read_metadata;
use penumbra::scene::{DEFAULT_SCENE_ORIGIN, DEFAULT_SCENE_SOURCE};

use super::meta::{self, sha256_hex};
use super::render;

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
        bail!("{}: no Penumbra metadata (not written by `penumbra render`?)", args.image.display());
    }
    let width = metadata.entries.iter().map(|(k, _)| k.len()).max().unwrap_or(0);
    for (key, value) in &metadata.entries {
        println!("{key:<width$}  {value}");
    }
    let Some(out) = &args.rerender else { return Ok(()) };

    let field = |key: &str| {
        metadata.get(key).with_context(|| format!("{}: metadata lacks `{key}`", args.image.display()))
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
        bail!(
            "{scene}: the scene changed since {} was made (sha256 {current}, recorded {recorded})",
            args.image.display()
        );
    }
    let replay: Vec<String> = serde_json::from_str(field(meta::ARGS)?).with_context(|| {
        format!("{}: `{}` is not a JSON list of strings", args.image.display(), meta::ARGS)
    })?;
    let argv = ["penumbra", "render"]
        .into_iter()
        .map(String::from)
        .chain(replay.iter().cloned())
        .chain(["-o".into(), out.display().to_string()]);
    let cli = super::Cli::try_parse_from(argv).context("the recorded arguments no longer parse")?;
    match cli.command {
        Some(super::Command::Render(render_args)) => render::run(&render_args, &replay),
        _ => bail!("the recorded arguments do not describe a render"),
    }
}
