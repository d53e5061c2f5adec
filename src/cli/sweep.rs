//! `penumbra sweep SCENE SCRIPT -o DIR`: one image per parameter set the script's
//! `fn sweep()` declares, plus `sweep.csv` and `sweep.json` with each set's render time and
//! ray counts.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use clap::Args;

use penumbra::film::{prepare_output, write_atomically, OutputFormat};
use penumbra::scene::inputs::Inputs;
use penumbra::scene::{self, SceneDesc};
use penumbra::script::sweep::{self, file_stem, params_of, SweepRecord};
use penumbra::script::{Limits, Script, ScriptedWorld};
use penumbra::trace::render_with_aovs;

use super::render::{absolute, say, warn_ray_trees, FrameArgs};
use super::{bad_input, meta};

/// Arguments of `penumbra sweep`.
#[derive(Args, Debug)]
pub struct SweepArgs {
    /// Scene file (RON).
    pub scene: PathBuf,
    /// Rhai script defining `fn sweep()` (the parameter sets) and optionally `fn apply(p)`
    /// and `fn setup()`.
    pub script: PathBuf,
    /// Folder for the images and the tables (created if missing).
    #[arg(short, long, default_value = "sweep")]
    pub output: PathBuf,
    /// Print nothing but errors.
    #[arg(long)]
    pub quiet: bool,
    /// How to render and encode each image.
    #[command(flatten)]
    pub frame: FrameArgs,
}

/// Runs the sweep as `args` say.
pub fn run(args: &SweepArgs) -> anyhow::Result<()> {
    args.frame.check_simd()?;
    let mut desc: SceneDesc = scene::load_scene(&args.scene)?;
    let scene_source =
        std::fs::read(&args.scene).with_context(|| format!("{}: cannot read scene", args.scene.display()))?;
    let script = Script::load(&args.script, Limits::default())?;
    script.require("sweep", 0, "returns the parameter sets, e.g. product(#{ aperture: [0.0, 0.1] })")?;
    let origin = args.scene.display().to_string();
    let inputs = Inputs::of_scene(&origin, &absolute(&args.scene), &scene_source, &desc)
        .map_err(|e| bad_input(e.to_string()))?
        .with_script(&args.script.display().to_string(), &absolute(&args.script), script.source().as_bytes());
    args.frame.apply_checked(&mut desc, &scene_source, &origin)?;
    warn_ray_trees(&desc);
    let format = args.frame.format.unwrap_or(OutputFormat::Png8);
    args.frame.check_memory(&desc, format)?;
    let extension = match format {
        OutputFormat::Png8 | OutputFormat::Png16 => "png",
        OutputFormat::ExrHalf | OutputFormat::ExrFloat => "exr",
    };
    let tone = args.frame.tone_mapping(&desc);
    let wanted = args.frame.aov.unwrap_or_default();
    std::fs::create_dir_all(&args.output)
        .with_context(|| format!("{}: cannot create the sweep folder", args.output.display()))?;
    prepare_output(&args.output.join("sweep.csv"))?;

    let pool = args.frame.thread_pool()?;
    let records = pool.install(|| -> anyhow::Result<Vec<SweepRecord>> {
        let mut declaring: ScriptedWorld = ScriptedWorld::from_scene(&desc, &script);
        declaring.setup()?;
        let sets = declaring.sweep_sets()?;
        let mut records = Vec::with_capacity(sets.len());
        for (index, set) in sets.iter().enumerate() {
            let started = Instant::now();
            // Every set starts from the scene as loaded, so sets are independent of order.
            let mut world: ScriptedWorld = ScriptedWorld::from_scene(&desc, &script);
            world.setup()?;
            world.apply(set, index)?;
            let script_seconds = started.elapsed().as_secs_f64();
            let snapshot = world.update();
            let settings = args.frame.settings(world.world().render_settings());
            let clock = world.world().stage_clock();
            let (film, aovs, mut stats) = render_with_aovs(&snapshot, &settings, wanted);
            stats.times.script = script_seconds;
            stats.times.world_update = clock.bounds;
            stats.times.grid_build = clock.grid_build;
            stats.times.snapshot = clock.snapshot;
            args.frame.check_film(&stats, &format!("parameter set {index}: "))?;

            let params = params_of(set);
            let file = format!("{}.{extension}", file_stem(index, &params));
            let (settings, _) = meta::pin_rounds(&settings, &stats, &[]);
            let mut metadata = meta::describe(&inputs, &settings, &tone, &[]);
            let values: serde_json::Map<String, serde_json::Value> =
                params.iter().map(|(k, v)| (k.clone(), v.json())).collect();
            metadata.set("penumbra.sweep.params", serde_json::Value::Object(values).to_string());
            let written = Instant::now();
            args.frame.write((&film, aovs.as_ref()), &args.output.join(&file), format, &tone, &metadata)?;
            stats.times.write = written.elapsed().as_secs_f64();
            let record =
                SweepRecord { index, file, params, stats, total_seconds: started.elapsed().as_secs_f64() };
            if !args.quiet {
                let params: Vec<String> =
                    record.params.iter().map(|(k, v)| format!("{k}={}", v.csv())).collect();
                say(&format!(
                    "set {index:>3}  {:>7.3} s  {:>10} rays  {}  {}",
                    record.total_seconds,
                    record.stats.rays.total(),
                    params.join(" "),
                    record.file
                ))?;
            }
            records.push(record);
        }
        Ok(records)
    })?;

    let csv_path = args.output.join("sweep.csv");
    write_atomically(&csv_path, sweep::csv(&records).as_bytes())?;
    let json = sweep::json(&records, &origin, &args.script.display().to_string());
    let json_path = args.output.join("sweep.json");
    write_atomically(&json_path, &serde_json::to_vec_pretty(&json).context("cannot encode sweep.json")?)?;
    if !args.quiet {
        say(&format!("{} sets; wrote {} and {}", records.len(), csv_path.display(), json_path.display()))?;
    }
    Ok(())
}
