//! Rhai scripting: the sandbox stops every runaway with its own limit and position, the API
//! round-trips, animation is deterministic and touches the World only where a script wrote,
//! and `focus_on` keeps a moving subject sharp.

use std::time::Duration;

use glam::DVec3;
use penumbra::film::Film;
use penumbra::math::Vec3;
use penumbra::scene::{self, SceneDesc};
use penumbra::script::{Animation, Clock, ErrorKind, Limit, Limits, Script, ScriptError, ScriptedWorld};
use penumbra::trace::render;
use penumbra::world::components::MaterialRef;
use penumbra::world::resources::{CameraRig, Materials};
use penumbra::world::SceneWorld;

const SCENE: &str = r#"Scene(
    camera: (position: (0, 2, -6), look_at: (0, 0.5, 0), fov_deg: 45, width: 40, height: 30),
    settings: (max_depth: 3, background: (0.2, 0.3, 0.5), ambient: (0.1, 0.1, 0.1), seed: 5),
    materials: [
        (name: "floor", kd: (0.7, 0.7, 0.7)),
        (name: "red", kd: (0.8, 0.1, 0.1), ks: 0.4, shininess: 30),
        (name: "mirror", kd: (0, 0, 0), kr: 0.9),
    ],
    lights: [
        Point(position: (-3, 6, -4), intensity: 0.9),
        Directional(direction: (1, -1, 1), intensity: 0.2),
    ],
    objects: [
        (name: "floor", shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "floor"),
        (name: "ball", shape: Sphere(centre: (0, 0, 0), radius: 0.8),
         transform: (translate: (-1, 0.8, 0)), material: "red"),
        (name: "twin", shape: Sphere(centre: (0, 0, 0), radius: 0.4),
         transform: (translate: (1.6, 0.4, -1)), material: "red"),
        (name: "crate", shape: Box(min: (-0.5, 0, -0.5), max: (0.5, 1, 0.5)),
         transform: (translate: (1.5, 0, 1.5)), material: "mirror"),
    ],
)"#;

fn desc() -> SceneDesc {
    scene::parse_scene(SCENE, "script-test.ron").expect("test scene is valid")
}

fn compile(source: &str) -> Result<Script, ScriptError> {
    compile_with(source, Limits::default())
}

fn compile_with(source: &str, limits: Limits) -> Result<Script, ScriptError> {
    Script::from_source("test.rhai", source, limits)
}

fn scripted(source: &str) -> ScriptedWorld {
    ScriptedWorld::new(scene::spawn_world(&desc()), &compile(source).expect("script compiles"))
}

/// 1-based line and column of the first occurrence of `needle` in `source`.
fn locate(source: &str, needle: &str) -> (usize, usize) {
    let offset = source.find(needle).unwrap_or_else(|| panic!("`{needle}` not in the script"));
    let before = &source[..offset];
    let line = before.matches('\n').count() + 1;
    let column = before.chars().rev().take_while(|&c| c != '\n').count() + 1;
    (line, column)
}

/// The error of running `frame(0)` (after `setup()`) with `limits`.
fn frame_error(source: &str, limits: Limits) -> ScriptError {
    let script = match compile_with(source, limits) {
        Ok(script) => script,
        Err(e) => return e,
    };
    let mut world: ScriptedWorld = ScriptedWorld::new(scene::spawn_world(&desc()), &script);
    world.setup().and_then(|_| world.frame(Clock::at(0, 24.0))).expect_err("the script must fail")
}

fn assert_limit(e: &ScriptError, limit: Limit, source: &str, needle: &str) {
    assert_eq!(e.kind, ErrorKind::Limit(limit), "{e}");
    assert_eq!(e.file, "test.rhai");
    let (line, _) = locate(source, needle);
    assert_eq!(e.line, Some(line), "{e}");
    assert!(e.column.is_some(), "{e}");
    assert!(e.to_string().contains(limit.name()), "the message names the limit: {e}");
}

#[test]
fn a_runaway_loop_stops_at_the_operation_limit_with_its_position() {
    let source = "fn frame(t) {\n    let n = 0;\n    loop { n += 1; }\n}\n";
    let limits = Limits { max_operations: 10_000, ..Limits::default() };
    let e = frame_error(source, limits);
    assert_limit(&e, Limit::Operations, source, "loop");
    assert!(e.to_string().contains("more than 10000 operations"), "{e}");
    assert!(e.to_string().contains("frame(0) at frame 0"), "{e}");
}

#[test]
fn deep_recursion_stops_at_the_call_level_limit() {
    let source = "fn dive(n) { dive(n + 1) }\nfn frame(t) {\n    dive(0);\n}\n";
    let e = frame_error(source, Limits { max_call_levels: 16, ..Limits::default() });
    assert_limit(&e, Limit::CallLevels, source, "fn dive");
}

#[test]
fn a_deeply_nested_expression_stops_at_the_depth_limit_when_compiled() {
    let nested = format!("{}1{}", "(".repeat(40), ")".repeat(40));
    let source = format!("fn frame(t) {{\n    let x = {nested};\n}}\n");
    let e = frame_error(&source, Limits { max_function_expr_depth: 20, ..Limits::default() });
    assert_limit(&e, Limit::ExpressionDepth, &source, "let x");
}

