//! `penumbra animate` and `penumbra sweep`: the shipped scripts run as shipped, frames and
//! tables are written, script errors are positioned and leave nothing behind, and `--video`
//! either encodes with ffmpeg or says clearly that it cannot before rendering anything.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_penumbra");

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn run(dir: &Path, args: &[&str], path: Option<&Path>) -> Output {
    let mut command = Command::new(BIN);
    command.args(args).current_dir(dir);
    if let Some(path) = path {
        command.env("PATH", path);
    }
    command.output().expect("the binary runs")
}

fn text(out: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
}

/// The visible files of `dir` (not the `.penumbra` manifest folder).
fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|d| d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect())
        .unwrap_or_default();
    names.retain(|n| !n.starts_with('.'));
    names.sort();
    names
}

/// Arguments that render the shipped scene small and fast.
const SMALL: [&str; 4] = ["--width", "48", "--height", "27"];

#[test]
fn the_shipped_fly_through_renders_its_frames() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/flythrough.ron");
    let script = root().join("scripts/flythrough.rhai");
    let mut args = vec!["animate", scene.to_str().unwrap(), script.to_str().unwrap(), "--frames", "0..=3"];
    args.extend(["--fps", "24", "-o", "frames"]);
    args.extend(SMALL);
    let out = run(dir.path(), &args, None);
    assert!(out.status.success(), "{}", text(&out));
    assert_eq!(
        files(&dir.path().join("frames")),
        ["frame_0000.png", "frame_0001.png", "frame_0002.png", "frame_0003.png"]
    );
    let first = image::open(dir.path().join("frames/frame_0000.png")).unwrap().to_rgb8();
    let last = image::open(dir.path().join("frames/frame_0003.png")).unwrap().to_rgb8();
    assert_eq!(first.dimensions(), (48, 27));
    assert_ne!(first, last, "the camera moves between frames");
    assert!(text(&out).contains("4 frames in"), "{}", text(&out));
}

#[test]
fn the_shipped_orbit_runs_and_a_frame_range_not_starting_at_zero_matches() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/flythrough.ron");
    let script = root().join("scripts/orbit.rhai");
    let (scene, script) = (scene.to_str().unwrap(), script.to_str().unwrap());
    let all = [&["animate", scene, script, "--frames", "0..3", "-o", "all", "--quiet"][..], &SMALL].concat();
    let tail = [&["animate", scene, script, "--frames", "2", "-o", "tail", "--quiet"][..], &SMALL].concat();
    for args in [&all, &tail] {
        let out = run(dir.path(), args, None);
        assert!(out.status.success(), "{}", text(&out));
        assert!(out.stdout.is_empty(), "--quiet prints nothing: {}", text(&out));
    }
    let a = std::fs::read(dir.path().join("all/frame_0002.png")).unwrap();
    let b = std::fs::read(dir.path().join("tail/frame_0002.png")).unwrap();
    assert_eq!(a, b, "frame 2 is the same file whether the range starts at 0 or at 2");
}

