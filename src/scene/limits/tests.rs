//! Tests of `src/scene/limits.rs`.

use glam::{DVec3, Vec3};

use super::*;
use crate::scene::default_scene;
use crate::scene::format::{LightDesc, ObjectDesc, ShapeDesc, TransformDesc};
use crate::scene::mesh::MeshLibrary;

fn sphere(radius: f32, scale: f32) -> ObjectDesc {
    ObjectDesc {
        name: None,
        shape: ShapeDesc::Sphere { centre: DVec3::ZERO, radius },
        material: "m".into(),
        transform: TransformDesc { scale: Vec3::splat(scale), ..Default::default() },
    }
}

#[test]
fn a_scaled_sphere_must_fit_and_the_limit_itself_is_legal() {
    let meshes = MeshLibrary::default();
    let v = object_violation(&sphere(1e17, 1e3), &meshes).expect("1e20 is beyond the limit");
    assert_eq!(v.path.to_string(), "transform.scale");
    assert!(v.rule.contains("radius 1e17 × scale 1000 puts the object at x = -1e20"), "{}", v.rule);
    assert_eq!(object_violation(&sphere(1e15, 1e3), &meshes), None, "1e18 is at the limit");
    let v = object_violation(&sphere(1e18, 0.5), &meshes);
    assert_eq!(v, None, "a shrinking scale never breaks the rule");
}

#[test]
fn a_translated_object_blames_its_translation() {
    let mut object = sphere(1e17, 1.0);
    object.transform.translate = DVec3::new(0.0, 0.95e18, 0.0);
    let v = object_violation(&object, &MeshLibrary::default()).expect("beyond");
    assert_eq!(v.path.to_string(), "transform.translate");
    assert!(v.rule.contains("y = 1.05e18"), "{}", v.rule);
}

#[test]
fn a_rotation_is_part_of_the_placement() {
    let corner = 0.8e18;
    let object = ObjectDesc {
        name: None,
        shape: ShapeDesc::Cuboid { min: DVec3::splat(-corner), max: DVec3::splat(corner) },
        material: "m".into(),
        transform: TransformDesc::default(),
    };
    assert_eq!(object_violation(&object, &MeshLibrary::default()), None);
    let turned = ObjectDesc {
        transform: TransformDesc { rotate_deg: Vec3::new(0.0, 45.0, 0.0), ..Default::default() },
        ..object
    };
    let v = object_violation(&turned, &MeshLibrary::default()).expect("the turned box reaches 1.13e18");
    assert_eq!(v.path.to_string(), "shape.max");
}

#[test]
fn the_radiance_budget_counts_every_summed_sample() {
    let mut scene = default_scene();
    scene.settings.adaptive = None;
    scene.settings.aa.samples = 4;
    scene.settings.glossy.samples = 8;
    scene.settings.max_depth = 4;
    scene.camera.aperture = 0.0;
    let budget = RadianceBudget::of(&PixelTerms::of(&scene));
    assert_eq!(budget.values, 4.0 * 8.0 * 5.0);
    scene.camera.aperture = 0.1;
    scene.camera.lens.samples = 3;
    assert_eq!(RadianceBudget::of(&PixelTerms::of(&scene)).values, 4.0 * 3.0 * 8.0 * 5.0);
    assert_eq!(radiance_violation(&PixelTerms::of(&scene)), None);
    scene.settings.background = Vec3::new(0.0, 3e38, 0.0);
    let v = radiance_violation(&PixelTerms::of(&scene)).expect("3e38 overflows");
    assert_eq!(v.path.to_string(), "settings.background");
    assert!(v.rule.contains("g = 3e38 is too bright"), "{}", v.rule);
    assert!(v.rule.contains("must stay ≤ 1e29"), "{}", v.rule);
}

#[test]
fn the_brightest_light_is_named() {
    let mut scene = default_scene();
    scene.lights.push(LightDesc::Point {
        position: DVec3::ZERO,
        colour: Vec3::splat(10.0),
        intensity: 3e38,
        falloff: Default::default(),
    });
    let v = radiance_violation(&PixelTerms::of(&scene)).expect("3e39 overflows");
    assert_eq!(v.path.to_string(), format!("lights[{}].intensity", scene.lights.len() - 1));
    assert!(v.rule.contains("colour × intensity = 10 × 3e38 = 3e39 in r is too bright"), "{}", v.rule);
}

#[test]
fn camera_samples_must_fit_32_bits_and_blame_the_time_samples() {
    let mut scene = crate::scene::default_scene();
    (scene.settings.aa.samples, scene.camera.time.samples) = (4096, 4096);
    assert_eq!(
        camera_samples_violation(&PixelTerms::of(&scene)),
        None,
        "a pinhole at 4096 × 4096 is the limit"
    );
    (scene.camera.aperture, scene.camera.lens.samples) = (0.1, 2);
    let v = camera_samples_violation(&PixelTerms::of(&scene)).expect("the lens counts with an aperture");
    assert_eq!(v.path.to_string(), "camera.time.samples");
    assert!(
        v.rule.contains("× camera.time.samples 4096 = 33554432 camera samples, more than 16777216"),
        "{}",
        v.rule
    );
    scene.settings.adaptive = Some(crate::scene::AdaptiveSettings { threshold: 0.1, max_depth: 3 });
    assert_eq!(
        camera_samples_violation(&PixelTerms::of(&scene)),
        None,
        "a lattice point takes the lens and time samples, not the AA samples"
    );
    // A corner takes every lens sample: past the limit only with more times than a field allows.
    (scene.camera.lens.samples, scene.camera.time.samples) = (4096, 4097);
    let v = camera_samples_violation(&PixelTerms::of(&scene)).expect("a corner takes every lens sample");
    assert!(
        v.rule.contains("a pixel corner (settings.adaptive) takes camera.lens.samples 4096"),
        "{}",
        v.rule
    );
    (scene.camera.lens.samples, scene.camera.time.samples) = (2, 4096);
    scene.settings.adaptive = None;
    assert_eq!(check(&scene).unwrap_err().path.to_string(), "camera.time.samples");
}

#[test]
fn the_lens_must_fit() {
    let mut camera = default_scene().file.camera;
    camera.aperture = 1e30;
    assert_eq!(lens_violation(&camera).expect("beyond").path.to_string(), "aperture");
    camera.aperture = 1e17;
    assert_eq!(lens_violation(&camera), None);
    camera.focus_on = None;
    camera.focus_distance = Some(3e18);
    assert_eq!(lens_violation(&camera).expect("beyond").path.to_string(), "focus_distance");
}
