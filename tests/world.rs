//! The ECS side: change detection decides when the grid is rebuilt, and an edited World
//! renders exactly like a World spawned fresh from the edited scene.

use std::sync::Arc;

use penumbra::math::{Quat, Vec3};
use penumbra::scene::{self, SceneDesc, ShapeDesc};
use penumbra::store::PrimitiveStore;
use penumbra::trace::{render, RenderSettings};
use penumbra::world::components::{MaterialRef, Transform};
use penumbra::world::resources::Materials;
use penumbra::world::SceneWorld;

const SCENE: &str = r#"Scene(
    camera: (position: (0, 2, -6), look_at: (0, 0.5, 0), fov_deg: 45, width: 48, height: 36),
    settings: (max_depth: 3, background: (0.2, 0.3, 0.5), ambient: (0.1, 0.1, 0.1)),
    materials: [
        (name: "floor", kd: (0.7, 0.7, 0.7)),
        (name: "red", kd: (0.8, 0.1, 0.1), ks: 0.4, shininess: 30),
        (name: "mirror", kd: (0, 0, 0), kr: 0.9),
    ],
    lights: [Point(position: (-3, 6, -4), intensity: 0.9)],
    objects: [
        (name: "floor", shape: Plane(point: (0, 0, 0), normal: (0, 1, 0)), material: "floor"),
        (name: "ball", shape: Sphere(centre: (0, 0, 0), radius: 0.8),
         transform: (translate: (-1, 0.8, 0)), material: "red"),
        (name: "crate", shape: Box(min: (-0.5, 0, -0.5), max: (0.5, 1, 0.5)),
         transform: (translate: (1.5, 0, 0.5)), material: "mirror"),
    ],
)"#;

fn desc() -> SceneDesc {
    scene::parse_scene(SCENE, "world-test.ron").expect("test scene is valid")
}

fn settings(world: &SceneWorld) -> RenderSettings {
    world.render_settings()
}

fn image(world: &mut SceneWorld) -> Vec<Vec3> {
    let snapshot = world.update();
    render(&snapshot, &settings(world)).0.pixels
}

#[test]
fn a_frame_where_nothing_changed_reuses_the_grid() {
    let mut world: SceneWorld = scene::spawn_world(&desc());
    let first = world.update();
    assert_eq!(world.grid_rebuilds(), 1, "the first frame builds the grid");
    let second = world.update();
    let third = world.update();
    assert_eq!(world.grid_rebuilds(), 1, "unchanged frames must not rebuild");
    assert!(Arc::ptr_eq(&first.grid, &second.grid) && Arc::ptr_eq(&second.grid, &third.grid));
}

#[test]
fn moving_a_sphere_rebuilds_the_grid_and_the_image_shows_it_moved() {
    let mut world: SceneWorld = scene::spawn_world(&desc());
    let before = image(&mut world);
    let ball = world.entity("ball").expect("ball exists");
    world.world_mut().get_mut::<Transform>(ball).expect("ball has a transform").translation.x += 0.7;
    let after = image(&mut world);
    assert_eq!(world.grid_rebuilds(), 2);
    assert_ne!(before, after, "the image must change");

    // The edited World renders bit-identically to one spawned with the ball already moved.
    let mut moved = desc();
    moved.objects[1].transform.translate.x += 0.7;
    let mut fresh: SceneWorld = scene::spawn_world(&moved);
    assert_eq!(after, image(&mut fresh));
}

#[test]
fn writing_an_equal_transform_does_not_rebuild() {
    let mut world: SceneWorld = scene::spawn_world(&desc());
    world.update();
    let ball = world.entity("ball").expect("ball exists");
    let same = *world.world().get::<Transform>(ball).expect("ball has a transform");
    // A plain mutable access marks Transform changed even though the value is equal.
    *world.world_mut().get_mut::<Transform>(ball).expect("ball has a transform") = same;
    world.update();
    assert_eq!(world.grid_rebuilds(), 1, "bounds are written with set_if_neq");
}

#[test]
fn changing_a_material_reuses_the_grid_but_changes_the_image() {
    let mut world: SceneWorld = scene::spawn_world(&desc());
    let before = image(&mut world);
    let ball = world.entity("ball").expect("ball exists");
    let mirror = world.world().resource::<Materials>().id("mirror").expect("mirror exists");
    world.world_mut().get_mut::<MaterialRef>(ball).expect("ball has a material").0 = mirror;
    let after = image(&mut world);
    assert_eq!(world.grid_rebuilds(), 1);
    assert_ne!(before, after);
}

#[test]
fn moving_a_plane_does_not_rebuild_the_grid() {
    let mut world: SceneWorld = scene::spawn_world(&desc());
    let before = image(&mut world);
    let floor = world.entity("floor").expect("floor exists");
    world.world_mut().get_mut::<Transform>(floor).expect("floor has a transform").translation.y -= 0.3;
    let after = image(&mut world);
    assert_eq!(world.grid_rebuilds(), 1, "planes are not in the grid");
    assert_ne!(before, after, "but the floor did move");
}

#[test]
fn despawning_an_object_rebuilds_once_and_later_frames_do_not() {
    let mut world: SceneWorld = scene::spawn_world(&desc());
    world.update();
    let crate_ = world.entity("crate").expect("crate exists");
    world.world_mut().despawn(crate_);
    let snapshot = world.update();
    assert_eq!(world.grid_rebuilds(), 2);
    assert_eq!(snapshot.store.bounded_count(), 1, "only the ball is left in the grid");
    world.update();
    world.update();
    assert_eq!(world.grid_rebuilds(), 2, "a removal is seen once, not on every later frame");
}

#[test]
fn rotating_a_box_in_place_rebuilds_even_though_its_bounds_are_equal() {
    // A cube turned by 90° about its vertical axis has the same world box, but different
    // geometry; the grid's exact overlap tests depend on the geometry.
    let mut world: SceneWorld = scene::spawn_world(&desc());
    world.update();
    let crate_ = world.entity("crate").expect("crate exists");
    world.world_mut().get_mut::<Transform>(crate_).expect("crate has a transform").rotation =
        Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
    world.update();
    assert_eq!(world.grid_rebuilds(), 2);
}

#[test]
fn spawned_objects_follow_the_file() {
    let d = desc();
    let mut world: SceneWorld = scene::spawn_world(&d);
    let snapshot = world.update();
    let spheres = d.objects.iter().filter(|o| matches!(o.shape, ShapeDesc::Sphere { .. })).count();
    assert_eq!(spheres, 1);
    assert_eq!(snapshot.materials.len(), d.materials.len());
    assert_eq!(snapshot.lights.len(), 1);
}