#[test]
fn the_shipped_sweep_writes_an_image_per_set_and_both_tables() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/flythrough.ron");
    let script = root().join("scripts/sweep_aperture_samples.rhai");
    let args =
        [&["sweep", scene.to_str().unwrap(), script.to_str().unwrap(), "-o", "sweep"][..], &SMALL].concat();
    let out = run(dir.path(), &args, None);
    assert!(out.status.success(), "{}", text(&out));
    let names = files(&dir.path().join("sweep"));
    assert_eq!(names.iter().filter(|n| n.ends_with(".png")).count(), 9, "{names:?}");
    assert!(names.contains(&"004_aperture-0.1_samples-4.png".to_owned()), "{names:?}");

    let csv = std::fs::read_to_string(dir.path().join("sweep/sweep.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 10, "a header and nine sets");
    let column = |name: &str| rows[0].iter().position(|c| *c == name).unwrap_or_else(|| panic!("no {name}"));
    let (aperture, samples, camera, lens) =
        (column("aperture"), column("samples"), column("rays_camera"), column("rays_lens"));
    for row in &rows[1..] {
        let pixels = 48 * 27;
        let lens_samples: u64 = row[samples].parse().unwrap();
        let (camera_rays, lens_rays): (u64, u64) = (row[camera].parse().unwrap(), row[lens].parse().unwrap());
        match row[aperture] {
            // A pinhole traces one camera ray per pixel and no lens rays, whatever the samples.
            "0" => assert_eq!((camera_rays, lens_rays), (pixels, 0), "{row:?}"),
            _ => assert_eq!((camera_rays, lens_rays), (0, pixels * lens_samples), "{row:?}"),
        }
    }
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("sweep/sweep.json")).unwrap()).unwrap();
    let sets = json["sets"].as_array().unwrap();
    assert_eq!(sets.len(), 9);
    assert_eq!(sets[4]["params"], serde_json::json!({ "aperture": 0.1, "samples": 4 }));
    assert!(sets[4]["stats"]["times"]["trace"].as_f64().unwrap() > 0.0);
}

#[test]
fn a_script_error_is_positioned_and_leaves_no_frame_behind() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.rhai"), "fn frame(t) {\n    let b = entity(\"nobody\");\n}\n")
        .unwrap();
    let scene = root().join("scenes/flythrough.ron");
    let args =
        [&["animate", scene.to_str().unwrap(), "bad.rhai", "--frames", "0..=2", "-o", "frames"][..], &SMALL]
            .concat();
    let out = run(dir.path(), &args, None);
    assert!(!out.status.success());
    assert!(text(&out).contains("bad.rhai:2:13: script error: no entity named `nobody`"), "{}", text(&out));
    assert!(files(&dir.path().join("frames")).is_empty(), "{:?}", files(&dir.path().join("frames")));
}

#[test]
fn video_without_ffmpeg_fails_before_rendering_and_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/flythrough.ron");
    let script = root().join("scripts/orbit.rhai");
    let args = [
        &["animate", scene.to_str().unwrap(), script.to_str().unwrap(), "--frames", "0..=1", "-o", "frames"]
            [..],
        &["--video", "out.mp4"],
        &SMALL,
    ]
    .concat();
    let empty = dir.path().join("empty-path");
    std::fs::create_dir(&empty).unwrap();
    let out = run(dir.path(), &args, Some(&empty));
    assert!(!out.status.success());
    assert!(text(&out).contains("ffmpeg is not on PATH"), "{}", text(&out));
    assert!(!dir.path().join("frames").exists(), "nothing was rendered");
}

#[cfg(unix)]
#[test]
fn video_hands_the_frames_to_ffmpeg_in_order() {
    use std::os::unix::fs::PermissionsExt;
    // A stand-in ffmpeg that records its arguments and writes the output file.
    let dir = tempfile::tempdir().unwrap();
    let bin = dir.path().join("bin");
    std::fs::create_dir(&bin).unwrap();
    let fake = bin.join("ffmpeg");
    std::fs::write(&fake, "#!/bin/sh\nprintf '%s\\n' \"$@\" > \"$(dirname \"$0\")/args.txt\"\nfor last; do :; done\necho video > \"$last\"\n").unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    let scene = root().join("scenes/flythrough.ron");
    let script = root().join("scripts/orbit.rhai");
    let args = [
        &["animate", scene.to_str().unwrap(), script.to_str().unwrap(), "--frames", "3..=5", "-o", "frames"]
            [..],
        &["--fps", "12", "--video", "out.mp4"],
        &SMALL,
    ]
    .concat();
    let path = format!("{}:/usr/bin:/bin", bin.display());
    let out = run(dir.path(), &args, Some(Path::new(&path)));
    assert!(out.status.success(), "{}", text(&out));
    assert_eq!(std::fs::read_to_string(dir.path().join("out.mp4")).unwrap(), "video\n");
    let recorded = std::fs::read_to_string(bin.join("args.txt")).unwrap();
    let recorded: Vec<&str> = recorded.lines().collect();
    let after = |flag: &str| recorded[recorded.iter().position(|a| *a == flag).unwrap() + 1];
    assert_eq!(after("-framerate"), "12");
    assert_eq!(after("-start_number"), "3");
    assert_eq!(after("-frames:v"), "3");
    assert_eq!(after("-i"), Path::new("frames").join("frame_%04d.png").to_str().unwrap());
    assert_eq!(*recorded.last().unwrap(), "out.mp4");
}

