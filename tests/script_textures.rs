//! Scripts animate textures: `texture(name)`'s `offset`, `scale` and `rotation` reach the next
//! frame's snapshot exactly as the scene file's fields would, are checked with the scene
//! file's rules, and a frame that changes no transform keeps the very same texture table.

use std::sync::Arc;

use penumbra::film::Film;
use penumbra::scene::{self, SceneDesc, SceneError};
use penumbra::script::{Animation, Clock, ErrorKind, Limits, Script, ScriptError, ScriptedWorld};
use penumbra::texture::Texture;
use penumbra::trace::render;
use penumbra::world::resources::Textures;

/// A camera looking straight down at a checkered floor, seeing x in about [8.6, 13.4] and z in
/// about [-12.8, -9.2]: texture coordinates in [8, 16), where adding a whole offset of up to
/// 2 is exact in f32, so a checker moved by two squares is the same image bit for bit. The
/// centre of the image is the middle of the square (11, -11)–(12, -12).
const SCENE: &str = r#"Scene(
    camera: (position: (11.5, 5, -11.5), look_at: (11.5, 0, -11.5), up: (0, 0, 1), fov_deg: 40,
             width: 40, height: 30),
    settings: (max_depth: 1, background: (0, 0, 0), ambient: (0.2, 0.2, 0.2), seed: 3),
    textures: [
        (name: "tiles", kind: Checker(a: (1, 0.1, 0.1), b: (0.1, 0.1, 1)), offset: (0, 0)),
        (name: "bands", kind: Stripes(a: (1, 1, 1), b: (0.2, 0.2, 0.2)), scale: (6, 6)),
    ],
    materials: [(name: "floor", kd: (0.9, 0.9, 0.9), kd_texture: "tiles")],
    lights: [Directional(direction: (0, -1, 0), intensity: 0.8)],
    objects: [(name: "floor", shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "floor")],
)"#;

/// The test scene with the checker's offset set in the file to `offset`.
fn scene_with_offset(offset: &str) -> SceneDesc {
    let text = SCENE.replace("offset: (0, 0)", &format!("offset: {offset}"));
    scene::parse_scene(&text, "floor.ron").unwrap_or_else(|e| panic!("{e}"))
}

fn desc() -> SceneDesc {
    scene_with_offset("(0, 0)")
}

fn compile(source: &str) -> Result<Script, ScriptError> {
    Script::from_source("test.rhai", source, Limits::default())
}

/// Frames `0..count` of `source` over `scene`, rendered in one animation.
fn frames(scene: &SceneDesc, source: &str, count: u32) -> Vec<Film> {
    let script = compile(source).unwrap_or_else(|e| panic!("{e}"));
    let mut animation: Animation = Animation::new(scene, &script, 24.0).unwrap_or_else(|e| panic!("{e}"));
    (0..count)
        .map(|n| {
            let snapshot = animation.step_to(n).unwrap_or_else(|e| panic!("{e}"));
            render(&snapshot, &animation.world().world().render_settings()).0
        })
        .collect()
}

/// Frame `n` of a script that writes nothing over `scene`.
fn still(scene: &SceneDesc, n: u32) -> Film {
    frames(scene, "fn frame(t) { }", n + 1).pop().unwrap()
}

/// The error of `setup()` then `frame(0)` of `source` over the test scene.
fn frame_error(scene: &SceneDesc, source: &str) -> ScriptError {
    let script = match compile(source) {
        Ok(script) => script,
        Err(e) => return e,
    };
    let mut world: ScriptedWorld = ScriptedWorld::from_scene(scene, &script);
    world.setup().and_then(|_| world.frame(Clock::at(0, 24.0))).expect_err("the script must fail")
}

/// The rule the scene file breaks when the test scene's checker entry gets `field`.
fn file_rule(field: &str) -> String {
    let text = SCENE.replace("offset: (0, 0)", field);
    match scene::parse_scene(&text, "bad.ron") {
        Err(SceneError::Invalid { rule, .. }) => rule,
        other => panic!("{field}: the scene must be refused, got {other:?}"),
    }
}

