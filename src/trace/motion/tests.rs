//! Tests of `src/trace/motion.rs`.

use super::*;

fn pose(x: f64, angle_deg: f32, scale: f32) -> Pose {
    Pose {
        translation: DVec3::new(x, 0.5, 3.0),
        rotation: Quat::from_rotation_y(angle_deg.to_radians()) * Quat::from_rotation_x(0.3),
        scale: Vec3::splat(scale),
    }
}

#[test]
fn poses_interpolate_from_open_to_close_exactly_at_the_ends() {
    let (a, b) = (pose(-1.0, 0.0, 1.0), pose(3.0, 90.0, 2.0));
    assert_eq!(a.lerp(&b, 0.0), a);
    assert_eq!(a.lerp(&b, 1.0), b);
    let mid = a.lerp(&b, 0.5);
    assert!((mid.translation.x - 1.0).abs() < 1e-12);
    assert!((mid.scale.x - 1.5).abs() < 1e-6);
    // Half the rotation from a to b, either way round.
    let half = a.rotation.angle_between(mid.rotation);
    assert!((half - 0.5 * a.rotation.angle_between(b.rotation)).abs() < 1e-4, "{half}");
}

#[test]
fn swept_bounds_hold_the_object_at_every_time() {
    let shapes = [
        Shape::Cuboid { min: DVec3::new(-1.0, -0.2, -0.5), max: DVec3::new(2.0, 0.3, 0.5) },
        Shape::Sphere { centre: DVec3::new(0.5, 0.0, 0.0), radius: 0.7 },
        Shape::Triangle { vertices: [DVec3::ZERO, DVec3::new(3.0, 0.0, 0.0), DVec3::new(0.0, 1.0, 1.0)] },
    ];
    let motions = [
        (pose(-1.0, 0.0, 1.0), pose(4.0, 0.0, 1.0)),
        (pose(0.0, 0.0, 1.0), pose(0.0, 170.0, 1.0)),
        (pose(-2.0, -60.0, 0.5), pose(1.0, 120.0, 1.5)),
    ];
    for shape in &shapes {
        for (open, close) in motions {
            let o = MovingObject { shape: shape.clone(), open, close, material: MaterialId(0) };
            let swept = o.swept_bounds().unwrap();
            for k in 0..=1000 {
                let b = o.placed_at(k as f32 / 1000.0).bounds().unwrap();
                let inside = swept.min.cmple(b.min).all() && b.max.cmple(swept.max).all();
                assert!(inside, "{shape:?} at {k}/1000: {b:?} outside {swept:?}");
            }
        }
    }
}

#[test]
fn the_motion_grid_finds_what_testing_every_object_finds_at_random_times() {
    use crate::sample::rng::{uniform, SampleKey};
    let mut objects = Vec::new();
    for i in 0..40u32 {
        let key = SampleKey { seed: 7, frame: 0, pixel: i, sample: 0 };
        let u = |d: u32| f64::from(uniform(&key, d, 0));
        let open = Pose {
            translation: DVec3::new(u(0) * 20.0 - 10.0, u(1) * 20.0 - 10.0, u(2) * 20.0 - 10.0),
            rotation: Quat::from_rotation_z(u(3) as f32 * 6.0),
            scale: Vec3::ONE,
        };
        let close = Pose {
            translation: open.translation + DVec3::new(u(4) * 6.0 - 3.0, u(5) * 6.0 - 3.0, 0.0),
            rotation: Quat::from_rotation_z(u(6) as f32 * 6.0),
            scale: Vec3::splat(0.5 + u(7) as f32),
        };
        let shape = match i % 3 {
            0 => Shape::Sphere { centre: DVec3::ZERO, radius: 0.8 },
            1 => Shape::Cuboid { min: DVec3::splat(-0.5), max: DVec3::new(1.0, 0.5, 0.5) },
            _ => {
                Shape::Polygon { vertices: vec![DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y] }
            }
        };
        objects.push((MovingObject { shape, open, close, material: MaterialId(i) }, format!("o{i}")));
    }
    let motion = SceneMotion::new(objects, None, 2.0);
    let meshes: &[Arc<MeshEntry<crate::store::SoaTriangles>>] = &[];
    let mut hits = 0;
    for r in 0..4000u32 {
        let key = SampleKey { seed: 9, frame: 1, pixel: r, sample: 0 };
        let u = |d: u32| uniform(&key, d, 0);
        let origin = Vec3::new(u(0) * 30.0 - 15.0, u(1) * 30.0 - 15.0, -20.0);
        let dir = (Vec3::new(u(2) * 20.0 - 10.0, u(3) * 20.0 - 10.0, 0.0) - origin).normalize();
        let ray = Ray::new(origin, dir);
        let s = u(4);
        let grid = motion.nearest(meshes, &ray, 0.0, f32::INFINITY, s, &mut crate::store::NoTally);
        let brute = motion.nearest_brute(meshes, &ray, 0.0, f32::INFINITY, s);
        assert_eq!(grid, brute, "ray {r} at time {s}");
        hits += grid.is_some() as u32;
    }
    assert!(hits > 400, "only {hits} rays hit anything: the test proves little");
}

#[test]
fn a_moving_camera_interpolates_its_pose() {
    let open = CameraPose {
        position: Vec3::ZERO,
        look_at: Vec3::Z,
        up: Vec3::Y,
        fov_y: 0.8,
        aperture: 0.0,
        focus_distance: 1.0,
    };
    let close = CameraPose { position: Vec3::new(2.0, 0.0, 0.0), look_at: Vec3::new(2.0, 0.0, 1.0), ..open };
    let m = CameraMotion { open, close };
    assert_eq!(m.at(0.0).position, Vec3::ZERO);
    assert!((m.at(0.25).position - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-6);
    assert!((m.at(0.25).forward - Vec3::Z).length() < 1e-6);
    // A pose whose eye lands on its look-at point falls back to an end's camera.
    let through = CameraMotion { open, close: CameraPose { position: Vec3::new(0.0, 0.0, 2.0), ..open } };
    assert!(through.at(0.5).forward.is_finite());
}
