//! Camera-relative snapshots: positions are authored in f64 and each frame is placed relative
//! to the camera before rounding to f32, so a scene far from the origin renders like the same
//! scene at the origin, a camera moving by less than f32's step out there still moves, and a
//! scripted frame rendered alone equals the same frame rendered in sequence.
//!
//! Run with `--nocapture` to see the measured differences.

use glam::DVec3;
use penumbra::film::encode_srgb8;
use penumbra::film::Film;
use penumbra::scene::{
    default_scene, parse_scene, spawn_world, LightDesc, SceneDesc, ShapeDesc, DEFAULT_SCENE_SOURCE,
};
use penumbra::script::{Animation, Limits, Script};
use penumbra::trace::render;
use penumbra::world::SceneWorld;

/// Image size: small enough to render in well under a second in release.
const SIZE: (u32, u32) = (200, 150);

/// The default scene at [`SIZE`], moved by `d` in world space: the camera's position, look-at
/// point and focus point, every light's position, corner or centre, and every object, through
/// its shape's positions when its transform is a pure translation (the spheres and the floor
/// of the default scene) and through `transform.translate` otherwise (the rotated, scaled box).
fn translated(d: DVec3) -> SceneDesc {
    let mut desc = default_scene();
    (desc.camera.width, desc.camera.height) = SIZE;
    desc.camera.position += d;
    desc.camera.look_at += d;
    desc.camera.focus_on = desc.camera.focus_on.map(|p| p + d);
    for light in &mut desc.lights {
        match light {
            LightDesc::Spot { position: p, look_at, .. } => {
                *p += d;
                *look_at += d;
            }
            LightDesc::Point { position: p, .. }
            | LightDesc::Rect { corner: p, .. }
            | LightDesc::Disk { centre: p, .. } => *p += d,
            LightDesc::Directional { .. } => {}
        }
    }
    for object in &mut desc.objects {
        let t = &mut object.transform;
        let moves_alone = t.rotate_deg == glam::Vec3::ZERO && t.scale == glam::Vec3::ONE;
        match &mut object.shape {
            ShapeDesc::Sphere { centre: p, .. } | ShapeDesc::Plane { point: p, .. } if moves_alone => *p += d,
            ShapeDesc::Triangle { vertices } if moves_alone => vertices.iter_mut().for_each(|v| *v += d),
            ShapeDesc::Polygon { vertices } if moves_alone => vertices.iter_mut().for_each(|v| *v += d),
            ShapeDesc::Cuboid { min, max } if moves_alone => (*min, *max) = (*min + d, *max + d),
            _ => t.translate += d,
        }
    }
    desc
}

/// The scene rendered at its settings, as linear values.
fn film(desc: &SceneDesc) -> Film {
    let mut world: SceneWorld = spawn_world(desc);
    let snapshot = world.update();
    render(&snapshot, &world.render_settings()).0
}

/// The scene rendered at its settings, as 8-bit sRGB bytes.
fn image(desc: &SceneDesc) -> Vec<u8> {
    encode_srgb8(&film(desc))
}

/// How two images differ: the share of pixels with some channel off by more than 1/255, and
/// the largest difference of any channel, in 1/255 steps.
fn difference(a: &[u8], b: &[u8]) -> (f64, u8) {
    assert_eq!(a.len(), b.len());
    let pixels = a.len() / 3;
    let channel = |i: usize| a[i].abs_diff(b[i]);
    let off = (0..pixels).filter(|&p| (0..3).any(|c| channel(3 * p + c) > 1)).count();
    let max = (0..a.len()).map(channel).max().unwrap_or(0);
    (off as f64 / pixels as f64, max)
}

/// Asserts the 1/255-on-99.9 %-of-pixels rule, and reports the measurement.
fn assert_close(reference: &[u8], image: &[u8], what: &str) {
    let (off, max) = difference(reference, image);
    eprintln!(
        "{what}: {:.4} % of pixels differ by more than 1/255; largest difference {max}/255",
        100.0 * off
    );
    assert!(off <= 1e-3, "{what}: {:.4} % of pixels differ by more than 1/255", 100.0 * off);
}

#[test]
fn the_default_scene_moved_a_million_units_renders_like_it_does_at_the_origin() {
    let home = film(&translated(DVec3::ZERO));
    assert!(home.pixels == film(&default_scene_at_size()).pixels, "a zero move changes nothing");
    for d in [DVec3::splat(1e6), DVec3::new(1e6, 0.0, 0.0), DVec3::new(0.0, 0.0, 1e6)] {
        let far = film(&translated(d));
        assert_close(&encode_srgb8(&home), &encode_srgb8(&far), &format!("moved by {d}"));
        let linear = home.pixels.iter().zip(&far.pixels).map(|(a, b)| (*a - *b).abs().max_element());
        eprintln!("moved by {d}: largest linear difference {:e}", linear.fold(0.0, f32::max));
    }
}

#[test]
fn a_scene_file_keeps_every_digit_of_a_far_position() {
    let text = DEFAULT_SCENE_SOURCE.replace("position: (0.0, 2.2, -7.5)", "position: (1000000.1, 2.2, -7.5)");
    assert_ne!(text, DEFAULT_SCENE_SOURCE);
    let desc = parse_scene(&text, "far.ron").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(desc.camera.position.x, 1000000.1);
    assert_ne!(desc.camera.position.x as f32 as f64, 1000000.1, "f32 would have lost the .1");
}

