//! Output a compositor can use, through the binary: EXR with AOV layers, 16-bit PNG, tone
//! mapping that never touches EXR, and metadata that reproduces an image bit for bit.

use std::path::Path;
use std::process::{Command, Output};

use penumbra::film::read_exr;

const BIN: &str = env!("CARGO_BIN_EXE_penumbra");

/// A wall at distance 6 straight ahead and a sphere in front of it.
const SCENE: &str = r#"Scene(
    camera: (position: (0, 0, 0), look_at: (0, 0, 1), fov_deg: 40, width: 32, height: 24),
    settings: (seed: 5, background: (3, 2, 1), aa: (samples: 4)),
    materials: [(name: "wall", kd: (0.5, 0.5, 0.5)), (name: "ball", kd: (0.8, 0.2, 0.1), ks: 0.8, shininess: 10)],
    lights: [Point(position: (1, 2, -1), intensity: 3)],
    objects: [
        (name: "wall", shape: Plane(point: (0, 0, 6), normal: (0, 0, -1)), material: "wall"),
        (name: "ball", shape: Sphere(centre: (0.8, 0, 4), radius: 0.7), material: "ball"),
    ],
)"#;

fn run(dir: &Path, args: &[&str]) -> Output {
    let out = Command::new(BIN).args(args).current_dir(dir).output().expect("the binary runs");
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    out
}

fn setup() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("scene.ron"), SCENE).unwrap();
    dir
}

#[test]
fn exr_holds_linear_colour_and_aov_layers() {
    let dir = setup();
    run(
        dir.path(),
        &[
            "render",
            "scene.ron",
            "-o",
            "f.exr",
            "--format",
            "exr-float",
            "--aov",
            "depth,normal,object,cost",
            "--exposure",
            "3",
        ],
    );
    let (film, aovs) = read_exr(&dir.path().join("f.exr")).unwrap();
    // Linear and untouched by tone mapping (despite --exposure 3): bit for bit the film the
    // library renders in this process, values above 1 included.
    let desc = penumbra::scene::parse_scene(SCENE, "scene.ron").unwrap();
    let mut world: penumbra::world::SceneWorld = penumbra::scene::spawn_world(&desc);
    let snapshot = world.update();
    let (expected, _) = penumbra::trace::render(&snapshot, &world.render_settings());
    assert!(film.pixels == expected.pixels, "EXR differs from the rendered film");
    assert!(film.pixels.iter().any(|p| p.max_element() > 1.0), "the scene has values above 1");
    let depth = aovs.depth.expect("depth layer");
    // The wall is at camera-space depth 6 wherever the sphere does not cover it.
    let object = aovs.object.expect("object layer");
    let wall_id = aovs.object_names.iter().position(|n| n == "wall").unwrap() as u32 + 1;
    let mut seen = 0;
    for (d, id) in depth.iter().zip(&object) {
        if *id == wall_id {
            assert!((d - 6.0).abs() < 1e-5, "wall depth {d}");
            seen += 1;
        }
    }
    assert!(seen > 500, "{seen} wall pixels");
    assert!(aovs.normal.is_some() && aovs.cost.is_some() && aovs.albedo.is_none());
}

#[test]
fn png16_and_tone_mapping_change_only_the_png() {
    let dir = setup();
    run(dir.path(), &["render", "scene.ron", "-o", "a.png", "--format", "png16"]);
    let img = image::open(dir.path().join("a.png")).unwrap();
    assert!(matches!(img, image::DynamicImage::ImageRgb16(_)), "16-bit PNG expected");
    run(dir.path(), &["render", "scene.ron", "-o", "b.png", "--exposure", "-1", "--tonemap", "reinhard"]);
    run(dir.path(), &["render", "scene.ron", "-o", "c.png"]);
    let (b, c) =
        (std::fs::read(dir.path().join("b.png")).unwrap(), std::fs::read(dir.path().join("c.png")).unwrap());
    assert_ne!(b, c);
    run(dir.path(), &["render", "scene.ron", "-o", "b.exr", "--exposure", "-1", "--tonemap", "reinhard"]);
    run(dir.path(), &["render", "scene.ron", "-o", "c.exr"]);
    let (b, c) =
        (read_exr(&dir.path().join("b.exr")).unwrap().0, read_exr(&dir.path().join("c.exr")).unwrap().0);
    assert_eq!(b.pixels, c.pixels, "tone mapping must not touch EXR");
}