#[test]
fn growing_a_string_an_array_or_a_map_stops_at_its_size_limit() {
    let limits = Limits { max_string_size: 100, max_array_size: 50, max_map_size: 20, ..Limits::default() };
    let string = "fn frame(t) {\n    let s = \"x\";\n    for i in 0..200 { s += \"yz\"; }\n}\n";
    assert_limit(&frame_error(string, limits), Limit::StringSize, string, "for i");
    let array = "fn frame(t) {\n    let a = [];\n    for i in 0..200 { a.push(i); }\n}\n";
    assert_limit(&frame_error(array, limits), Limit::ArraySize, array, "for i");
    // `m.set(k, v)`: Rhai 1.27 checks the map limit on map functions, not on `m[k] = v`.
    let map = "fn frame(t) {\n    let m = #{};\n    for i in 0..200 { m.set(`k${i}`, i); }\n}\n";
    assert_limit(&frame_error(map, limits), Limit::MapSize, map, "for i");
}

#[test]
fn too_many_variables_or_functions_stop_at_their_limits() {
    let lets: String = (0..30).map(|i| format!("let v{i} = {i}; ")).collect();
    let source = format!("fn frame(t) {{\n    {lets}\n}}\n");
    let e = frame_error(&source, Limits { max_variables: 10, ..Limits::default() });
    assert_limit(&e, Limit::Variables, &source, "let v0");
    let functions: String = (0..10).map(|i| format!("fn f{i}() {{ }}\n")).collect();
    let source = format!("fn frame(t) {{ }}\n{functions}");
    let e = frame_error(&source, Limits { max_functions: 4, ..Limits::default() });
    assert_eq!(e.kind, ErrorKind::Limit(Limit::Functions), "{e}");
}

#[test]
fn a_script_that_runs_too_long_stops_at_the_time_limit() {
    let source = "fn frame(t) {\n    loop { }\n}\n";
    let limits = Limits { max_operations: 0, time_limit: Duration::from_millis(50), ..Limits::default() };
    let e = frame_error(source, limits);
    assert_limit(&e, Limit::Time, source, "loop");
}

#[test]
fn scripts_cannot_import_files_eval_code_sleep_or_read_the_clock() {
    let import = "import \"../shared/secrets\" as s;\nfn frame(t) { }\n";
    let e = frame_error(import, Limits::default());
    assert_eq!(e.kind, ErrorKind::Sandbox, "{e}");
    assert_eq!((e.line, e.column), (Some(1), Some(8)), "{e}");

    let eval = "fn frame(t) {\n    eval(\"1 + 1\");\n}\n";
    let e = frame_error(eval, Limits::default());
    assert_eq!((e.kind.clone(), e.line), (ErrorKind::Syntax, Some(2)), "{e}");

    let sleep = "fn frame(t) {\n    sleep(10);\n}\n";
    let e = frame_error(sleep, Limits::default());
    assert_eq!((e.kind.clone(), e.line), (ErrorKind::Runtime, Some(2)), "{e}");
    assert!(e.message.contains("sleep is not available"), "{e}");

    let clock = "fn frame(t) {\n    let now = timestamp();\n}\n";
    let e = frame_error(clock, Limits::default());
    assert_eq!((e.kind.clone(), e.line), (ErrorKind::Runtime, Some(2)), "{e}");
}

#[test]
fn a_syntax_error_names_file_line_and_column() {
    let e = compile("fn frame(t) {\n    let x = 1 +;\n}\n").err().expect("does not parse");
    assert_eq!(e.kind, ErrorKind::Syntax);
    assert_eq!(e.line, Some(2));
    assert!(e.to_string().starts_with("test.rhai:2:"), "{e}");
}

#[test]
fn reading_a_missing_entity_names_it_and_where_it_was_asked_for() {
    let source = "fn frame(t) {\n    let b = entity(\"bal\");\n}\n";
    let e = frame_error(source, Limits::default());
    assert_eq!(e.kind, ErrorKind::Runtime);
    assert_eq!((e.line, e.column), (Some(2), Some(locate(source, "entity").1)), "{e}");
    assert!(e.message.contains("no entity named `bal`"), "{e}");
    assert!(e.message.contains("did you mean `ball`?"), "{e}");
    assert!(e.message.contains("crate, floor"), "lists the names: {e}");
}

