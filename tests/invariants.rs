//! Image-level invariants: every shipped scene renders to finite values only, and a mirror box
//! (kr + kt ≤ 1) never brightens the light it carries.

use glam::{DAffine3, DVec3};
use penumbra::camera::Camera;
use penumbra::geom::Shape;
use penumbra::math::Vec3;
use penumbra::scene::{load_scene, spawn_world};
use penumbra::store::{MaterialId, PlacedObject};
use penumbra::trace::{render, Light, Material, RenderSettings, SceneTables, TraceScene};
use penumbra::world::SceneWorld;

#[test]
fn every_shipped_scene_renders_finite_values_only() {
    let mut rendered = 0;
    for path in crate::common::shipped_scenes() {
        let desc = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
        let mut world: SceneWorld = spawn_world(&desc);
        let mut settings = world.render_settings();
        (settings.width, settings.height) = (40, 30);
        let (film, _) = render(&world.update(), &settings);
        let bad = film.pixels.iter().filter(|p| !p.is_finite()).count();
        assert_eq!(bad, 0, "{}: {bad} non-finite pixels", path.display());
        rendered += 1;
    }
    assert!(rendered >= 10, "only {rendered} scenes rendered");
}

#[test]
fn a_closed_mirror_box_never_brightens_the_light_it_carries() {
    // A diffuse ball lit by a point light inside a closed box whose walls are perfect black
    // mirrors (kd = ks = 0) with kr + kt ≤ 1. Every pixel sees the ball directly or through
    // mirrors, each of which multiplies by kr ≤ 1: no pixel may exceed the ball's brightest
    // direct shading, ambient + kd·I (+ ks·I).
    for (kr, kt) in [(1.0, 0.0), (0.9, 0.1), (0.5, 0.5), (0.3, 0.0)] {
        let ball = Material { kd: Vec3::new(0.8, 0.6, 0.4), ks: 0.2, shininess: 20.0, ..Material::default() };
        let wall =
            Material { kd: Vec3::ZERO, ks: 0.0, kr, kt: Vec3::splat(kt), ior: 1.0, ..Material::default() };
        let intensity = 0.9;
        let ambient = Vec3::splat(0.05);
        let tables = SceneTables {
            materials: vec![ball, wall],
            lights: vec![Light::Point {
                position: Vec3::new(1.5, 1.5, -1.0),
                radiance: Vec3::splat(intensity),
                falloff: Default::default(),
            }],
            camera: Camera::look_at(Vec3::new(-1.5, 0.5, -1.8), Vec3::ZERO, Vec3::Y, 1.2),
            // With kt = 0 nothing may leave the box: a bright background would show at once.
            // With kt > 0 light does pass the walls, so outside is dark.
            background: if kt == 0.0 { Vec3::splat(10.0) } else { Vec3::ZERO },
            ambient,
        };
        let objects = [
            PlacedObject {
                geometry: Shape::Sphere { centre: DVec3::ZERO, radius: 0.6 }
                    .place(&DAffine3::IDENTITY, DVec3::ZERO),
                material: MaterialId(0),
            },
            PlacedObject {
                geometry: Shape::Cuboid { min: DVec3::splat(-2.0), max: DVec3::splat(2.0) }
                    .place(&DAffine3::IDENTITY, DVec3::ZERO),
                material: MaterialId(1),
            },
        ];
        let scene: TraceScene = TraceScene::build(&objects, tables, 2.0);
        let settings = RenderSettings {
            width: 64,
            height: 48,
            max_depth: 12,
            min_contribution: 0.0,
            ..RenderSettings::default()
        };
        let (film, stats) = render(&scene, &settings);
        assert!(stats.rays.reflection > 0);
        let bound = ambient * ball.kd + (ball.kd + Vec3::splat(ball.ks)) * intensity;
        for (i, p) in film.pixels.iter().enumerate() {
            assert!(
                p.cmple(bound + Vec3::splat(1e-5)).all(),
                "kr {kr}, kt {kt}: pixel {i} = {p} exceeds {bound}"
            );
        }
    }
}
