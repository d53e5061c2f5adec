//! Noise-driven adaptive sampling: a flat image takes the minimum everywhere, samples gather
//! in a soft shadow's penumbra, the estimated error tracks the true error against a
//! high-sample reference, a lower target costs more and errs less, a time limit stops after a
//! complete round, and the bits do not depend on the thread count.

use penumbra::film::metrics::rmse;
use penumbra::film::{AovSet, Film};
use penumbra::sample::Pattern;
use penumbra::scene::{self, LightDesc, NoiseSettings, SceneDesc};
use penumbra::simd::SimdLevel;
use penumbra::trace::{render, render_with_aovs, NoiseStop, RenderSettings, RenderStats};
use penumbra::world::SceneWorld;

/// The soft shadow of a square light behind an edge: a wall's top edge shades half the floor
/// seen from above, with a penumbra between. `light` shadow samples, `aa` camera samples.
fn penumbra_scene(aa: u32, light: u32) -> SceneDesc {
    let text = format!(
        r#"Scene(
    camera: (position: (0, 6, -0.01), look_at: (0, 0, 0), fov_deg: 50, width: 24, height: 24),
    settings: (max_depth: 0, background: (0, 0, 0), ambient: (0.05, 0.05, 0.05), seed: 11,
               aa: (samples: {aa}, pattern: Jittered)),
    materials: [(name: "white", kd: (0.9, 0.9, 0.9), ks: 0)],
    lights: [Rect(corner: (-0.5, 4, -0.5), edge_u: (1, 0, 0), edge_v: (0, 0, 1), intensity: 1,
                  samples: {light})],
    objects: [
        (name: "floor", shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "white"),
        (name: "wall", shape: Box(min: (0, 0, -3), max: (0.05, 2, 3)), material: "white"),
    ],
)"#
    );
    scene::parse_scene(&text, "penumbra.ron").expect("test scene is valid")
}

fn with_noise(mut desc: SceneDesc, noise: NoiseSettings) -> SceneDesc {
    desc.settings.noise = Some(noise);
    desc
}

fn rendered(desc: &SceneDesc, threads: usize) -> (Film, RenderStats) {
    let mut world: SceneWorld = scene::spawn_world(desc);
    let snapshot = world.update();
    let settings = world.render_settings();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
    pool.install(|| render(&snapshot, &settings))
}

fn bits(film: &Film) -> Vec<u32> {
    film.pixels.iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect()
}

#[test]
fn a_flat_image_takes_the_minimum_everywhere_in_one_round() {
    let mut desc = penumbra_scene(4, 4);
    desc.objects.clear();
    desc.settings.background = glam::Vec3::new(0.3, 0.4, 0.5);
    let (film, stats) =
        rendered(&with_noise(desc, NoiseSettings { min_samples: 8, ..NoiseSettings::default() }), 2);
    let n = &stats.noise;
    assert_eq!((n.rounds, n.batch, n.samples_min, n.samples_max), (1, 4, 8, 8));
    assert_eq!((n.stopped_by, n.estimated_rmse, n.pixels_above_target), (NoiseStop::Target, 0.0, 0));
    assert!(film.pixels.iter().all(|&c| c == glam::Vec3::new(0.3, 0.4, 0.5)));
    assert_eq!(stats.rays.camera, 24 * 24 * 8);
}

#[test]
fn samples_gather_in_the_penumbra() {
    let desc =
        with_noise(penumbra_scene(1, 4), NoiseSettings { target_error: 0.01, ..NoiseSettings::default() });
    let mut world: SceneWorld = scene::spawn_world(&desc);
    let snapshot = world.update();
    let wanted = AovSet { cost: true, ..AovSet::default() };
    let (film, aovs, stats) = render_with_aovs(&snapshot, &world.render_settings(), wanted);
    let cost = aovs.and_then(|a| a.cost).expect("cost AOV");
    // Looking straight down, a column of pixels is 0.23 units of floor wide: the penumbra (and
    // the wall's top) lies within 0.5 of the middle, the light falls unoccluded beyond 1.2.
    let column_cost = |near: bool| {
        let (mut rays, mut pixels) = (0u64, 0u64);
        for (i, &c) in cost.iter().enumerate() {
            let x = ((i % 24) as f32 + 0.5 - 12.0) * 5.6 / 24.0;
            if (near && x.abs() < 0.5) || (!near && x.abs() > 1.2) {
                (rays, pixels) = (rays + u64::from(c), pixels + 1);
            }
        }
        rays as f64 / pixels as f64
    };
    let (soft, lit) = (column_cost(true), column_cost(false));
    assert!(soft > 2.0 * lit, "rays per pixel: penumbra {soft}, unoccluded {lit}");
    assert!(film.pixels.iter().all(|c| c.is_finite()));
    assert!(stats.noise.samples_max > 4 * stats.noise.samples_min, "{:?}", stats.noise);
    assert!(stats.noise.rounds > 1);
    // The cost AOV adds up to every ray traced.
    assert_eq!(cost.iter().map(|&c| u64::from(c)).sum::<u64>(), stats.rays.total());
}