const SCROLL: &str = r#"
    fn frame(t) {
        let tiles = texture("tiles");
        tiles.offset = [frame_number(), 0];   // one checker square per frame
    }
"#;

#[test]
fn a_checker_scrolled_one_square_per_frame_alternates_and_matches_the_scene_file() {
    let animated = frames(&desc(), SCROLL, 3);
    let (w, h) = (animated[0].width, animated[0].height);
    let centre = |film: &Film| film.pixels[(h / 2 * w + w / 2) as usize];

    // The centre sees (11.5, 11.5)-ish in (u, v): an even square, colour `a` (red), until a
    // one-square offset makes it odd (blue); two squares make it even again.
    let (c0, c1, c2) = (centre(&animated[0]), centre(&animated[1]), centre(&animated[2]));
    assert!(c0.x > 2.0 * c0.z, "frame 0: red square expected, got {c0}");
    assert!(c1.z > 2.0 * c1.x, "frame 1: blue square expected, got {c1}");
    assert_eq!(c2, c0, "frame 2: the red square again");
    assert_ne!(animated[0].pixels, animated[1].pixels);

    // Each frame is the image the scene file with that offset makes (same frame number, so
    // the same samples): frame 1 the file's offset (1, 0), frames 0 and 2 the unshifted file.
    assert_eq!(animated[0].pixels, still(&desc(), 0).pixels);
    assert_eq!(animated[1].pixels, still(&scene_with_offset("(1, 0)"), 1).pixels);
    assert_ne!(animated[1].pixels, still(&desc(), 1).pixels, "the offset reached the snapshot");
    assert_eq!(animated[2].pixels, still(&desc(), 2).pixels, "two squares: the same bits");
}

#[test]
fn scale_and_rotation_render_as_the_scene_files_fields() {
    let source = r#"
        fn frame(t) {
            let tiles = texture("tiles");
            tiles.scale = [0.5, 2];
            tiles.rotation = 30;
            tiles.offset = vec3(0.25, 0.5, 0);
        }
    "#;
    let field = "scale: (0.5, 2), rotate_deg: 30, offset: (0.25, 0.5)";
    let text = SCENE.replace("offset: (0, 0)", field);
    let file = scene::parse_scene(&text, "turned.ron").unwrap_or_else(|e| panic!("{e}"));
    let animated = frames(&desc(), source, 1).pop().unwrap();
    assert_eq!(animated.pixels, still(&file, 0).pixels);
    assert_ne!(animated.pixels, still(&desc(), 0).pixels);
}

#[test]
fn the_handle_reads_back_what_was_written_and_lists_the_textures() {
    let source = r#"
        fn setup() {
            if texture_names() != ["tiles", "bands"] { throw `names: ${texture_names()}`; }
            if !has_texture("bands") || has_texture("water") { throw "has_texture"; }
            let bands = texture("bands");
            if bands.scale != vec3(6, 6, 0) || bands.offset != vec3(0) || bands.rotation != 0.0 {
                throw `bands reads ${bands.scale} ${bands.offset} ${bands.rotation}`;
            }
            if bands.name != "bands" || `${bands}` != "texture(\"bands\")" { throw `${bands}`; }
            // The table keeps f32: values it holds exactly read back exactly.
            bands.offset = [0.25, 0.5];
            if bands.offset != vec3(0.25, 0.5, 0) { throw `offset ${bands.offset}`; }
            bands.offset.x += 1;                 // a component, written back through the handle
            bands.offset += vec3(0, 1, 0);
            if bands.offset != vec3(1.25, 1.5, 0) { throw `offset ${bands.offset}`; }
            bands.offset = [0.1, 0];
            if abs(bands.offset.x - 0.1) > 1e-8 { throw `offset ${bands.offset}`; }
            bands.offset = [1.1, 1.2];
            bands.scale = 2;                     // one number: both coordinates
            bands.rotation = 12.5;
            if bands.scale != vec3(2, 2, 0) || bands.rotation != 12.5 { throw `${bands.scale}`; }
            // A rejected write leaves the texture as it was.
            try { bands.scale = [0, 1]; } catch { }
            if bands.scale != vec3(2, 2, 0) { throw `scale after a failed write ${bands.scale}`; }
        }
    "#;
    let script = compile(source).unwrap_or_else(|e| panic!("{e}"));
    let mut world: ScriptedWorld = ScriptedWorld::from_scene(&desc(), &script);
    world.setup().unwrap_or_else(|e| panic!("{e}"));
    world.update();
    let textures = world.world().world().resource::<Textures>();
    let bands = textures.table[1].transform();
    assert_eq!((bands.offset.x, bands.offset.y), (1.1, 1.2));
    assert_eq!((bands.scale.x, bands.scale.y, bands.rotate_deg), (2.0, 2.0, 12.5));
    assert_eq!(*textures.table[0].transform(), *desc().assets.texture_table[0].transform());
}

