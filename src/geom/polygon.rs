//! Convex planar polygon, stored as a fan of triangles sharing its first vertex.

use crate::math::Vec3;

/// Fan triangulation `(v0, v_i, v_{i+1})` of a convex polygon, as vertex triples.
/// Exact for convex polygons (validated on load); every fan triangle keeps the winding, and
/// neighbours share their edge's vertices bit for bit (the watertight test relies on it).
pub fn fan(vertices: &[Vec3]) -> Vec<[Vec3; 3]> {
    let Some((&v0, rest)) = vertices.split_first() else {
        return Vec::new();
    };
    rest.windows(2)
        .map(|w| [v0, w[0], w[1]])
        .filter(|[a, b, c]| (*b - *a).cross(*c - *a).length_squared() > 0.0)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fan_of_a_square_is_two_triangles_covering_its_area() {
        let square = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let tris = fan(&square);
        assert_eq!(tris.len(), 2);
        let area: f32 = tris.iter().map(|[a, b, c]| (*b - *a).cross(*c - *a).length() * 0.5).sum();
        assert!((area - 1.0).abs() < 1e-6);
    }
}
