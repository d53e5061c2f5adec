//! Batch frame sequences: shards cover a range exactly once with frames identical to a
//! single-process render, kills at any moment leave no partial frame and resume to the same
//! bytes, changed inputs are re-rendered and unchanged frames skipped.

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use penumbra::batch::{Shard, Split};
use penumbra::script::FrameRange;

const BIN: &str = env!("CARGO_BIN_EXE_penumbra");

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A copy of the shipped fly-through scene and script in `dir` (so tests can change them).
fn stage(dir: &Path) {
    std::fs::copy(root().join("scenes/flythrough.ron"), dir.join("scene.ron")).unwrap();
    std::fs::copy(root().join("scripts/flythrough.rhai"), dir.join("fly.rhai")).unwrap();
}

fn animate(dir: &Path, out: &str, frames: &str, extra: &[&str]) -> Command {
    let mut c = Command::new(BIN);
    c.current_dir(dir)
        .args(["animate", "scene.ron", "fly.rhai", "--frames", frames, "-o", out, "--quiet"])
        .args(if extra.contains(&"--width") { &[][..] } else { &["--width", "64", "--height", "36"][..] })
        .args(extra)
        .env_remove("SLURM_ARRAY_TASK_ID")
        .env_remove("JOB_COMPLETION_INDEX");
    c
}

fn ok(mut c: Command) -> Output {
    let out = c.output().expect("the binary runs");
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn frame_files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|d| d.filter_map(Result::ok).map(|e| e.file_name().to_string_lossy().into_owned()).collect())
        .unwrap_or_default();
    names.retain(|n| n.starts_with("frame_"));
    names.sort();
    names
}

fn same_files(a: &Path, b: &Path) {
    let (fa, fb) = (frame_files(a), frame_files(b));
    assert_eq!(fa, fb);
    for f in &fa {
        assert!(std::fs::read(a.join(f)).unwrap() == std::fs::read(b.join(f)).unwrap(), "{f} differs");
    }
}

#[test]
fn shards_cover_the_range_once_and_equal_a_single_process_render() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    ok(animate(dir, "single", "2..=9", &[]));
    assert_eq!(frame_files(&dir.join("single")).len(), 8);
    for n in [1u32, 2, 3, 7] {
        for split in ["contiguous", "interleaved"] {
            let out = format!("{split}{n}");
            let mut seen = Vec::new();
            for i in 0..n {
                let shard = format!("{i}/{n}");
                ok(animate(dir, &out, "2..=9", &["--shard", &shard, "--split", split]));
                seen.extend(
                    Shard::new(i, n).unwrap().frames(FrameRange::new(2, 9), split.parse::<Split>().unwrap()),
                );
            }
            seen.sort_unstable();
            assert_eq!(seen, (2..=9).collect::<Vec<_>>(), "{n} {split} shards cover 2..=9 once");
            same_files(&dir.join("single"), &dir.join(&out));
        }
    }
}

#[test]
fn the_scheduler_environment_picks_the_shard() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    for (i, name) in [(0, "a"), (1, "b")] {
        let mut c = animate(dir, "slurm", "0..=3", &[]);
        c.env("SLURM_ARRAY_TASK_ID", (i + 10).to_string())
            .env("SLURM_ARRAY_TASK_MIN", "10")
            .env("SLURM_ARRAY_TASK_MAX", "11");
        ok(c);
        let mut c = animate(dir, "k8s", "0..=3", &[]);
        c.env("JOB_COMPLETION_INDEX", i.to_string()).env("PENUMBRA_SHARD_COUNT", "2");
        ok(c);
        let expected: Vec<String> = (0..=(1 + 2 * i)).map(|n| format!("frame_{n:04}.png")).collect();
        assert_eq!(frame_files(&dir.join("slurm")), expected, "after task {name}");
        assert_eq!(frame_files(&dir.join("k8s")), expected, "after index {name}");
    }
    let mut c = animate(dir, "bad", "0..=3", &[]);
    c.env("JOB_COMPLETION_INDEX", "1");
    let out = c.output().unwrap();
    assert!(!out.status.success());
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("--shard-count"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A small deterministic generator for kill times.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

#[test]
fn killing_a_render_at_random_moments_never_leaves_a_partial_frame_and_resume_completes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    let big = ["--width", "160", "--height", "90"];
    let started = Instant::now();
    ok(animate(dir, "reference", "0..=5", &big));
    // Kill points spread over one uninterrupted run's duration. That run may have been slowed
    // by other tests sharing the cores: a kill that finds its run already finished shortens the
    // span to its own wait (an upper bound on a run's length), so most kills still land mid-run.
    let mut span = started.elapsed().as_micros().max(2_000) as u64;
    let reference = dir.join("reference");
    let mut rng = SplitMix(20261123);
    let (mut kills_mid_run, mut frames_left) = (0, Vec::new());
    for attempt in 0..20 {
        let out = format!("killed{attempt}");
        let mut child =
            animate(dir, &out, "0..=5", &big).stdout(Stdio::null()).stderr(Stdio::null()).spawn().unwrap();
        let wait = rng.next() % span;
        std::thread::sleep(Duration::from_micros(wait));
        if child.try_wait().unwrap().is_none() {
            kills_mid_run += 1;
        } else {
            span = span.min(wait.max(2_000));
        }
        let _ = child.kill();
        child.wait().unwrap();
        // Every final frame present is complete: the same bytes as the uninterrupted run.
        frames_left.push(frame_files(&dir.join(&out)).len());
        for f in frame_files(&dir.join(&out)) {
            let bytes = std::fs::read(dir.join(&out).join(&f)).unwrap();
            assert!(
                bytes == std::fs::read(reference.join(&f)).unwrap(),
                "attempt {attempt}: {f} is partial or wrong"
            );
        }
        // The resumed run completes and equals the uninterrupted one.
        ok(animate(dir, &out, "0..=5", &big));
        same_files(&reference, &dir.join(&out));
    }
    eprintln!("{kills_mid_run} of 20 kills mid-run over {span} µs; complete frames found after each: {frames_left:?}");
    assert!(kills_mid_run >= 15, "most kills must land mid-run ({kills_mid_run} of 20)");
    assert!(frames_left.iter().any(|&n| n > 0 && n < 6), "some kills land between frames: {frames_left:?}");
}