#[test]
fn bad_values_fail_with_the_rule_they_broke() {
    let cases = [
        ("entity(\"ball\").kd = vec3(0.5, 1.2, 0.5)", "kd must be in [0, 1] in every channel, got g = 1.2"),
        ("entity(\"ball\").ior = 0", "ior must be > 0, got 0"),
        ("camera.fov = 180", "camera.fov: must be in (0, 180) degrees, got 180"),
        ("camera.aperture = -1", "camera.aperture: must be >= 0, got -1"),
        ("settings.samples = 0", "settings.samples must be in 1..=4096, got 0"),
        ("entity(\"ball\").scale = vec3(1, 2, 1)", "must be uniform for a sphere"),
        ("entity(\"crate\").scale = vec3(1, 0, 1)", "must be non-zero on every axis"),
        ("entity(\"light_1\").position = vec3(0, 1, 0)", "is a directional light: it has no position"),
        ("entity(\"light_0\").kd = vec3(1, 1, 1)", "is a light: it has no material"),
        ("camera.fov = \"wide\"", "camera.fov must be a number, got string"),
    ];
    for (statement, rule) in cases {
        // Assignments to a temporary are not Rhai; bind the entity first.
        let statement =
            statement.replacen("entity(\"", "let e = entity(\"", 1).replacen("\").", "\"); e.", 1);
        let source = format!("fn frame(t) {{\n    {statement};\n}}\n");
        let e = frame_error(&source, Limits::default());
        assert_eq!((e.kind.clone(), e.line), (ErrorKind::Runtime, Some(2)), "{statement}: {e}");
        assert!(e.message.contains(rule), "{statement}: expected `{rule}` in {e}");
    }
}

#[test]
fn rules_across_fields_are_checked_once_the_frame_has_written_everything() {
    // kr then kt in two statements: valid only if checked after both.
    let fine = "fn frame(t) {\n    let b = entity(\"ball\");\n    b.kt = 0.0;\n    b.kr = 0.6;\n    b.kt = 0.4;\n}\n";
    let mut world = scripted(fine);
    world.setup().and_then(|_| world.frame(Clock::at(0, 24.0))).expect("kr + kt = 1 is allowed");

    let source = "fn frame(t) {\n    let b = entity(\"ball\");\n    b.kr = 0.7;\n    b.kt = 0.5;\n}\n";
    let e = frame_error(source, Limits::default());
    assert!(e.message.contains("entity `ball`: kt: `kr + kt` must be <= 1"), "{e}");

    let source = "fn frame(t) {\n    camera.look_at = camera.position;\n}\n";
    let e = frame_error(source, Limits::default());
    assert!(e.message.contains("camera.look_at: must differ from `position`"), "{e}");
}

#[test]
fn every_property_reads_back_what_was_written() {
    let source = r#"
        fn frame(t) {
            let b = entity("ball");
            b.position = vec3(0.25, 1.5, -0.75);
            b.rotation = vec3(10, 20, 30);
            b.scale = 1.25;
            b.visible = false;
            b.kd = vec3(0.1, 0.2, 0.3);
            b.ks = 0.35; b.shininess = 12.5; b.kr = 0.2; b.kt = 0.3; b.ior = 1.33; b.glossiness = 0.45;
            camera.position = vec3(1, 2, -7);
            camera.look_at = vec3(0, 1, 0);
            camera.up = vec3(0, 1, 0.1);
            camera.fov = 35.5;
            camera.aperture = 0.05;
            camera.focus_distance = 6.5;
            settings.samples = 3; settings.lens_samples = 5; settings.glossy_samples = 7; settings.time_samples = 6;
            settings.max_depth = 4; settings.seed = 99; settings.width = 64; settings.height = 48;
            settings.adaptive = 0.02; settings.adaptive_depth = 2;
            // Positions and counts are kept as written: f64 and integers.
            let got = [b.position, b.scale, b.visible, b.shininess, camera.position, camera.look_at,
                       camera.focus_distance, settings.samples, settings.lens_samples,
                       settings.glossy_samples, settings.max_depth, settings.seed, settings.width,
                       settings.height, settings.adaptive_depth, settings.time_samples];
            let want = [vec3(0.25, 1.5, -0.75), vec3(1.25, 1.25, 1.25), false, 12.5, vec3(1, 2, -7),
                        vec3(0, 1, 0), 6.5, 3, 5, 7, 4, 99, 64, 48, 2, 6];
            for i in 0..want.len() {
                if got[i] != want[i] { throw `property ${i}: wrote ${want[i]}, read ${got[i]}`; }
            }
            // The rest as the tracer keeps them: f32 (within its rounding), and the rotation as
            // the angles of its quaternion.
            let got = [b.rotation, b.kd, b.ks, b.kr, b.kt, b.ior, b.glossiness, camera.up, camera.fov,
                       camera.aperture, settings.adaptive];
            let want = [vec3(10, 20, 30), vec3(0.1, 0.2, 0.3), 0.35, 0.2, 0.3, 1.33, 0.45, vec3(0, 1, 0.1),
                        35.5, 0.05, 0.02];
            let within = [1e-4, 1e-7, 1e-7, 1e-7, 1e-7, 1e-6, 1e-7, 1e-7, 1e-5, 1e-8, 1e-8];
            for i in 0..want.len() {
                let d = got[i] - want[i];
                let off = if type_of(d) == "f64" { abs(d) } else { length(d) };
                if off > within[i] || got[i] == () { throw `property ${i}: wrote ${want[i]}, read ${got[i]}`; }
            }
            settings.adaptive = ();
            if settings.adaptive != () { throw "adaptive did not turn off"; }
        }
    "#;
    let mut world = scripted(source);
    world.setup().unwrap();
    world.frame(Clock::at(0, 24.0)).unwrap_or_else(|e| panic!("{e}"));

    // And the World got the same values.
    let snapshot = world.update();
    let settings = world.world().render_settings();
    assert_eq!((settings.width, settings.height, settings.seed, settings.max_depth), (64, 48, 99, 4));
    assert_eq!((settings.aa.samples, settings.lens.samples, settings.glossy.samples), (3, 5, 7));
    assert_eq!(settings.time.samples, 6);
    assert!(settings.adaptive.is_none());
    let camera = snapshot.camera;
    let rig = *world.world().world().resource::<CameraRig>();
    assert_eq!((rig.position, rig.look_at), (DVec3::new(1.0, 2.0, -7.0), DVec3::new(0.0, 1.0, 0.0)));
    assert_eq!(camera.position, Vec3::ZERO, "the snapshot is relative to the camera");
    assert_eq!((camera.aperture, camera.focus_distance), (0.05, 6.5));
    assert!((camera.fov_y().to_degrees() - 35.5).abs() < 1e-4);
    let ball = world.world_mut().entity("ball").unwrap();
    let transform = *world.world().world().get::<penumbra::world::components::Transform>(ball).unwrap();
    assert_eq!(transform.translation, DVec3::new(0.25, 1.5, -0.75));
    assert_eq!(transform.scale, Vec3::splat(1.25));
    assert!(snapshot.object_names.iter().all(|n| n != "ball"), "the hidden ball is not in the snapshot");
}

