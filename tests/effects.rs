//! Distribution effects: each one is paid for only when the scene asks for it (proven by ray
//! counts), and each matches an analytic expectation.

use penumbra::math::Vec3;
use penumbra::scene::{self, SceneDesc};
use penumbra::trace::{render, RayCounts, RenderSettings, RenderStats};
use penumbra::world::SceneWorld;

/// A scene with one of each kind of object, no effects: hard shadows, sharp mirror and glass.
const PLAIN: &str = r#"Scene(
    camera: (position: (0, 2, -6), look_at: (0, 0.6, 0), fov_deg: 45, width: 40, height: 30),
    settings: (max_depth: 4, background: (0.3, 0.4, 0.6)),
    materials: [
        (name: "floor", kd: (0.7, 0.7, 0.7)),
        (name: "mirror", kd: (0.1, 0.1, 0.1), kr: 0.8),
        (name: "glass", kd: (0, 0, 0), kt: 0.9, ior: 1.5),
    ],
    lights: [Point(position: (-3, 6, -4))],
    objects: [
        (shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "floor"),
        (shape: Sphere(centre: (-1, 0.7, 0), radius: 0.7), material: "mirror"),
        (shape: Sphere(centre: (1, 0.7, 0), radius: 0.7), material: "glass"),
    ],
)"#;

fn desc(text: &str) -> SceneDesc {
    scene::parse_scene(text, "effects-test.ron").expect("test scene is valid")
}

fn render_desc(d: &SceneDesc) -> (Vec<Vec3>, RenderStats) {
    let mut world: SceneWorld = scene::spawn_world(d);
    let snapshot = world.update();
    let (film, stats) = render(&snapshot, &world.render_settings());
    (film.pixels, stats)
}

fn no_effect_rays(r: &RayCounts) {
    assert_eq!(r.lens, 0, "lens rays without an aperture");
    assert_eq!(r.area_shadow, 0, "area-shadow rays without an area light");
    assert_eq!(r.glossy, 0, "glossy rays without a glossy material");
    assert_eq!(r.blurry, 0, "blurry rays without a blurry material");
}

#[test]
fn a_scene_without_effects_traces_one_camera_ray_per_pixel_and_no_effect_rays() {
    let (_, stats) = render_desc(&desc(PLAIN));
    assert_eq!(stats.rays.camera, 40 * 30);
    no_effect_rays(&stats.rays);
    assert!(stats.rays.shadow > 0 && stats.rays.reflection > 0 && stats.rays.refraction > 0);
    assert_eq!(stats.effects.names(), ["reflection", "transmission"]);
    assert_eq!(stats.samples_per_pixel, 1);
}

#[test]
fn aa_multiplies_camera_rays_and_nothing_else_appears() {
    let mut d = desc(PLAIN);
    d.settings.aa.samples = 9;
    let (_, stats) = render_desc(&d);
    assert_eq!(stats.rays.camera, 9 * 40 * 30);
    no_effect_rays(&stats.rays);
}

#[test]
fn zero_aperture_takes_no_lens_samples_and_gives_the_pinhole_image() {
    let pinhole = render_desc(&desc(PLAIN));
    let mut d = desc(PLAIN);
    d.camera.aperture = 0.0;
    d.camera.lens.samples = 16;
    let zero = render_desc(&d);
    assert_eq!(zero.1.rays.lens, 0);
    assert_eq!(pinhole.0, zero.0, "aperture 0 must be the pinhole image, bit for bit");
}

#[test]
fn glossiness_zero_is_exactly_the_mirror_image_and_costs_no_glossy_rays() {
    let sharp = render_desc(&desc(PLAIN));
    let mut d = desc(PLAIN);
    d.settings.glossy.samples = 16;
    let (pixels, stats) = render_desc(&d);
    assert_eq!(stats.rays.glossy + stats.rays.blurry, 0);
    assert_eq!(sharp.0, pixels);
}

