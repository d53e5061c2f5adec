//! `--simd` on `render`, `animate`, `sweep` and `report`: every level this CPU has gives the
//! same bytes as the single-ray reference (`scalar`) and the same rays; the level used is in
//! the statistics, the manifest and the report; an unknown level, or one this CPU lacks, is
//! refused before anything is written; and a resumed animation skips its finished frames
//! whatever level either run used (as it would on another CPU).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use penumbra::simd::SimdLevel;

const BIN: &str = env!("CARGO_BIN_EXE_penumbra");

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("JOB_COMPLETION_INDEX")
        .output()
        .expect("the binary runs")
}

fn text(out: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
}

fn ok(dir: &Path, args: &[&str]) -> Output {
    let out = run(dir, args);
    assert!(out.status.success(), "{args:?}: {}", text(&out));
    out
}

fn json(path: &Path) -> serde_json::Value {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_slice(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn available() -> Vec<SimdLevel> {
    SimdLevel::ALL.into_iter().filter(|l| l.available()).collect()
}

/// The level the statistics must report for `--simd level`: `auto` is what this CPU has best.
fn used(level: SimdLevel) -> &'static str {
    match level {
        SimdLevel::Auto => SimdLevel::detect().name(),
        other => other.name(),
    }
}

/// The fly-through scene and script in `dir`, and a two-set sweep script.
fn stage(dir: &Path) {
    std::fs::copy(root().join("scenes/flythrough.ron"), dir.join("scene.ron")).unwrap();
    std::fs::copy(root().join("scripts/flythrough.rhai"), dir.join("fly.rhai")).unwrap();
    std::fs::write(dir.join("sweep.rhai"), "fn sweep() {\n    product(#{ aperture: [0.0, 0.1] })\n}\n")
        .unwrap();
    std::fs::write(dir.join("report.ron"), "Sweep(\n    axes: [Aa(samples: [1, 2])],\n    reference: (aa: 4, lens: 2, area_light: 4, glossy: 4),\n)\n")
        .unwrap();
}

/// One command of each kind that takes `--simd`, writing only under `out` (or `out.png`).
fn commands() -> Vec<(&'static str, Vec<&'static str>)> {
    let small = ["--width", "16", "--height", "9"];
    vec![
        ("render", [&["render", "scene.ron", "-o", "out.png", "--stats", "out.json"][..], &small].concat()),
        (
            "animate",
            [&["animate", "scene.ron", "fly.rhai", "--frames", "0..=1", "-o", "out"][..], &small].concat(),
        ),
        ("sweep", [&["sweep", "scene.ron", "sweep.rhai", "-o", "out"][..], &small].concat()),
        (
            "report",
            [&["report", "scene.ron", "--sweep", "report.ron", "--runs", "1", "-o", "out"][..], &small]
                .concat(),
        ),
    ]
}

/// The files in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Renders with `args` at every level this CPU has (`--threads 2`, so tiles are shared
/// out as in real use) and checks that each file equals the scalar one byte for byte, that the
/// rays by kind agree, and that the statistics name the level that traced.
fn same_bytes_at_every_level(dir: &Path, name: &str, extension: &str, args: &[&str]) {
    let mut reference: Option<(Vec<u8>, serde_json::Value)> = None;
    // Scalar first: it is the reference every other level must equal.
    let mut levels = available();
    levels.sort_by_key(|&l| l != SimdLevel::Scalar);
    for level in levels {
        let image = format!("{name}-{level}.{extension}");
        let stats = format!("{name}-{level}.json");
        let mut all = vec!["render"];
        all.extend_from_slice(args);
        all.extend(["--threads", "2", "--simd", level.name(), "-o", &image, "--stats", &stats]);
        let out = ok(dir, &all);
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            stdout.contains(&format!("2 threads, simd {},", used(level))),
            "{name} --simd {level}: {stdout}"
        );
        let json = json(&dir.join(&stats));
        assert_eq!(json["simd"], used(level), "{name} --simd {level}: the level that traced");
        let bytes = read(&dir.join(&image));
        match &reference {
            None => reference = Some((bytes, json)),
            Some((want, scalar)) => {
                assert!(bytes == *want, "{name}: --simd {level} gives other bytes than --simd scalar");
                assert_eq!(
                    json["rays"], scalar["rays"],
                    "{name}: --simd {level} traces other rays than scalar"
                );
            }
        }
    }
}

#[test]
fn every_level_this_cpu_has_renders_the_same_bytes_as_scalar() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    // Odd sizes, so that rows and tiles end in partly filled packets.
    same_bytes_at_every_level(dir, "default", "png", &["--width", "37"]);
    // Linear float EXR: what PNG quantisation would hide.
    same_bytes_at_every_level(dir, "default", "exr", &["--width", "37", "--format", "exr-float"]);
    // Every effect (lens, glossy, area light, tent filter), and adaptive supersampling.
    let showcase = root().join("scenes/showcase.ron");
    let showcase = showcase.to_str().unwrap();
    let few =
        ["--samples", "aa=2", "--samples", "lens=2", "--samples", "glossy=2", "--samples", "area_light=2"];
    same_bytes_at_every_level(dir, "showcase", "png", &[&[showcase, "--width", "29"][..], &few].concat());
    let adaptive = [&[showcase, "--width", "23", "--adaptive", "0.05:2"][..], &few].concat();
    same_bytes_at_every_level(dir, "adaptive", "exr", &[&adaptive[..], &["--format", "exr-float"]].concat());
}