#[test]
fn the_clock_gives_frame_time_and_fps() {
    let source = "fn frame(t) {\n    if t != time() || frame_number() != 36 || fps() != 24.0 || t != 1.5 { throw `${t} ${time()} ${frame_number()} ${fps()}`; }\n}\n";
    let mut world = scripted(source);
    world.setup().unwrap();
    world.frame(Clock::at(36, 24.0)).unwrap_or_else(|e| panic!("{e}"));
    world.update();
    assert_eq!(world.world().world().resource::<CameraRig>().position, DVec3::new(0.0, 2.0, -6.0));
    assert_eq!(world.world().render_settings().frame, 36, "the frame number keys the samples");
}

#[test]
fn changing_one_objects_material_leaves_the_objects_sharing_it_alone() {
    let mut world =
        scripted("fn frame(t) {\n    let b = entity(\"ball\");\n    b.kd = vec3(0.1, 0.8, 0.1);\n}\n");
    world.setup().unwrap();
    world.update();
    let material_of = |world: &mut ScriptedWorld, name: &str| {
        let entity = world.world_mut().entity(name).unwrap();
        let w = world.world().world();
        let id = w.get::<MaterialRef>(entity).unwrap().0;
        w.resource::<Materials>().table[id.0 as usize]
    };
    let (ball_before, twin_before) = (material_of(&mut world, "ball"), material_of(&mut world, "twin"));
    assert_eq!(ball_before, twin_before, "the two share `red`");
    world.frame(Clock::at(0, 24.0)).unwrap();
    world.update();
    assert_eq!(material_of(&mut world, "ball").kd, Vec3::new(0.1, 0.8, 0.1));
    assert_eq!(material_of(&mut world, "twin"), twin_before, "the twin keeps the shared red");
}

/// Renders frames `frames` of `source` over the test scene, starting the animation anew.
fn animate(source: &str, frames: &[u32]) -> Vec<(Film, u64)> {
    let script = compile(source).expect("compiles");
    let mut animation: Animation = Animation::new(&desc(), &script, 24.0).unwrap_or_else(|e| panic!("{e}"));
    frames
        .iter()
        .map(|&n| {
            let snapshot = animation.step_to(n).unwrap_or_else(|e| panic!("{e}"));
            let settings = animation.world().world().render_settings();
            (render(&snapshot, &settings).0, animation.world().world().grid_rebuilds())
        })
        .collect()
}

const MOVING: &str = r#"
    fn frame(t) {
        let b = entity("ball");
        b.position = vec3(-1.0 + 0.5 * sin(3.0 * t), 0.8, 0.2 * frame_number());
        camera.position = vec3(0.5 * t, 2, -6);
        let twin = entity("twin");
        twin.kd = vec3(0.2, 0.2, 0.9 - 0.1 * frame_number());
    }
"#;

#[test]
fn the_same_script_renders_the_same_bytes_twice() {
    let first = animate(MOVING, &[0, 1, 2, 3]);
    let second = animate(MOVING, &[0, 1, 2, 3]);
    for (n, (a, b)) in first.iter().zip(&second).enumerate() {
        assert_eq!(a.0.pixels, b.0.pixels, "frame {n} differs between runs");
    }
    assert_ne!(first[0].0.pixels, first[3].0.pixels, "the animation moves");
}

#[test]
fn a_frame_is_the_same_whether_the_range_starts_at_zero_or_at_it() {
    let from_zero = animate(MOVING, &[0, 1, 2, 3, 4, 5]);
    let from_four = animate(MOVING, &[4, 5]);
    assert_eq!(from_zero[4].0.pixels, from_four[0].0.pixels);
    assert_eq!(from_zero[5].0.pixels, from_four[1].0.pixels);
}

