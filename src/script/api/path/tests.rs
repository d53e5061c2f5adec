//! Tests of `src/script/api/path.rs`.

use super::*;
use crate::script::api::testing::{eval, eval_err};
use rhai::FLOAT;

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

fn curvy() -> Vec<DVec3> {
    vec![
        v(0.0, 0.0, 0.0),
        v(1.0, 2.0, 0.0),
        v(3.0, 3.0, 1.0),
        v(4.0, 0.0, 2.0),
        v(6.0, 1.0, -1.0),
        v(5.0, 4.0, 0.0),
    ]
}

/// The centripetal segment in Hermite form (independent of the Barry–Goldman pyramid).
fn hermite(p: [DVec3; 4], tau: f64) -> DVec3 {
    let d: Vec<f64> = (0..3).map(|k| p[k].distance(p[k + 1]).sqrt()).collect();
    let (t0, t1, t2, t3) = (0.0, d[0], d[0] + d[1], d[0] + d[1] + d[2]);
    let m1 = (t2 - t1) * ((p[1] - p[0]) / (t1 - t0) - (p[2] - p[0]) / (t2 - t0) + (p[2] - p[1]) / (t2 - t1));
    let m2 = (t2 - t1) * ((p[2] - p[1]) / (t2 - t1) - (p[3] - p[1]) / (t3 - t1) + (p[3] - p[2]) / (t3 - t2));
    let (s2, s3) = (tau * tau, tau * tau * tau);
    p[1] * (2.0 * s3 - 3.0 * s2 + 1.0)
        + m1 * (s3 - 2.0 * s2 + tau)
        + p[2] * (-2.0 * s3 + 3.0 * s2)
        + m2 * (s3 - s2)
}

#[test]
fn barry_goldman_matches_the_hermite_form() {
    let p = [v(0.0, 0.0, 0.0), v(1.0, 3.0, 0.0), v(1.5, 3.2, 0.5), v(4.0, 0.0, 0.0)];
    let segment = Segment::new(p);
    for i in 0..=20 {
        let tau = f64::from(i) / 20.0;
        let (c, dc) = segment.eval(tau);
        assert!(c.distance(hermite(p, tau)) < 1e-12, "tau {tau}");
        let h = 1e-6;
        let numeric = (hermite(p, tau + h) - hermite(p, tau - h)) / (2.0 * h);
        assert!(dc.distance(numeric) < 1e-6, "tau {tau}: {dc} vs {numeric}");
    }
}

#[test]
fn passes_through_every_control_point() {
    for closed in [false, true] {
        let points = curvy();
        let path = Path::new(points.clone(), closed).unwrap();
        for (i, p) in points.iter().enumerate() {
            let u = path.arc[i * SAMPLES] / path.length();
            let error = path.at(u).distance(*p);
            assert!(error <= 1e-9 * p.length().max(1.0), "closed {closed}, point {i}: {error}");
        }
    }
}

#[test]
fn open_ends_are_exact_and_u_is_clamped() {
    let points = curvy();
    let path = Path::new(points.clone(), false).unwrap();
    assert_eq!(path.at(0.0), points[0]);
    assert_eq!(path.at(1.0), points[5]);
    assert_eq!(path.at(-3.0), points[0]);
    assert_eq!(path.at(7.0), points[5]);
    assert_eq!(path.at(f64::NAN), points[0]);
}

#[test]
fn closed_paths_wrap() {
    let path = Path::new(curvy(), true).unwrap();
    assert_eq!(path.at(0.0), path.at(1.0));
    assert_eq!(path.at(1.0), curvy()[0]);
    assert_eq!(path.at(-1e-300), curvy()[0]);
    assert!(path.at(0.25).distance(path.at(1.25)) < 1e-12);
    assert!(path.at(0.25).distance(path.at(-0.75)) < 1e-12);
    assert!(path.at(1.0 - 1e-9).distance(path.at(0.0)) < 1e-6);
}

#[test]
fn evenly_spaced_collinear_points_move_linearly() {
    let (first, step) = (v(1.0, -2.0, 0.5), v(0.5, 1.5, -1.0));
    let points: Vec<DVec3> = (0..5).map(|k| first + step * f64::from(k)).collect();
    let last = points[4];
    let path = Path::new(points, false).unwrap();
    assert!((path.length() - first.distance(last)).abs() < 1e-9);
    for i in 0..=100 {
        let u = f64::from(i) / 100.0;
        let error = path.at(u).distance(first.lerp(last, u));
        assert!(error < 1e-6, "u {u}: {error}");
        assert!(path.tangent(u).distance(step.normalize()) < 1e-9, "u {u}");
    }
}

/// Distances between `at(i / 100)` and `at((i + 1) / 100)`, each measured along
/// `pieces` chords.
fn steps(path: &Path, pieces: u32) -> Vec<f64> {
    let at = |i: u32, j: u32| path.at((f64::from(i) + f64::from(j) / f64::from(pieces)) / 100.0);
    (0..100).map(|i| (0..pieces).map(|j| at(i, j).distance(at(i, j + 1))).sum()).collect()
}

fn assert_even(steps: &[f64], tolerance: f64, what: &str) {
    let mean = steps.iter().sum::<f64>() / steps.len() as f64;
    for (i, step) in steps.iter().enumerate() {
        let deviation = (step - mean).abs() / mean;
        assert!(deviation < tolerance, "{what}, step {i}: {step} vs {mean}");
    }
}