#[test]
fn each_effect_counts_its_own_rays() {
    let mut d = desc(PLAIN);
    d.materials[1].glossiness = 0.2;
    d.materials[2].glossiness = 0.2;
    d.settings.glossy.samples = 4;
    let (_, stats) = render_desc(&d);
    assert!(stats.rays.glossy > 0 && stats.rays.blurry > 0, "{:?}", stats.rays);
    // With 4 camera samples per pixel each first-bounce glossy hit takes a quarter of the 4.
    let mut shared = d.clone();
    shared.settings.aa.samples = 4;
    let (_, four) = render_desc(&shared);
    assert_eq!(four.rays.camera, 4 * 40 * 30);
    assert!(four.rays.glossy < 2 * stats.rays.glossy, "{} vs {}", four.rays.glossy, stats.rays.glossy);
    assert_eq!(stats.rays.area_shadow + stats.rays.lens, 0);

    let mut d = desc(PLAIN);
    d.camera.aperture = 0.1;
    d.camera.lens.samples = 4;
    let (_, stats) = render_desc(&d);
    assert_eq!((stats.rays.camera, stats.rays.lens), (0, 4 * 40 * 30));
}

/// A floor point at the origin seen from above, lit by `light`, with an opaque slab that can
/// hide the half x < 0 of anything at height 4 above it.
fn light_scene(light: &str, occluded: bool) -> SceneDesc {
    let slab = if occluded {
        r#"(shape: Box(min: (-10, 1.9, -10), max: (0, 2, 10)), material: "white"),"#
    } else {
        ""
    };
    desc(&format!(
        r#"Scene(
    camera: (position: (0.5, 1, -1), look_at: (0, 0, 0), fov_deg: 1, width: 1, height: 1),
    settings: (max_depth: 0, ambient: (0, 0, 0)),
    materials: [(name: "white", kd: (1, 1, 1))],
    lights: [{light}],
    objects: [
        (shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "white"),
        {slab}
    ],
)"#
    ))
}

const SQUARE_LIGHT: &str =
    "Rect(corner: (-0.5, 4, -0.5), edge_u: (1, 0, 0), edge_v: (0, 0, 1), samples: 1024, pattern: Jittered)";

#[test]
fn a_square_light_half_hidden_behind_a_straight_edge_casts_half_a_shadow() {
    // The slab's edge at x = 0, halfway up, hides exactly the half x < 0 of the light as seen
    // from the origin; by symmetry that half carries half of the light.
    let lit = render_desc(&light_scene(SQUARE_LIGHT, false)).0[0].x;
    for seed in 0..8 {
        let mut d = light_scene(SQUARE_LIGHT, true);
        d.settings.seed = seed;
        let (pixels, stats) = render_desc(&d);
        let fraction = pixels[0].x / lit;
        assert!((fraction - 0.5).abs() < 0.01, "seed {seed}: visible fraction {fraction}, want 0.5 ± 0.01");
        assert_eq!(stats.rays.area_shadow, 1024);
        assert_eq!(stats.rays.shadow, 0);
    }
}

#[test]
fn a_pixels_area_light_samples_are_shared_among_its_camera_samples_and_stay_stratified() {
    // 16 camera samples share the light's 1024 samples per pixel: 64 each, the strata of all
    // 16 together a permutation of the 1024, so the half shadow is still exact to 1 %.
    let lit = render_desc(&light_scene(SQUARE_LIGHT, false)).0[0].x;
    let mut d = light_scene(SQUARE_LIGHT, true);
    d.settings.aa.samples = 16;
    let (pixels, stats) = render_desc(&d);
    assert_eq!(stats.rays.camera, 16);
    assert_eq!(stats.rays.area_shadow, 1024, "the per-pixel budget, not 16 × 1024");
    let fraction = pixels[0].x / lit;
    assert!((fraction - 0.5).abs() < 0.01, "visible fraction {fraction}, want 0.5 ± 0.01");
}

#[test]
fn a_tiny_fully_visible_area_light_matches_the_point_light_at_its_centre() {
    let tiny =
        "Rect(corner: (-0.0005, 4, -0.0005), edge_u: (0.001, 0, 0), edge_v: (0, 0, 0.001), samples: 16)";
    let (area, _) = render_desc(&light_scene(tiny, false));
    let (point, stats) = render_desc(&light_scene("Point(position: (0, 4, 0))", false));
    assert_eq!(stats.rays.area_shadow, 0);
    assert!((area[0] - point[0]).abs().max_element() < 1e-4, "{} vs {}", area[0], point[0]);
}