#[test]
fn the_grid_is_rebuilt_exactly_on_the_frames_where_something_moved() {
    // Frames 0, 1 and 3 write the ball's current position back (no change); 2 and 4 move it.
    // A material changes every frame, which never needs the grid. The camera is written every
    // frame but moves only at 5: snapshots are relative to the camera, so a moving camera
    // places the geometry anew and rebuilds the grid.
    let source = r#"
        fn frame(t) {
            let n = frame_number();
            let b = entity("ball");
            b.position = vec3(-1.0 + (if n >= 4 { 2.0 } else if n >= 2 { 1.0 } else { 0.0 }), 0.8, 0.0);
            let crate = entity("crate");
            crate.rotation = vec3(0, 0, 0);
            camera.position = vec3(if n >= 5 { 0.1 } else { 0.0 }, 2, -6);
            let twin = entity("twin");
            twin.ks = 0.1 * n;
        }
    "#;
    let frames = animate(source, &[0, 1, 2, 3, 4, 5]);
    let rebuilds: Vec<u64> = frames.iter().map(|(_, r)| *r).collect();
    assert_eq!(rebuilds, [1, 1, 2, 2, 3, 4], "the first frame builds; 2 and 4 rebuild, and 5 (camera)");
}

#[test]
fn hiding_and_showing_an_object_rebuilds_the_grid_and_changes_the_image() {
    let source = "fn frame(t) {\n    let b = entity(\"ball\");\n    b.visible = frame_number() == 1;\n}\n";
    let frames = animate(source, &[0, 1, 2]);
    let rebuilds: Vec<u64> = frames.iter().map(|(_, r)| *r).collect();
    assert_eq!(rebuilds, [1, 2, 3]);
    assert_ne!(frames[0].0.pixels, frames[1].0.pixels);
    assert_eq!(frames[0].0.pixels, frames[2].0.pixels, "hidden again: the same image as frame 0");

    // Hidden from frame 0 equals a scene without the ball.
    let mut without = desc();
    without.objects.retain(|o| o.name.as_deref() != Some("ball"));
    let mut world: SceneWorld = scene::spawn_world(&without);
    let snapshot = world.update();
    assert_eq!(render(&snapshot, &world.render_settings()).0.pixels, frames[0].0.pixels);
}

/// Root-mean-square difference between horizontally and vertically adjacent pixels in a
/// window: how sharp the edges in it are (blurring a step over w pixels divides its squared
/// gradient sum by w; a plain mean of |differences| would not change).
fn local_contrast(film: &Film, centre: (u32, u32), half: u32) -> f32 {
    let luminance = |x: u32, y: u32| film.get(x, y).dot(Vec3::new(0.2126, 0.7152, 0.0722));
    let (mut sum, mut count) = (0.0, 0);
    for y in centre.1 - half..centre.1 + half {
        for x in centre.0 - half..centre.0 + half {
            sum += (luminance(x + 1, y) - luminance(x, y)).powi(2)
                + (luminance(x, y + 1) - luminance(x, y)).powi(2);
            count += 2;
        }
    }
    (sum / count as f32).sqrt()
}

#[test]
fn focus_on_keeps_a_moving_subject_as_sharp_as_a_pinhole_would() {
    // A flat card (a square facing the camera) recedes from 4 to 10 units; the camera looks
    // past it at a wall. With `focus_on` the card's edges stay as sharp as a pinhole's; with
    // the focus left on the wall they blur.
    let scene = r#"Scene(
        camera: (position: (0, 0, -10), look_at: (0, 0, 0), fov_deg: 30, width: 96, height: 96,
                 aperture: 0.4, lens: (samples: 64, pattern: Jittered)),
        settings: (max_depth: 1, background: (0, 0, 0), ambient: (0.3, 0.3, 0.3), seed: 3,
                   aa: (samples: 4, pattern: Jittered)),
        materials: [(name: "white", kd: (1, 1, 1)), (name: "grey", kd: (0.3, 0.3, 0.3))],
        lights: [Directional(direction: (0, 0, 1), intensity: 0.7)],
        objects: [
            (name: "wall", shape: Plane(point: (0, 0, 10), normal: (0, 0, -1)), material: "grey"),
            (name: "card", shape: Polygon(vertices: [(-0.5, -0.5, 0), (0.5, -0.5, 0), (0.5, 0.5, 0), (-0.5, 0.5, 0)]),
             material: "white", transform: (translate: (0, 0, -6))),
        ],
    )"#;
    let desc = scene::parse_scene(scene, "focus-test.ron").unwrap();
    let script = |focus: &str| {
        format!(
            "fn frame(t) {{\n    let card = entity(\"card\");\n    card.position = vec3(0, 0, -6 + 1.5 * frame_number());\n    {focus}\n}}\n"
        )
    };
    let frames = |source: &str, aperture: f64| -> Vec<Film> {
        let source =
            source.replace("fn frame(t) {", &format!("fn frame(t) {{\n    camera.aperture = {aperture};"));
        let script = compile(&source).unwrap();
        let mut animation: Animation = Animation::new(&desc, &script, 24.0).unwrap();
        (0..5)
            .map(|n| {
                let snapshot = animation.step_to(n).unwrap_or_else(|e| panic!("{e}"));
                render(&snapshot, &animation.world().world().render_settings()).0
            })
            .collect()
    };
    let pinhole = frames(&script(""), 0.0);
    let focused = frames(&script("camera.focus_on(\"card\");"), 0.4);
    let on_wall = frames(&script("camera.focus_distance = 20.0;"), 0.4);
    for n in 0..5 {
        // The card's right edge crosses the image centre row at x = 48 + its half width in pixels.
        let depth = 4.0 + 1.5 * n as f32;
        let half_width = 0.5 * 48.0 / (15f32.to_radians().tan() * depth);
        let edge = (48.0 + half_width).round() as u32;
        let window = ((edge, 48), 4);
        let sharp = local_contrast(&pinhole[n], window.0, window.1);
        let kept = local_contrast(&focused[n], window.0, window.1);
        let blurred = local_contrast(&on_wall[n], window.0, window.1);
        assert!((kept - sharp).abs() <= 0.05 * sharp, "frame {n}: focus_on {kept} vs pinhole {sharp}");
        assert!(blurred < 0.7 * sharp, "frame {n}: the control must blur ({blurred} vs {sharp})");
    }
}

