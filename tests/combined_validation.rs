//! What fields produce together (issue 22, item 2) and one-line errors (item 6): each case
//! exits 2 naming `file:line:col`, the field and the rule, through the scene, the command line
//! and script writes; the legal variants just inside each limit still load; names with
//! control characters or of 200 KB give a short error on one line.

use std::path::PathBuf;
use std::process::Command;

use penumbra::scene::{load_scene, parse_scene};
use penumbra::script::{Clock, Limits, Script, ScriptedWorld};

const BIN: &str = env!("CARGO_BIN_EXE_penumbra");

/// A small valid scene; each case replaces one piece of it.
const BASE: &str = r#"Scene(
    camera: (position: (0, 1, -5), look_at: (0, 0.5, 0), fov_deg: 40, width: 8, height: 6),
    materials: [
        (name: "m", kd: (0.7, 0.6, 0.5)),
    ],
    lights: [
        Point(position: (-2, 4, -3), colour: (1, 1, 1), intensity: 0.9),
    ],
    objects: [
        (name: "ball", shape: Sphere(centre: (0, 0.5, 0), radius: 0.5), material: "m"),
    ],
)
"#;

/// The base scene with `from` replaced by `to`.
fn scene(from: &str, to: &str) -> String {
    assert!(BASE.contains(from), "the base scene lacks `{from}`");
    BASE.replacen(from, to, 1)
}

/// The 1-based line and character column of `needle`'s first place in `text`.
fn position(text: &str, needle: &str) -> (usize, usize) {
    let byte = text.find(needle).unwrap_or_else(|| panic!("`{needle}` is not in\n{text}"));
    let before = &text[..byte];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    (line, col)
}

/// Runs the binary in a fresh folder holding `files`; `{dir}` in `args` is that folder.
/// Returns the exit code, standard error and the folder (kept alive by the guard).
fn run(files: &[(&str, &str)], args: &[&str]) -> (Option<i32>, String, tempfile::TempDir) {
    let tmp = tempfile::tempdir().expect("a temporary folder");
    for (name, text) in files {
        std::fs::write(tmp.path().join(name), text).expect("writable temporary folder");
    }
    let dir = tmp.path().display().to_string();
    let args: Vec<String> = args.iter().map(|a| a.replace("{dir}", &dir)).collect();
    let out = Command::new(BIN).args(&args).current_dir(tmp.path()).output().expect("the binary runs");
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned(), tmp)
}

