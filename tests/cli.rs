//! The `penumbra` binary: renders, reports statistics, and on bad input exits non-zero with a
//! positioned message and leaves no output file behind.

use std::path::Path;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_penumbra");

/// A valid scene; each bad case below replaces one snippet of it.
const BASE: &str = r#"// A small valid scene.
Scene(
    camera: (position: (0, 1, -5), look_at: (0, 0.5, 0), up: (0, 1, 0), fov_deg: 40, width: 32, height: 24),
    settings: (max_depth: 4, min_contribution: 0.01, background: (0.1, 0.1, 0.2), ambient: (0.1, 0.1, 0.1), seed: 3),
    materials: [
        (name: "matte", kd: (0.7, 0.6, 0.5), ks: 0.2, shininess: 20, kr: 0.1, kt: 0.0, ior: 1.5, glossiness: 0),
        (name: "glass", kd: (0, 0, 0), kr: 0.1, kt: 0.85, ior: 1.5),
    ],
    lights: [
        Point(position: (-2, 4, -3), colour: (1, 1, 1), intensity: 0.9),
        Directional(direction: (0, -1, 1), intensity: 0.3),
    ],
    objects: [
        (name: "floor", shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "matte"),
        (name: "ball", shape: Sphere(centre: (0, 0.5, 0), radius: 0.5), material: "glass"),
        (name: "tri", shape: Triangle(vertices: ((1, 0, 1), (2, 0, 1), (1, 1, 1))), material: "matte"),
        (name: "quad", shape: Polygon(vertices: [(-2, 0, 1), (-1, 0, 1), (-1, 1, 1), (-2, 1, 1)]), material: "matte"),
        (name: "crate", shape: Box(min: (0, 0, 0), max: (0.5, 0.5, 0.5)), material: "matte",
         transform: (translate: (1, 0, -1), rotate_deg: (0, 20, 0), scale: (1, 1, 1))),
    ],
)
"#;

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN).args(args).current_dir(dir).output().expect("the binary runs")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// 1-based line and column (in characters) of byte offset `at` in `text`.
fn line_col(text: &str, at: usize) -> (usize, usize) {
    let before = &text[..at];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

#[test]
fn no_arguments_render_the_default_scene_to_penumbra_png() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(dir.path(), &[]);
    assert!(out.status.success(), "{}", stderr(&out));
    let img = image::open(dir.path().join("penumbra.png")).expect("a readable PNG").to_rgb8();
    assert_eq!((img.width(), img.height()), (800, 600));
    // Not a blank image: the default scene has sky, floor and coloured spheres.
    let distinct: std::collections::HashSet<_> = img.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 1000, "only {} distinct colours", distinct.len());
}

#[test]
fn render_writes_the_requested_size_and_stats_json() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.ron"), BASE).unwrap();
    let out = run(
        dir.path(),
        &["render", "scene.ron", "-o", "img.png", "--width", "40", "--threads", "2", "--stats", "s.json"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let img = image::open(dir.path().join("img.png")).unwrap();
    assert_eq!((img.width(), img.height()), (40, 30), "height follows the scene's 4:3 aspect");
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(stats["rays"]["camera"], 40 * 30);
    assert!(stats["rays"]["shadow"].as_u64().unwrap() > 0);
    assert!(stats["rays"]["refraction"].as_u64().unwrap() > 0, "the glass ball refracts");
    assert_eq!(stats["threads"], 2);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("Mrays/s") && stdout.contains("grid build"), "{stdout}");
}

#[test]
fn a_missing_scene_file_fails_without_output() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(dir.path(), &["render", "nope.ron", "-o", "img.png"]);
    assert!(!out.status.success());
    assert!(stderr(&out).contains("nope.ron"), "{}", stderr(&out));
    assert!(!dir.path().join("img.png").exists());
}