/// Camera at the origin looking down +z at a triangle lying in the plane z = `wall_z`, lit by
/// ambient light only (view-independent shading), black background.
fn focal_plane_scene(wall_z: f32, aperture: f32) -> SceneDesc {
    desc(&format!(
        r#"Scene(
    camera: (position: (0, 0, 0), look_at: (0, 0, 1), fov_deg: 40, width: 48, height: 48,
             aperture: {aperture}, focus_distance: 5, lens: (samples: 16)),
    settings: (max_depth: 0, ambient: (1, 1, 1)),
    materials: [(name: "white", kd: (0.9, 0.6, 0.3))],
    objects: [(shape: Triangle(vertices: ((-1, -1, {wall_z}), (1.2, -0.8, {wall_z}), (-0.5, 1.1, {wall_z}))), material: "white")],
)"#
    ))
}

#[test]
fn a_surface_on_the_focal_plane_renders_the_same_with_any_aperture() {
    // At AA 1 the 16 lens samples of a pixel take the 16 positions an AA 16 render takes, so on
    // the focal plane a lens sees what a pinhole with AA 16 sees.
    let mut pinhole = focal_plane_scene(5.0, 0.0);
    pinhole.settings.aa.samples = 16;
    let (pinhole, _) = render_desc(&pinhole);
    for aperture in [0.05, 0.3, 1.0] {
        let (lens, stats) = render_desc(&focal_plane_scene(5.0, aperture));
        assert_eq!(stats.rays.lens, 16 * 48 * 48);
        let worst = pinhole.iter().zip(&lens).map(|(a, b)| (*a - *b).abs().max_element()).fold(0.0, f32::max);
        assert!(worst < 1e-3, "aperture {aperture}: a pixel differs by {worst}");
    }
    // Off the focal plane the same triangle blurs.
    let (sharp, _) = render_desc(&focal_plane_scene(8.0, 0.0));
    let (blurred, _) = render_desc(&focal_plane_scene(8.0, 0.3));
    assert!(sharp.iter().zip(&blurred).any(|(a, b)| (*a - *b).abs().max_element() > 0.2));
}

#[test]
fn lens_samples_anti_alias_in_focus_edges_at_aa_1() {
    // The triangle on the focal plane, its colour's red channel 0.9 (ambient 1): a pinhole at
    // AA 1 gives each pixel all or nothing of it; a lens at AA 1 with 16 lens samples covers
    // each pixel with its samples, so pixels the edges cross take values in between.
    let partial = |pixels: &[Vec3]| pixels.iter().filter(|p| p.x > 0.05 && p.x < 0.85).count();
    let (pinhole, _) = render_desc(&focal_plane_scene(5.0, 0.0));
    let (lens, _) = render_desc(&focal_plane_scene(5.0, 0.05));
    assert_eq!(partial(&pinhole), 0, "a pinhole at AA 1 steps");
    // The three edges cross about 60 pixels of the 48 × 48 image.
    assert!(partial(&lens) > 40, "{} partly covered pixels", partial(&lens));
}

fn rmse(a: &[Vec3], b: &[Vec3]) -> f32 {
    let sum: f32 = a.iter().zip(b).map(|(a, b)| (*a - *b).length_squared()).sum();
    (sum / (3 * a.len()) as f32).sqrt()
}

