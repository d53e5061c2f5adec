//! Every frame traceable to all its inputs, and every command as careful as the renderer:
//! mesh files in provenance (`status` names a changed input, `info --rerender` refuses it),
//! re-rendering from any folder and from moved files, outputs checked before any work, stray
//! temporaries cleared, concurrent runs on one folder, and progress only on a terminal.

use crate::common;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::Duration;

use common::wait_at_most;

const BIN: &str = env!("CARGO_BIN_EXE_penumbra");

/// A scene with a mesh (`m.obj`, a unit cube), a floor and a light.
const SCENE: &str = r#"Scene(
    camera: (position: (1.5, 2, -4), look_at: (0, 0.5, 0), fov_deg: 45, width: 40, height: 30),
    settings: (seed: 7),
    materials: [(name: "clay", kd: (0.8, 0.5, 0.3), ks: 0.3, shininess: 30), (name: "floor", kd: (0.6, 0.6, 0.6))],
    lights: [Point(position: (-3, 5, -4), intensity: 1.0)],
    objects: [
        (name: "floor", shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "floor"),
        (name: "cube", shape: Mesh(file: "m.obj", smooth: false), material: "clay",
         transform: (translate: (0, 0.5, 0), rotate_deg: (0, 30, 0), scale: (1, 1, 1))),
    ],
)
"#;

/// A unit cube centred at the origin.
fn cube(stretch: f32) -> String {
    let mut obj = String::new();
    for i in 0..8 {
        let (x, y, z) = ((i & 1) as f32 - 0.5, ((i >> 1) & 1) as f32 - 0.5, ((i >> 2) & 1) as f32 - 0.5);
        obj += &format!("v {} {} {}\n", x * stretch, y, z);
    }
    for f in ["1 3 4 2", "5 6 8 7", "1 2 6 5", "3 7 8 4", "1 5 7 3", "2 4 8 6"] {
        obj += &format!("f {f}\n");
    }
    obj
}

const SCRIPT: &str = "fn frame(t) {\n}\n";

/// The scene, its cube and the script in `dir`.
fn stage(dir: &Path) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("s.ron"), SCENE).unwrap();
    std::fs::write(dir.join("m.obj"), cube(1.0)).unwrap();
    std::fs::write(dir.join("f.rhai"), SCRIPT).unwrap();
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

fn status(dir: &Path, frames: &str) -> serde_json::Value {
    serde_json::from_slice(&ok(dir, &["status", frames, "--json"]).stdout).unwrap()
}

fn pixels(path: &Path) -> Vec<u8> {
    image::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).to_rgb8().into_raw()
}

#[test]
fn a_changed_mesh_makes_frames_stale_naming_it_and_info_refuses_to_rerender() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    ok(dir, &["animate", "s.ron", "f.rhai", "--frames", "0..=1", "-o", "frames", "--quiet"]);
    ok(dir, &["render", "s.ron", "-o", "r.png"]);
    assert_eq!(status(dir, "frames")["done"], serde_json::json!([0, 1]));

    // Stretch the cube: the pixels change, so everything made from it must be stale.
    std::fs::write(dir.join("m.obj"), cube(1.6)).unwrap();
    let s = status(dir, "frames");
    assert_eq!((s["stale"].clone(), s["done"].clone()), (serde_json::json!([0, 1]), serde_json::json!([])));
    assert_eq!(s["changed"], serde_json::json!(["mesh m.obj"]));
    let printed = text(&ok(dir, &["status", "frames"]));
    assert!(printed.contains("changed  mesh m.obj"), "{printed}");

    for image in ["r.png", "frames/frame_0000.png"] {
        let out = run(dir, &["info", image, "--rerender", "again.png"]);
        let says = text(&out);
        assert_eq!(out.status.code(), Some(2), "{says}");
        assert!(says.contains("the mesh `m.obj` changed since"), "{says}");
        assert!(!dir.join("again.png").exists());
    }
    // The next run renders both frames again, from the stretched cube.
    let before = std::fs::read(dir.join("frames/frame_0001.png")).unwrap();
    let log = text(&ok(dir, &["animate", "s.ron", "f.rhai", "--frames", "0..=1", "-o", "frames"]));
    assert!(log.contains("0 done, 2 to render"), "{log}");
    assert_ne!(std::fs::read(dir.join("frames/frame_0001.png")).unwrap(), before);
    assert_eq!(status(dir, "frames")["done"], serde_json::json!([0, 1]));
}