#[test]
fn png_compression_changes_the_file_not_the_pixels() {
    let dir = setup();
    let size = ["--width", "192"];
    run(dir.path(), &[&["render", "scene.ron", "-o", "default.png"], &size[..]].concat());
    for level in ["fast", "balanced", "high"] {
        let out = format!("{level}.png");
        run(
            dir.path(),
            &[&["render", "scene.ron", "-o", &out, "--png-compression", level], &size[..]].concat(),
        );
    }
    // The compressed image data (the files' metadata differ: each records its command line).
    let data = |name: &str| idat(&std::fs::read(dir.path().join(name)).unwrap());
    let pixels = |name: &str| image::open(dir.path().join(name)).unwrap().into_rgb8().into_raw();
    assert!(data("default.png") == data("fast.png"), "fast is the default");
    for level in ["balanced", "high"] {
        let name = format!("{level}.png");
        assert!(data(&name) != data("fast.png"), "{level}: compressed as fast is");
        assert!(pixels(&name) == pixels("fast.png"), "{level}: other pixels than fast");
    }
    assert!(data("high.png").len() <= data("balanced.png").len());
    let refused = Command::new(BIN)
        .args(["render", "scene.ron", "-o", "x.png", "--png-compression", "best"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{err}");
    assert!(err.contains("--png-compression") && err.contains("fast, balanced or high"), "{err}");
    assert!(!dir.path().join("x.png").exists());
}

/// The concatenated `IDAT` chunks of a PNG file.
fn idat(png: &[u8]) -> Vec<u8> {
    let mut data = Vec::new();
    let mut at = 8;
    while at + 8 <= png.len() {
        let len = u32::from_be_bytes(png[at..at + 4].try_into().unwrap()) as usize;
        if &png[at + 4..at + 8] == b"IDAT" {
            data.extend_from_slice(&png[at + 8..at + 8 + len]);
        }
        at += 12 + len;
    }
    assert!(!data.is_empty(), "no image data");
    data
}

#[test]
fn info_rerenders_the_identical_file() {
    let dir = setup();
    for (out, extra) in [
        ("a.png", vec![]),
        ("b.png", vec!["--aov", "depth,object", "--tonemap", "aces", "--samples", "aa=2"]),
        ("c.exr", vec!["--aov", "normal"]),
        ("e.png", vec!["--png-compression", "high"]),
    ] {
        let mut args = vec!["render", "scene.ron", "-o", out, "--threads", "2"];
        args.extend(extra);
        run(dir.path(), &args);
        let shown = run(dir.path(), &["info", out]);
        let text = String::from_utf8_lossy(&shown.stdout);
        assert!(text.contains("penumbra.scene.sha256") && text.contains("scene.ron"), "{text}");
        let again = format!("again-{out}");
        run(dir.path(), &["info", out, "--rerender", &again]);
        let (a, b) =
            (std::fs::read(dir.path().join(out)).unwrap(), std::fs::read(dir.path().join(&again)).unwrap());
        assert!(a == b, "{out}: the re-render differs");
    }
    // The default scene, with no arguments at all, replays too.
    run(dir.path(), &["render", "-o", "d.png", "--width", "40"]);
    run(dir.path(), &["info", "d.png", "--rerender", "d2.png"]);
    assert_eq!(
        std::fs::read(dir.path().join("d.png")).unwrap(),
        std::fs::read(dir.path().join("d2.png")).unwrap()
    );
}

#[test]
fn info_refuses_to_rerender_a_changed_scene() {
    let dir = setup();
    run(dir.path(), &["render", "scene.ron", "-o", "a.png"]);
    std::fs::write(dir.path().join("scene.ron"), SCENE.replace("seed: 5", "seed: 6")).unwrap();
    let out = Command::new(BIN)
        .args(["info", "a.png", "--rerender", "b.png"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "a changed input is bad input");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("the scene `scene.ron` changed since"), "{err}");
    assert!(!dir.path().join("b.png").exists());
}

#[test]
fn png_aovs_are_written_beside_the_image() {
    let dir = setup();
    let out = run(
        dir.path(),
        &[
            "render",
            "scene.ron",
            "-o",
            "f.png",
            "--aov",
            "depth,normal,albedo,object,cost",
            "--stats",
            "s.json",
        ],
    );
    for aov in ["depth", "normal", "albedo", "object", "cost"] {
        let img = image::open(dir.path().join(format!("f.{aov}.png"))).unwrap();
        assert_eq!((img.width(), img.height()), (32, 24), "{aov}");
    }
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("s.json")).unwrap()).unwrap();
    let legend = stats["object_ids"].as_object().expect("object legend in stats");
    assert_eq!(legend.len(), 2);
    assert!(String::from_utf8_lossy(&out.stdout).contains("AOV"));
}
