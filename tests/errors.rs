//! Every error a user can trigger from a scene, a mesh, a script, a sweep file or a
//! command-line flag, one row each: the exit code (2 bad input, 1 a failed render or write),
//! nothing written to the output, and a message naming the file with its line and column
//! (where the input has positions), the field or argument, and the rule.
//!
//! This is the enumeration; `scene_validation.rs`, `obj.rs`'s unit tests, `script_cli.rs`,
//! `batch.rs` and `report.rs` check each family in depth.

use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_penumbra");

/// A small valid scene; `OBJECT` and `MATERIAL` are replaced by each row (or left as is).
const BASE: &str = r#"// A small valid scene.
Scene(
    camera: (position: (0, 1, -5), look_at: (0, 0.5, 0), fov_deg: 40, width: 8, height: 6),
    materials: [
        MATERIAL
    ],
    lights: [
        Point(position: (-2, 4, -3), colour: (1, 1, 1), intensity: 0.9),
    ],
    objects: [
        OBJECT
    ],
)
"#;

const MATERIAL: &str = r#"(name: "m", kd: (0.7, 0.6, 0.5))"#;
const OBJECT: &str = r#"(name: "ball", shape: Sphere(centre: (0, 0.5, 0), radius: 0.5), material: "m")"#;
const MESH: &str = r#"(name: "mesh", shape: Mesh(file: "m.obj"), material: "m")"#;

/// A scene with `object` and `material` in place of the defaults.
fn scene_with(object: &str, material: &str) -> String {
    BASE.replace("OBJECT", object).replace("MATERIAL", material)
}

/// The valid scene with `from` replaced by `to`.
fn scene(from: &str, to: &str) -> String {
    let text = scene_with(OBJECT, MATERIAL);
    assert!(text.contains(from), "the base scene lacks `{from}`");
    text.replacen(from, to, 1)
}

/// Where a message must point: the `needle`'s first place in `file`, as `file:line:col` or
/// (for OBJ files, which have no columns) `file:line:`.
#[derive(Clone, Copy)]
enum At {
    Nowhere,
    Col(&'static str, &'static str),
    Line(&'static str, &'static str),
}

/// One user-triggerable error.
struct Row {
    name: &'static str,
    /// Files written to the row's folder before the run: name and text.
    files: Vec<(&'static str, String)>,
    /// Arguments; `{dir}` is the row's folder.
    args: Vec<&'static str>,
    /// Expected exit code.
    code: i32,
    at: At,
    /// Fragments the message must contain: the field or argument and the rule (`{dir}` is
    /// replaced as in `args`).
    says: Vec<&'static str>,
}

fn row(name: &'static str, code: i32, args: &[&'static str]) -> Row {
    Row { name, files: Vec::new(), args: args.to_vec(), code, at: At::Nowhere, says: Vec::new() }
}

impl Row {
    fn file(mut self, name: &'static str, text: impl Into<String>) -> Self {
        self.files.push((name, text.into()));
        self
    }

    /// The valid scene as `s.ron`.
    fn valid_inputs(self) -> Self {
        self.file("s.ron", scene_with(OBJECT, MATERIAL))
    }

    fn at(mut self, at: At) -> Self {
        self.at = at;
        self
    }

    fn says(mut self, parts: &[&'static str]) -> Self {
        self.says = parts.to_vec();
        self
    }
}

const RENDER: &[&str] = &["render", "{dir}/s.ron", "-o", "{dir}/out.png"];
const ANIMATE: &[&str] = &["animate", "{dir}/s.ron", "{dir}/s.rhai", "--frames", "0..=1", "-o", "{dir}/out"];
const SWEEP: &[&str] = &["sweep", "{dir}/s.ron", "{dir}/s.rhai", "-o", "{dir}/out"];
const REPORT: &[&str] = &["report", "{dir}/s.ron", "--runs", "1", "--quiet", "-o", "{dir}/out"];

/// `base` followed by `extra`.
fn with(base: &[&'static str], extra: &[&'static str]) -> Vec<&'static str> {
    base.iter().chain(extra).copied().collect()
}

