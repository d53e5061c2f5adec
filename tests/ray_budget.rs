//! The per-camera-sample budget of secondary rays (`settings.max_secondary_rays`): a ray tree
//! that doubles at every bounce finishes within it, deterministically and counted in the
//! statistics; the shipped scenes never reach it, so their pixels are what they were; and the
//! renderer warns before it starts when the settings make such trees likely.

use std::path::Path;
use std::process::{Command, Output};

use penumbra::scene::ray_tree::ray_tree_warnings;
use penumbra::scene::validate::MAX_SECONDARY_RAYS;
use penumbra::scene::{load_scene, parse_scene, spawn_world};
use penumbra::script::{Clock, Limits, Script, ScriptedWorld};
use penumbra::trace::{render, RenderSettings, RenderStats};
use penumbra::world::SceneWorld;

const BIN: &str = env!("CARGO_BIN_EXE_penumbra");

/// The camera inside a glass ball (kr 0.5, kt 0.5) inside a mirror ball: every ray that
/// leaves the glass comes back to it, and each glass hit spawns both a reflection and a
/// refraction, so without a budget a camera sample would trace about 2^32 rays at depth 64.
/// `SETTINGS` and `GLOSSINESS` are replaced by each test.
const GLASS_IN_A_MIRROR: &str = r#"Scene(
    camera: (position: (0, 0, 0), look_at: (0, 0, 1), fov_deg: 60, width: 4, height: 4),
    settings: (min_contribution: 0, max_depth: 64, SETTINGS),
    materials: [
        (name: "glass", kd: (0.1, 0.1, 0.1), ks: 0.3, kr: 0.5, kt: 0.5, ior: 1.5, glossiness: GLOSSINESS),
        (name: "mirror", kd: (0, 0, 0), kr: 1.0),
    ],
    lights: [Point(position: (0, 0.5, 0.2), colour: (1, 1, 1), intensity: 0.8)],
    objects: [
        (name: "glass_ball", shape: Sphere(centre: (0, 0, 0), radius: 1), material: "glass"),
        (name: "mirror_ball", shape: Sphere(centre: (0, 0, 0), radius: 3), material: "mirror"),
    ],
)
"#;

fn glass_scene(settings: &str, glossiness: f32) -> String {
    GLASS_IN_A_MIRROR.replace("SETTINGS", settings).replace("GLOSSINESS", &glossiness.to_string())
}

/// Renders scene text with its own settings.
fn render_text(text: &str) -> (penumbra::film::Film, RenderStats, RenderSettings) {
    let desc = parse_scene(text, "test.ron").unwrap_or_else(|e| panic!("{e}"));
    let mut world: SceneWorld = spawn_world(&desc);
    let settings = world.render_settings();
    let (film, stats) = render(&world.update(), &settings);
    (film, stats, settings)
}

/// Reflection, refraction, glossy and blurry rays: what the budget counts.
fn secondary(stats: &RenderStats) -> u64 {
    let r = &stats.rays;
    r.reflection + r.refraction + r.glossy + r.blurry
}

fn bits(film: &penumbra::film::Film) -> Vec<[u32; 3]> {
    film.pixels.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
}

#[test]
fn a_doubling_glass_tree_at_depth_64_finishes_within_its_budget_and_is_counted() {
    for glossiness in [0.0, 0.2] {
        let (film, stats, settings) = render_text(&glass_scene("glossy: (samples: 16)", glossiness));
        assert_eq!(settings.max_secondary_rays, 1024, "the documented default");
        let samples = stats.rays.primary();
        assert_eq!(samples, 16);
        let b = stats.ray_budget;
        assert_eq!(b.max_secondary_rays, 1024);
        assert!(
            secondary(&stats) <= samples * 1024,
            "glossiness {glossiness}: {} secondary rays",
            secondary(&stats)
        );
        assert!(b.max_per_sample <= 1024, "{b:?}");
        // The tree is far bigger than the budget everywhere: every sample spends all of it.
        assert_eq!(b.cut_samples, samples, "{b:?}");
        assert_eq!(b.max_per_sample, 1024, "{b:?}");
        assert!(b.refused_rays >= b.cut_samples, "{b:?}");
        assert!(film.pixels.iter().all(|p| p.is_finite()));
    }
}