#[test]
fn info_rerenders_from_any_folder_and_from_moved_inputs() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, elsewhere) = (tmp.path().join("a"), tmp.path().join("elsewhere"));
    stage(&a);
    std::fs::create_dir_all(&elsewhere).unwrap();
    ok(&a, &["render", "s.ron", "-o", "out.png", "--width", "32"]);
    ok(&a, &["animate", "s.ron", "f.rhai", "--frames", "0..=2", "-o", "frames", "--quiet"]);

    // From another folder: the same bytes, metadata included.
    ok(&elsewhere, &["info", "../a/out.png", "--rerender", "again.png"]);
    assert_eq!(
        std::fs::read(elsewhere.join("again.png")).unwrap(),
        std::fs::read(a.join("out.png")).unwrap()
    );
    ok(&elsewhere, &["info", "../a/frames/frame_0001.png", "--rerender", "f1.png"]);
    assert_eq!(
        std::fs::read(elsewhere.join("f1.png")).unwrap(),
        std::fs::read(a.join("frames/frame_0001.png")).unwrap()
    );

    // Moved: the recorded paths are gone (exit 2, saying how to point at them) until
    // --scene/--script say where the files are now.
    let moved = tmp.path().join("moved");
    std::fs::rename(&a, &moved).unwrap();
    let out = run(&elsewhere, &["info", "../moved/out.png", "--rerender", "x.png"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(
        text(&out).contains("the scene `s.ron` is missing") && text(&out).contains("--scene"),
        "{}",
        text(&out)
    );
    assert!(!elsewhere.join("x.png").exists());

    ok(&elsewhere, &["info", "../moved/out.png", "--rerender", "x.png", "--scene", "../moved/s.ron"]);
    assert_eq!(pixels(&elsewhere.join("x.png")), pixels(&moved.join("out.png")));
    let frame_args =
        ["info", "../moved/frames/frame_0002.png", "--rerender", "f2.png", "--scene", "../moved/s.ron"];
    let out = run(&elsewhere, &frame_args);
    assert_eq!(out.status.code(), Some(2), "the script is still missing: {}", text(&out));
    assert!(text(&out).contains("the script `f.rhai` is missing"), "{}", text(&out));
    ok(&elsewhere, &[&frame_args[..], &["--script", "../moved/f.rhai"]].concat());
    assert_eq!(pixels(&elsewhere.join("f2.png")), pixels(&moved.join("frames/frame_0002.png")));

    // A moved scene without its mesh beside it: the mesh is named as missing.
    std::fs::remove_file(moved.join("m.obj")).unwrap();
    let out =
        run(&elsewhere, &["info", "../moved/out.png", "--rerender", "y.png", "--scene", "../moved/s.ron"]);
    assert_eq!(out.status.code(), Some(2), "{}", text(&out));
    assert!(text(&out).contains("the mesh `m.obj` is missing"), "{}", text(&out));
}

#[test]
fn outputs_are_checked_before_any_rendering() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    // A render of minutes into a folder that cannot exist (a file is in the way): refused at once.
    let heavy = ["render", "s.ron", "--width", "4000", "--samples", "aa=256"];
    for (output, stats) in [("s.ron/out.png", "stats.json"), ("out.png", "s.ron/stats.json")] {
        let child = Command::new(BIN)
            .args(heavy)
            .args(["-o", output, "--stats", stats])
            .current_dir(dir)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let out = wait_at_most(child, Duration::from_secs(60));
        let says = text(&out);
        assert_eq!(out.status.code(), Some(1), "{says}");
        let bad = if output.starts_with("s.ron") { output } else { stats };
        assert!(says.contains(&format!("{bad}: cannot write output")), "{says}");
        assert_eq!(says.matches(".penumbra-").count(), 0, "no temporary-file names: {says}");
        assert!(!dir.join("out.png").exists() && !dir.join("stats.json").exists());
    }
    // Missing folders are created, as `animate`, `sweep` and `report` do.
    ok(dir, &["render", "s.ron", "-o", "new/sub/out.png", "--stats", "other/stats.json"]);
    assert!(dir.join("new/sub/out.png").is_file() && dir.join("other/stats.json").is_file());
    // A format that contradicts the extension: exit 2, nothing written.
    for (output, format) in [("y.exr", "png16"), ("y.png", "exr-float")] {
        let out = run(dir, &["render", "s.ron", "-o", output, "--format", format]);
        assert_eq!(out.status.code(), Some(2), "{}", text(&out));
        assert!(text(&out).contains("contradicts the extension"), "{}", text(&out));
        assert!(!dir.join(output).exists());
    }
    // An agreeing format, and a format for a name without a known extension, are fine.
    ok(dir, &["render", "s.ron", "-o", "z.png", "--format", "png16"]);
    ok(dir, &["render", "s.ron", "-o", "z.image", "--format", "exr-half"]);
    assert!(std::fs::read(dir.join("z.image")).unwrap().starts_with(&[0x76, 0x2f, 0x31, 0x01]), "EXR magic");
}