#[test]
fn info_rerenders_a_frame_of_an_animation_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/flythrough.ron");
    let script = root().join("scripts/orbit.rhai");
    let args = [
        &["animate", scene.to_str().unwrap(), script.to_str().unwrap(), "--frames", "0..=2", "-o", "frames"]
            [..],
        &SMALL,
    ]
    .concat();
    let out = run(dir.path(), &args, None);
    assert!(out.status.success(), "{}", text(&out));
    let out = run(dir.path(), &["info", "frames/frame_0002.png", "--rerender", "again.png"], None);
    assert!(out.status.success(), "{}", text(&out));
    assert!(text(&out).contains("penumbra.script.sha256"), "{}", text(&out));
    let original = std::fs::read(dir.path().join("frames/frame_0002.png")).unwrap();
    let again = std::fs::read(dir.path().join("again.png")).unwrap();
    assert_eq!(original, again);
    assert_eq!(files(dir.path()), ["again.png", "frames"], "the scratch folder is gone");
}

#[test]
fn the_readme_example_script_animates_and_sweeps() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let start = readme.find("```rhai\n").expect("README has a rhai example") + "```rhai\n".len();
    let example = &readme[start..start + readme[start..].find("```").unwrap()];
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("example.rhai"), example).unwrap();
    let scene = root().join("scenes/flythrough.ron");
    let scene = scene.to_str().unwrap();
    let animate =
        [&["animate", scene, "example.rhai", "--frames", "0..=1", "-o", "frames"][..], &SMALL].concat();
    let out = run(dir.path(), &animate, None);
    assert!(out.status.success(), "{}", text(&out));
    let sweep = [&["sweep", scene, "example.rhai", "-o", "sweep", "--quiet"][..], &SMALL].concat();
    let out = run(dir.path(), &sweep, None);
    assert!(out.status.success(), "{}", text(&out));
    assert_eq!(files(&dir.path().join("sweep")).len(), 9 + 2);
}

/// The lines a script printed (standard error lines starting with its file name).
fn printed(out: &Output, file: &str) -> Vec<String> {
    let prefix = format!("{file}: ");
    String::from_utf8_lossy(&out.stderr)
        .lines()
        .filter_map(|l| l.strip_prefix(&prefix).map(str::to_owned))
        .collect()
}

#[test]
fn print_shows_once_per_rendered_frame_with_or_without_quiet() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("talk.rhai"),
        "fn setup() { print(\"setup\"); }\nfn frame(t) { print(`frame ${frame_number()}`); }\n",
    )
    .unwrap();
    let scene = root().join("scenes/flythrough.ron");
    let scene = scene.to_str().unwrap();
    // Frames 0 and 1 run (script only) to reach frame 2; they print nothing.
    for (out_dir, frames, quiet, lines) in [
        ("a", "2..=4", false, vec!["setup", "frame 2", "frame 3", "frame 4"]),
        ("b", "2..=4", true, vec!["setup", "frame 2", "frame 3", "frame 4"]),
        ("c", "1..=9:4", true, vec!["setup", "frame 1", "frame 5", "frame 9"]),
    ] {
        let mut args = vec!["animate", scene, "talk.rhai", "--frames", frames, "-o", out_dir];
        args.extend(SMALL);
        if quiet {
            args.push("--quiet");
        }
        let out = run(dir.path(), &args, None);
        assert!(out.status.success(), "{}", text(&out));
        assert_eq!(printed(&out, "talk.rhai"), lines, "--frames {frames}, quiet {quiet}: {}", text(&out));
    }
    // Top-level code runs before every call: once for setup, then once per rendered frame.
    std::fs::write(dir.path().join("top.rhai"), "print(\"top\");\nfn frame(t) { }\n").unwrap();
    let args =
        [&["animate", scene, "top.rhai", "--frames", "3..=4", "-o", "d", "--quiet"][..], &SMALL].concat();
    let out = run(dir.path(), &args, None);
    assert!(out.status.success(), "{}", text(&out));
    assert_eq!(printed(&out, "top.rhai"), ["top", "top", "top"], "{}", text(&out));
}

