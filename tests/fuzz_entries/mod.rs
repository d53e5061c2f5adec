//! The fuzz targets' bodies, shared by `fuzz/fuzz_targets/*.rs` (through `#[path]`) and by
//! `tests/fuzz_regressions.rs`, so a regression test runs exactly the code that crashed.
//!
//! Each entry takes arbitrary bytes and returns `Ok` when the input was accepted or the error
//! message when it was refused. It panics (the fuzzer's "crash") when an input is accepted but
//! produces something invalid, or refused with a message that does not name its file.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::time::Duration;

use penumbra::accel::MESH_LAMBDA;
use penumbra::scene::obj::parse_obj;
use penumbra::scene::LightDesc;
use penumbra::scene::{parse_scene_at, spawn_world, SceneDesc};
use penumbra::script::{Animation, Limits, Script};
use penumbra::store::{MeshAsset, SoaStore};
use penumbra::world::components::WorldAabb;

/// Meshes above this many triangles are only parsed, not built (keeps each execution fast).
pub const MAX_BUILT_TRIANGLES: usize = 10_000;

/// A folder that does not exist: `Mesh(file: ...)` references in fuzzed scenes resolve against
/// it and fail cleanly, and nothing is left behind in the temporary folder.
fn empty_dir() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| std::env::temp_dir().join("penumbra-fuzz-no-meshes-here"))
}

/// Every object the World indexes has finite bounds (an accepted value must never overflow the
/// World's 32-bit floats), and none is NaN.
pub fn check_bounds(world: &bevy_ecs::world::World) {
    let mut aabbs = world.try_query::<&WorldAabb>().expect("WorldAabb is registered");
    for aabb in aabbs.iter(world) {
        let b = aabb.0;
        assert!(!b.min.is_nan() && !b.max.is_nan(), "NaN bounds {b:?}");
        if aabb.is_bounded() {
            assert!(b.min.is_finite() && b.max.is_finite(), "non-finite bounds {b:?}");
        }
    }
}

/// Target `scene`: the bytes as a RON scene file `fuzz.ron`. Parsing and validation return a
/// scene or an error naming `fuzz.ron`; a scene that passes spawns into a World and updates once
/// (no render: a valid scene may ask for a 16384-pixel-wide image).
pub fn scene(data: &[u8]) -> Result<(), String> {
    let text = String::from_utf8_lossy(data);
    match parse_scene_at(&text, "fuzz.ron", empty_dir()) {
        Ok(desc) => {
            let mut world = spawn_world::<SoaStore>(&desc);
            world.update();
            check_bounds(world.world());
            Ok(())
        }
        Err(error) => {
            let message = error.to_string();
            assert!(message.contains("fuzz.ron"), "the error does not name the file: {message}");
            Err(message)
        }
    }
}

/// Target `render`: the bytes as a RON scene file `fuzz.ron`, accepted scenes rendered end to
/// end at a tiny size with every sample count small (at most 8×6 pixels, 4 samples of each
/// effect, adaptive depth 2, ray depth 6). The film must be finite without dropping a single
/// sample: a non-finite sample is a numerical gap that legal input reached.
pub fn render(data: &[u8]) -> Result<(), String> {
    let text = String::from_utf8_lossy(data);
    let mut desc = match parse_scene_at(&text, "fuzz.ron", empty_dir()) {
        Ok(desc) => desc,
        Err(error) => {
            let message = error.to_string();
            assert!(message.contains("fuzz.ron"), "the error does not name the file: {message}");
            return Err(message);
        }
    };
    shrink(&mut desc);
    let mut world = spawn_world::<SoaStore>(&desc);
    let snapshot = world.update();
    let settings = world.render_settings();
    let (film, stats) = penumbra::trace::render(&snapshot, &settings);
    assert_eq!(stats.dropped.samples, 0, "non-finite samples: {:?}", stats.dropped);
    assert!(film.pixels.iter().all(|c| c.is_finite()), "a non-finite pixel");
    Ok(())
}