#[test]
fn the_next_run_on_a_folder_removes_temporaries_that_killed_runs_left() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    let animate = ["animate", "s.ron", "f.rhai", "--frames", "0..=1", "-o", "frames"];
    ok(dir, &animate);
    std::fs::write(dir.join("frames/.penumbra-killed1.tmp"), "half a frame").unwrap();
    std::fs::write(dir.join("frames/.penumbra/.penumbra-killed2.tmp"), "half an entry").unwrap();
    assert_eq!(status(dir, "frames")["stray_temporaries"].as_array().unwrap().len(), 2);
    let log = text(&ok(dir, &animate));
    assert!(log.contains("removed 2 temporary files of interrupted runs"), "{log}");
    assert_eq!(status(dir, "frames")["stray_temporaries"], serde_json::json!([]));
    assert_eq!(status(dir, "frames")["done"], serde_json::json!([0, 1]));
}

#[test]
fn two_concurrent_animate_runs_on_one_folder_render_each_frame_once() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    // Heavy enough per frame (tens of milliseconds) that the two runs overlap.
    let args = ["animate", "s.ron", "f.rhai", "--frames", "0..=11", "--width", "160", "--samples", "aa=4"];
    let spawn = |out: &str| {
        Command::new(BIN)
            .args(args)
            .args(["-o", out, "--threads", "1"])
            .current_dir(dir)
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("JOB_COMPLETION_INDEX")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap()
    };
    let (first, second) = (spawn("frames"), spawn("frames"));
    let outputs = [first.wait_with_output().unwrap(), second.wait_with_output().unwrap()];
    let mut rendered = 0;
    for out in &outputs {
        assert!(out.status.success(), "{}", text(out));
        rendered += String::from_utf8_lossy(&out.stdout).lines().filter(|l| l.starts_with("frame ")).count();
    }
    assert_eq!(
        rendered,
        12,
        "each frame rendered by exactly one run:\n{}\n{}",
        text(&outputs[0]),
        text(&outputs[1])
    );
    let s = status(dir, "frames");
    assert_eq!(s["done"].as_array().unwrap().len(), 12, "{s}");
    assert_eq!(s["stray_temporaries"], serde_json::json!([]));
    // The same bytes as one run alone.
    ok(dir, &[&args[..], &["-o", "alone", "--quiet"]].concat());
    for n in 0..12 {
        let name = format!("frame_{n:04}.png");
        assert!(
            std::fs::read(dir.join("frames").join(&name)).unwrap()
                == std::fs::read(dir.join("alone").join(&name)).unwrap(),
            "{name} differs"
        );
    }
}

/// `penumbra ARGS` under a pseudo-terminal: what the terminal showed (`None` without `script`).
fn on_a_terminal(dir: &Path, args: &str) -> Option<String> {
    common::on_a_terminal(dir, &format!("{BIN} {args}"))
}

#[test]
fn render_draws_a_tile_bar_on_a_terminal_only() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    stage(dir);
    // Not a terminal: standard error stays empty.
    let out = ok(dir, &["render", "s.ron", "-o", "a.png", "--width", "400"]);
    assert!(out.stderr.is_empty(), "{}", String::from_utf8_lossy(&out.stderr));
    let Some(shown) = on_a_terminal(dir, "render s.ron -o b.png --width 400") else {
        eprintln!("skipped: util-linux `script` is not installed");
        return;
    };
    assert!(shown.contains("tiles"), "{shown}");
    let quiet = on_a_terminal(dir, "render s.ron -o c.png --width 400 --quiet").unwrap();
    assert!(!quiet.contains("tiles"), "{quiet}");
    assert_eq!(std::fs::read(dir.join("b.png")).unwrap(), std::fs::read(dir.join("c.png")).unwrap());
    let animated = on_a_terminal(dir, "animate s.ron f.rhai --frames 0..=2 -o frames").unwrap();
    assert!(!animated.contains("0/0 tiles"), "{animated}");
}
