//! Bounded memory and honest estimates: a render that cannot fit is refused before any work
//! (exit 2, with the estimate), the estimate tracks the memory a render really takes, and the
//! work a frame asks for is shown with the progress bar.

use crate::common;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use common::wait_at_most;

const BIN: &str = env!("CARGO_BIN_EXE_penumbra");

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN).args(args).current_dir(dir).output().expect("the binary runs")
}

fn text(out: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
}

/// Runs `args`, killing it and failing if it takes longer than `limit` (a refusal that came
/// after the work would take hours).
fn refused_at_once(dir: &Path, args: &[&str], limit: Duration) -> Output {
    let child = Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    wait_at_most(child, limit)
}

const HUGE: [&str; 10] = [
    "render",
    "--width",
    "16384",
    "--height",
    "16384",
    "--aov",
    "depth,normal,albedo,object,cost",
    "--format",
    "exr-float",
    "-o",
];

#[test]
fn a_render_that_cannot_fit_is_refused_before_any_work_with_its_estimate() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let out = refused_at_once(
        dir,
        &[&HUGE[..], &["x.exr", "--max-memory", "20G"]].concat(),
        Duration::from_secs(30),
    );
    let says = text(&out);
    assert_eq!(out.status.code(), Some(2), "{says}");
    assert!(says.contains("the render needs about 36.3 GiB (film 3.0 GiB"), "{says}");
    assert!(says.contains("--max-memory allows 20.0 GiB"), "{says}");
    assert_eq!(says.lines().count(), 1, "one line: {says}");
    assert!(!dir.join("x.exr").exists());

    // Without --max-memory the limit is what the machine has available.
    let available = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|m| m.lines().find(|l| l.starts_with("MemAvailable:")).map(str::to_owned))
        .and_then(|l| l.split_whitespace().nth(1).and_then(|k| k.parse::<u64>().ok()));
    match available {
        Some(kib) if kib * 1024 < 36 << 30 => {
            let out = refused_at_once(dir, &[&HUGE[..], &["x.exr"]].concat(), Duration::from_secs(30));
            assert_eq!(out.status.code(), Some(2), "{}", text(&out));
            assert!(text(&out).contains("this machine has available"), "{}", text(&out));
        }
        _ => eprintln!("skipped the machine-limit case: this machine has 36 GiB available or is not Linux"),
    }

    // Animations and sweeps check their frames the same way.
    std::fs::write(dir.join("s.rhai"), "fn frame(t) {\n}\n").unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/default.ron");
    let scene = scene.to_str().unwrap();
    let args = [
        "animate",
        scene,
        "s.rhai",
        "--frames",
        "0..=1",
        "--width",
        "16384",
        "--max-memory",
        "1G",
        "-o",
        "frames",
    ];
    let out = refused_at_once(dir, &args, Duration::from_secs(30));
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(text(&out).contains("--max-memory allows 1.0 GiB"), "{}", text(&out));
}

#[test]
fn the_estimate_tracks_the_memory_a_render_takes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for case in [
        &["-o", "a.png"][..],
        &["--aov", "depth,normal,albedo,object,cost", "--format", "exr-float", "-o", "b.exr"],
        &["--aov", "depth,normal,albedo,object,cost", "--format", "exr-half", "-o", "c.exr"],
        &["--aov", "depth", "-o", "d.png"],
        &["--format", "png16", "-o", "e.png"],
    ] {
        let args =
            [&["render", "--width", "1024", "--height", "1024", "--stats", "s.json"][..], case].concat();
        let out = run(dir, &args);
        assert!(out.status.success(), "{}", text(&out));
        let stats: serde_json::Value =
            serde_json::from_slice(&std::fs::read(dir.join("s.json")).unwrap()).unwrap();
        let estimated = stats["memory"]["estimated_bytes"].as_f64().unwrap();
        let Some(peak) = stats["memory"]["peak_rss_bytes"].as_f64() else {
            eprintln!("skipped: no peak resident size on this system");
            return;
        };
        let ratio = estimated / peak;
        assert!(
            (0.8..=1.4).contains(&ratio),
            "{case:?}: estimated {estimated}, peak {peak} (ratio {ratio:.2})"
        );
    }
}

#[test]
fn max_memory_takes_sizes_with_units_and_lets_a_fitting_render_through() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let out = run(dir, &["render", "--width", "64", "--max-memory", "64M", "-o", "a.png"]);
    assert!(out.status.success(), "{}", text(&out));
    for bad in ["0", "lots", "-1G"] {
        let flag = format!("--max-memory={bad}");
        let out = run(dir, &["render", "--width", "64", &flag, "-o", "b.png"]);
        assert_eq!(out.status.code(), Some(2), "{bad}: {}", text(&out));
        assert!(text(&out).contains("--max-memory"), "{}", text(&out));
    }
}

#[test]
fn the_progress_bar_shows_the_work_a_frame_asks_for() {
    let tmp = tempfile::tempdir().unwrap();
    let Some(shown) =
        common::on_a_terminal(tmp.path(), &format!("{BIN} render --width 400 --samples aa=4 -o a.png"))
    else {
        eprintln!("skipped: util-linux `script` is not installed");
        return;
    };
    // 400 × 300 pixels × 4 samples.
    assert!(shown.contains("480000 camera samples"), "{shown}");
}