#[test]
fn speed_along_a_curvy_path_is_constant() {
    // A wavy loop: the chord between successive hundredths is within 2 % of the mean.
    let wavy: Vec<DVec3> = (0..7)
        .map(|k| {
            let a = f64::from(k) * std::f64::consts::TAU / 7.0;
            v(3.0 * a.cos(), 2.0 * a.sin(), (2.0 * a).sin())
        })
        .collect();
    for closed in [false, true] {
        for (name, points) in [("curvy", curvy()), ("wavy", wavy.clone())] {
            let path = Path::new(points, closed).unwrap();
            let what = format!("{name}, closed {closed}");
            if name == "wavy" || !closed {
                assert_even(&steps(&path, 1), 0.02, &what);
            }
            // Measured along the arc, even the hairpin closing `curvy` moves evenly.
            let along = steps(&path, 32);
            assert_even(&along, 0.005, &what);
            let total: f64 = along.iter().sum();
            assert!((total - path.length()).abs() < 1e-3 * path.length(), "{what}");
        }
    }
}

#[test]
fn tangent_is_the_unit_direction_of_travel() {
    let path = Path::new(curvy(), false).unwrap();
    for i in 1..100 {
        let u = f64::from(i) / 100.0;
        let t = path.tangent(u);
        assert!((t.length() - 1.0).abs() < 1e-12);
        let numeric = (path.at(u + 1e-5) - path.at(u - 1e-5)).normalize();
        assert!(t.distance(numeric) < 1e-3, "u {u}: {t} vs {numeric}");
    }
    assert!(path.tangent(0.0).is_normalized() && path.tangent(1.0).is_normalized());
}

#[test]
fn duplicate_consecutive_points_stay_finite() {
    let points = vec![
        v(0.0, 0.0, 0.0),
        v(0.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(2.0, 1.0, 0.0),
        v(2.0, 1.0, 0.0),
    ];
    for closed in [false, true] {
        let path = Path::new(points.clone(), closed).unwrap();
        assert!(path.length().is_finite() && path.length() > 0.0);
        for i in 0..=200 {
            let u = f64::from(i) / 200.0;
            assert!(path.at(u).is_finite(), "closed {closed}, u {u}");
            assert!(path.tangent(u).is_normalized(), "closed {closed}, u {u}");
        }
        for (i, p) in points.iter().enumerate() {
            let u = path.arc[i * SAMPLES] / path.length();
            assert!(path.at(u).distance(*p) < 1e-9, "closed {closed}, point {i}");
        }
    }
}

#[test]
fn bad_point_lists_are_errors() {
    assert!(Path::new(vec![v(1.0, 2.0, 3.0)], false).unwrap_err().contains("at least 2"));
    assert!(Path::new(vec![DVec3::ONE; 3], true).unwrap_err().contains("coincide"));
    let infinite = vec![DVec3::ZERO, v(f64::INFINITY, 0.0, 0.0)];
    assert!(Path::new(infinite, false).unwrap_err().contains("point 1 is not finite"));
    let huge = vec![DVec3::splat(-1e308), DVec3::splat(1e308)];
    assert!(Path::new(huge, false).unwrap_err().contains("not finite"));
    let cases = [
        ("catmull_rom([])", "catmull_rom: a path needs at least 2 points, got 0"),
        ("catmull_rom([vec3(1)])", "at least 2 points, got 1"),
        ("catmull_rom([vec3(1), 2, vec3(3)])", "catmull_rom point 1 must be a vec3, got i64"),
        ("catmull_rom(vec3(1))", "catmull_rom points must be an array of vec3, got vec3"),
        ("catmull_rom([vec3(0), vec3(1)], 1)", "closed must be true or false, got i64"),
        ("catmull_rom([vec3(0), vec3(1)]).at(\"a\")", "path at u must be a number, got string"),
    ];
    for (script, expected) in cases {
        let e = eval_err(script);
        assert!(e.contains(expected), "{script}: {e}");
    }
}

#[test]
fn scripts_build_and_query_paths() {
    let line = "let p = catmull_rom([vec3(0, 0, 0), vec3(2, 0, 0)]);";
    assert_eq!(eval::<DVec3>(&format!("{line} p.at(0.25)")), v(0.5, 0.0, 0.0));
    assert_eq!(eval::<DVec3>(&format!("{line} at(p, 1)")), v(2.0, 0.0, 0.0));
    assert_eq!(eval::<DVec3>(&format!("{line} p.tangent(0.3)")), DVec3::X);
    assert_eq!(eval::<FLOAT>(&format!("{line} p.length")), 2.0);
    assert_eq!(eval::<FLOAT>(&format!("{line} length(p)")), 2.0);
    assert_eq!(eval::<INT>(&format!("{line} len(p) + p.len()")), 4);
    assert!(eval::<bool>(&format!("{line} p.points[1] == vec3(2, 0, 0)")));
    let text = eval::<String>(&format!("{line} p.to_string()"));
    assert_eq!(text, "path(2 points, open, length 2)");
    let ring = "let r = catmull_rom([vec3(1, 0, 0), vec3(0, 1, 0), vec3(-1, 0, 0), vec3(0, -1, 0)], true);";
    assert!(eval::<bool>(&format!("{ring} r.at(0) == r.at(1)")));
    assert_eq!(eval::<String>(&format!("{ring} `${{r}}`")).split(',').nth(1), Some(" closed"));
}