#[test]
fn adaptive_lattice_points_take_their_share_of_the_lens_samples() {
    // The triangle off the focal plane, blurred by a lens of 16 samples.
    let mut adaptive = focal_plane_scene(8.0, 0.3);
    adaptive.settings.adaptive = Some(scene::AdaptiveSettings { threshold: 1e30, max_depth: 2 });
    let (corners_only, stats) = render_desc(&adaptive);
    assert_eq!(stats.rays.lens, 49 * 49 * 16, "every pixel corner takes all 16 lens samples");

    let mut reference = focal_plane_scene(8.0, 0.3);
    reference.camera.lens.samples = 1024;
    let (reference, _) = render_desc(&reference);
    let mut last = f32::INFINITY;
    for (threshold, max_depth) in [(0.05, 2), (0.02, 3), (0.01, 3)] {
        adaptive.settings.adaptive = Some(scene::AdaptiveSettings { threshold, max_depth });
        let (refined, stats) = render_desc(&adaptive);
        // The fixed render with at least the adaptive render's rays.
        let mut fixed = focal_plane_scene(8.0, 0.3);
        fixed.camera.lens.samples = (stats.rays.lens as u32).div_ceil(48 * 48);
        let (fixed, fixed_stats) = render_desc(&fixed);
        assert!(fixed_stats.rays.lens >= stats.rays.lens);
        let (a, f) = (rmse(&refined, &reference), rmse(&fixed, &reference));
        // Corners alone (16 lens samples each, 49² of them) are closer than fixed too.
        assert!(rmse(&corners_only, &reference) < f, "{} against fixed {f}", rmse(&corners_only, &reference));
        // Deeper points take 4 lens samples, then 1: their noise must not read as contrast,
        // and must not outweigh the corners' 16, or a lower threshold traces more for less.
        assert!(a <= f, "{threshold}:{max_depth}: adaptive RMSE {a} against fixed {f} with as many rays");
        assert!(a <= last * 1.02, "{threshold}:{max_depth}: RMSE {a} after {last} at a higher threshold");
        last = a;
    }
}

#[test]
fn a_point_off_the_focal_plane_spreads_over_the_analytic_circle_of_confusion() {
    // A small sphere at depth z, focus at f, lens radius A, image height H, field of view φ:
    // on the image plane its blur is a disc of diameter A·|z − f|·H / (f·z·tan(φ/2)) pixels.
    let (z, f, a, r, h, fov) = (10.0f32, 5.0f32, 0.6f32, 0.05f32, 97u32, 40f32);
    let d = desc(&format!(
        r#"Scene(
    camera: (position: (0, 0, 0), look_at: (0, 0, 1), fov_deg: {fov}, width: {h}, height: {h},
             aperture: {a}, focus_distance: {f}, lens: (samples: 256, pattern: Jittered)),
    settings: (max_depth: 0, ambient: (1, 1, 1)),
    materials: [(name: "white", kd: (1, 1, 1))],
    objects: [(shape: Sphere(centre: (0, 0, {z}), radius: {r}), material: "white")],
)"#
    ));
    let (pixels, _) = render_desc(&d);
    let scale = h as f32 / (2.0 * (fov.to_radians() / 2.0).tan()); // pixels per unit of image plane
    let want = a * (z - f).abs() * 2.0 * scale / (f * z);
    // Intensity-weighted second moment about the centroid: a uniform disc of radius R has
    // E[r²] = R²/2; the sphere's own pinhole image (radius ρ) and the pixel grid (1/6) add theirs.
    let (mut sum, mut cx, mut cy) = (0.0f64, 0.0f64, 0.0f64);
    for (i, p) in pixels.iter().enumerate() {
        let (x, y, v) = ((i as u32 % h) as f64 + 0.5, (i as u32 / h) as f64 + 0.5, p.x as f64);
        sum += v;
        cx += v * x;
        cy += v * y;
    }
    let (cx, cy) = (cx / sum, cy / sum);
    let m2 = pixels
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let (x, y) = ((i as u32 % h) as f64 + 0.5, (i as u32 / h) as f64 + 0.5);
            p.x as f64 * ((x - cx).powi(2) + (y - cy).powi(2))
        })
        .sum::<f64>()
        / sum;
    let rho = (r / (z * z - r * r).sqrt() * scale) as f64;
    let radius = (2.0 * m2 - rho * rho - 1.0 / 3.0).sqrt();
    let got = 2.0 * radius as f32;
    assert!((got - want).abs() < 0.1 * want, "circle of confusion {got:.2} px, analytic {want:.2} px");
}

