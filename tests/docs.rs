//! The documentation's RON agrees with the loader: the copy of `scenes/every_type.ron` in
//! `docs/scene-format.md` is the file, that scene names every field the loader accepts, and
//! every RON example in the README and `docs/` parses.

use std::path::Path;

use penumbra::scene::parse_scene_at;

fn read(file: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(file)).unwrap()
}

/// The ```ron blocks of a Markdown text, with the line each starts on.
fn ron_blocks(text: &str) -> Vec<(usize, String)> {
    let mut blocks = Vec::new();
    let mut open: Option<(usize, String)> = None;
    for (i, line) in text.lines().enumerate() {
        match &mut open {
            None if line.trim_start() == "```ron" => open = Some((i + 2, String::new())),
            Some(_) if line.trim_start() == "```" => blocks.extend(open.take()),
            Some((_, block)) => {
                block.push_str(line);
                block.push('\n');
            }
            None => {}
        }
    }
    assert!(open.is_none(), "an unclosed ```ron block");
    blocks
}

#[test]
fn the_scene_formats_copy_of_every_type_ron_is_the_file() {
    let doc = read("docs/scene-format.md");
    let intro = "`scenes/every_type.ron`:\n\n```ron\n";
    let start = doc.find(intro).expect("docs/scene-format.md reproduces every_type.ron") + intro.len();
    let copy = &doc[start..start + doc[start..].find("```\n").expect("the block is closed")];
    let file = read("scenes/every_type.ron");
    if let Some((n, (a, b))) = copy.lines().zip(file.lines()).enumerate().find(|(_, (a, b))| a != b) {
        panic!("the doc's copy differs at line {}:\n  doc:  {a}\n  file: {b}", n + 1);
    }
    assert_eq!(copy, file, "the doc's copy and the file differ in length or line endings");
}

/// A valid scene with a hole in each struct whose fields we ask the loader for.
const PROBE: &str = r#"Scene(
    camera: (position: (0, 1, -5), look_at: (0, 0, 0), fov_deg: 45, width: 8, height: 8, CAMERA),
    settings: (SETTINGS),
    materials: [(name: "m", kd: (0.5, 0.5, 0.5), MATERIAL)],
    objects: [(shape: Sphere(centre: (0, 0, 0), radius: 1), material: "m", transform: (TRANSFORM))],
)"#;

/// The fields the loader accepts in a struct, read from its unknown-field error. `hole` names
/// the placeholder in [`PROBE`] and `probe` is what goes there, with `zz` an unknown field.
fn accepted_fields(hole: &str, probe: &str) -> Vec<String> {
    let mut text = PROBE.to_owned();
    for h in ["CAMERA", "SETTINGS", "MATERIAL", "TRANSFORM"] {
        text = text.replace(h, if h == hole { probe } else { "" });
    }
    let error = parse_scene_at(&text, "probe.ron", Path::new(".")).unwrap_err().to_string();
    let (_, list) =
        error.split_once("expected one of ").unwrap_or_else(|| panic!("no field list in: {error}"));
    list.split(", ").map(|f| f.trim_matches('`').to_owned()).collect()
}

#[test]
fn every_type_ron_and_the_schema_tables_name_every_field_the_loader_accepts() {
    let scene = read("scenes/every_type.ron");
    let doc = read("docs/scene-format.md");
    let structs = [
        ("camera", "CAMERA", "zz: 0"),
        ("camera.lens", "CAMERA", "lens: (zz: 0)"),
        ("settings", "SETTINGS", "zz: 0"),
        ("settings.aa", "SETTINGS", "aa: (zz: 0)"),
        ("settings.adaptive", "SETTINGS", "adaptive: (zz: 0)"),
        ("settings.noise", "SETTINGS", "noise: (zz: 0)"),
        ("camera.time", "CAMERA", "time: (zz: 0)"),
        ("settings.tonemap", "SETTINGS", "tonemap: (zz: 0)"),
        ("material", "MATERIAL", "zz: 0"),
        ("transform", "TRANSFORM", "zz: 0"),
    ];
    for (name, hole, probe) in structs {
        let fields = accepted_fields(hole, probe);
        assert!(fields.len() >= 2, "{name}: {fields:?}");
        for field in fields {
            // `adaptive` is off in the scene; its fields are named in the comment beside it.
            assert!(scene.contains(&format!("{field}:")), "every_type.ron does not name {name}.{field}");
            assert!(
                doc.lines().any(|l| l.starts_with(&format!("| `{field}`"))),
                "docs/scene-format.md has no table row for {name}.{field}"
            );
        }
    }
}