#[test]
fn a_frame_step_renders_every_nth_frame_and_status_shards_and_rerender_follow_it() {
    let dir = tempfile::tempdir().unwrap();
    let scene = root().join("scenes/flythrough.ron");
    let script = root().join("scripts/orbit.rhai");
    let (scene, script) = (scene.to_str().unwrap(), script.to_str().unwrap());
    let animate = |frames: &str, out_dir: &str, extra: &[&str]| {
        let args =
            [&["animate", scene, script, "--frames", frames, "-o", out_dir][..], extra, &SMALL].concat();
        run(dir.path(), &args, None)
    };
    let stepped = ["frame_0000.png", "frame_0004.png", "frame_0008.png", "frame_0012.png"];
    let out = animate("0..=12:4", "stepped", &[]);
    assert!(out.status.success(), "{}", text(&out));
    assert_eq!(files(&dir.path().join("stepped")), stepped);
    assert!(text(&out).contains("4 frames in"), "{}", text(&out));

    // Status knows the job is the stepped list: all done, none missing.
    let out = run(dir.path(), &["status", "stepped", "--json"], None);
    assert!(out.status.success(), "{}", text(&out));
    let status: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(status["done"], serde_json::json!([0, 4, 8, 12]), "{status}");
    assert_eq!(status["missing"], serde_json::json!([]), "{status}");

    // Shards split the stepped list, and make the same files as one process.
    for split in ["contiguous", "interleaved"] {
        let mut seen = Vec::new();
        for shard in ["0/2", "1/2"] {
            let out = animate("0..=12:4", split, &["--shard", shard, "--split", split, "--quiet"]);
            assert!(out.status.success(), "{}", text(&out));
            let now = files(&dir.path().join(split));
            assert_eq!(
                now.len(),
                seen.len() + 2,
                "shard {shard} of 2 renders two of the four frames: {now:?}"
            );
            seen = now;
        }
        assert_eq!(seen, stepped, "{split}");
        for name in stepped {
            let single = std::fs::read(dir.path().join("stepped").join(name)).unwrap();
            assert_eq!(std::fs::read(dir.path().join(split).join(name)).unwrap(), single, "{split} {name}");
        }
    }

    // A stepped frame is made again on its own, byte for byte.
    let out = run(dir.path(), &["info", "stepped/frame_0008.png", "--rerender", "again.png"], None);
    assert!(out.status.success(), "{}", text(&out));
    let original = std::fs::read(dir.path().join("stepped/frame_0008.png")).unwrap();
    assert_eq!(std::fs::read(dir.path().join("again.png")).unwrap(), original);

    // A zero step, or a step with a video, is refused before anything is written.
    for (frames, extra, says) in [
        ("0..=12:0", &[][..], "the step after `:` must be a whole number >= 1, got `0`"),
        ("0..=12:4", &["--video", "out.mp4"][..], "--video needs consecutive frames"),
    ] {
        let out = animate(frames, "refused", extra);
        assert_eq!(out.status.code(), Some(2), "{frames} {extra:?}: {}", text(&out));
        assert!(text(&out).contains(says), "{}", text(&out));
        assert!(!dir.path().join("refused").exists());
    }
}