/// A glossy floor reflecting a bright sphere; `glossiness` on the floor, 8 glossy rays.
fn glossy_scene(glossiness: f32, seed: u64) -> SceneDesc {
    let mut d = desc(&format!(
        r#"Scene(
    camera: (position: (0, 1, -5), look_at: (0, 0.3, 0), fov_deg: 40, width: 32, height: 24),
    settings: (max_depth: 2, background: (0.1, 0.1, 0.1), glossy: (samples: 8)),
    materials: [
        (name: "floor", kd: (0.1, 0.1, 0.1), kr: 0.8, glossiness: {glossiness}),
        (name: "bright", kd: (1, 0.8, 0.2)),
    ],
    lights: [Point(position: (0, 5, -2))],
    objects: [
        (shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "floor"),
        (shape: Sphere(centre: (0, 0.8, 1), radius: 0.8), material: "bright"),
    ],
)"#
    ));
    d.settings.seed = seed;
    d
}

#[test]
fn growing_glossiness_raises_the_noise_monotonically() {
    // Per-pixel variance across seeds, averaged over the image: zero for a mirror, growing
    // with the cone the glossy rays are spread over.
    let mut last = -1.0f64;
    for g in [0.0, 0.05, 0.2, 0.5] {
        let images: Vec<Vec<Vec3>> = (0..6).map(|seed| render_desc(&glossy_scene(g, seed)).0).collect();
        let n = images.len() as f64;
        let variance = (0..images[0].len())
            .map(|p| {
                let mean = images.iter().map(|im| im[p].x as f64).sum::<f64>() / n;
                images.iter().map(|im| (im[p].x as f64 - mean).powi(2)).sum::<f64>() / n
            })
            .sum::<f64>()
            / images[0].len() as f64;
        if g == 0.0 {
            assert_eq!(variance, 0.0, "a mirror has no noise");
        }
        assert!(variance > last, "glossiness {g}: variance {variance} not above {last}");
        last = variance;
    }
}

/// Flat regions: a big matte wall and the background, one straight edge between them.
fn flat_scene(adaptive: bool, aa: u32) -> SceneDesc {
    let mut d = desc(
        r#"Scene(
    camera: (position: (0, 0, -5), look_at: (0, 0, 0), fov_deg: 40, width: 40, height: 30),
    settings: (max_depth: 0, background: (0.2, 0.3, 0.5), ambient: (1, 1, 1)),
    materials: [(name: "wall", kd: (0.9, 0.8, 0.1))],
    objects: [(shape: Triangle(vertices: ((-0.3, -10, 0), (10, -10, 0), (0.4, 10, 0))), material: "wall")],
)"#,
    );
    d.settings.aa.samples = aa;
    d.settings.aa.pattern = penumbra::sample::Pattern::Grid;
    if adaptive {
        d.settings.adaptive = Some(scene::AdaptiveSettings { threshold: 0.05, max_depth: 2 });
    }
    d
}

#[test]
fn adaptive_on_a_flat_background_traces_only_the_pixel_corners() {
    let d = desc(
        r#"Scene(
    camera: (position: (0, 0, -5), look_at: (0, 0, 0), fov_deg: 40, width: 40, height: 30),
    settings: (background: (0.2, 0.3, 0.5), adaptive: (threshold: 0.01, max_depth: 3)),
    materials: [(name: "m", kd: (1, 1, 1))],
    objects: [],
)"#,
    );
    let (pixels, stats) = render_desc(&d);
    assert_eq!(stats.rays.camera, 41 * 31, "W×H pixels share (W+1)×(H+1) corners");
    assert_eq!(stats.adaptive.subdivisions, 0);
    assert!(pixels.iter().all(|p| *p == Vec3::new(0.2, 0.3, 0.5)));
}

