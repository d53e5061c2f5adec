//! Tests of `src/script/lent.rs`.

use super::*;
use crate::scene::{default_scene, spawn_world};
use crate::world::resources::Materials;
use bevy_ecs::prelude::DetectChanges;

#[test]
fn degrees_round_trip_through_the_scene_rotation() {
    for deg in
        [DVec3::new(10.0, -35.0, 80.0), DVec3::new(0.0, 90.0 - 1e-3, 0.0), DVec3::new(-170.0, 5.0, 12.0)]
    {
        let q = rotation_from_degrees(deg);
        let back = degrees_from_rotation(q);
        assert!(rotation_from_degrees(back).angle_between(q) < 1e-5, "{deg} -> {back}");
        assert!((back - deg).abs().max_element() < 1e-3, "{deg} -> {back}");
    }
}

#[test]
fn an_area_light_moves_by_its_centre() {
    let rect = trace::Light::Rect {
        corner: Vec3::ZERO,
        edge_u: Vec3::X * 2.0,
        edge_v: Vec3::Z,
        radiance: Vec3::ONE,
        samples: 4,
        pattern: crate::sample::Pattern::Grid,
        falloff: Default::default(),
        visible: false,
    };
    let rect = Light::at(DVec3::ZERO, rect);
    assert_eq!(light_position(&rect), Some(DVec3::new(1.0, 0.0, 0.5)));
    // Far out, a move finer than f32's step there is kept.
    let to = DVec3::new(1e6 + 0.01, 3.0, 0.5);
    let moved = moved_light(&rect, to);
    assert_eq!(light_position(&moved), Some(to));
    assert_eq!(moved.position(), Some(DVec3::new(1e6 + 0.01 - 1.0, 3.0, 0.0)));
    assert_eq!(moved.source.with_radiance(Vec3::new(0.5, 2.0, 0.0)).radiance(), Vec3::new(0.5, 2.0, 0.0));
}

/// A spawned default scene, prepared for a script, with its first object.
fn prepared() -> (World, Vec<(String, Entity)>) {
    let mut scene = spawn_world::<crate::store::SoaStore>(&default_scene());
    let world = std::mem::take(scene.world_mut());
    let mut world = world;
    let names = prepare(&mut world);
    (world, names)
}

#[test]
fn a_write_of_the_value_already_there_marks_nothing_changed_and_a_refused_one_is_undone() {
    let (mut world, names) = prepared();
    let (_, ball) = names.iter().find(|(_, e)| world.get::<Transform>(*e).is_some()).cloned().unwrap();
    let lent = LentWorld::new(names);
    world.clear_trackers();
    let before = *world.get::<Transform>(ball).unwrap();
    let (result, written) = lent.lend(&mut world, false, || {
        let mut lent = lent.lock();
        let mut scene = lent.scene()?;
        scene.set(ball, before, |_| Ok(()))?;
        let moved = Transform { translation: DVec3::new(1.0, 2.0, 3.0), ..before };
        let refused = scene.set(ball, moved, |_| error("no"));
        assert!(refused.is_err());
        Ok::<(), Box<rhai::EvalAltResult>>(())
    });
    result.unwrap();
    assert_eq!(written, Written::default());
    assert_eq!(*world.get::<Transform>(ball).unwrap(), before, "the refused write is undone");
    assert!(!world.entity(ball).get_ref::<Transform>().unwrap().is_changed());

    // A kept write is marked; a quiet one is not.
    let moved = Transform { translation: DVec3::new(1.0, 2.0, 3.0), ..before };
    let quiet = Transform { translation: DVec3::new(4.0, 2.0, 3.0), ..before };
    for (value, quiet_call, marked) in [(moved, false, true), (quiet, true, false)] {
        world.clear_trackers();
        let _ =
            lent.lend(&mut world, quiet_call, || lent.lock().scene().unwrap().set(ball, value, |_| Ok(())));
        assert_eq!(*world.get::<Transform>(ball).unwrap(), value);
        assert_eq!(world.entity(ball).get_ref::<Transform>().unwrap().is_changed(), marked);
    }
}

#[test]
fn a_material_write_makes_the_object_its_own_copy_once() {
    let (mut world, names) = prepared();
    let (_, ball) = names.iter().find(|(_, e)| world.get::<ScriptMaterial>(*e).is_some()).cloned().unwrap();
    let shared = world.get::<MaterialRef>(ball).unwrap().0;
    let table_len = world.resource::<Materials>().table.len();
    let lent = LentWorld::new(names);
    let original = world.resource::<Materials>().table[shared.0 as usize];
    for kd in [0.25, 0.5] {
        let wanted = Material { kd: Vec3::splat(kd), ..original };
        let (_, written) =
            lent.lend(&mut world, false, || lent.lock().scene().unwrap().set_material(ball, wanted));
        assert_eq!(written.materials, vec![ball]);
        let own = world.get::<MaterialRef>(ball).unwrap().0;
        assert_ne!(own, shared);
        assert_eq!(world.resource::<Materials>().table[own.0 as usize], wanted);
        assert_eq!(world.resource::<Materials>().table.len(), table_len + 1, "one copy, reused");
        assert_eq!(world.resource::<Materials>().table[shared.0 as usize], original, "the shared one stays");
    }
}

#[test]
fn the_script_reads_the_focus_distance_the_renderer_uses() {
    let (mut world, names) = prepared();
    let object = names.iter().find(|(_, e)| world.get::<Transform>(*e).is_some()).map(|(_, e)| *e).unwrap();
    let mut rig = *world.resource::<CameraRig>();
    rig.position = DVec3::new(0.0, 0.0, -5.0);
    rig.look_at = DVec3::new(0.0, 0.0, 3.0);
    world.insert_resource(rig);
    // The object's centre, wherever it is, is the focus the renderer gets after `follow_focus`.
    world.insert_resource(FocusOn(Some(object)));
    let script_reads = resolved_rig(&world).focus_distance();
    follow_focus(&mut world);
    let renderer = world.resource::<CameraRig>().camera().focus_distance;
    assert_eq!(script_reads, renderer);
    assert_eq!(world.resource::<CameraRig>().focus, Focus::Point(centre(&world, object).unwrap()));
}

#[test]
fn reaching_the_world_again_while_holding_it_is_an_error_not_a_deadlock() {
    let lent = LentWorld::new(Vec::new());
    let held = lent.get().unwrap();
    let again = lent.get().err().expect("the lock is held");
    assert!(again.to_string().contains("already being read or written"), "{again}");
    drop(held);
    assert!(lent.get().is_ok());
}