#[test]
fn the_probe_sees_a_field_the_scene_would_lack() {
    // The check above is only as good as the field lists; `tonemap` is the one once missing.
    let fields = accepted_fields("SETTINGS", "zz: 0");
    assert!(fields.iter().any(|f| f == "tonemap"), "{fields:?}");
    assert!(fields.iter().any(|f| f == "max_depth"), "{fields:?}");
}

/// A base scene that one documented item (a field, a light, a shape) is put into; each item is
/// followed by a line break, as it may end in a `//` comment.
fn with_item(item: &str) -> Option<String> {
    let item = item.trim().trim_end_matches(',');
    let camera = "camera: (position: (0, 1, -5), look_at: (0, 0, 0), fov_deg: 45, width: 8, height: 8)";
    let materials = r#"materials: [(name: "m", kd: (0.5, 0.5, 0.5))]"#;
    let ball = r#"(shape: Sphere(centre: (0, 0, 0), radius: 1), material: "m")"#;
    let first = item.split(['(', ':']).next().unwrap_or("");
    Some(match first {
        "camera" => format!("Scene({item}\n, {materials}, objects: [{ball}])"),
        "settings" => format!("Scene({camera}, {item}\n, {materials}, objects: [{ball}])"),
        // A texture entry, used by the material.
        "" if item.starts_with("(name:") && item.contains("kind:") => format!(
            "Scene({camera}, materials: [(name: \"m\", kd: (1, 1, 1), kd_texture: Some({:?}))], textures: [\n{item}\n], objects: [{ball}])",
            item.split('"').nth(1).unwrap_or("")
        ),
        "Point" | "Spot" | "Directional" | "Rect" | "Disk" => {
            format!("Scene({camera}, {materials}, lights: [\n{item}\n], objects: [{ball}])")
        }
        "Sphere" | "Plane" | "Triangle" | "Polygon" | "Box" | "Mesh" => {
            format!("Scene({camera}, {materials}, objects: [(shape:\n{item}\n, material: \"m\")])")
        }
        _ => return None,
    })
}

/// Splits a block of examples into items: a line that starts at column 0 starts a new one.
fn items(block: &str) -> Vec<String> {
    let mut items: Vec<String> = Vec::new();
    for line in block.lines().filter(|l| !l.trim().is_empty()) {
        match items.last_mut() {
            Some(item) if line.starts_with(' ') => {
                item.push('\n');
                item.push_str(line);
            }
            _ => items.push(line.to_owned()),
        }
    }
    items
}

#[test]
fn every_ron_example_in_the_readme_and_the_docs_parses() {
    let mut files = vec!["README.md".to_owned()];
    let docs = std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs")).unwrap();
    let mut md: Vec<String> = docs
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    md.sort();
    files.extend(md);
    let (mut scenes, mut fragments, mut sweeps) = (0, 0, 0);
    // Meshes resolve against scenes/, where the examples' bunny_res3.obj lives.
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
    for file in &files {
        for (line, block) in ron_blocks(&read(file)) {
            let at = format!("{file}:{line}");
            let body = block.trim_start_matches(|c: char| c.is_whitespace());
            let code = body.lines().find(|l| !l.trim_start().starts_with("//")).unwrap_or("").trim_start();
            if code.starts_with("Scene(") || code.starts_with("#![") {
                parse_scene_at(&block, &at, &base).unwrap_or_else(|e| panic!("{e}"));
                scenes += 1;
            } else if code.starts_with("Sweep(") {
                penumbra::report::sweep::SweepDesc::parse(&block, &at).unwrap_or_else(|e| panic!("{e}"));
                sweeps += 1;
            } else {
                for item in items(&block) {
                    let text = with_item(&item)
                        .unwrap_or_else(|| panic!("{at}: not a scene, sweep or known item: {item}"));
                    match parse_scene_at(&text, &at, &base) {
                        Ok(_) => {}
                        // A path made up for the example (`models/part.obj`): it got as far as
                        // reading the file, so it parsed and validated.
                        Err(e) if e.to_string().contains("cannot load mesh") && item.contains("models/") => {}
                        // The same for a picture made up for the example.
                        Err(e)
                            if e.to_string().contains("cannot read texture") && item.contains("wood.png") => {
                        }
                        Err(e) => panic!("{at}: {item}\n{e}"),
                    }
                    fragments += 1;
                }
            }
        }
    }
    // The README's full scene, every_type.ron's copy, the README's sweep, the schema's examples.
    assert!(
        scenes >= 2 && sweeps >= 1 && fragments >= 10,
        "{scenes} scenes, {sweeps} sweeps, {fragments} items"
    );
}