#[test]
fn sweeps_declare_parameter_sets_and_apply_them_by_name_or_through_apply() {
    let source = "fn sweep() { product(#{ aperture: [0.0, 0.2], samples: [1, 4] }) }\n";
    let mut world = scripted(source);
    world.setup().unwrap();
    let sets = world.sweep_sets().unwrap();
    assert_eq!(sets.len(), 4);
    world.apply(&sets[3], 3).unwrap();
    world.update();
    let settings = world.world().render_settings();
    assert_eq!(settings.aa.samples, 4, "`samples` is the settings property");
    assert_eq!(world.update().camera.aperture, 0.2);

    let custom = "fn sweep() { [#{ look: 3 }] }\nfn apply(p) { settings.lens_samples = p.look; }\n";
    let mut world = scripted(custom);
    let sets = world.sweep_sets().unwrap();
    world.apply(&sets[0], 0).unwrap();
    world.update();
    assert_eq!(world.world().render_settings().lens.samples, 3);

    let unknown = "fn sweep() { [#{ zoom: 2 }] }\n";
    let mut world = scripted(unknown);
    let sets = world.sweep_sets().unwrap();
    let e = world.apply(&sets[0], 0).unwrap_err();
    assert!(e.message.contains("unknown parameter `zoom`"), "{e}");
    let bad = "fn sweep() { [1, 2] }\n";
    let e = scripted(bad).sweep_sets().unwrap_err();
    assert!(e.message.contains("element 0 is not an object map"), "{e}");
}

#[test]
fn an_animation_needs_a_frame_function() {
    let script = compile("fn setup() { }\n").unwrap();
    let e = Animation::<penumbra::store::SoaStore>::new(&desc(), &script, 24.0).err().expect("no frame()");
    assert_eq!(e.kind, ErrorKind::MissingFunction);
    assert!(e.to_string().contains("fn frame(t)"), "{e}");
}

/// The text of a script error's message, checked for Rhai's internal wording.
fn plain(e: &ScriptError) -> &str {
    for internal in ["registered", "getter", "setter", "Expression cannot be assigned"] {
        assert!(!e.message.contains(internal), "Rhai's internals leak into the message: {e}");
    }
    &e.message
}

#[test]
fn an_unknown_property_names_the_object_suggests_the_closest_and_lists_them() {
    let cases = [
        // (statement, what the message must hold), each at line 2.
        (
            "camera.positon = vec3(0, 2, -6)",
            "camera has no property `positon`; did you mean `position`? camera has: position, look_at, up, \
             fov, aperture, focus_distance; methods: focus_on(name)",
        ),
        ("let f = camera.fvo", "camera has no property `fvo`; did you mean `fov`?"),
        (
            "settings.sample = 4",
            "settings has no property `sample`; did you mean `samples`? settings has: samples,",
        ),
        (
            "let b = entity(\"ball\"); b.color = vec3(1, 0, 0)",
            "entity has no property `color`; did you mean `colour`?",
        ),
        (
            "let b = entity(\"ball\"); b.weight = 3",
            "entity has no property `weight`; entity has: position, rotation,",
        ),
        ("let b = entity(\"ball\"); b.centre = vec3(0, 0, 0)", "entity.centre can be read but not written;"),
        ("let v = vec3(1, 2, 3); v.w = 4", "vec3 has no property `w`; vec3 has: x, y, z"),
        ("camera.position = 5", "camera.position must be a vec3, e.g. vec3(0, 1, 2), got i64"),
    ];
    for (statement, message) in cases {
        let source = format!("fn frame(t) {{\n    {statement};\n}}\n");
        let e = frame_error(&source, Limits::default());
        assert_eq!((e.kind.clone(), e.line), (ErrorKind::Runtime, Some(2)), "{statement}: {e}");
        assert!(e.column.is_some(), "{e}");
        assert!(plain(&e).contains(message), "{statement}: expected `{message}` in {e}");
        assert!(e.to_string().starts_with("test.rhai:2:"), "{e}");
    }
}