#[test]
fn raising_the_budget_in_the_scene_raises_the_rays_traced() {
    let (_, low, _) = render_text(&glass_scene("", 0.0));
    let (_, high, settings) = render_text(&glass_scene("max_secondary_rays: 4096", 0.0));
    assert_eq!(settings.max_secondary_rays, 4096);
    assert_eq!(high.ray_budget.max_secondary_rays, 4096);
    assert!(secondary(&high) > secondary(&low), "{} vs {}", secondary(&high), secondary(&low));
    assert!(secondary(&high) <= high.rays.primary() * 4096);
    assert_eq!(high.ray_budget.max_per_sample, 4096);
    assert!(high.ray_budget.cut_samples > 0, "2^32 rays still do not fit");
}

#[test]
fn a_cut_tree_keeps_its_shallow_siblings() {
    // Two rays per camera sample: the first bounce's reflection and refraction, not a
    // reflection of a reflection (the refraction's ray is set aside while the reflection's
    // tree is traced).
    let (_, stats, _) = render_text(&glass_scene("max_secondary_rays: 2", 0.0));
    assert_eq!(stats.rays.reflection, 16);
    assert_eq!(stats.rays.refraction, 16);
    // A cone keeps all of its first-bounce rays the same way: 16 glossy, 16 blurry.
    let (_, stats, _) = render_text(&glass_scene("max_secondary_rays: 32, glossy: (samples: 16)", 0.2));
    assert_eq!((stats.rays.glossy, stats.rays.blurry), (16 * 16, 16 * 16));
}

#[test]
fn a_cut_image_is_the_same_at_one_and_two_threads() {
    for glossiness in [0.0, 0.2] {
        let text = glass_scene("max_secondary_rays: 300, aa: (samples: 3)", glossiness);
        let desc = parse_scene(&text, "test.ron").unwrap();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| {
                let mut world: SceneWorld = spawn_world(&desc);
                let mut settings = world.render_settings();
                (settings.width, settings.height) = (23, 17); // several tiles, ragged edges
                render(&world.update(), &settings)
            })
        };
        let ((one, s1), (two, s2)) = (run(1), run(2));
        assert!(s1.ray_budget.cut_samples > 0);
        assert_eq!(s1.ray_budget, s2.ray_budget);
        assert_eq!(s1.rays.total(), s2.rays.total());
        assert!(bits(&one) == bits(&two), "glossiness {glossiness}: pixels differ between 1 and 2 threads");
    }
}

#[test]
fn no_shipped_scene_reaches_the_budget_so_its_pixels_are_unchanged() {
    for path in crate::common::shipped_scenes() {
        let desc = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let mut world: SceneWorld = spawn_world(&desc);
        let mut settings = world.render_settings();
        (settings.width, settings.height) = (32, 24);
        let snapshot = world.update();
        let (film, stats) = render(&snapshot, &settings);
        let b = stats.ray_budget;
        assert_eq!((b.cut_samples, b.refused_rays), (0, 0), "{}: {b:?}", path.display());
        // Far from it: the busiest shipped scene (effects_glossy) uses about a quarter.
        assert!(b.max_per_sample <= 512, "{}: {b:?}", path.display());
        // The same bits as with a budget that cannot be reached.
        let unbounded = RenderSettings { max_secondary_rays: MAX_SECONDARY_RAYS, ..settings };
        let (reference, reference_stats) = render(&snapshot, &unbounded);
        assert!(bits(&film) == bits(&reference), "{}: the budget changed pixels", path.display());
        assert_eq!(stats.rays.total(), reference_stats.rays.total(), "{}", path.display());
        assert!(ray_tree_warnings(&desc).is_empty(), "{}: {:?}", path.display(), ray_tree_warnings(&desc));
    }
}

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN).args(args).current_dir(dir).output().expect("the binary runs")
}