/// Makes an accepted scene cheap to render without making it easier: the size and the sample
/// counts only go down (every rule still holds), the geometry, materials and lights stay.
pub fn shrink(desc: &mut SceneDesc) {
    desc.camera.width = desc.camera.width.min(8);
    desc.camera.height = desc.camera.height.min(6);
    desc.camera.lens.samples = desc.camera.lens.samples.min(4);
    desc.settings.aa.samples = desc.settings.aa.samples.min(4);
    desc.settings.glossy.samples = desc.settings.glossy.samples.min(4);
    desc.settings.max_depth = desc.settings.max_depth.min(6);
    if let Some(adaptive) = desc.settings.adaptive.as_mut() {
        adaptive.max_depth = adaptive.max_depth.min(2);
    }
    for light in &mut desc.lights {
        if let LightDesc::Rect { samples, .. } | LightDesc::Disk { samples, .. } = light {
            *samples = (*samples).min(4);
        }
    }
}

/// Target `obj`: the bytes as a Wavefront OBJ file `fuzz.obj`, parsed smooth and flat. Errors
/// start with `fuzz.obj:`; every normal of a mesh that parses is finite and unit, and a small
/// mesh with finite bounds builds its `MeshAsset` (Morton order, grid) with unit normals too.
pub fn obj(data: &[u8]) -> Result<(), String> {
    let text = String::from_utf8_lossy(data);
    for smooth in [true, false] {
        let mesh = match parse_obj(&text, Path::new("fuzz.obj"), smooth) {
            Ok(mesh) => mesh,
            Err(error) => {
                let message = error.to_string();
                assert!(message.starts_with("fuzz.obj:"), "the error does not name the file: {message}");
                return Err(message);
            }
        };
        check_unit(&mesh.normals, "parsed");
        assert!(
            mesh.normals.is_empty() || mesh.normals.len() == mesh.positions.len(),
            "one normal per vertex"
        );
        let b = mesh.bounds;
        if mesh.triangle_count() <= MAX_BUILT_TRIANGLES && b.min.is_finite() && b.max.is_finite() {
            let asset = MeshAsset::new("fuzz", mesh, MESH_LAMBDA);
            check_unit(&asset.data.normals, "built");
        }
    }
    Ok(())
}

fn check_unit(normals: &[penumbra::math::Vec3], stage: &str) {
    for (i, n) in normals.iter().enumerate() {
        assert!(n.is_finite() && (n.length() - 1.0).abs() <= 1e-3, "{stage} normal {i} is not unit: {n:?}");
    }
}

/// The stage scripts run against: `scenes/flythrough.ron`, compiled in.
fn stage() -> &'static SceneDesc {
    static STAGE: OnceLock<SceneDesc> = OnceLock::new();
    STAGE.get_or_init(|| {
        let text = include_str!("../../scenes/flythrough.ron");
        parse_scene_at(text, "flythrough.ron", empty_dir()).expect("scenes/flythrough.ron loads")
    })
}

/// Tight limits: a runaway script stops in milliseconds instead of seconds.
pub fn script_limits() -> Limits {
    Limits {
        max_operations: 50_000,
        max_string_size: 4096,
        max_array_size: 4096,
        max_map_size: 1024,
        time_limit: Duration::from_secs(1),
        ..Limits::default()
    }
}

/// Target `script`: the bytes as a Rhai animation script `fuzz.rhai` on the flythrough stage.
/// Compiling, `setup()` and frames 0 and 1 succeed or fail with an error naming `fuzz.rhai`.
pub fn script(data: &[u8]) -> Result<(), String> {
    let source = String::from_utf8_lossy(data);
    let run = || -> Result<(), String> {
        let script = Script::from_source("fuzz.rhai", &source, script_limits()).map_err(|e| e.to_string())?;
        let mut animation = Animation::<SoaStore>::new(stage(), &script, 24.0).map_err(|e| e.to_string())?;
        for frame in [0, 1] {
            animation.step_to(frame).map_err(|e| e.to_string())?;
            check_bounds(animation.world().world().world());
        }
        Ok(())
    };
    run().inspect_err(|message| {
        assert!(message.contains("fuzz.rhai"), "the error does not name the file: {message}");
    })
}