/// A scene row: render `text` as `s.ron`.
fn scene_row(name: &'static str, text: String, at: &'static str, says: &[&'static str]) -> Row {
    row(name, 2, RENDER).file("s.ron", text).at(At::Col("s.ron", at)).says(says)
}

/// A mesh row: a scene naming `m.obj` holding `obj` (none when `None`).
fn mesh_row(name: &'static str, obj: Option<&str>, at: At, says: &[&'static str]) -> Row {
    let r = row(name, 2, RENDER).file("s.ron", scene_with(MESH, MATERIAL)).at(at).says(says);
    match obj {
        Some(text) => r.file("m.obj", text),
        None => r,
    }
}

/// A script row: animate the valid scene with `script` as `s.rhai`.
fn script_row(name: &'static str, script: &str, at: &'static str, says: &[&'static str]) -> Row {
    let r = row(name, 2, ANIMATE).valid_inputs().file("s.rhai", script).says(says);
    match at {
        "" => r,
        needle => r.at(At::Col("s.rhai", needle)),
    }
}

/// A flag row: render the valid scene with `extra` arguments.
fn flag_row(name: &'static str, extra: &[&'static str], says: &[&'static str]) -> Row {
    row(name, 2, &with(RENDER, extra)).valid_inputs().says(says)
}

const FRAME: &str = "fn frame(t) {\n}\n";

/// An animate row: the valid scene and an empty `frame(t)`, with `args` as the whole command.
fn animate_row(name: &'static str, args: &[&'static str], says: &[&'static str]) -> Row {
    row(name, 2, args).valid_inputs().file("s.rhai", FRAME).says(says)
}

fn rows() -> Vec<Row> {
    vec![
        // Scene: RON errors.
        scene_row(
            "ron syntax error",
            scene("(0, 0.5, 0), radius", "(0, 0.5, 0) radius"),
            "radius",
            &["objects[0].shape", "Expected comma"],
        ),
        scene_row(
            "unknown field",
            scene("material: \"m\")", "material: \"m\", colour: 1)"),
            "colour: 1",
            &["objects[0].colour", "unknown field `colour`", "expected one of"],
        ),
        scene_row(
            "missing field",
            scene(", radius: 0.5", ""),
            "Sphere",
            &["objects[0].shape.radius", "missing required field `radius`"],
        ),
        scene_row(
            "wrong type",
            scene("radius: 0.5", "radius: \"big\""),
            "\"big\"",
            &["objects[0].shape.radius", "expected"],
        ),
        // Scene: validation rules.
        scene_row(
            "radius <= 0",
            scene("radius: 0.5", "radius: -1"),
            "-1",
            &["objects[0].shape.radius", "must be > 0", "got -1"],
        ),
        scene_row(
            "kd out of [0, 1]",
            scene("kd: (0.7, 0.6, 0.5)", "kd: (0.7, 1.6, 0.5)"),
            "(0.7, 1.6",
            &["materials[0].kd", "must be in [0, 1]", "1.6"],
        ),
        scene_row(
            "kr + kt > 1",
            scene("kd: (0.7, 0.6, 0.5)", "kd: (0.7, 0.6, 0.5), kr: 0.6, kt: 0.6"),
            "0.6)\n",
            &["materials[0].kt", "`kr + kt` must be <= 1", "1.2"],
        ),
        scene_row(
            "unknown material",
            scene("material: \"m\"", "material: \"nope\""),
            "\"nope\"",
            &["objects[0].material", "nope"],
        ),
        scene_row(
            "duplicate material name",
            scene_with(OBJECT, &format!("{MATERIAL}, (name: \"m\", kd: (0.1, 0.1, 0.1))")),
            "\"m\", kd: (0.1",
            &["materials[1].name", "duplicate"],
        ),
        scene_row(
            "duplicate object name",
            scene_with(&format!("{OBJECT}, {OBJECT}"), MATERIAL),
            "\"ball\", shape: Sphere(centre: (0, 0.5, 0), radius: 0.5), material: \"m\")\n",
            &["objects[1].name", "duplicate"],
        ),
        scene_row(
            "degenerate triangle",
            scene_with(
                "(shape: Triangle(vertices: ((0, 0, 0), (1, 0, 0), (2, 0, 0))), material: \"m\")",
                MATERIAL,
            ),
            "((0, 0, 0), (1",
            &["objects[0].shape.vertices", "non-zero area", "collinear"],
        ),
        scene_row(
            "non-convex polygon",
            scene_with(
                "(shape: Polygon(vertices: [(0, 0, 0), (2, 0, 0), (1, 0.5, 0), (2, 2, 0), (0, 2, 0)]), material: \"m\")",
                MATERIAL,
            ),
            "(1, 0.5, 0)",
            &["objects[0].shape.vertices[2]", "non-convex"],
        ),
        scene_row(
            "box max <= min",
            scene_with("(shape: Box(min: (0, 0, 0), max: (1, 0, 1)), material: \"m\")", MATERIAL),
            "(1, 0, 1)",
            &["objects[0].shape.max", "min"],
        ),
        scene_row(
            "non-uniform sphere scale",
            scene("material: \"m\")", "material: \"m\", transform: (scale: (1, 2, 1)))"),
            "(1, 2, 1)",
            &["objects[0].transform.scale", "must be uniform for a sphere"],
        ),
        scene_row(
            "coordinate beyond 1e18",
            scene("centre: (0, 0.5, 0)", "centre: (0, 0.5, 3e19)"),
            "(0, 0.5, 3e19)",
            &["objects[0].shape.centre", "must lie within ±1e18", "z = 3e19"],
        ),
        scene_row(
            "camera width 0",
            scene("width: 8", "width: 0"),
            "0, height",
            &["camera.width", "must be in 1..=16384", "got 0"],
        ),
        scene_row(
            "fov out of range",
            scene("fov_deg: 40", "fov_deg: 200"),
            "200",
            &["camera.fov_deg", "must be in (0, 180)"],
        ),
        scene_row(
            "negative light intensity",
            scene("intensity: 0.9", "intensity: -1"),
            "-1",
            &["lights[0].intensity", "must be >= 0"],
        ),
        // Scene: what fields produce together (src/scene/limits.rs).
        scene_row(
            "object beyond 1e18 in world space",
            scene("radius: 0.5), material: \"m\")", "radius: 1e17), material: \"m\", transform: (scale: (1e3, 1e3, 1e3)))"),
            "(1e3, 1e3, 1e3)",
            &["objects[0].transform.scale", "world-space bounds", "within ±1e18"],
        ),
        scene_row(
            "light overflows the film",
            scene("colour: (1, 1, 1), intensity: 0.9", "colour: (10, 1, 1), intensity: 3e38"),
            "3e38",
            &["lights[0].intensity", "colour × intensity = 10 × 3e38", "must stay ≤ 1e29"],
        ),
        scene_row(
            "shininess beyond 1e4",
            scene("kd: (0.7, 0.6, 0.5)", "kd: (0.7, 0.6, 0.5), ks: 0.5, shininess: 1e9"),
            "1e9",
            &["materials[0].shininess", "must be at most 1e4"],
        ),
        // Meshes: reported at the scene's `file` field, with the OBJ file's own line.
        mesh_row(
            "missing OBJ file",
            None,
            At::Col("s.ron", "\"m.obj\""),
            &["objects[0].shape.file", "m.obj", "cannot read mesh"],
        ),
        mesh_row(
            "OBJ face index out of range",
            Some("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 5\n"),
            At::Line("m.obj", "f 1 2 5"),
            &["objects[0].shape.file", "face index 5 is out of range"],
        ),
        mesh_row(
            "OBJ malformed number",
            Some("v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n"),
            At::Line("m.obj", "v 1 x 0"),
            &["objects[0].shape.file", "malformed number `x`"],
        ),
        mesh_row(
            "OBJ face with two vertices",
            Some("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"),
            At::Line("m.obj", "f 1 2"),
            &["objects[0].shape.file", "a face needs at least 3"],
        ),
        mesh_row(
            "OBJ without triangles",
            Some("v 0 0 0\nv 1 0 0\n"),
            At::Line("m.obj", "v 1 0 0"),
            &["objects[0].shape.file", "no triangles"],
        ),
        // Scripts (animate).
        script_row(
            "script syntax error",
            "fn frame(t) {\n    let x = ;\n}\n",
            ";\n}",
            &["syntax error"],
        ),
        script_row(
            "script runtime error in frame(t)",
            "fn frame(t) {\n    let x = [1, 2][7];\n}\n",
            "7]",
            &["script error", "frame("],
        ),
        script_row(
            "script unknown entity",
            "fn frame(t) {\n    let b = entity(\"nobody\");\n}\n",
            "entity(",
            &["script error", "no entity named `nobody`"],
        ),
        script_row(
            "script bad property value",
            "fn frame(t) {\n    camera.fov = 500.0;\n}\n",
            "fov = 500",
            &["camera.fov", "must be in (0, 180)", "500"],
        ),
        script_row(
            "script position beyond 1e18",
            "fn frame(t) {\n    let b = entity(\"ball\");\n    b.position = vec3(1e38 * 10.0, 0.0, 0.0);\n}\n",
            "position =",
            &["entity `ball`: position", "must be finite in every component (as a 32-bit float)"],
        ),
        script_row(
            "script light overflows the film",
            "fn frame(t) {\n    let key = entity(\"light_0\");\n    key.intensity = 3e38;\n}\n",
            "intensity =",
            &["entity `light_0`: intensity", "must stay ≤ 1e29"],
        ),
        script_row(
            "script operation limit",
            "fn frame(t) {\n    loop { }\n}\n",
            "loop",
            &["script limit `max_operations` exceeded", "operations in one call"],
        ),
        script_row("script without frame(t)", "fn setup() {\n}\n", "", &["missing function", "frame"]),
        row("missing script file", 2, ANIMATE)
            .valid_inputs()
            .says(&["{dir}/s.rhai", "cannot read script"]),
        row("sweep script without sweep()", 2, SWEEP)
            .valid_inputs()
            .file("s.rhai", FRAME)
            .says(&["{dir}/s.rhai", "missing function", "sweep"]),
        // Missing files.
        row("missing scene file", 2, RENDER).says(&["{dir}/s.ron", "cannot read scene"]),
        row("missing scene file (animate)", 2, ANIMATE)
            .file("s.rhai", FRAME)
            .says(&["{dir}/s.ron", "cannot read scene"]),
        // Command-line flags.
        flag_row("--width 0", &["--width", "0"], &["--width", "1..=16384"]),
        flag_row("--height too large", &["--height", "20000"], &["--height", "1..=16384"]),
        flag_row("--threads 0", &["--threads", "0"], &["--threads", "1..=1024"]),
        flag_row("--samples aa=0", &["--samples", "aa=0"], &["--samples", "sample count must be a whole number in 1..=4096"]),
        flag_row("--samples bogus=4", &["--samples", "bogus=4"], &["--samples", "unknown effect `bogus`"]),
        flag_row("--samples without =", &["--samples", "16"], &["--samples", "expected EFFECT=VALUE"]),
        flag_row("--pattern lens=zigzag", &["--pattern", "lens=zigzag"], &["--pattern", "unknown pattern `zigzag`"]),
        flag_row("--adaptive -0.5", &["--adaptive", "-0.5"], &["--adaptive", "threshold ≥ 0"]),
        flag_row("--adaptive depth 9", &["--adaptive", "0.1:9"], &["--adaptive", "depth in 1..=6"]),
        flag_row("--aperture -1", &["--aperture", "-1"], &["--aperture", "aperture must be a finite number ≥ 0"]),
        flag_row("--aperture 1e30", &["--aperture", "1e30"], &["camera.aperture", "the lens must lie within ±1e18", "`--aperture 1e30`"]),
        row("--samples aa=4096 on a bright light", 2, &with(RENDER, &["--samples", "aa=4096"]))
            .file("s.ron", scene("intensity: 0.9", "intensity: 1e26"))
            .at(At::Col("s.ron", "1e26"))
            .says(&["lights[0].intensity", "must stay ≤ 1e29", "`--samples aa=4096`"]),
        flag_row("--format bad", &["--format", "bad"], &["--format", "unknown output format `bad`"]),
        flag_row("--aov bogus", &["--aov", "bogus"], &["--aov", "bogus"]),
        flag_row("--tonemap bad", &["--tonemap", "bad"], &["--tonemap", "unknown tone operator `bad`"]),
        flag_row("--exposure 99", &["--exposure", "99"], &["--exposure", "[-30, 30]"]),
        flag_row("--white 0", &["--white", "0"], &["--white", "> 0"]),
        flag_row("--layout bad", &["--layout", "bad"], &["--layout", "possible values"]),
        flag_row("--simd bogus", &["--simd", "sse9"], &["--simd", "unknown SIMD level `sse9`", "auto, scalar, baseline, avx2, avx512"]),
        flag_row("--adaptive with --no-adaptive", &["--adaptive", "0.1", "--no-adaptive"], &["--no-adaptive", "cannot be used with"]),
        row("unknown output extension", 2, &["render", "{dir}/s.ron", "-o", "{dir}/out.txt"])
            .valid_inputs()
            .says(&["{dir}/out.txt", "unknown output extension", "--format"]),
        animate_row("animate --frames bad range", &["animate", "{dir}/s.ron", "{dir}/s.rhai", "--frames", "5..=2", "-o", "{dir}/out"], &["--frames", "the first frame comes after the last"]),
        animate_row("animate --frames not a number", &["animate", "{dir}/s.ron", "{dir}/s.rhai", "--frames", "x..=2", "-o", "{dir}/out"], &["--frames", "is not a frame number"]),
        animate_row("animate --shard bad", &with(ANIMATE, &["--shard", "bad"]), &["--shard", "expected INDEX/COUNT"]),
        animate_row("animate --shard out of range", &with(ANIMATE, &["--shard", "4/4"]), &["--shard", "shard index 4 is out of range for 4 shards"]),
        animate_row("animate --fps 0", &with(ANIMATE, &["--fps", "0"]), &["--fps", "fps must be a number in (0, 1000]"]),
        animate_row("animate --split bogus", &with(ANIMATE, &["--split", "bogus"]), &["--split", "unknown split `bogus`"]),
        animate_row("animate --video with EXR frames", &with(ANIMATE, &["--format", "exr-half", "--video", "{dir}/v.mp4"]), &["--video", "encoding needs PNG frames"]),
        row("report --simd bogus", 2, &with(REPORT, &["--simd", "sse9"])).valid_inputs().says(&["--simd", "unknown SIMD level `sse9`"]),
        row("report --runs 0", 2, &["report", "{dir}/s.ron", "--runs", "0", "--quiet", "-o", "{dir}/out"]).valid_inputs().says(&["--runs", "1..=99"]),
        row("report sweep file: bad sample count", 2, &with(REPORT, &["--sweep", "{dir}/w.ron"]))
            .valid_inputs()
            .file("w.ron", "Sweep(\n    axes: [Lens(samples: [4, 0])],\n)\n")
            .at(At::Col("w.ron", "0]"))
            .says(&["axes[0].samples[1]", "sample count must be in 1..=4096"]),
        row("report sweep file: unknown axis", 2, &with(REPORT, &["--sweep", "{dir}/w.ron"]))
            .valid_inputs()
            .file("w.ron", "Sweep(\n    axes: [Zoom(samples: [4])],\n)\n")
            .at(At::Col("w.ron", "Zoom"))
            .says(&["axes[0]", "Zoom"]),
        // The reference takes the most samples of every effect: it breaks the rule first.
        row("report sweep point overflows a bright light", 2, &with(REPORT, &["--sweep", "{dir}/w.ron"]))
            .file("s.ron", scene("intensity: 0.9", "intensity: 1e27"))
            .file("w.ron", "Sweep(\n    axes: [Aa(samples: [1, 64])],\n)\n")
            .says(&["sweep point `reference`", "lights[0].intensity", "settings.aa.samples 64", "must stay ≤ 1e29"]),
        row("report sweep file missing", 2, &with(REPORT, &["--sweep", "{dir}/w.ron"]))
            .valid_inputs()
            .says(&["{dir}/w.ron", "cannot read sweep"]),
        row("report -o names a file", 2, &["report", "{dir}/s.ron", "--quiet", "-o", "{dir}/s.ron"])
            .valid_inputs()
            .says(&["{dir}/s.ron", "is a file; the report needs a folder"]),
        row("report --reference that is no image", 2, &with(REPORT, &["--reference", "{dir}/s.ron"]))
            .valid_inputs()
            .says(&["{dir}/s.ron: not a PNG or EXR file", "--reference takes a linear EXR", "8/16-bit sRGB PNG"]),
        flag_row("--format contradicts the extension", &["--format", "exr-half"], &["--format exr-half", "contradicts the extension of {dir}/out.png"]),
        row("-o y.exr --format png16", 2, &["render", "{dir}/s.ron", "-o", "{dir}/out.exr", "--format", "png16"])
            .valid_inputs()
            .says(&["--format png16", "contradicts the extension of {dir}/out.exr"]),
        row("status of a missing folder", 2, &["status", "{dir}/no/such/frames"]).says(&["{dir}/no/such/frames: no such folder"]),
        row("info on a file that is no image", 2, &["info", "{dir}/s.ron"])
            .valid_inputs()
            .says(&["{dir}/s.ron", "neither a PNG nor an EXR file"]),
        // Failures to write: exit 1.
        row("output folder is a file", 1, &["render", "{dir}/s.ron", "-o", "{dir}/s.ron/out.png"])
            .valid_inputs()
            .says(&["{dir}/s.ron/out.png", "cannot write output"]),
        row("stats folder is a file", 1, &with(RENDER, &["--stats", "{dir}/s.ron/stats.json"]))
            .valid_inputs()
            .says(&["{dir}/s.ron/stats.json", "cannot write output"]),
        row("output in a read-only location", 1, &["render", "{dir}/s.ron", "-o", "/proc/penumbra-out.png"])
            .valid_inputs()
            .says(&["/proc/penumbra-out.png", "cannot write output"]),
    ]
}

/// The 1-based line and character column of `needle`'s first place in `text`.
fn position(text: &str, needle: &str) -> (usize, usize) {
    let byte = text.find(needle).unwrap_or_else(|| panic!("`{needle}` is not in\n{text}"));
    let before = &text[..byte];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    (line, col)
}

/// Image files under `path` (itself included): not the manifest's JSON files and locks.
fn images(path: &Path) -> Vec<String> {
    if path.is_dir() {
        let entries = std::fs::read_dir(path).expect("readable folder");
        entries.filter_map(Result::ok).flat_map(|e| images(&e.path())).collect()
    } else if path.exists() && path.extension().is_none_or(|e| e != "json" && e != "lock") {
        vec![path.display().to_string()]
    } else {
        Vec::new()
    }
}

/// Runs `row`; the problems found, if any.
fn check(row: &Row) -> Vec<String> {
    let tmp = tempfile::tempdir().expect("a temporary folder");
    let dir = tmp.path().display().to_string();
    for (name, text) in &row.files {
        std::fs::write(tmp.path().join(name), text).expect("writable temporary folder");
    }
    let args: Vec<String> = row.args.iter().map(|a| a.replace("{dir}", &dir)).collect();
    let out = Command::new(BIN).args(&args).current_dir(tmp.path()).output().expect("the binary runs");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    let mut problems = Vec::new();
    if out.status.code() != Some(row.code) {
        problems.push(format!("exit code {:?}, expected {}", out.status.code(), row.code));
    }
    let mut wanted: Vec<String> = row.says.iter().map(|s| s.replace("{dir}", &dir)).collect();
    let file_text = |file: &str| {
        row.files.iter().find(|(n, _)| *n == file).map(|(_, t)| t.clone()).expect("the row writes the file")
    };
    match row.at {
        At::Nowhere => {}
        At::Col(file, needle) => {
            let (line, col) = position(&file_text(file), needle);
            wanted.push(format!("{dir}/{file}:{line}:{col}:"));
        }
        At::Line(file, needle) => {
            let (line, _) = position(&file_text(file), needle);
            wanted.push(format!("{dir}/{file}:{line}:"));
        }
    }
    for part in wanted {
        if !stderr.contains(&part) {
            problems.push(format!("stderr lacks `{part}`"));
        }
    }
    for output in ["out.png", "out.exr", "out"] {
        let written = images(&tmp.path().join(output));
        if !written.is_empty() {
            problems.push(format!("wrote {written:?}"));
        }
    }
    if !problems.is_empty() {
        problems.insert(0, format!("{}: {}\n  stderr: {}", row.name, args.join(" "), stderr.trim()));
    }
    problems
}

#[test]
fn every_user_error_exits_with_its_code_and_names_place_field_and_rule() {
    let rows = rows();
    assert!(rows.len() >= 40, "{} rows", rows.len());
    let mut names: Vec<&str> = rows.iter().map(|r| r.name).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), rows.len(), "row names must be unique");
    let failures: Vec<String> = rows.iter().flat_map(check).collect();
    assert!(failures.is_empty(), "{} problems:\n{}", failures.len(), failures.join("\n"));
}