#[test]
fn adaptive_traces_fewer_rays_than_fixed_aa_at_the_same_density_and_stays_within_the_threshold() {
    let (fixed, fixed_stats) = render_desc(&flat_scene(false, 16));
    let (adaptive, adaptive_stats) = render_desc(&flat_scene(true, 1));
    assert!(adaptive_stats.adaptive.subdivisions > 0, "the edge must be refined");
    assert!(adaptive_stats.adaptive.reused > 0, "neighbouring squares share points");
    assert!(
        2 * adaptive_stats.rays.camera < fixed_stats.rays.camera,
        "adaptive {} vs fixed {} camera rays",
        adaptive_stats.rays.camera,
        fixed_stats.rays.camera
    );
    let mean_error = fixed.iter().zip(&adaptive).map(|(a, b)| (*a - *b).abs().max_element()).sum::<f32>()
        / fixed.len() as f32;
    assert!(mean_error < 0.05, "mean difference from the fixed image {mean_error}");
}

#[test]
fn every_effect_on_gives_identical_bytes_on_one_and_two_threads() {
    let mut d = glossy_scene(0.3, 7);
    d.camera.aperture = 0.1;
    d.camera.lens.samples = 2;
    d.settings.aa.samples = 2;
    d.lights.push(penumbra::scene::LightDesc::Disk {
        centre: glam::DVec3::new(2.0, 4.0, -1.0),
        normal: Vec3::NEG_Y,
        radius: 0.5,
        colour: Vec3::ONE,
        intensity: 0.5,
        samples: 4,
        pattern: penumbra::sample::Pattern::Jittered,
        falloff: Default::default(),
        visible: false,
    });
    for adaptive in [false, true] {
        if adaptive {
            d.settings.adaptive = Some(scene::AdaptiveSettings { threshold: 0.02, max_depth: 2 });
        }
        let mut world: SceneWorld = scene::spawn_world(&d);
        let snapshot = world.update();
        let settings: RenderSettings = world.render_settings();
        let images: Vec<Vec<u32>> = [1, 2]
            .map(|threads| {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                let (film, stats) = pool.install(|| render(&snapshot, &settings));
                assert!(stats.rays.lens > 0 && stats.rays.glossy > 0 && stats.rays.area_shadow > 0);
                film.pixels.iter().flat_map(|c| c.to_array().map(f32::to_bits)).collect()
            })
            .into();
        assert!(images[0] == images[1], "adaptive {adaptive}: 1 and 2 threads differ");
    }
}

#[test]
fn adaptive_depth_of_field_is_never_worse_than_fixed_with_as_many_rays_at_any_threshold() {
    // The shipped depth-of-field scene, small: defocused spheres before and behind the focal
    // plane. A corner takes 16 lens samples, a level-1 point 4, deeper points 1: the spread of
    // a point's samples tells its noise from an edge, and a leaf weights its corners by their
    // samples, so lowering the threshold refines edges without buying noise.
    let mut d = desc(include_str!("../scenes/effects_dof.ron"));
    (d.camera.width, d.camera.height) = (96, 72);
    let with_lens = |samples: u32| {
        let mut fixed = d.clone();
        fixed.camera.lens.samples = samples;
        render_desc(&fixed)
    };
    let (reference, _) = with_lens(256);
    // The fixed curve through 16 and 64 lens samples (square strata both), read log-log at
    // the adaptive render's rays, as `penumbra report` reads equal-error savings.
    let fixed: Vec<(f64, f64)> = [16, 64]
        .map(|n| {
            let (image, stats) = with_lens(n);
            ((stats.rays.lens as f64).ln(), f64::from(rmse(&image, &reference)).ln())
        })
        .to_vec();
    let slope = (fixed[1].1 - fixed[0].1) / (fixed[1].0 - fixed[0].0);
    assert!(slope < -0.3, "the fixed curve falls with rays (slope {slope})");
    for threshold in [0.1, 0.05, 0.02] {
        let mut adaptive = d.clone();
        adaptive.settings.adaptive = Some(scene::AdaptiveSettings { threshold, max_depth: 3 });
        let (refined, stats) = render_desc(&adaptive);
        let rays = stats.rays.lens as f64;
        let f = (fixed[0].1 + slope * (rays.ln() - fixed[0].0)).exp();
        let a = f64::from(rmse(&refined, &reference));
        assert!(a <= f, "{threshold}:3: adaptive RMSE {a} against fixed {f} at its {rays} lens rays");
    }
}
