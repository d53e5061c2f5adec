//! Triangle stored as a vertex and two edges, intersected with Möller–Trumbore.

use crate::math::{Aabb, Ray, Vec3};

/// A triangle hit: ray parameter and barycentrics of `v1` and `v2`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleHit {
    /// Ray parameter.
    pub t: f32,
    /// Barycentric weight of `v1`.
    pub u: f32,
    /// Barycentric weight of `v2`.
    pub v: f32,
}

/// The bounds of a triangle given by `v0` and edges `e1 = v1 - v0`, `e2 = v2 - v0`.
#[inline]
pub fn bounds(v0: Vec3, e1: Vec3, e2: Vec3) -> Aabb {
    Aabb::from_points([v0, v0 + e1, v0 + e2])
}

/// Möller–Trumbore intersection within `(t_min, t_max)`; both faces are hit.
///
/// Edge tests are inclusive (`u ≥ 0`, `v ≥ 0`, `u + v ≤ 1`), so a ray through a shared edge is
/// never lost between two triangles.
#[inline]
pub fn intersect(v0: Vec3, e1: Vec3, e2: Vec3, ray: &Ray, t_min: f32, t_max: f32) -> Option<TriangleHit> {
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let inv_det = 1.0 / det;
    let s = ray.origin - v0;
    let u = s.dot(p) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.dir.dot(q) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv_det;
    (t > t_min && t < t_max).then_some(TriangleHit { t, u, v })
}

/// Unit geometric normal (`e1 × e2`, counter-clockwise front).
#[inline]
pub fn normal(e1: Vec3, e2: Vec3) -> Vec3 {
    e1.cross(e2).normalize()
}

/// True when the triangle overlaps the box: separating-axis test of Akenine-Möller
/// (box axes, triangle normal and the nine edge cross products). Exact, not a bounds test.
pub fn overlaps_box(v0: Vec3, e1: Vec3, e2: Vec3, cell: &Aabb) -> bool {
    let centre = (cell.min + cell.max) * 0.5;
    let half = (cell.max - cell.min) * 0.5;
    let a = v0 - centre;
    let b = a + e1;
    let c = a + e2;
    let edges = [e1, e2 - e1, -e2];
    // The nine axes edge × box-axis.
    for edge in edges {
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            let l = axis.cross(edge);
            let (pa, pb, pc) = (a.dot(l), b.dot(l), c.dot(l));
            let r = half.dot(l.abs());
            if pa.min(pb).min(pc) > r || pa.max(pb).max(pc) < -r {
                return false;
            }
        }
    }
    // The three box axes: triangle bounds against the box.
    let lo = a.min(b).min(c);
    let hi = a.max(b).max(c);
    if lo.cmpgt(half).any() || hi.cmplt(-half).any() {
        return false;
    }
    // The triangle's plane.
    let n = e1.cross(e2);
    let r = half.dot(n.abs());
    n.dot(a).abs() <= r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn barycentrics_match_hit_point() {
        let (v0, v1, v2) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let ray = Ray::new(Vec3::new(0.25, 0.5, -1.0), Vec3::Z);
        let hit = intersect(v0, v1 - v0, v2 - v0, &ray, 0.0, f32::INFINITY).unwrap();
        assert_eq!((hit.t, hit.u, hit.v), (1.0, 0.25, 0.5));
    }

    #[test]
    fn box_overlap_is_exact_not_bounds() {
        // A diagonal triangle whose bounds cover the cell corner but whose surface does not.
        let v0 = Vec3::new(1.0, 0.0, 0.0);
        let (e1, e2) = (Vec3::new(-1.0, 1.0, 0.0), Vec3::new(-1.0, 0.0, 1.0));
        let corner = Aabb::new(Vec3::ZERO, Vec3::splat(0.2));
        assert!(bounds(v0, e1, e2).overlaps(&corner));
        assert!(!overlaps_box(v0, e1, e2, &corner));
        let through = Aabb::new(Vec3::splat(0.3), Vec3::splat(0.4));
        assert!(overlaps_box(v0, e1, e2, &through));
    }
}