#[test]
fn an_unwritable_output_path_fails_cleanly() {
    let dir = tempfile::tempdir().unwrap();
    // Missing folders are created; a file where a folder should be cannot be written through.
    std::fs::write(dir.path().join("blocker"), "a file").unwrap();
    let out = run(dir.path(), &["render", "-o", "blocker/dir/img.png", "--width", "8"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stderr(&out).contains("blocker/dir/img.png"), "{}", stderr(&out));
    assert!(!out.stderr.is_empty() && !String::from_utf8_lossy(&out.stderr).contains("panicked"));
}

#[test]
fn out_of_range_command_line_sizes_are_rejected() {
    let dir = tempfile::tempdir().unwrap();
    for bad in [["--width", "0"], ["--height", "16385"], ["--threads", "0"]] {
        let out = run(dir.path(), &["render", "-o", "img.png", bad[0], bad[1]]);
        assert!(!out.status.success(), "{bad:?} accepted");
        assert!(!dir.path().join("img.png").exists());
    }
}

/// One broken scene per rule: (snippet of BASE, replacement, field named in the message,
/// words of the rule). The expected position is where the replacement's marked part starts.
const BAD: &[(&str, &str, &str, &str)] = &[
    ("radius: 0.5", "radius: -0.5", "objects[1].shape.radius", "> 0"),
    ("radius: 0.5", "radius: 0", "objects[1].shape.radius", "> 0"),
    ("radius: 0.5", "radius: NaN", "objects[1].shape.radius", "finite"),
    ("radius: 0.5", "radius: inf", "objects[1].shape.radius", "finite"),
    ("radius: 0.5", "radius: 0.5, colour: 1", "objects[1].shape", "colour"),
    ("radius: 0.5", "radius: \"big\"", "objects[1].shape.radius", ""),
    ("width: 32", "width: 0", "camera.width", "16384"),
    ("width: 32", "width: 16385", "camera.width", "16384"),
    ("height: 24", "height: 0", "camera.height", "16384"),
    ("kd: (0.7, 0.6, 0.5)", "kd: (0.7, 1.6, 0.5)", "materials[0].kd", "[0, 1]"),
    ("ks: 0.2", "ks: -0.2", "materials[0].ks", "[0, 1]"),
    ("kr: 0.1, kt: 0.0", "kr: 1.1, kt: 0.0", "materials[0].kr", "[0, 1]"),
    ("kt: 0.85", "kt: 1.5", "materials[1].kt", "[0, 1]"),
    ("kr: 0.1, kt: 0.85", "kr: 0.2, kt: 0.85", "materials[1].kt", "kr + kt"),
    ("ior: 1.5, glossiness", "ior: 0, glossiness", "materials[0].ior", "> 0"),
    ("material: \"glass\"", "material: \"steel\"", "objects[1].material", "steel"),
    (
        "vertices: ((1, 0, 1), (2, 0, 1), (1, 1, 1))",
        "vertices: ((1, 0, 1), (2, 0, 1), (3, 0, 1))",
        "objects[2].shape.vertices",
        "non-zero area",
    ),
    (
        "(-1, 1, 1), (-2, 1, 1)]",
        "(-1, 1, 1.5), (-2, 1, 1)]",
        "objects[3].shape.vertices",
        "plane of the polygon",
    ),
    ("(-1, 1, 1), (-2, 1, 1)]", "(-2, 1, 1), (-1, 1, 1)]", "objects[3].shape.vertices", "convex"),
    ("fov_deg: 40, ", "", "camera", "fov_deg"),
];

#[test]
fn every_bad_scene_names_file_line_column_field_and_rule_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for &(from, to, field, rule) in BAD {
        assert!(BASE.contains(from), "fixture snippet {from:?} not in BASE");
        let text = BASE.replacen(from, to, 1);
        std::fs::write(dir.path().join("bad.ron"), &text).unwrap();
        let out = run(dir.path(), &["render", "bad.ron", "-o", "img.png"]);
        let err = stderr(&out);
        assert!(!out.status.success(), "{to:?} was accepted");
        assert!(!dir.path().join("img.png").exists(), "{to:?} left an output file");
        assert!(!err.contains("panicked"), "{to:?} panicked: {err}");
        // Value rules point at the value: the text after the first `: ` of the replacement.
        let at = BASE.find(from).unwrap() + to.find(": ").map_or(0, |i| i + 2);
        let (line, col) = line_col(&text, at);
        let position = if to.contains(": ") && !to.contains(", ") {
            format!("bad.ron:{line}:{col}:")
        } else {
            format!("bad.ron:{line}:")
        };
        assert!(err.contains(&position), "{to:?}: expected {position} in {err}");
        assert!(err.contains(&format!("`{field}")), "{to:?}: expected field {field} in {err}");
        assert!(err.contains(rule), "{to:?}: expected rule words {rule:?} in {err}");
    }
}

#[test]
fn a_closed_stdout_is_not_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = Command::new(BIN)
        .args(["render", "-o", "img.png", "--width", "16", "--stats", "s.json"])
        .current_dir(dir.path())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the binary runs");
    drop(child.stdout.take()); // like `penumbra render | head -0`
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(dir.path().join("img.png").exists() && dir.path().join("s.json").exists());
}

#[test]
fn effect_flags_override_the_scene_and_bad_ones_are_rejected() {
    let dir = tempfile::tempdir().unwrap();
    let out = run(
        dir.path(),
        &[
            "render",
            "-o",
            "img.png",
            "--width",
            "16",
            "--samples",
            "aa=4",
            "--pattern",
            "aa=grid",
            "--aperture",
            "0.1",
            "--samples",
            "lens=2",
            "--stats",
            "s.json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(stats["rays"]["camera"], 0, "an aperture turns camera rays into lens rays");
    assert_eq!(stats["rays"]["lens"], 16 * 12 * 4 * 2);

    let out = run(
        dir.path(),
        &["render", "-o", "a.png", "--width", "16", "--adaptive", "0.05:2", "--stats", "a.json"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("a.json")).unwrap()).unwrap();
    assert!(stats["adaptive"]["traced"].as_u64().unwrap() >= 17 * 13);

    for bad in [
        &["--samples", "blur=3"][..],
        &["--samples", "aa=0"],
        &["--pattern", "aa=sobol"],
        &["--adaptive", "0.1:9"],
        &["--aperture", "-1"],
    ] {
        let mut args = vec!["render", "-o", "bad.png", "--width", "8"];
        args.extend_from_slice(bad);
        let out = run(dir.path(), &args);
        assert!(!out.status.success(), "{bad:?} accepted");
        assert!(!dir.path().join("bad.png").exists());
    }
}