#[test]
fn the_estimated_error_tracks_the_true_error_and_a_lower_target_costs_more() {
    let reference = rendered(&penumbra_scene(64, 1024), 2).0;
    let mut last: Option<(f64, u64)> = None;
    for target in [0.04, 0.02, 0.01] {
        let noise = NoiseSettings {
            target_error: target,
            min_samples: 4,
            max_samples: 4096,
            ..NoiseSettings::default()
        };
        let (film, stats) = rendered(&with_noise(penumbra_scene(1, 4), noise), 2);
        let truth = rmse(&film, &reference).unwrap();
        let estimate = stats.noise.estimated_rmse;
        assert!(
            (0.75..=1.25).contains(&(estimate / truth)),
            "target {target}: estimated RMSE {estimate:.3e} against true {truth:.3e}"
        );
        assert_eq!(stats.noise.stopped_by, NoiseStop::Target);
        let rays = stats.rays.total();
        if let Some((error, cost)) = last {
            assert!(
                truth < error && rays > cost,
                "target {target}: error {truth} ({rays} rays) against {error} ({cost})"
            );
        }
        last = Some((truth, rays));
    }
}

#[test]
fn a_time_limit_stops_after_a_complete_round() {
    let noise = NoiseSettings { target_error: 0.0, time_limit: Some(1e-9), ..NoiseSettings::default() };
    let (film, stats) = rendered(&with_noise(penumbra_scene(1, 4), noise), 2);
    assert_eq!((stats.noise.rounds, stats.noise.stopped_by), (1, NoiseStop::TimeLimit));
    assert_eq!((stats.noise.samples_min, stats.noise.samples_max), (16, 16), "round 0 always completes");
    assert!(film.pixels.iter().all(|c| c.is_finite()));
    // Without a limit and a target of 0, every pixel goes to the maximum.
    let noise = NoiseSettings { target_error: 0.0, max_samples: 64, ..NoiseSettings::default() };
    let (_, stats) = rendered(&with_noise(penumbra_scene(1, 4), noise), 2);
    assert_eq!((stats.noise.samples_min, stats.noise.stopped_by), (64, NoiseStop::MaxSamples));
}

#[test]
fn rounds_stop_the_render_and_a_time_limited_render_equals_its_rounds() {
    let rounds = NoiseSettings { target_error: 0.0, rounds: Some(3), ..NoiseSettings::default() };
    let (_, stats) = rendered(&with_noise(penumbra_scene(1, 4), rounds), 2);
    assert_eq!((stats.noise.rounds, stats.noise.stopped_by), (3, NoiseStop::Rounds));
    // What a time-limited render records of itself renders the same bits.
    let limited = NoiseSettings { target_error: 0.0, time_limit: Some(1e-9), ..NoiseSettings::default() };
    let (film, stats) = rendered(&with_noise(penumbra_scene(1, 4), limited), 2);
    assert_eq!(stats.noise.stopped_by, NoiseStop::TimeLimit);
    let pinned = NoiseSettings { time_limit: None, rounds: Some(stats.noise.rounds), ..limited };
    let (again, _) = rendered(&with_noise(penumbra_scene(1, 4), pinned), 1);
    assert_eq!(bits(&film), bits(&again));
}

