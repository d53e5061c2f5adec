//! `penumbra info IMAGE [--rerender OUT [--scene S] [--script F]]`: how an image was made, and
//! making it again.
//!
//! A re-render first checks every input the image records (scene, script, each mesh) against
//! the file at its recorded absolute path, so it works from any folder; `--scene`/`--script`
//! point at moved files (meshes are then looked up beside the given scene, by the names the
//! scene uses). A missing or changed input refuses the re-render with exit 2, naming the file.

use std::path::{Path, PathBuf};

use clap::{Args, Parser};

use penumbra::film::{read_metadata, Metadata};
use penumbra::scene::inputs::{check, sha256_hex, InputCheck, InputFile, InputRole, Inputs};
use penumbra::scene::{DEFAULT_SCENE_ORIGIN, DEFAULT_SCENE_SOURCE};

use super::meta;
use super::{animate, bad_input, render};

/// Arguments of `penumbra info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// An image written by `penumbra render`, `animate` or `sweep` (PNG or EXR).
    pub image: PathBuf,
    /// Render the image again, with the same inputs and arguments, to this path. Refused
    /// (exit 2) if any input file (scene, script, mesh) is missing or changed since.
    #[arg(long, value_name = "OUT")]
    pub rerender: Option<PathBuf>,
    /// With `--rerender`: read the scene from this file instead of its recorded place (its
    /// meshes are looked up beside it, by the names the scene gives them).
    #[arg(long, value_name = "SCENE.ron", requires = "rerender")]
    pub scene: Option<PathBuf>,
    /// With `--rerender`: read the script from this file instead of its recorded place.
    #[arg(long, value_name = "SCRIPT.rhai", requires = "rerender")]
    pub script: Option<PathBuf>,
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

    let recorded = recorded_inputs(&args.image, &metadata)?;
    let located = locate(&recorded, args.scene.as_deref(), args.script.as_deref());
    verify(&args.image, &located)?;
    let field = |key: &str| {
        metadata
            .get(key)
            .ok_or_else(|| bad_input(format!("{}: metadata lacks `{key}`", args.image.display())))
    };
    let replay: Vec<String> = serde_json::from_str(field(meta::ARGS)?).map_err(|e| {
        bad_input(format!("{}: `{}` is not a JSON list of strings: {e}", args.image.display(), meta::ARGS))
    })?;
    let place = |role| located.iter().find(|(f, _)| f.role == role);
    let scene = place(InputRole::Scene).ok_or_else(|| bad_input("the image records no scene"))?;
    if replay.first().is_some_and(|a| a == "animate") {
        let script = place(InputRole::Script).ok_or_else(|| bad_input("the frame records no script"))?;
        return rerender_frame(&replay, out, scene, script);
    }
    let argv = ["penumbra", "render"]
        .into_iter()
        .map(String::from)
        .chain(replay.iter().cloned())
        .chain(["-o".into(), out.display().to_string()]);
    let cli = super::Cli::try_parse_from(argv)
        .map_err(|e| bad_input(format!("the recorded arguments no longer parse: {e}")))?;
    let Some(super::Command::Render(mut render_args)) = cli.command else {
        return Err(bad_input("the recorded arguments do not describe a render"));
    };
    match &scene.1 {
        Some(path) => {
            render_args.scene = Some(path.clone());
            render::run_named(&render_args, &replay, Some(&scene.0.name))
        }
        None => render::run(&render_args, &replay),
    }
}

/// The inputs an image records: `penumbra.inputs`, or for images made before it existed the
/// scene and script entries (their names relative to the current folder).
fn recorded_inputs(image: &Path, metadata: &Metadata) -> anyhow::Result<Vec<InputFile>> {
    if let Some(json) = metadata.get(meta::INPUTS) {
        return Inputs::from_json(json).map(|i| i.files).map_err(|e| {
            bad_input(format!("{}: `{}` is not a list of input files: {e}", image.display(), meta::INPUTS))
        });
    }
    let lacks = |key: &str| bad_input(format!("{}: metadata lacks `{key}`", image.display()));
    let scene = metadata.get(meta::SCENE).ok_or_else(|| lacks(meta::SCENE))?;
    let mut files = vec![InputFile {
        role: InputRole::Scene,
        name: scene.to_owned(),
        path: (scene != DEFAULT_SCENE_ORIGIN).then(|| PathBuf::from(scene)),
        sha256: metadata.get(meta::SCENE_HASH).ok_or_else(|| lacks(meta::SCENE_HASH))?.to_owned(),
    }];
    if let (Some(script), Some(hash)) = (metadata.get(meta::SCRIPT), metadata.get(meta::SCRIPT_HASH)) {
        files.push(InputFile {
            role: InputRole::Script,
            name: script.to_owned(),
            path: Some(PathBuf::from(script)),
            sha256: hash.to_owned(),
        });
    }
    Ok(files)
}

