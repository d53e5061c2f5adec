//! Tests of `src/report/sweep.rs`.

use super::*;

#[test]
fn the_default_sweep_covers_only_the_effects_a_scene_uses() {
    let none = SweepDesc::default_for(&Effects::default());
    let names: Vec<&str> = none.axes.iter().map(Axis::name).collect();
    assert_eq!(names, ["aa", "adaptive", "noise"]);
    let all = Effects { area_lights: true, glossy: true, lens: true, motion: true, ..Effects::default() };
    let names: Vec<&str> = SweepDesc::default_for(&all).axes.iter().map(Axis::name).collect();
    assert_eq!(names, ["aa", "adaptive", "noise", "area_light", "glossy", "lens", "time"]);
    assert_eq!(SweepDesc::default_for(&Effects::default()).variants().len(), 12 + 4 + 4);
}

#[test]
fn motion_blur_is_off_in_the_time_axis_cost_and_on_in_the_reference() {
    let mut scene = crate::scene::default_scene();
    scene.camera.shutter = Some((0.0, 0.5));
    assert_eq!(cheapest("time", &scene).unwrap().camera.shutter, None);
    let reference = ReferenceSettings::default().apply(&scene);
    assert_eq!((reference.camera.shutter, reference.camera.time.samples), (Some((0.0, 0.5)), 4));
    let moving = Effects { motion: true, ..Effects::default() };
    assert_eq!(ReferenceSettings::default().describe(&moving), "aa 64 jittered, time 4");
    assert_eq!(ReferenceSettings::default().describe(&Effects::default()), "aa 64 jittered");
}

#[test]
fn sweep_files_parse_and_bad_ones_name_the_place() {
    let text = "Sweep(axes: [Aa(samples: [1, 4]), Lens(samples: [2])], reference: (aa: 32))";
    let sweep = SweepDesc::parse(text, "s.ron").unwrap();
    assert_eq!(sweep.variants().len(), 3);
    assert_eq!(sweep.reference, ReferenceSettings { aa: 32, ..ReferenceSettings::default() });
    assert_eq!(sweep.variants()[1].label(), "aa 4 jittered");
    let e = SweepDesc::parse("Sweep(axes: [Aa(samples: [1, 4], pattern: [Grid])])", "s.ron").unwrap_err();
    assert!(e.to_string().starts_with("s.ron:1:"), "{e}");
    let e = SweepDesc::parse("Sweep(axes: [Lens(samples: [2, 0])])", "s.ron").unwrap_err().to_string();
    assert_eq!(e, "s.ron:1:32: field `axes[0].samples[1]`: lens: sample count must be in 1..=4096, got 0");
    let sweep =
        SweepDesc::parse("Sweep(axes: [Time(samples: [1, 8])], reference: (time: 16))", "s.ron").unwrap();
    assert_eq!(sweep.variants()[1].label(), "time 8");
    assert_eq!(sweep.variants()[1].apply(&crate::scene::default_scene()).camera.time.samples, 8);
    assert_eq!(sweep.reference.time, 16);
    let e = SweepDesc::parse("Sweep(axes: [Time(samples: [4097])])", "s.ron").unwrap_err().to_string();
    assert!(e.contains("field `axes[0].samples[0]`: time: sample count must be in 1..=4096"), "{e}");
    let e = SweepDesc::parse("Sweep(axes: [Time(samples: [1])], reference: (time: 0))", "s.ron")
        .unwrap_err()
        .to_string();
    assert!(e.contains("field `reference.time`: must be in 1..=4096, got 0"), "{e}");
    let e = SweepDesc::parse("Sweep(axes: [])", "s.ron").unwrap_err().to_string();
    assert!(e.contains("field `axes`") && e.contains("no axis"), "{e}");
    let e = SweepDesc::parse("Sweep(axes: [Aa(samples: [1])], reference: (aa: 0))", "s.ron").unwrap_err();
    assert!(e.to_string().contains("s.ron:1:49: field `reference.aa`: must be in 1..=4096, got 0"), "{e}");
}
