//! What an image says about how it was made: the metadata written into every output, and the
//! command-line arguments that reproduce it.

use penumbra::film::{Metadata, ToneMapping};
use penumbra::sample::NoiseSettings;
pub use penumbra::scene::inputs::sha256_hex;
use penumbra::scene::inputs::{InputRole, Inputs};
use penumbra::simd::SimdLevel;
use penumbra::trace::{NoiseStop, RenderSettings, RenderStats};

/// Metadata keys.
pub const VERSION: &str = "penumbra.version";
/// The scene file as given on the command line (or the built-in scene's name).
pub const SCENE: &str = "penumbra.scene";
/// SHA-256 of the scene file's bytes, hex.
pub const SCENE_HASH: &str = "penumbra.scene.sha256";
/// SHA-256 of the script's bytes, or `none`.
pub const SCRIPT_HASH: &str = "penumbra.script.sha256";
/// Render arguments that reproduce the image, as a JSON array of strings; a frame of an
/// animation starts with `animate`.
pub const ARGS: &str = "penumbra.args";
/// The script file as given on the command line.
pub const SCRIPT: &str = "penumbra.script";

/// Every file the image was made from (scene, script, meshes) with its role, the name the user
/// wrote, the absolute path it was read at and its SHA-256, as JSON ([`Inputs::to_json`]).
pub const INPUTS: &str = "penumbra.inputs";

/// The metadata of a render: program version, every input file and its hash, frame, seed,
/// settings, tone mapping and the replay arguments. Nothing time- or host-dependent, so
/// re-rendering gives the same bytes: the settings are recorded with `simd` at `auto`, since
/// the level (`--simd`, or what `auto` found on this CPU) never changes the pixels and an image
/// must be the same file whichever level traced it (the level used is in `--stats` and in an
/// animation's manifest).
pub fn describe(
    inputs: &Inputs,
    settings: &RenderSettings,
    tone: &ToneMapping,
    replay: &[String],
) -> Metadata {
    let mut m = Metadata::default();
    m.set(VERSION, env!("CARGO_PKG_VERSION"));
    if let Some(scene) = inputs.get(InputRole::Scene) {
        m.set(SCENE, scene.name.clone());
        m.set(SCENE_HASH, scene.sha256.clone());
    }
    match inputs.get(InputRole::Script) {
        Some(script) => {
            m.set(SCRIPT, script.name.clone());
            m.set(SCRIPT_HASH, script.sha256.clone());
        }
        None => m.set(SCRIPT_HASH, "none"),
    }
    m.set(INPUTS, inputs.to_json());
    m.set("penumbra.frame", settings.frame.to_string());
    m.set("penumbra.seed", settings.seed.to_string());
    let settings = RenderSettings { simd: SimdLevel::Auto, ..*settings };
    m.set("penumbra.settings", format!("{settings:?}"));
    m.set("penumbra.tonemap", format!("{tone:?}"));
    m.set(ARGS, serde_json::Value::from(replay.to_vec()).to_string());
    m
}

/// What a render records of itself when its time limit stopped it: the rounds it ran, in place
/// of the limit. The image depends on how many rounds fitted, which depends on the machine;
/// the rounds do not, so the settings get `noise.rounds` and no time limit, and the replay
/// arguments lose any `--time-limit` and gain `--noise-rounds R`. Any other render is
/// recorded as it was asked for.
pub fn pin_rounds(
    settings: &RenderSettings,
    stats: &RenderStats,
    replay: &[String],
) -> (RenderSettings, Vec<String>) {
    let (Some(noise), NoiseStop::TimeLimit) = (settings.noise, stats.noise.stopped_by) else {
        return (*settings, replay.to_vec());
    };
    let rounds = stats.noise.rounds;
    let noise = NoiseSettings { time_limit: None, rounds: Some(rounds), ..noise };
    let mut tokens = Vec::with_capacity(replay.len() + 2);
    let mut given = replay.iter();
    while let Some(t) = given.next() {
        match t.as_str() {
            "--time-limit" => {
                given.next();
            }
            t if t.starts_with("--time-limit=") => {}
            t => tokens.push(t.to_owned()),
        }
    }
    // An empty replay is a command line that records none (a sweep's variants).
    if !replay.is_empty() {
        tokens.extend(["--noise-rounds".to_owned(), rounds.to_string()]);
    }
    (RenderSettings { noise: Some(noise), ..*settings }, tokens)
}

/// The arguments that make frame `frame` of an `animate` command line again: `animate`, then
/// everything that determines the image, with `--frames` narrowed to the one frame (without
/// `--threads` and `--simd`, which never change the pixels, so a frame re-renders on any CPU).
pub fn animate_replay(argv: &[String], frame: u32) -> Vec<String> {
    let mut tokens = argv.iter().skip(1).skip_while(|t| t.as_str() != "animate").skip(1);
    let mut kept = vec!["animate".to_owned()];
    let with_value = [
        "-o",
        "--output",
        "--threads",
        "--simd",
        "--video",
        "--frames",
        "--shard",
        "--shard-count",
        "--split",
    ];
    while let Some(t) = tokens.next() {
        let flag = t.split_once('=').map_or(t.as_str(), |(f, _)| f);
        if t == "--quiet" || t == "--force" || (t.starts_with("-o") && t.len() > 2 && !t.starts_with("--")) {
            continue;
        }
        if with_value.contains(&flag) {
            if !t.contains('=') {
                tokens.next();
            }
            continue;
        }
        kept.push(t.clone());
    }
    kept.extend(["--frames".to_owned(), frame.to_string()]);
    kept
}