#[test]
fn the_cli_warns_before_an_exponential_tree_and_reports_the_cut() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("glass.ron"), glass_scene("", 0.0)).unwrap();
    let out = run(dir.path(), &["render", "glass.ron", "-o", "g.png", "--quiet", "--stats", "s.json"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.starts_with("warning:")).collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    for part in [
        "material `glass`",
        "kr 0.5, kt 0.5",
        "settings.min_contribution 0",
        "settings.max_depth 64",
        "2^65",
        "settings.max_secondary_rays 1024",
    ] {
        assert!(warnings[0].contains(part), "`{part}` missing from {}", warnings[0]);
    }
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(stats["ray_budget"]["max_secondary_rays"], 1024);
    assert_eq!(stats["ray_budget"]["cut_samples"], 16);
    assert!(stats["ray_budget"]["refused_rays"].as_u64().unwrap() > 0);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("ray budget 1024 secondary rays per camera sample: 16 samples cut"), "{stdout}");

    // A shipped scene: no warning at all.
    let default = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/default.ron");
    let out =
        run(dir.path(), &["render", default.to_str().unwrap(), "-o", "d.png", "--width", "16", "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
}

#[test]
fn a_budget_out_of_range_exits_2_at_its_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    for bad in ["0", "16777217"] {
        let text = glass_scene(&format!("max_secondary_rays: {bad}"), 0.0);
        std::fs::write(dir.path().join("bad.ron"), &text).unwrap();
        let out = run(dir.path(), &["render", "bad.ron", "-o", "bad.png"]);
        assert_eq!(out.status.code(), Some(2));
        let at = text.find(&format!("max_secondary_rays: {bad}")).unwrap() + "max_secondary_rays: ".len();
        let line = text[..at].matches('\n').count() + 1;
        let col = at - text[..at].rfind('\n').map_or(0, |i| i + 1) + 1;
        let stderr = String::from_utf8_lossy(&out.stderr);
        let expected = format!(
            "bad.ron:{line}:{col}: field `settings.max_secondary_rays`: must be in 1..=16777216, got {bad}"
        );
        assert!(stderr.contains(&expected), "expected `{expected}` in {stderr}");
        assert!(!dir.path().join("bad.png").exists());
    }
}

#[test]
fn a_script_sets_the_budget_within_its_range() {
    let desc = parse_scene(&glass_scene("", 0.0), "test.ron").unwrap();
    let script = |body: &str| {
        let source = format!("fn frame(t) {{\n    {body}\n}}\n");
        let script = Script::from_source("budget.rhai", &source, Limits::default()).unwrap();
        let mut world: ScriptedWorld = ScriptedWorld::new(spawn_world(&desc), &script);
        world.setup().unwrap();
        let result = world.frame(Clock::at(0, 24.0));
        (result, world)
    };
    let (result, mut world) = script("settings.max_secondary_rays = settings.max_secondary_rays * 4;");
    result.unwrap_or_else(|e| panic!("{e}"));
    let snapshot = world.update();
    let settings = world.world().render_settings();
    assert_eq!(settings.max_secondary_rays, 4096);
    let (_, stats) = render(&snapshot, &settings);
    assert_eq!(stats.ray_budget.max_per_sample, 4096);
    for bad in ["0", "16777217"] {
        let (result, _) = script(&format!("settings.max_secondary_rays = {bad};"));
        let e = result.expect_err("out of range");
        let rule = format!("settings.max_secondary_rays must be in 1..=16777216, got {bad}");
        assert!(e.to_string().contains(&rule), "{e}");
        assert_eq!(e.line, Some(2), "{e}");
    }
}