#[test]
fn sigterm_stops_cleanly_and_the_next_run_renders_only_the_rest() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    let big = ["--width", "320", "--height", "180"];
    let child =
        animate(dir, "frames", "0..=11", &big).stdout(Stdio::null()).stderr(Stdio::piped()).spawn().unwrap();
    // Wait until some frames are done, then ask it to stop.
    let deadline = Instant::now() + Duration::from_secs(60);
    while frame_files(&dir.join("frames")).len() < 2 && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(5));
    }
    let signalled = Command::new("kill").args(["-TERM", &child.id().to_string()]).status().unwrap();
    assert!(signalled.success());
    let out = child.wait_with_output().unwrap();
    let done = frame_files(&dir.join("frames")).len();
    if done < 12 {
        assert_eq!(out.status.code(), Some(128 + 15), "{}", String::from_utf8_lossy(&out.stderr));
        assert!(String::from_utf8_lossy(&out.stderr).contains("stopped by SIGTERM"));
    }
    let leftovers: Vec<String> = std::fs::read_dir(dir.join("frames"))
        .unwrap()
        .chain(std::fs::read_dir(dir.join("frames/.penumbra")).unwrap())
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "no temporary file survives a clean stop: {leftovers:?}");

    // The resumed run renders exactly the frames that were not finished.
    let mut resume = animate(dir, "frames", "0..=11", &big);
    resume.args(["--threads", "2"]).env("COLUMNS", "80");
    let args: Vec<String> =
        resume.get_args().map(|a| a.to_string_lossy().into_owned()).filter(|a| a != "--quiet").collect();
    let mut resume = Command::new(BIN);
    resume.current_dir(dir).args(&args);
    let out = ok(resume);
    let log = String::from_utf8_lossy(&out.stdout);
    assert!(log.contains(&format!("{done} done, {} to render", 12 - done)), "{log}");
    assert_eq!(frame_files(&dir.join("frames")).len(), 12);
    ok(animate(dir, "reference", "0..=11", &big));
    same_files(&dir.join("reference"), &dir.join("frames"));
}

#[test]
fn a_changed_scene_makes_frames_stale_and_unchanged_frames_are_skipped() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    ok(animate(dir, "frames", "0..=3", &[]));
    let manifest = dir.join("frames/.penumbra/frame_0002.json");
    let written = std::fs::metadata(&manifest).unwrap().modified().unwrap();
    let status = |dir: &Path| -> serde_json::Value {
        let out = ok({
            let mut c = Command::new(BIN);
            c.current_dir(dir).args(["status", "frames", "--json"]);
            c
        });
        serde_json::from_slice(&out.stdout).unwrap()
    };
    assert_eq!(status(dir)["done"], serde_json::json!([0, 1, 2, 3]));

    // Unchanged: nothing is rendered (the entries are not even rewritten).
    let mut again = animate(dir, "frames", "0..=3", &[]);
    let args: Vec<String> =
        again.get_args().map(|a| a.to_string_lossy().into_owned()).filter(|a| a != "--quiet").collect();
    again = Command::new(BIN);
    again.current_dir(dir).args(&args);
    let log = String::from_utf8_lossy(&ok(again).stdout).into_owned();
    assert!(log.contains("4 done, 0 to render") && !log.contains("frame     "), "{log}");
    assert_eq!(std::fs::metadata(&manifest).unwrap().modified().unwrap(), written);

    // A changed scene (a brighter light) makes every frame stale, and a rerun renders them.
    let scene = std::fs::read_to_string(dir.join("scene.ron")).unwrap();
    std::fs::write(dir.join("scene.ron"), scene.replace("intensity: 0.85", "intensity: 0.95")).unwrap();
    let s = status(dir);
    assert_eq!(
        (s["stale"].clone(), s["done"].clone()),
        (serde_json::json!([0, 1, 2, 3]), serde_json::json!([]))
    );
    let before = std::fs::read(dir.join("frames/frame_0001.png")).unwrap();
    ok(animate(dir, "frames", "0..=3", &[]));
    assert_eq!(status(dir)["done"], serde_json::json!([0, 1, 2, 3]));
    assert_ne!(
        std::fs::read(dir.join("frames/frame_0001.png")).unwrap(),
        before,
        "re-rendered with the new light"
    );

    // --force renders done frames again, to the same bytes.
    ok(animate(dir, "frames", "0..=3", &["--force"]));
    assert_ne!(std::fs::metadata(&manifest).unwrap().modified().unwrap(), written);
}

#[test]
fn video_needs_every_frame() {
    let tmp = tempfile::tempdir().unwrap();
    stage(tmp.path());
    let out =
        animate(tmp.path(), "frames", "0..=3", &["--shard", "1/2", "--video", "v.mp4"]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--video needs every frame"));
}