/// The render arguments of a command line that determine the image: everything after the
/// program name and `render`, without the output path, the statistics file, the thread count,
/// the SIMD level and `--quiet` (which never change the pixels; without `--simd`, `info
/// --rerender` works on a CPU that lacks the level the image was traced with).
pub fn replay_tokens(argv: &[String]) -> Vec<String> {
    let mut tokens = argv.iter().skip(1).peekable();
    if tokens.peek().is_some_and(|t| t.as_str() == "render") {
        tokens.next();
    }
    let mut kept = Vec::new();
    while let Some(t) = tokens.next() {
        let with_value = ["-o", "--output", "--stats", "--threads", "--simd"];
        if t == "--quiet" {
            // Progress display only.
        } else if with_value.contains(&t.as_str()) {
            tokens.next();
        } else if with_value.iter().any(|f| t.starts_with(&format!("{f}=")))
            || (t.starts_with("-o") && !t.starts_with("--"))
        {
            // `--output=x`, `--stats=x`, `--threads=x`, `--simd=x`, `-ox`: the value is attached.
        } else {
            kept.push(t.clone());
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(s: &[&str]) -> Vec<String> {
        s.iter().map(|t| t.to_string()).collect()
    }

    #[test]
    fn a_render_stopped_by_its_time_limit_records_its_rounds_instead() {
        let noise = NoiseSettings { time_limit: Some(2.0), ..NoiseSettings::default() };
        let settings = RenderSettings { noise: Some(noise), ..RenderSettings::default() };
        let mut stats = RenderStats::default();
        (stats.noise.rounds, stats.noise.stopped_by) = (3, NoiseStop::TimeLimit);
        for replay in [
            strings(&["s.ron", "--time-limit", "2", "-w", "64"]),
            strings(&["s.ron", "--time-limit=2", "-w", "64"]),
        ] {
            let (pinned, args) = pin_rounds(&settings, &stats, &replay);
            assert_eq!(args, strings(&["s.ron", "-w", "64", "--noise-rounds", "3"]));
            let noise = pinned.noise.unwrap();
            assert_eq!((noise.time_limit, noise.rounds), (None, Some(3)));
            assert_eq!(RenderSettings { noise: settings.noise, ..pinned }, settings, "nothing else changes");
        }
        // A render the limit did not stop is recorded as asked for.
        stats.noise.stopped_by = NoiseStop::Target;
        let replay = strings(&["s.ron", "--time-limit", "2"]);
        assert_eq!(pin_rounds(&settings, &stats, &replay), (settings, replay));
    }

    #[test]
    fn replay_drops_outputs_threads_and_simd_only() {
        let argv = strings(&[
            "penumbra",
            "render",
            "s.ron",
            "-o",
            "x.png",
            "--width",
            "64",
            "--threads=2",
            "--simd",
            "scalar",
            "--stats",
            "s.json",
            "--aov",
            "depth",
            "--quiet",
        ]);
        assert_eq!(replay_tokens(&argv), strings(&["s.ron", "--width", "64", "--aov", "depth"]));
        assert_eq!(replay_tokens(&strings(&["penumbra"])), Vec::<String>::new());
        assert_eq!(
            replay_tokens(&strings(&["penumbra", "render", "-ox.png", "--output=y.exr", "--simd=avx512"])),
            Vec::<String>::new()
        );
    }

    #[test]
    fn animate_replay_keeps_what_makes_the_frame_and_narrows_the_range() {
        let argv = strings(&[
            "penumbra",
            "animate",
            "s.ron",
            "f.rhai",
            "--frames",
            "0..=119",
            "--fps",
            "24",
            "-o",
            "out",
            "--video",
            "v.mp4",
            "--quiet",
            "--threads=2",
            "--simd",
            "avx2",
            "--width",
            "64",
        ]);
        assert_eq!(
            animate_replay(&argv, 17),
            strings(&["animate", "s.ron", "f.rhai", "--fps", "24", "--width", "64", "--frames", "17"])
        );
        let argv =
            strings(&["penumbra", "animate", "--frames=3..5", "s.ron", "f.rhai", "-ofr", "--simd=scalar"]);
        assert_eq!(animate_replay(&argv, 4), strings(&["animate", "s.ron", "f.rhai", "--frames", "4"]));
    }

    #[test]
    fn sha256_matches_a_known_vector() {
        use penumbra::scene::inputs::sha256_hex;
        assert_eq!(sha256_hex(b"abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    }
}
