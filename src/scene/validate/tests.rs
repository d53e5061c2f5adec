//! Tests of `src/scene/validate.rs`.

use super::objects::polygon;
use super::*;

fn polygon_rule(vertices: &[Vec3]) -> Option<(String, String)> {
    let path = FieldPath::root().field("vertices");
    let vertices: Vec<DVec3> = vertices.iter().map(|v| v.as_dvec3()).collect();
    polygon(&path, &vertices).err().map(|v| (v.path.to_string(), v.rule))
}

fn regular(n: usize, step: usize, scale: f32) -> Vec<Vec3> {
    (0..n)
        .map(|k| {
            let angle = std::f32::consts::TAU * (k * step) as f32 / n as f32;
            Vec3::new(angle.cos(), angle.sin(), 0.0) * scale + Vec3::splat(3.0 * scale)
        })
        .collect()
}

#[test]
fn a_bow_tie_is_non_convex_not_collinear() {
    for scale in [1e-3, 1.0, 1e4] {
        let bow_tie =
            [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)].map(|(x, y)| Vec3::new(x, y, 2.0) * scale);
        let (_, rule) = polygon_rule(&bow_tie).expect("a bow-tie is rejected");
        assert!(rule.contains("non-convex") && rule.contains("crosses itself"), "{rule}");
        let line = [0.0, 1.0, 3.0].map(|x| Vec3::new(x, 2.0 * x, 0.0) * scale);
        let (_, rule) = polygon_rule(&line).expect("collinear vertices are rejected");
        assert!(rule.contains("collinear"), "{rule}");
    }
}

#[test]
fn convex_polygons_pass_at_every_scale_and_either_winding() {
    for scale in [1e-3, 1.0, 1e4] {
        let mut hexagon = regular(6, 1, scale);
        assert_eq!(polygon_rule(&hexagon), None, "scale {scale}");
        hexagon.reverse();
        assert_eq!(polygon_rule(&hexagon), None, "reversed, scale {scale}");
    }
}

#[test]
fn a_pentagram_winds_twice() {
    let (path, rule) = polygon_rule(&regular(5, 2, 1.0)).expect("rejected");
    assert_eq!(path, "vertices");
    assert!(rule.contains("winds 2 times"), "{rule}");
}

#[test]
fn a_folded_polygon_is_not_convex() {
    let folded = [Vec3::ZERO, Vec3::X, Vec3::new(0.5, 0.0, 0.0), Vec3::Y];
    let (path, rule) = polygon_rule(&folded).expect("rejected");
    assert_eq!(path, "vertices[1]");
    assert!(rule.contains("non-convex"), "{rule}");
}

#[test]
fn rounding_in_kr_plus_kt_is_tolerated() {
    let material = MaterialDesc {
        name: "glass".into(),
        kd: Vec3::ZERO,
        ks: 0.0,
        shininess: 32.0,
        kr: 0.08,
        kt: Vec3::splat(0.92),
        ior: 1.5,
        glossiness: 0.0,
        emission: Vec3::ZERO,
        fresnel: false,
        absorption: Vec3::ZERO,
        kd_texture: None,
        ks_texture: None,
        bump_texture: None,
        bump_depth: 0.01,
    };
    assert_eq!(self::material(&FieldPath::root(), &material), Ok(()));
}