#[test]
fn smaller_and_mixed_moves_render_like_the_origin_too() {
    let home = image(&translated(DVec3::ZERO));
    for d in [
        DVec3::new(1e3, 0.0, 0.0),
        DVec3::new(0.0, 1e5, 0.0),
        DVec3::splat(-1e6),
        DVec3::new(-1e6, 1e6, -1e6),
        DVec3::new(-723_456.789, 1e5 + 0.3, 987_654.321),
    ] {
        assert_close(&home, &image(&translated(d)), &format!("moved by {d}"));
    }
}

#[test]
fn rounding_the_positions_to_f32_at_a_million_would_fail_the_same_check() {
    // The check above can fail: the same scene with its positions first rounded to f32 (steps
    // of 1/16 at 1e6, what an f32 World held) is visibly different from the scene at home.
    let mut rounded = translated(DVec3::splat(1e6));
    let f32_at = |p: &mut DVec3| *p = p.as_vec3().as_dvec3();
    f32_at(&mut rounded.camera.position);
    f32_at(&mut rounded.camera.look_at);
    for object in &mut rounded.objects {
        match &mut object.shape {
            ShapeDesc::Sphere { centre: p, .. } | ShapeDesc::Plane { point: p, .. } => f32_at(p),
            _ => f32_at(&mut object.transform.translate),
        }
    }
    let (off, max) = difference(&image(&translated(DVec3::ZERO)), &image(&rounded));
    eprintln!("rounded to f32 at 1e6: {:.4} % of pixels off, largest {max}/255", 100.0 * off);
    assert!(off > 1e-3, "rounding to f32 at 1e6 should move edges by about a pixel");
}

#[test]
fn a_camera_move_finer_than_f32_s_step_at_a_million_still_moves_the_image() {
    let d = DVec3::new(1e6, 0.0, 0.0);
    assert_eq!((1e6 + 0.01) as f32, 1e6f32, "in f32 the move would vanish");
    let step = DVec3::new(0.01, 0.0, 0.0);
    let far = translated(d);
    let mut nudged = far.clone();
    nudged.camera.position += step;
    nudged.camera.look_at += step;
    let (far_image, nudged_image) = (image(&far), image(&nudged));
    assert!(far_image != nudged_image, "a 0.01 camera move at 1e6 must change the image");
    // And it changes it the way the same move does at the origin.
    let mut nudged_home = translated(DVec3::ZERO);
    nudged_home.camera.position += step;
    nudged_home.camera.look_at += step;
    assert_close(&image(&nudged_home), &nudged_image, "a 0.01 camera move at 1e6 against at home");
}

#[test]
fn a_far_scene_renders_the_same_bytes_on_one_and_two_threads() {
    let mut world: SceneWorld = spawn_world(&translated(DVec3::new(-1e6, 1e5, 1e6)));
    let snapshot = world.update();
    let settings = world.render_settings();
    let bytes = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
        encode_srgb8(&pool.install(|| render(&snapshot, &settings)).0)
    };
    assert!(bytes(1) == bytes(2), "thread counts disagree");
}

/// A fly-through far from the origin: the camera creeps along x by 0.004 per frame (a
/// sixteenth of f32's step at 1e6) and a ball moves too.
const FLY: &str = r#"
    fn frame(t) {
        let n = frame_number();
        camera.position = vec3(1000000.0 + 0.004 * n, 1000002.2, 999992.5);
        camera.look_at = vec3(1000000.0 + 0.004 * n, 1000000.9, 1000000.0);
        let ball = entity("red_ball");
        ball.position = vec3(0.0005 * n, 0.0, 0.0);
    }
"#;

#[test]
fn a_scripted_far_frame_rendered_alone_equals_the_same_frame_in_sequence() {
    let desc = translated(DVec3::splat(1e6));
    let script = Script::from_source("fly.rhai", FLY, Limits::default()).expect("compiles");
    let frames = |wanted: &[u32]| {
        let mut animation: Animation = Animation::new(&desc, &script, 24.0).expect("frame() exists");
        let images: Vec<Vec<u8>> = wanted
            .iter()
            .map(|&n| {
                let snapshot = animation.step_to(n).expect("the script runs");
                encode_srgb8(&render(&snapshot, &animation.world().world().render_settings()).0)
            })
            .collect();
        (images, animation.world().world().grid_rebuilds())
    };
    let (sequence, rebuilds) = frames(&[0, 1, 2, 3]);
    assert_eq!(rebuilds, 4, "a moving camera rebuilds the top-level grid every frame");
    for pair in sequence.windows(2) {
        assert!(pair[0] != pair[1], "consecutive frames differ: the camera moved by 0.004 at 1e6");
    }
    let (alone, _) = frames(&[3]);
    assert!(alone[0] == sequence[3], "frame 3 alone equals frame 3 after frames 0 to 2");
    let (resumed, _) = frames(&[2, 3]);
    assert!(resumed == sequence[2..], "a run resumed at frame 2 gives the same frames");
}

#[test]
fn a_still_camera_far_out_reuses_the_grid() {
    let mut world: SceneWorld = spawn_world(&translated(DVec3::splat(1e6)));
    let first = world.update();
    let second = world.update();
    assert_eq!(world.grid_rebuilds(), 1, "nothing moved, the camera included");
    assert!(std::sync::Arc::ptr_eq(&first.grid, &second.grid));
    world.world_mut().resource_mut::<penumbra::world::resources::CameraRig>().position.x += 0.01;
    world.update();
    assert_eq!(world.grid_rebuilds(), 2, "the camera moved: the geometry is placed anew");
}

/// The default scene at [`SIZE`], untouched.
fn default_scene_at_size() -> SceneDesc {
    let mut desc = default_scene();
    (desc.camera.width, desc.camera.height) = SIZE;
    desc
}