#[test]
fn bad_values_break_the_scene_files_rules_naming_the_texture_and_property() {
    let cases = [
        ("tiles.scale = [0, 1]", "scale", "scale: (0, 1)"),
        ("tiles.scale = vec3(1, 0, 0)", "scale", "scale: (1, 0)"),
        ("tiles.offset = [sqrt(-1.0), 0]", "offset", "offset: (NaN, 0)"),
        ("tiles.offset = [1e39, 0]", "offset", "offset: (inf, 0)"),
        ("tiles.rotation = 1e300", "rotation", "rotate_deg: inf"),
    ];
    for (statement, property, field) in cases {
        let source = format!("fn frame(t) {{\n    let tiles = texture(\"tiles\");\n    {statement};\n}}\n");
        let e = frame_error(&desc(), &source);
        assert_eq!((e.kind.clone(), e.line), (ErrorKind::Runtime, Some(3)), "{statement}: {e}");
        let expected = format!("texture `tiles`: {property} {}", file_rule(field));
        assert!(e.message.contains(&expected), "{statement}: expected `{expected}` in {e}");
    }
    let e = frame_error(&desc(), "fn frame(t) { let w = texture(\"tiles\"); w.offset = vec3(1, 2, 3); }");
    assert!(e.message.contains("texture `tiles`: offset must be [u, v] or vec3(u, v, 0)"), "{e}");
    let e = frame_error(&desc(), "fn frame(t) { let w = texture(\"tiles\"); w.offset = 2; }");
    assert!(e.message.contains("offset must be [u, v] or vec3(u, v, 0), got i64"), "{e}");
}

