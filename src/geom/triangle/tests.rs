//! Tests of `src/geom/triangle.rs`.

use super::*;

fn hit(v: [Vec3; 3], ray: Ray) -> Option<TriangleHit> {
    intersect(v[0], v[1], v[2], &WatertightRay::new(&ray), 0.0, f32::INFINITY)
}

#[test]
fn barycentrics_match_hit_point() {
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let h = hit(tri, Ray::new(Vec3::new(0.25, 0.5, -1.0), Vec3::Z)).unwrap();
    assert_eq!((h.t, h.u, h.v), (1.0, 0.25, 0.5));
    // From behind, along a non-unit direction: same point, t scaled.
    let h = hit(tri, Ray::new(Vec3::new(0.25, 0.5, 2.0), Vec3::new(0.0, 0.0, -2.0))).unwrap();
    assert_eq!((h.t, h.u, h.v), (1.0, 0.25, 0.5));
}

#[test]
fn t_range_is_open_at_both_ends() {
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let r = WatertightRay::new(&Ray::new(Vec3::new(0.2, 0.2, -1.0), Vec3::Z));
    assert!(intersect(tri[0], tri[1], tri[2], &r, 1.0, 2.0).is_none());
    assert!(intersect(tri[0], tri[1], tri[2], &r, 0.0, 1.0).is_none());
    assert!(intersect(tri[0], tri[1], tri[2], &r, 0.5, 1.5).is_some());
}

#[test]
fn degenerate_triangles_are_never_hit_and_have_a_finite_normal() {
    let line = [Vec3::ZERO, Vec3::X, Vec3::X * 2.0];
    assert!(hit(line, Ray::new(Vec3::new(0.5, 0.0, -1.0), Vec3::Z)).is_none());
    let point = [Vec3::ONE; 3];
    assert!(hit(point, Ray::new(Vec3::new(1.0, 1.0, -1.0), Vec3::Z)).is_none());
    assert!(normal(line[0], line[1], line[2]).is_finite());
}

#[test]
fn a_ray_through_a_shared_edge_or_vertex_hits_exactly_one_triangle() {
    // A square split along its diagonal, and a fan of six triangles around a centre vertex.
    let (a, b, c, d) = (Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y);
    let square = [[a, b, c], [a, c, d]];
    let centre = Vec3::new(0.3, 0.2, 0.0);
    let ring: Vec<Vec3> = (0..6)
        .map(|k| {
            let phi = k as f32 * std::f32::consts::TAU / 6.0;
            centre + Vec3::new(phi.cos(), phi.sin(), 0.0)
        })
        .collect();
    let fan: Vec<[Vec3; 3]> = (0..6).map(|k| [centre, ring[k], ring[(k + 1) % 6]]).collect();
    for dir in [Vec3::Z, -Vec3::Z, Vec3::new(0.3, -0.2, 1.0), Vec3::new(-0.7, 0.1, -0.4)] {
        for (tris, target) in [(&square[..], Vec3::new(0.5, 0.5, 0.0)), (&fan[..], centre)] {
            let ray = Ray::new(target - dir * 3.0, dir);
            let hits = tris.iter().filter(|t| hit(**t, ray).is_some()).count();
            assert_eq!(hits, 1, "dir {dir:?} target {target:?}");
        }
    }
}

#[test]
fn box_overlap_is_exact_not_bounds() {
    // A diagonal triangle whose bounds cover the cell corner but whose surface does not.
    let (v0, v1, v2) = (Vec3::X, Vec3::Y, Vec3::Z);
    let corner = Aabb::new(Vec3::ZERO, Vec3::splat(0.2));
    assert!(bounds(v0, v1, v2).overlaps(&corner));
    assert!(!overlaps_box(v0, v1, v2, &corner));
    let through = Aabb::new(Vec3::splat(0.3), Vec3::splat(0.4));
    assert!(overlaps_box(v0, v1, v2, &through));
}

/// A packet's prepared lanes are [`WatertightRay::new`]'s, bit for bit, at every SIMD level:
/// every direction whose components come from ±0, ±1, ±2, ±∞, NaN and a subnormal (ties
/// between axes, zero and non-finite components included), some lanes dead; the common
/// permutation is the one all live lanes share, and there is none when they differ.
#[test]
fn a_prepared_packet_is_the_prepared_rays_lane_for_lane() {
    use crate::math::RayPacket;
    use crate::simd::SimdLevel;
    let values = [0.0, -0.0, 1.0, -1.0, 2.0, -2.0, f32::INFINITY, f32::NEG_INFINITY, f32::NAN, 1e-40];
    let dirs: Vec<Vec3> = (0..values.len().pow(3))
        .map(|n| Vec3::new(values[n % 10], values[n / 10 % 10], values[n / 100]))
        .collect();
    let bits = |w: &WatertightRay| {
        let [kx, ky, kz] = w.permutation();
        let (sx, sy, sz) = w.shear_constants();
        let o = w.origin.to_array().map(f32::to_bits);
        (o, [kx, ky, kz], [sx, sy, sz].map(f32::to_bits))
    };
    let mut shared_seen = [false; 2];
    for (n, chunk) in dirs.chunks(16).enumerate() {
        // Lanes share their directions' pattern in some packets (one repeated direction).
        let same = n % 3 == 0;
        let mut p = RayPacket::<16>::default();
        for (i, &d) in chunk.iter().enumerate() {
            let d = if same { chunk[0] } else { d };
            p.set(i, &Ray::new(Vec3::new(i as f32, -0.5 * n as f32, 3.0), d), 0.0, 1.0);
        }
        let live: [bool; 16] = std::array::from_fn(|i| p.active[i] && (i + n) % 5 != 4);
        for level in SimdLevel::ALL.into_iter().filter(|l| l.available()) {
            let w = level.run(
                #[inline(always)]
                || WatertightPacket::new(&p, &live),
            );
            let mut common = None;
            let mut agree = true;
            for (i, &on) in live.iter().enumerate() {
                if !on {
                    assert_eq!(bits(&w.ray(i)), ([0; 3], [0; 3], [0; 3]), "dead lane {i} is zero");
                    continue;
                }
                let want = WatertightRay::new(&p.ray(i));
                assert_eq!(bits(&w.ray(i)), bits(&want), "lane {i} of packet {n} at {level}");
                match common {
                    None => common = Some(want.permutation()),
                    Some(c) => agree &= c == want.permutation(),
                }
            }
            let want = if agree { common } else { None };
            assert_eq!(w.common_permutation(), want, "packet {n} at {level}");
            shared_seen[usize::from(want.is_some())] = true;
        }
    }
    assert_eq!(shared_seen, [true, true], "packets with and without a common permutation");
}