#[test]
fn assigning_to_a_property_of_an_entity_call_shows_how_to_write_it() {
    let source = "fn frame(t) {\n    entity(\"ball\").kd = vec3(0.1, 0.8, 0.1);\n}\n";
    let e = compile(source).err().expect("Rhai cannot assign to a call's property");
    assert_eq!((e.kind.clone(), e.line), (ErrorKind::Syntax, Some(2)), "{e}");
    let wanted = "let ball = entity(\"ball\"); ball.kd = …;";
    assert!(plain(&e).contains("`entity(\"ball\").kd` cannot be assigned to directly"), "{e}");
    assert!(e.message.contains(wanted), "{e}");

    // What the message says to write works.
    let fixed = format!("fn frame(t) {{\n    {}\n}}\n", wanted.replace('…', "vec3(0.1, 0.8, 0.1)"));
    let mut world = scripted(&fixed);
    world.setup().and_then(|_| world.frame(Clock::at(0, 24.0))).unwrap_or_else(|e| panic!("{fixed}: {e}"));
    let ball = world.world_mut().entity("ball").unwrap();
    let w = world.world().world();
    let id = w.get::<penumbra::world::components::MaterialRef>(ball).unwrap().0;
    let kd = w.resource::<penumbra::world::resources::Materials>().table[id.0 as usize].kd;
    assert_eq!(kd, Vec3::new(0.1, 0.8, 0.1));

    // A name that is no identifier gets a plain variable; other expressions get the general rule.
    let e = compile("fn frame(t) {\n    entity(\"red ball\").visible = false;\n}\n").err().unwrap();
    assert!(e.message.contains("let e = entity(\"red ball\"); e.visible = …;"), "{e}");
    let e = compile("fn frame(t) {\n    vec3(1, 2, 3).x = 4;\n}\n").err().unwrap();
    assert!(plain(&e).contains("only a variable or a variable's property can be"), "{e}");
}

/// Renders frame `n` of `source` over `scene` (frames before it run the script only).
fn frame_of(scene: &SceneDesc, source: &str, n: u32) -> Film {
    let script = compile(source).expect("compiles");
    let mut animation: Animation = Animation::new(scene, &script, 24.0).unwrap_or_else(|e| panic!("{e}"));
    let snapshot = animation.step_to(n).unwrap_or_else(|e| panic!("{e}"));
    render(&snapshot, &animation.world().world().render_settings()).0
}

#[test]
fn a_script_animates_a_lights_colour_and_intensity_as_the_scene_file_would_set_them() {
    // The test scene's key light is white at intensity 0.9; the script reads that, then turns
    // it red-orange and brighter from frame 1 and switches the sun off at frame 2.
    let source = r#"
        fn frame(t) {
            let key = entity("light_0");
            let sun = entity("light_1");
            if frame_number() == 0 {
                if key.colour != vec3(1, 1, 1) || abs(key.intensity - 0.9) > 1e-6 || abs(sun.intensity - 0.2) > 1e-6 {
                    throw `the lights read ${key.colour} × ${key.intensity} and ${sun.intensity}`;
                }
            }
            if frame_number() >= 1 { key.colour = vec3(1, 0.25, 0.5); key.intensity = 1.5; }
            if frame_number() >= 2 { sun.intensity = 0; }
        }
    "#;
    let lit = |key: &str, sun: &str| {
        let text = SCENE
            .replace("Point(position: (-3, 6, -4), intensity: 0.9)", key)
            .replace("Directional(direction: (1, -1, 1), intensity: 0.2)", sun);
        assert_ne!(text, SCENE);
        scene::parse_scene(&text, "lit.ron").unwrap()
    };
    let key = "Point(position: (-3, 6, -4), colour: (1, 0.25, 0.5), intensity: 1.5)";
    let sun = "Directional(direction: (1, -1, 1), intensity: 0.2)";
    let off = "Directional(direction: (1, -1, 1), intensity: 0)";
    let frames: Vec<Film> = (0..3).map(|n| frame_of(&desc(), source, n)).collect();
    assert_ne!(frames[0].pixels, frames[1].pixels, "the light changed");
    assert_ne!(frames[1].pixels, frames[2].pixels, "the sun went out");
    // Each frame is the frame the scene file with those lights makes.
    let still = "fn frame(t) { }";
    assert_eq!(frames[0].pixels, frame_of(&desc(), still, 0).pixels);
    assert_eq!(frames[1].pixels, frame_of(&lit(key, sun), still, 1).pixels);
    assert_eq!(frames[2].pixels, frame_of(&lit(key, off), still, 2).pixels);
}