#[test]
fn an_unknown_texture_or_property_is_named_with_the_closest_and_the_list() {
    let e = frame_error(&desc(), "fn frame(t) { texture(\"tile\"); }");
    assert!(
        e.message
            .contains("no texture named `tile` in the scene (did you mean `tiles`?); it has: bands, tiles"),
        "{e}"
    );
    let bare = scene::parse_scene(
        &SCENE.replace(", kd_texture: \"tiles\"", "").replace(
            "textures: [\n        (name: \"tiles\", kind: Checker(a: (1, 0.1, 0.1), b: (0.1, 0.1, 1)), offset: (0, 0)),\n        (name: \"bands\", kind: Stripes(a: (1, 1, 1), b: (0.2, 0.2, 0.2)), scale: (6, 6)),\n    ],\n",
            "",
        ),
        "bare.ron",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(bare.textures.is_empty());
    let e = frame_error(&bare, "fn frame(t) { texture(\"water\"); }");
    assert!(e.message.contains("no texture named `water` in the scene; it has no textures"), "{e}");

    let e = frame_error(&desc(), "fn frame(t) { let w = texture(\"tiles\"); w.ofset = [1, 0]; }");
    assert!(e.message.contains("texture has no property `ofset`; did you mean `offset`?"), "{e}");
    let e = frame_error(&desc(), "fn frame(t) { let w = texture(\"tiles\"); w.name = \"x\"; }");
    assert!(e.message.contains("texture.name can be read but not written"), "{e}");
    let e = frame_error(&desc(), "fn frame(t) {\n    texture(\"tiles\").offset = [1, 0];\n}\n");
    assert!(e.message.contains("write `let tiles = texture(\"tiles\"); tiles.offset = …;`"), "{e}");
}

#[test]
fn a_frame_that_changes_no_transform_keeps_the_same_table() {
    // Frames 0 and 1 write the scene's own values, frame 2 moves the checker, frame 3 writes
    // that again.
    let source = r#"
        fn frame(t) {
            let tiles = texture("tiles");
            let n = frame_number();
            tiles.offset = if n >= 2 { [0.5, 0] } else { [0, 0] };
            tiles.scale = 1;
            let bands = texture("bands");
            bands.scale = bands.scale;
        }
    "#;
    let desc = desc();
    let script = compile(source).unwrap_or_else(|e| panic!("{e}"));
    let mut world: ScriptedWorld = ScriptedWorld::from_scene(&desc, &script);
    world.setup().unwrap_or_else(|e| panic!("{e}"));
    let mut tables: Vec<Arc<[Texture]>> = Vec::new();
    for n in 0..4 {
        world.frame(Clock::at(n, 24.0)).unwrap_or_else(|e| panic!("{e}"));
        let snapshot = world.update();
        let table = world.world().world().resource::<Textures>().table.clone();
        assert!(Arc::ptr_eq(&snapshot.textures, &table), "frame {n}: the snapshot reads the World's table");
        tables.push(table);
    }
    assert!(Arc::ptr_eq(&tables[0], &desc.assets.texture_table), "frame 0 keeps the scene's table");
    assert!(Arc::ptr_eq(&tables[1], &tables[0]), "frame 1 writes the same values");
    assert!(!Arc::ptr_eq(&tables[2], &tables[1]), "frame 2 moves the checker");
    assert_eq!(tables[2][0].transform().offset.x, 0.5);
    assert_eq!(tables[2][1], tables[1][1], "the stripes are untouched");
    assert!(Arc::ptr_eq(&tables[3], &tables[2]), "frame 3 writes frame 2's values");
}

#[test]
fn under_a_shutter_the_texture_is_at_shutter_open() {
    // Evaluating the pose at shutter close runs the script again and undoes it: the textures
    // keep their transforms at shutter open (texture transforms are not blurred), even one the
    // script writes only at shutter close.
    let text = SCENE.replace("width: 40, height: 30", "width: 40, height: 30, shutter: (0.0, 0.5)");
    let shuttered = scene::parse_scene(&text, "shutter.ron").unwrap_or_else(|e| panic!("{e}"));
    let source = r#"
        fn frame(t) {
            let at_close = t * fps() - frame_number() > 0.25;
            let tiles = texture("tiles");
            tiles.offset = [frame_number() + if at_close { 0.5 } else { 0.0 }, 0];
            if at_close {
                let bands = texture("bands");
                bands.offset = [0.5, 0.5];
            }
        }
    "#;
    let script = compile(source).unwrap_or_else(|e| panic!("{e}"));
    let mut animation: Animation =
        Animation::new(&shuttered, &script, 24.0).unwrap_or_else(|e| panic!("{e}"));
    for n in 0..3 {
        let snapshot = animation.step_to(n).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(snapshot.textures[0].transform().offset.x, n as f32, "frame {n}");
        assert_eq!(
            snapshot.textures[1], shuttered.assets.texture_table[1],
            "frame {n}: bands as the file has it"
        );
    }
    let film = render(&animation.step_to(3).unwrap(), &animation.world().world().render_settings()).0;
    assert_eq!(film.pixels, frames(&shuttered, SCROLL, 4)[3].pixels);
}
