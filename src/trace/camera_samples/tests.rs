//! Tests of `src/trace/camera_samples.rs`.

use super::*;

#[test]
fn times_keep_to_their_strata_by_pattern() {
    let n = 8;
    for k in 0..n {
        let (lo, hi) = (k as f32 / n as f32, (k + 1) as f32 / n as f32);
        for u in [0.0, 0.3, 1.0f32.next_down()] {
            let t = stratum_time(Pattern::Jittered, k, n, u);
            assert!((lo..hi).contains(&t), "jittered time {t} of stratum {k} at u = {u}");
        }
        assert_eq!(stratum_time(Pattern::Grid, k, n, 0.9), (k as f32 + 0.5) / n as f32);
        assert_eq!(stratum_time(Pattern::Random, k, n, 0.9), 0.9, "random ignores the stratum");
    }
    // The last stratum's end is pulled back inside it.
    assert!(stratum_time(Pattern::Jittered, 2, 3, 1.0f32.next_down()) < 1.0);
}

/// A pinhole camera's single sample goes through the pixel's centre, on the packet path
/// (`image_point`) and the single-ray path (`sample`) alike; several spread over the pixel.
#[test]
fn one_sample_goes_through_the_pixel_centre_and_several_spread_over_the_pixel() {
    let text = "Scene(camera: (position: (0, 1, -5), look_at: (0, 0, 0), fov_deg: 40, width: 8, height: 6), \
                materials: [(name: \"white\", kd: (0.8, 0.8, 0.8))], \
                objects: [(shape: Sphere(centre: (0, 0, 0), radius: 1), material: \"white\")])";
    let desc = crate::scene::parse_scene(text, "test").expect("test scene parses");
    let mut world: crate::world::SceneWorld = crate::scene::spawn_world(&desc);
    let scene = world.update();
    let base = world.render_settings();
    let (x, y) = (3, 2);
    for n in [1, 4, 9] {
        let settings = RenderSettings { aa: AntiAliasing { samples: n, ..base.aa }, ..base };
        let sampler = CameraSampler::new(&scene, &settings);
        let mut rays = RayCounts::default();
        let points: Vec<Vec2> = (0..n).map(|s| sampler.image_point(x, y, s, &mut rays).0).collect();
        for (s, point) in points.iter().enumerate() {
            let (ray, _, _) = sampler.sample(x, y, s as u32, &mut rays);
            assert_eq!(
                ray,
                scene.camera.ray(point.x, point.y, settings.width, settings.height),
                "sample {s} of {n}"
            );
            let offset = *point - Vec2::new(x as f32, y as f32);
            assert!((0.0..1.0).contains(&offset.x) && (0.0..1.0).contains(&offset.y), "{offset} of {n}");
        }
        if n == 1 {
            assert_eq!(points, [Vec2::new(x as f32 + 0.5, y as f32 + 0.5)]);
        } else {
            let mut distinct = points.iter().map(|p| (p.x.to_bits(), p.y.to_bits())).collect::<Vec<_>>();
            distinct.dedup();
            assert_eq!(distinct.len(), n as usize, "{n} samples take {n} places: {points:?}");
        }
        assert_eq!(rays.camera, 2 * u64::from(n));
    }
}