/// Renders `text` (with `extra` arguments) and asserts exit 2, one `error:` line at
/// `s.ron:line:col` of `at`, and every part of `says`.
fn assert_refused(text: &str, extra: &[&str], at: &str, says: &[&str]) {
    let mut args = vec!["render", "{dir}/s.ron", "-o", "{dir}/out.png"];
    args.extend_from_slice(extra);
    let (code, stderr, tmp) = run(&[("s.ron", text)], &args);
    let (line, col) = position(text, at);
    let place = format!("{}/s.ron:{line}:{col}: ", tmp.path().display());
    assert_eq!(code, Some(2), "{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "one error line:\n{stderr}");
    assert!(errors[0].contains(&place), "`{place}` not in\n{stderr}");
    for part in says {
        assert!(errors[0].contains(part), "`{part}` not in\n{stderr}");
    }
    assert!(!tmp.path().join("out.png").exists(), "nothing is written");
}

/// Asserts that `text` loads.
fn assert_loads(text: &str) {
    if let Err(e) = parse_scene(text, "s.ron") {
        panic!("should load: {e}\n{text}");
    }
}

#[test]
fn a_sphere_scaled_beyond_the_limit_is_refused_and_one_at_it_loads() {
    let text = scene("material: \"m\")", "material: \"m\", transform: (scale: (1000, 1000, 1000)))")
        .replace("radius: 0.5", "radius: 1e17");
    assert_refused(
        &text,
        &[],
        "(1000, 1000, 1000)",
        &[
            "field `objects[0].transform.scale`",
            "world-space bounds",
            "within ±1e18",
            "radius 1e17 × scale 1000 puts the object at",
            "1e20",
        ],
    );
    assert_loads(&text.replace("radius: 1e17", "radius: 1e15"));
}

#[test]
fn a_mesh_whose_placed_bounds_exceed_the_limit_is_refused() {
    let obj = "v 0 0 0\nv 10 0 0\nv 0 10 0\nf 1 2 3\n";
    let mesh =
        r#"(name: "tri", shape: Mesh(file: "m.obj"), material: "m", transform: (scale: (1e18, 1e18, 1e18)))"#;
    let text =
        scene(r#"(name: "ball", shape: Sphere(centre: (0, 0.5, 0), radius: 0.5), material: "m")"#, mesh);
    let (code, stderr, tmp) =
        run(&[("s.ron", &text), ("m.obj", obj)], &["render", "{dir}/s.ron", "-o", "{dir}/o.png"]);
    let (line, col) = position(&text, "(1e18, 1e18, 1e18)");
    assert_eq!(code, Some(2), "{stderr}");
    let place = format!("{}/s.ron:{line}:{col}: field `objects[0].transform.scale`", tmp.path().display());
    assert!(stderr.contains(&place), "{stderr}");
    assert!(stderr.contains("its mesh bounds × transform puts the object at x = 1e19"), "{stderr}");
    // The same mesh a tenth the size sits exactly at the limit.
    let smaller = text.replace("(1e18, 1e18, 1e18)", "(1e17, 1e17, 1e17)");
    let (code, stderr, _tmp) =
        run(&[("s.ron", &smaller), ("m.obj", obj)], &["render", "{dir}/s.ron", "-o", "{dir}/o.png"]);
    assert_ne!(code, Some(2), "{stderr}");
}

#[test]
fn a_box_moved_beyond_the_limit_blames_its_translation() {
    let cube = r#"(shape: Box(min: (-1e17, -1e17, -1e17), max: (1e17, 1e17, 1e17)), material: "m", transform: (translate: (0, 9.5e17, 0)))"#;
    let text =
        scene(r#"(name: "ball", shape: Sphere(centre: (0, 0.5, 0), radius: 0.5), material: "m")"#, cube);
    assert_refused(
        &text,
        &[],
        "(0, 9.5e17, 0)",
        &[
            "field `objects[0].transform.translate`",
            "its box corners × transform puts the object at y = 1.05e18",
        ],
    );
    assert_loads(&text.replace("9.5e17", "8.9e17"));
}

#[test]
fn an_aperture_beyond_the_limit_is_refused_in_the_scene_and_on_the_command_line() {
    let text = scene("width: 8, height: 6", "width: 8, height: 6, aperture: 1e30");
    assert_refused(
        &text,
        &[],
        "1e30",
        &["field `camera.aperture`", "the lens must lie within ±1e18", "1e30"],
    );
    assert_loads(&text.replace("1e30", "9e17"));
    // On the command line: reported at the camera (the file has no aperture), naming the flag.
    assert_refused(
        BASE,
        &["--aperture", "1e30"],
        "(position: (0, 1, -5)",
        &["field `camera.aperture`", "the lens must lie within", "`--aperture 1e30`"],
    );
    let (code, stderr, _tmp) =
        run(&[("s.ron", BASE)], &["render", "{dir}/s.ron", "-o", "{dir}/out.png", "--aperture", "0.1"]);
    assert_eq!(code, Some(0), "{stderr}");
}

#[test]
fn a_focus_distance_beyond_the_limit_is_refused() {
    let text = scene("width: 8, height: 6", "width: 8, height: 6, aperture: 0.1, focus_distance: 1e19");
    assert_refused(&text, &[], "1e19", &["field `camera.focus_distance`", "the focus point"]);
}

#[test]
fn a_light_that_overflows_is_refused() {
    let text = scene("colour: (1, 1, 1), intensity: 0.9", "colour: (10, 1, 1), intensity: 3e38");
    assert_refused(
        &text,
        &[],
        "3e38",
        &["field `lights[0].intensity`", "colour × intensity = 10 × 3e38 = 3e39 in r", "must stay ≤ 1e29"],
    );
}

#[test]
fn a_background_that_overflows_over_the_samples_is_refused() {
    let text = scene("objects: [", "settings: (background: (3e38, 0, 0), aa: (samples: 4)),\n    objects: [");
    assert_refused(
        &text,
        &[],
        "(3e38, 0, 0)",
        &["field `settings.background`", "r = 3e38 is too bright", "settings.aa.samples 4"],
    );
}

#[test]
fn samples_on_the_command_line_can_push_a_legal_light_over() {
    // 1e26 × 2 × 48 values (1 × glossy 8 × depth 6) = 9.6e27 ≤ 1e29; × 4096 camera samples is not.
    let text = scene("intensity: 0.9", "intensity: 1e26");
    let (code, stderr, _tmp) = run(&[("s.ron", &text)], &["render", "{dir}/s.ron", "-o", "{dir}/out.png"]);
    assert_eq!(code, Some(0), "{stderr}");
    assert_refused(
        &text,
        &["--samples", "aa=4096"],
        "1e26",
        &[
            "field `lights[0].intensity`",
            "a pixel sums 196608 values",
            "settings.aa.samples 4096",
            "the command line set settings.aa.samples from `--samples aa=4096`",
        ],
    );
}

#[test]
fn the_radiance_limit_itself_is_legal() {
    // 48 values × (0.1 + 2 × L) ≤ 1e29 for L just under 1.0416e27.
    assert_loads(&scene("intensity: 0.9", "intensity: 1.04e27"));
    let error = parse_scene(&scene("intensity: 0.9", "intensity: 1.05e27"), "s.ron").expect_err("over");
    assert!(error.to_string().contains("lights[0].intensity"), "{error}");
}

#[test]
fn shininess_is_bounded_where_the_highlight_stays_finite() {
    let text = scene("kd: (0.7, 0.6, 0.5)", "kd: (0.7, 0.6, 0.5), ks: 0.5, shininess: 1e9");
    assert_refused(&text, &[], "1e9", &["field `materials[0].shininess`", "must be at most 1e4", "got 1e9"]);
    assert_loads(&text.replace("1e9", "1e4"));
}

/// Animates the base scene (with a bright light when `bright`) with `script` for frame 0.
fn animate(script: &str, extra: &[&str]) -> (Option<i32>, String) {
    let mut args = vec!["animate", "{dir}/s.ron", "{dir}/s.rhai", "--frames", "0..=0", "-o", "{dir}/out"];
    args.extend_from_slice(extra);
    let text = scene("radius: 0.5", "radius: 1e15").replace("intensity: 0.9", "intensity: 1e26");
    let (code, stderr, tmp) = run(&[("s.ron", &text), ("s.rhai", script)], &args);
    (code, stderr.replace(&tmp.path().display().to_string(), "{dir}"))
}

#[test]
fn script_writes_obey_the_same_rules_at_their_own_line() {
    let cases: [(&str, &str, &[&str]); 6] = [
        (
            "let b = entity(\"ball\");\n    b.scale = 1e4;",
            "scale =",
            &["entity `ball`: scale", "world-space bounds", "within ±1e18", "x = -1e19"],
        ),
        (
            "let b = entity(\"ball\");\n    b.position = vec3(0.0, 9.995e17, 0.0);",
            "position =",
            &["entity `ball`: position", "world-space bounds"],
        ),
        ("camera.aperture = 1e30;", "aperture =", &["camera.aperture", "the lens must lie within ±1e18"]),
        (
            "let key = entity(\"light_0\");\n    key.colour = vec3(10.0, 1.0, 1.0);\n    key.intensity = 3e38;",
            "intensity =",
            &["entity `light_0`: intensity: colour × intensity = 10 × 3e38", "must stay ≤ 1e29"],
        ),
        (
            "settings.samples = 4096;",
            "samples =",
            &["settings.samples: entity `light_0`: intensity: colour × intensity", "settings.samples 4096", "must stay ≤ 1e29"],
        ),
        (
            "let b = entity(\"ball\");\n    b.ks = 0.5;\n    b.shininess = 1e9;",
            "shininess =",
            &["entity `ball`: shininess must be at most 1e4"],
        ),
    ];
    for (body, at, says) in cases {
        let script = format!("fn frame(t) {{\n    {body}\n}}\n");
        let (code, stderr) = animate(&script, &[]);
        let (line, col) = position(&script, at);
        assert_eq!(code, Some(2), "{body}: {stderr}");
        let place = format!("{{dir}}/s.rhai:{line}:{col}: script error: ");
        assert!(stderr.contains(&place), "{body}: `{place}` not in\n{stderr}");
        for part in says {
            assert!(stderr.contains(part), "{body}: `{part}` not in\n{stderr}");
        }
    }
    // Just inside the limits: scale 1e3 on radius 1e15 reaches 1e18; 1024 samples × 48 × 2e26.
    let script =
        "fn frame(t) {\n    let b = entity(\"ball\");\n    b.scale = 1e3;\n    settings.samples = 2;\n}\n";
    let (code, stderr) = animate(script, &["--width", "4", "--height", "3"]);
    assert_eq!(code, Some(0), "{stderr}");
}

#[test]
fn a_name_with_a_newline_gives_a_one_line_error() {
    let text = BASE.replace(
        r#"(name: "m", kd: (0.7, 0.6, 0.5)),"#,
        "(name: \"a\\nb\\u{0}c\", kd: (0.7, 0.6, 0.5)),\n        (name: \"a\\nb\\u{0}c\", kd: (0.1, 0.1, 0.1)),",
    );
    let (code, stderr, _tmp) = run(&[("s.ron", &text)], &["render", "{dir}/s.ron", "-o", "{dir}/out.png"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line:\n{stderr}");
    assert!(stderr.contains("duplicate material name `a\\nb\\0c`"), "{stderr}");
    // An entity name a script asks for, with an escape character.
    let (code, stderr) = animate("fn frame(t) {\n    entity(\"x\\n\\x1b[31m\");\n}\n", &[]);
    assert_eq!(code, Some(2), "{stderr}");
    assert_eq!(stderr.trim_end().lines().filter(|l| !l.starts_with("shard")).count(), 1, "{stderr}");
    assert!(stderr.contains("no entity named `x\\n\\u{1b}[31m`"), "{stderr}");
}

#[test]
fn a_200_kb_name_is_shortened() {
    let name = "n".repeat(200_000);
    let text = BASE.replace("material: \"m\")", &format!("material: \"{name}\")"));
    let (code, stderr, _tmp) = run(&[("s.ron", &text)], &["render", "{dir}/s.ron", "-o", "{dir}/out.png"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.len() < 2_000, "{} bytes", stderr.len());
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains(&format!("material `{}… (200000 characters)` is not defined", "n".repeat(60))),
        "{stderr}"
    );
    // And through a script, whose strings may be as long as the sandbox allows.
    let script = "fn frame(t) {\n    let n = \"q\";\n    for i in 0..15 { n += n; }\n    entity(n);\n}\n";
    let (code, stderr) = animate(script, &[]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.len() < 2_000, "{} bytes: {stderr}", stderr.len());
    assert!(stderr.contains("(32768 characters)"), "{stderr}");
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn every_shipped_scene_and_script_passes_the_combined_rules() {
    for path in crate::common::shipped_scenes() {
        if let Err(e) = load_scene(&path) {
            panic!("{}: {e}", path.display());
        }
    }
    let fly = load_scene(&root().join("scenes/flythrough.ron")).expect("loads");
    for script in ["flythrough.rhai", "orbit.rhai"] {
        let script = Script::load(&root().join("scripts").join(script), Limits::default()).expect("compiles");
        let mut world: ScriptedWorld = ScriptedWorld::from_scene(&fly, &script);
        world.setup().expect("setup");
        for frame in [0, 30, 60, 95, 119] {
            if let Err(e) = world.frame(Clock::at(frame, 24.0)) {
                panic!("{}: {e}", script.file());
            }
        }
    }
    let sweep =
        Script::load(&root().join("scripts/sweep_aperture_samples.rhai"), Limits::default()).expect("ok");
    let mut world: ScriptedWorld = ScriptedWorld::from_scene(&fly, &sweep);
    world.setup().expect("setup");
    for (i, set) in world.sweep_sets().expect("sets").iter().enumerate() {
        if let Err(e) = world.apply(set, i) {
            panic!("set {i}: {e}");
        }
    }
}

#[test]
fn the_error_line_of_a_missing_file_with_a_newline_is_one_line() {
    let (code, stderr, _tmp) = run(&[], &["render", "{dir}/no\nsuch.ron", "-o", "{dir}/out.png"]);
    assert_eq!(code, Some(2), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("no\\nsuch.ron: cannot read scene"), "{stderr}");
}