#[test]
fn bad_light_values_break_the_scene_files_rules_at_the_scripts_line() {
    let cases = [
        ("key.intensity = -2", "Point(position: (-3, 6, -4), intensity: -2)"),
        ("key.colour = vec3(1, -0.5, 0)", "Point(position: (-3, 6, -4), colour: (1, -0.5, 0))"),
    ];
    for (statement, light) in cases {
        let text = SCENE.replace("Point(position: (-3, 6, -4), intensity: 0.9)", light);
        let rule = match scene::parse_scene(&text, "bad.ron") {
            Err(scene::SceneError::Invalid { rule, .. }) => rule,
            other => panic!("{light}: the scene must be refused, got {other:?}"),
        };
        let field = statement.split(['.', ' ']).nth(1).unwrap();
        let source = format!("fn frame(t) {{\n    let key = entity(\"light_0\");\n    {statement};\n}}\n");
        let e = frame_error(&source, Limits::default());
        assert_eq!((e.kind.clone(), e.line), (ErrorKind::Runtime, Some(3)), "{statement}: {e}");
        let expected = format!("entity `light_0`: {field} {rule}");
        assert!(e.message.contains(&expected), "{statement}: expected `{expected}` in {e}");
    }
    let e = frame_error(
        "fn frame(t) {\n    let b = entity(\"ball\");\n    b.intensity = 2;\n}\n",
        Limits::default(),
    );
    assert!(e.message.contains("entity `ball` is an object: it has no intensity"), "{e}");
    let e = frame_error(
        "fn frame(t) {\n    let key = entity(\"light_0\");\n    key.colour = 0.5;\n}\n",
        Limits::default(),
    );
    assert!(e.message.contains("entity `light_0`: colour must be a vec3"), "{e}");
}

#[test]
fn an_error_in_a_replayed_frame_still_stops_the_run() {
    // Frames replayed to reach a later one run with their output muted, not their errors.
    let source = "fn frame(t) {\n    if frame_number() < 3 { throw `replayed ${frame_number()}`; }\n}\n";
    let script = compile(source).unwrap();
    let mut animation: Animation = Animation::new(&desc(), &script, 24.0).unwrap();
    let e = animation.step_to(3).expect_err("frames 0..3 throw");
    assert_eq!(
        e.context.as_deref(),
        Some("frame(0) at frame 0"),
        "errors of replayed frames still stop the run"
    );
}

/// A value a script writes and the same value in a scene file are checked by one rule and
/// refused in the same words: the script's message ends with the rule the file's error gives.
#[test]
fn a_script_write_and_a_scene_file_value_break_the_same_rule_in_the_same_words() {
    let cases = [
        ("camera.fov = 200.0;", "fov_deg: 45", "fov_deg: 200"),
        ("camera.aperture = -1.0;", "fov_deg: 45", "fov_deg: 45, aperture: -1"),
        (
            "let b = entity(\"ball\"); b.kd = vec3(1.5, 0.1, 0.1);",
            "kd: (0.8, 0.1, 0.1)",
            "kd: (1.5, 0.1, 0.1)",
        ),
        ("let b = entity(\"ball\"); b.shininess = -2.0;", "shininess: 30", "shininess: -2"),
        ("let b = entity(\"ball\"); b.shininess = 2e4;", "shininess: 30", "shininess: 2e4"),
        ("let b = entity(\"ball\"); b.ks = 1.5;", "ks: 0.4", "ks: 1.5"),
        ("let b = entity(\"ball\"); b.ior = 0.0;", "ks: 0.4", "ks: 0.4, ior: 0"),
        ("let b = entity(\"ball\"); b.kt = 0.5; b.kr = 0.7;", "ks: 0.4", "ks: 0.4, kt: 0.5, kr: 0.7"),
        ("camera.focus_distance = 0.0;", "fov_deg: 45", "fov_deg: 45, focus_distance: 0"),
        ("camera.up = vec3(0.0, -3.0, 12.0);", "fov_deg: 45", "fov_deg: 45, up: (0, -3, 12)"),
        ("settings.width = 0;", "width: 40", "width: 0"),
        ("settings.max_depth = 65;", "max_depth: 3", "max_depth: 65"),
        ("settings.samples = 5000;", "seed: 5", "seed: 5, aa: (samples: 5000)"),
        ("let k = entity(\"light_0\"); k.intensity = -1.0;", "intensity: 0.9", "intensity: -1"),
        (
            "let k = entity(\"light_0\"); k.colour = vec3(1.0, -0.5, 1.0);",
            "intensity: 0.9",
            "intensity: 0.9, colour: (1, -0.5, 1)",
        ),
    ];
    for (write, from, to) in cases {
        let file = SCENE.replacen(from, to, 1);
        assert_ne!(file, SCENE, "{to}");
        let Err(scene::SceneError::Invalid { rule, .. }) = scene::parse_scene(&file, "same.ron") else {
            panic!("the file with `{to}` must be refused");
        };
        let e = frame_error(&format!("fn frame(t) {{ {write} }}"), Limits::default());
        assert!(e.message.ends_with(&rule), "script `{write}`: `{}`\nfile `{to}`: `{rule}`", e.message);
    }
}