/// Where each recorded input is to be read now: the overrides, else the recorded path; meshes
/// beside an overriding scene. `None` for the built-in scene.
fn locate(
    recorded: &[InputFile],
    scene: Option<&Path>,
    script: Option<&Path>,
) -> Vec<(InputFile, Option<PathBuf>)> {
    let scene_dir = scene.map(|s| s.parent().unwrap_or_else(|| Path::new("")).to_path_buf());
    recorded
        .iter()
        .map(|file| {
            let place = match (file.role, scene, script, &scene_dir) {
                (InputRole::Scene, Some(s), _, _) => Some(s.to_path_buf()),
                (InputRole::Script, _, Some(s), _) => Some(s.to_path_buf()),
                (InputRole::Mesh | InputRole::Library | InputRole::Texture, _, _, Some(dir)) => {
                    Some(dir.join(&file.name))
                }
                _ => file.path.clone(),
            };
            (file.clone(), place)
        })
        .collect()
}

/// Refuses (exit 2) when any input is missing or differs from what the image records, naming
/// every such file.
fn verify(image: &Path, located: &[(InputFile, Option<PathBuf>)]) -> anyhow::Result<()> {
    let mut problems = Vec::new();
    for (file, place) in located {
        let state = match place {
            Some(path) => check(file, path),
            None if file.role == InputRole::Scene && file.name == DEFAULT_SCENE_ORIGIN => {
                let sha256 = sha256_hex(DEFAULT_SCENE_SOURCE.as_bytes());
                match sha256 == file.sha256 {
                    true => InputCheck::Unchanged,
                    false => InputCheck::Changed { path: PathBuf::from(DEFAULT_SCENE_ORIGIN), sha256 },
                }
            }
            None => InputCheck::Missing { path: PathBuf::from(&file.name) },
        };
        match state {
            InputCheck::Unchanged => {}
            InputCheck::Missing { path } => problems.push(format!(
                "the {} `{}` is missing (looked for {}){}",
                file.role,
                file.name,
                path.display(),
                match file.role {
                    InputRole::Scene => "; pass --scene PATH where it is now",
                    InputRole::Script => "; pass --script PATH where it is now",
                    InputRole::Mesh | InputRole::Library | InputRole::Texture => {
                        "; pass --scene PATH of a scene with its meshes and textures beside it"
                    }
                }
            )),
            InputCheck::Changed { path, sha256 } => problems.push(format!(
                "the {} `{}` changed since ({}: sha256 {sha256}, recorded {})",
                file.role,
                file.name,
                path.display(),
                file.sha256
            )),
        }
    }
    match problems.is_empty() {
        true => Ok(()),
        false => Err(bad_input(format!("{}: cannot re-render: {}", image.display(), problems.join("; ")))),
    }
}

/// Makes a frame of an animation again: runs the recorded `animate` arguments (one frame) on
/// the located scene and script into a scratch folder beside `out` and moves the frame there.
fn rerender_frame(
    replay: &[String],
    out: &Path,
    scene: &(InputFile, Option<PathBuf>),
    script: &(InputFile, Option<PathBuf>),
) -> anyhow::Result<()> {
    let (Some(scene_path), Some(script_path)) = (&scene.1, &script.1) else {
        return Err(bad_input("the frame records no scene or script file"));
    };
    let parent = out.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    penumbra::film::prepare_output(out)?;
    let scratch = tempfile::Builder::new()
        .prefix(".penumbra-rerender-")
        .tempdir_in(parent)
        .map_err(|e| anyhow::anyhow!("{}: cannot make a scratch folder: {e}", parent.display()))?;
    let argv: Vec<String> = ["penumbra"]
        .into_iter()
        .map(String::from)
        .chain(replay.iter().cloned())
        .chain(["--quiet".into(), "-o".into(), scratch.path().display().to_string()])
        .collect();
    let cli = super::Cli::try_parse_from(&argv)
        .map_err(|e| bad_input(format!("the recorded arguments no longer parse: {e}")))?;
    let Some(super::Command::Animate(mut animate_args)) = cli.command else {
        return Err(bad_input("the recorded arguments do not describe an animation"));
    };
    animate_args.scene = scene_path.clone();
    animate_args.script = script_path.clone();
    animate::run_named(&animate_args, &argv, Some((&scene.0.name, &script.0.name)))?;
    let frame = std::fs::read_dir(scratch.path())?
        .filter_map(Result::ok)
        .map(|e| e.path())
        .find(|p| p.file_name().is_some_and(|n| n.to_string_lossy().starts_with("frame_")))
        .ok_or_else(|| anyhow::anyhow!("the animation wrote no frame"))?;
    std::fs::rename(&frame, out)
        .map_err(|e| anyhow::anyhow!("cannot move the frame to {}: {e}", out.display()))?;
    println!("wrote {}", out.display());
    Ok(())
}