#[test]
fn the_stats_name_scalar_for_scalar_and_what_auto_found_for_auto() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(dir, &["render", "--width", "16", "-o", "s.png", "--simd", "scalar", "--stats", "s.json"]);
    ok(dir, &["render", "--width", "16", "-o", "a.png", "--stats", "a.json"]);
    assert_eq!(json(&dir.join("s.json"))["simd"], "scalar");
    let auto = json(&dir.join("a.json"))["simd"].as_str().unwrap().to_owned();
    assert!(auto != "auto" && auto != "scalar", "auto traces packets at a concrete level, got {auto}");
    assert_eq!(auto, SimdLevel::detect().name(), "auto is the best level this CPU has");
    assert!(read(&dir.join("s.png")) == read(&dir.join("a.png")), "--simd scalar and auto differ");
}

#[test]
fn an_unknown_level_is_refused_by_every_command_with_the_levels_listed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    let before = listing(dir);
    for (command, args) in commands() {
        let out = run(dir, &[&args[..], &["--simd", "sse9"]].concat());
        let message = text(&out);
        assert_eq!(out.status.code(), Some(2), "{command}: {message}");
        for part in ["--simd", "sse9", "auto, scalar, baseline, avx2, avx512"] {
            assert!(message.contains(part), "{command}: no `{part}` in: {message}");
        }
        assert_eq!(listing(dir), before, "{command} wrote something");
    }
}

#[test]
fn a_level_this_cpu_lacks_is_refused_by_every_command_before_anything_is_written() {
    let lacking: Vec<SimdLevel> = SimdLevel::ALL.into_iter().filter(|l| !l.available()).collect();
    if lacking.is_empty() {
        // `every_level_this_cpu_has_renders_the_same_bytes_as_scalar` covers every level here.
        eprintln!("this CPU has every SIMD level; nothing to refuse");
        return;
    }
    let have: Vec<&str> = available().iter().map(|l| l.name()).collect();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    let before = listing(dir);
    for level in lacking {
        for (command, args) in commands() {
            let out = run(dir, &[&args[..], &["--simd", level.name()]].concat());
            let message = String::from_utf8_lossy(&out.stderr).into_owned();
            assert_eq!(out.status.code(), Some(2), "{command} --simd {level}: {message}");
            let wanted = [
                format!("--simd {level}: this CPU does not support"),
                format!("available: {}", have.join(", ")),
            ];
            for part in wanted {
                assert!(message.contains(&part), "{command}: no `{part}` in: {message}");
            }
            assert_eq!(message.lines().count(), 1, "{command}: one line: {message}");
            assert_eq!(listing(dir), before, "{command} --simd {level} wrote something");
        }
    }
}

#[test]
fn a_resumed_animation_skips_finished_frames_whatever_the_level() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    let animate = |out: &str, level: &str| {
        let args = ["animate", "scene.ron", "fly.rhai", "--frames", "0..=2", "-o", out, "--width", "48"];
        ok(dir, &[&args[..], &["--height", "27", "--simd", level]].concat())
    };
    animate("frames", "scalar");
    let entry = json(&dir.join("frames/.penumbra/frame_0001.json"));
    assert_eq!(entry["simd"], "scalar", "the manifest records the level that traced");

    // Another level, as on a CPU with other instruction sets: every frame is already done.
    for level in available() {
        let log = String::from_utf8_lossy(&animate("frames", level.name()).stdout).into_owned();
        assert!(log.contains("3 done, 0 to render"), "--simd {level} after scalar: {log}");
    }
    let status = json_of(&ok(dir, &["status", "frames", "--json"]));
    assert_eq!(status["done"], serde_json::json!([0, 1, 2]));

    // The same frames, byte for byte, from a run at the best level.
    animate("auto", "auto");
    assert_eq!(json(&dir.join("auto/.penumbra/frame_0001.json"))["simd"], used(SimdLevel::Auto));
    for n in 0..=2 {
        let file = format!("frame_{n:04}.png");
        assert!(
            read(&dir.join("frames").join(&file)) == read(&dir.join("auto").join(&file)),
            "{file} differs"
        );
    }
}

fn json_of(out: &Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{e}: {}", text(out)))
}

#[test]
fn sweep_and_report_trace_at_the_level_asked_and_record_it() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    for level in [SimdLevel::Scalar, SimdLevel::Auto] {
        let out = format!("sweep-{level}");
        ok(
            dir,
            &[
                "sweep",
                "scene.ron",
                "sweep.rhai",
                "-o",
                &out,
                "--width",
                "32",
                "--simd",
                level.name(),
                "--quiet",
            ],
        );
        let sets = json(&dir.join(&out).join("sweep.json"))["sets"].as_array().unwrap().clone();
        assert_eq!(sets.len(), 2);
        for set in &sets {
            assert_eq!(set["stats"]["simd"], used(level), "sweep --simd {level}");
        }

        let out = format!("report-{level}");
        let args =
            ["report", "scene.ron", "--sweep", "report.ron", "--runs", "1", "--width", "16", "--quiet"];
        ok(dir, &[&args[..], &["--simd", level.name(), "-o", &out]].concat());
        assert_eq!(json(&dir.join(&out).join("results.json"))["simd"], used(level), "report --simd {level}");
        let page = std::fs::read_to_string(dir.join(&out).join("index.html")).unwrap();
        assert!(page.contains(&format!("<dt>SIMD</dt><dd>{}</dd>", used(level))), "report --simd {level}");
    }
    for file in listing(&dir.join("sweep-scalar")).iter().filter(|f| f.ends_with(".png")) {
        let (a, b) = (dir.join("sweep-scalar").join(file), dir.join("sweep-auto").join(file));
        assert!(read(&a) == read(&b), "sweep image {file} differs between scalar and auto");
    }
}
