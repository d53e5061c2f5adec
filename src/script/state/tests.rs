//! Tests of `src/script/state.rs`.

use super::sync::{light_position, moved_light};
use super::*;
use crate::trace;
use crate::world::components::Light;

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
}

#[test]
fn the_script_reads_the_focus_distance_the_renderer_uses() {
    let mut state = ScriptState::default();
    state.camera.position = DVec3::new(0.0, 0.0, -5.0);
    state.camera.look_at = DVec3::new(0.0, 0.0, 3.0);
    let renderer = |state: &ScriptState| f64::from(state.rig().camera().focus_distance);
    for focus in [
        FocusState::LookAt,
        FocusState::Point(DVec3::new(1.0, 2.0, 4.5)),
        // Behind the eye (the camera flew past the point): the nearest plane in front, not a
        // negative distance.
        FocusState::Point(DVec3::new(0.0, 0.0, -9.0)),
    ] {
        state.camera.focus = focus;
        let distance = state.focus_distance();
        assert_eq!(distance, renderer(&state), "{focus:?}");
        assert!(distance > 0.0, "{focus:?}: {distance}");
    }
    state.camera.focus = FocusState::LookAt;
    assert_eq!(state.focus_distance(), 8.0);
    state.camera.focus = FocusState::Point(DVec3::new(1.0, 2.0, 4.5));
    assert_eq!(state.focus_distance(), 9.5);
    // A distance the script wrote reads back as written (the renderer takes it in f32).
    state.camera.focus = FocusState::Distance(2.3);
    assert_eq!(state.focus_distance(), 2.3);
    assert_eq!(renderer(&state), f64::from(2.3f32));
}