#[test]
fn a_time_limited_render_records_its_rounds_and_renders_again_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
            .current_dir(dir.path())
            .args(args)
            .output()
            .unwrap();
        assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/effects_soft_shadows.ron");
    let flags = ["--width", "24", "--target-error", "0", "--noise-samples", "4:65536"];
    run(&[&["render", scene, "-o", "t.png", "--time-limit", "0.05", "--stats", "s.json"], &flags[..]]
        .concat());
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(json["noise"]["stopped_by"], "time_limit", "{}", json["noise"]);
    let rounds = json["noise"]["rounds"].as_u64().unwrap();
    // The image records the rounds it ran, not the machine-dependent limit.
    let info = run(&["info", "t.png"]);
    assert!(info.contains(&format!(r#""--noise-rounds","{rounds}""#)), "{info}");
    assert!(!info.contains("--time-limit"), "{info}");
    assert!(info.contains(&format!("time_limit: None, rounds: Some({rounds})")), "{info}");
    run(&["info", "t.png", "--rerender", "t2.png"]);
    assert_eq!(
        std::fs::read(dir.path().join("t.png")).unwrap(),
        std::fs::read(dir.path().join("t2.png")).unwrap()
    );
}

#[test]
fn noise_driven_images_are_the_same_bits_on_one_and_two_threads() {
    let desc =
        with_noise(penumbra_scene(2, 4), NoiseSettings { target_error: 0.01, ..NoiseSettings::default() });
    let (one, a) = rendered(&desc, 1);
    let (two, b) = rendered(&desc, 2);
    assert_eq!(bits(&one), bits(&two));
    assert_eq!((a.rays, a.noise.rounds), (b.rays, b.noise.rounds));
}

#[test]
fn noise_driven_images_are_the_same_bits_with_packets_and_single_rays() {
    // Packets take each pixel's pending samples in turn, several per pixel where few pixels
    // remain: a soft shadow (area-light packets) beside a point light's hard one.
    let mut desc =
        with_noise(penumbra_scene(1, 16), NoiseSettings { target_error: 0.005, ..NoiseSettings::default() });
    desc.lights.push(LightDesc::Point {
        position: glam::DVec3::new(2.0, 3.0, -1.0),
        colour: glam::Vec3::ONE,
        intensity: 0.5,
        falloff: Default::default(),
    });
    let mut world: SceneWorld = scene::spawn_world(&desc);
    let snapshot = world.update();
    let base = world.render_settings();
    let levels =
        [SimdLevel::Scalar, SimdLevel::Baseline, SimdLevel::Avx2, SimdLevel::Avx512, SimdLevel::Auto];
    let mut results = levels.into_iter().filter(|l| l.available()).map(|simd| {
        let (film, stats) = render(&snapshot, &RenderSettings { simd, ..base });
        (simd, bits(&film), stats)
    });
    let (_, want, scalar) = results.next().expect("scalar is always available");
    assert!(scalar.noise.rounds > 2, "{:?}", scalar.noise);
    for (simd, got, stats) in results {
        assert!(got == want, "{simd}: the image differs from single rays");
        assert_eq!((stats.rays.total(), stats.noise.rounds), (scalar.rays.total(), scalar.noise.rounds));
    }
}

#[test]
fn noise_rules_are_refused_with_their_place() {
    let base = "Scene(camera: (position: (0, 0, -5), look_at: (0, 0, 0), fov_deg: 40, width: 8, height: 8), settings: (SETTINGS), materials: [], lights: [], objects: [])";
    for (settings, field, rule) in [
        ("noise: (target_error: 2)", "settings.noise.target_error", "must be in [0, 1]"),
        (
            "noise: (min_samples: 64, max_samples: 8)",
            "settings.noise.max_samples",
            "must be in min_samples..=65536",
        ),
        ("noise: (time_limit: 0)", "settings.noise.time_limit", "must be > 0 seconds"),
        ("noise: (rounds: 0)", "settings.noise.rounds", "must be at least 1"),
        ("adaptive: (threshold: 0.1), noise: ()", "settings.noise", "choose one adaptive mode"),
    ] {
        let e = scene::parse_scene(&base.replace("SETTINGS", settings), "n.ron").unwrap_err().to_string();
        assert!(
            e.starts_with("n.ron:1:") && e.contains(&format!("field `{field}`")) && e.contains(rule),
            "{e}"
        );
    }
}

#[test]
fn the_command_line_turns_it_on_and_reports_it() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        std::process::Command::new(env!("CARGO_BIN_EXE_penumbra"))
            .current_dir(dir.path())
            .args([
                "render",
                concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/effects_soft_shadows.ron"),
                "--width",
                "32",
            ])
            .args(args)
            .output()
            .unwrap()
    };
    let out = run(&["-o", "n.png", "--target-error", "0.02", "--noise-samples", "4:64", "--stats", "s.json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("s.json")).unwrap()).unwrap();
    let noise = &json["noise"];
    assert!(
        noise["rounds"].as_u64().unwrap() >= 1 && noise["samples_max"].as_u64().unwrap() <= 64,
        "{noise}"
    );
    assert_eq!(noise["samples_min"], 4);
    assert!(["target", "max_samples"].contains(&noise["stopped_by"].as_str().unwrap()), "{noise}");
    for (args, message) in [
        (&["--target-error", "2"][..], "expected a target error in [0, 1]"),
        (&["--noise-samples", "8:4"][..], "1 <= MIN <= MAX <= 65536"),
        (&["--time-limit", "0"][..], "finite and > 0"),
        (&["--noise-rounds", "0"][..], "--noise-rounds"),
        (&["--noise-rounds", "2", "--time-limit", "1"][..], "cannot be used with"),
        (&["--target-error", "0.01", "--adaptive", "0.1"][..], "cannot be used with"),
    ] {
        let out = run(&[&["-o", "bad.png"], args].concat());
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains(message),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(!dir.path().join("bad.png").exists());
    }
}

#[test]
fn a_pixels_samples_stay_stratified_across_batches() {
    // Every pixel takes 16 batches of one camera sample (target 0, maximum 16). Drawn from
    // progressive sequences, those 16 samples (four interleaved replicates of 4) are nearly as
    // good as a fixed jittered set of 16, and far better than 16 independent points (what
    // independent batches gave before).
    let reference = rendered(&penumbra_scene(64, 1024), 2).0;
    let noise =
        NoiseSettings { target_error: 0.0, min_samples: 2, max_samples: 16, ..NoiseSettings::default() };
    let (film, stats) = rendered(&with_noise(penumbra_scene(1, 4), noise), 2);
    assert_eq!((stats.noise.samples_min, stats.noise.samples_max), (16, 16));
    let fixed = |pattern: &str| {
        let mut desc = penumbra_scene(16, 64);
        let pattern = if pattern == "random" { Pattern::Random } else { Pattern::Jittered };
        desc.settings.aa.pattern = pattern;
        for light in &mut desc.lights {
            if let LightDesc::Rect { pattern: p, .. } = light {
                *p = pattern;
            }
        }
        rmse(&rendered(&desc, 2).0, &reference).unwrap()
    };
    let (progressive, jittered, random) =
        (rmse(&film, &reference).unwrap(), fixed("jittered"), fixed("random"));
    assert!(progressive < 1.35 * jittered, "progressive {progressive:.3e}, fixed jittered {jittered:.3e}");
    assert!(progressive < 0.75 * random, "progressive {progressive:.3e}, independent points {random:.3e}");
}

#[test]
fn noise_driven_depth_of_field_is_closer_to_the_reference_than_fixed_with_as_many_rays() {
    // A triangle off the focal plane, blurred by the lens; batches of 4 lens samples.
    let scene = |lens_samples: u32| {
        let text = format!(
            r#"Scene(
    camera: (position: (0, 0, 0), look_at: (0, 0, 1), fov_deg: 40, width: 48, height: 48,
             aperture: 0.3, focus_distance: 5, lens: (samples: {lens_samples})),
    settings: (max_depth: 0, ambient: (1, 1, 1)),
    materials: [(name: "white", kd: (0.9, 0.6, 0.3))],
    objects: [(shape: Triangle(vertices: ((-1, -1, 8), (1.2, -0.8, 8), (-0.5, 1.1, 8))), material: "white")],
)"#
        );
        scene::parse_scene(&text, "dof.ron").expect("test scene is valid")
    };
    let reference = rendered(&scene(1024), 2).0;
    let noise =
        NoiseSettings { target_error: 0.01, min_samples: 8, max_samples: 1024, ..NoiseSettings::default() };
    let (film, stats) = rendered(&with_noise(scene(4), noise), 2);
    let fixed_samples = (stats.rays.lens as u32).div_ceil(48 * 48);
    let (fixed, fixed_stats) = rendered(&scene(fixed_samples), 2);
    assert!(fixed_stats.rays.lens >= stats.rays.lens);
    let (adaptive, uniform) = (rmse(&film, &reference).unwrap(), rmse(&fixed, &reference).unwrap());
    assert!(
        adaptive <= uniform,
        "noise-driven RMSE {adaptive:.3e} ({} lens rays) against fixed {uniform:.3e} ({fixed_samples} per pixel)",
        stats.rays.lens
    );
}
