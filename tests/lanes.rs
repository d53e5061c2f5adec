//! Lane-wise sampling against the scalar functions it replaces: the area-light packets work out
//! their sample points, directions and reciprocal directions sixteen lanes at a time, camera
//! packets their pinhole rays, and every lane must be the bits the scalar function gives, at every SIMD level (the lane loops are
//! compiled for each level's vectors), on random and on edge-case inputs.

use glam::Vec2;
use penumbra::camera::Camera;
use penumbra::math::{Ray, RayPacket, Vec3};
use penumbra::sample::pattern::{square_point_in, square_points_in, strata};
use penumbra::sample::rng::{Dimension, Permutation, SampleKey};
use penumbra::sample::Pattern;
use penumbra::simd::SimdLevel;
use penumbra::trace::light::Falloff;
use penumbra::trace::Light;
use proptest::prelude::*;

const N: usize = 16;

/// The levels this CPU runs.
fn levels() -> impl Iterator<Item = SimdLevel> {
    SimdLevel::ALL.into_iter().filter(|l| l.available())
}

fn patterns() -> impl Strategy<Value = Pattern> {
    prop_oneof![Just(Pattern::Jittered), Just(Pattern::Grid), Just(Pattern::Random)]
}

/// Unit-square inputs as `uniform2` gives them, including 0 and the largest below 1.
fn unit() -> impl Strategy<Value = f32> {
    prop_oneof![Just(0.0f32), Just(1.0 - f32::EPSILON / 2.0), 0.0f32..1.0]
}

fn rect(corner: Vec3, edge_u: Vec3, edge_v: Vec3, falloff: Falloff) -> Light {
    Light::Rect {
        corner,
        edge_u,
        edge_v,
        radiance: Vec3::new(3.0, 2.0, 1.0),
        samples: 16,
        pattern: Pattern::Jittered,
        falloff,
        visible: false,
    }
}

fn disk(centre: Vec3, radius: f32, falloff: Falloff) -> Light {
    Light::Disk {
        centre,
        axis_u: Vec3::X,
        axis_v: Vec3::Z,
        radius,
        radiance: Vec3::new(1.0, 2.0, 3.0),
        samples: 16,
        pattern: Pattern::Grid,
        falloff,
        visible: false,
    }
}

/// Asserts that every lane of `light`'s lanes for `p` equals [`Light::sample`], bit for bit,
/// at every level.
fn check_light(light: &Light, p: Vec3, st: &[Vec2; N]) {
    let want: Vec<_> = st.iter().map(|&st| light.sample(p, st)).collect();
    for level in levels() {
        let lanes = level.run(
            #[inline(always)]
            || light.sample_lanes(p, st),
        );
        let radiances = lanes.radiances(light);
        for (lane, &st) in st.iter().enumerate() {
            let (dir, dist, radiance) = lanes.sample(lane, light, p, st);
            if lanes.ok[lane] {
                // The whole-packet path takes the radiance from here.
                assert_eq!(
                    radiances[lane].to_array().map(f32::to_bits),
                    radiance.to_array().map(f32::to_bits)
                );
            }
            let (wd, wl, wr) = want[lane];
            assert_eq!(
                (dir.to_array().map(f32::to_bits), dist.to_bits(), radiance.to_array().map(f32::to_bits)),
                (wd.to_array().map(f32::to_bits), wl.to_bits(), wr.to_array().map(f32::to_bits)),
                "{level:?}, lane {lane}, point {st} from {p}: {light:?}"
            );
        }
    }
}

#[test]
fn light_lanes_fall_back_where_the_light_point_is_at_far_or_near_the_shading_point() {
    // A light point exactly at p (distance 0), one 1e-20 away (below the fast path's reach),
    // and points 1e30 away whose squared distance overflows.
    let st: [Vec2; N] = std::array::from_fn(|k| Vec2::new(k as f32 / N as f32, 0.5));
    let at = rect(Vec3::ZERO, Vec3::X, Vec3::Z, Falloff::InverseSquare);
    check_light(&at, Vec3::ZERO, &st);
    check_light(&at, Vec3::new(0.5, 1e-20, 0.5), &st);
    let far = rect(Vec3::splat(1e30), Vec3::new(1e29, 0.0, 0.0), Vec3::new(0.0, 0.0, 1e29), Falloff::None);
    check_light(&far, Vec3::splat(-1e30), &st);
    check_light(&disk(Vec3::new(0.0, 1e-25, 0.0), 1e-25, Falloff::InverseSquare), Vec3::ZERO, &st);
    // Point and directional lights have no points: every lane takes the scalar sample.
    let point = Light::Point { position: Vec3::Y, radiance: Vec3::ONE, falloff: Falloff::None };
    check_light(&point, Vec3::ZERO, &st);
}

#[test]
fn reciprocals_of_zero_and_negative_zero_directions_match_set() {
    let dirs = [
        Vec3::new(0.0, -0.0, 1.0),
        Vec3::new(-0.0, 1e-40, -3.0),
        Vec3::new(f32::MAX, -f32::MIN_POSITIVE, 0.5),
    ];
    let mut want = RayPacket::<N>::default();
    let mut got = RayPacket::<N>::default();
    for (lane, &d) in dirs.iter().enumerate() {
        want.set(lane * 5, &Ray::new(Vec3::ONE, d), 0.0, 1.0);
        got.put(lane * 5, &Ray::new(Vec3::ONE, d), 0.0, 1.0);
    }
    for level in levels() {
        let mut packet = got;
        level.run(
            #[inline(always)]
            || packet.reciprocals(),
        );
        let bits = |p: &RayPacket<N>| p.inv_dir.map(|a| a.map(f32::to_bits));
        assert_eq!(bits(&packet), bits(&want), "{level:?}");
        assert_eq!(packet, want, "{level:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 500, ..ProptestConfig::default() })]

    /// Every lane of a permutation's lanes is [`Permutation::at`], for sizes that are and are
    /// not powers of two (where the walk takes several steps).
    #[test]
    fn permutation_lanes_equal_single_elements(n in 1u32..5000, seed in any::<u64>(), first in 0u32..5000) {
        let order = Permutation::new(n, seed);
        let index: [u32; N] = std::array::from_fn(|k| (first + k as u32 * 7) % n);
        let want = index.map(|i| order.at(i));
        for level in levels() {
            let got = level.run(#[inline(always)] || order.at_lanes(&index));
            prop_assert_eq!(got, want, "{:?}", level);
        }
    }

    /// Every lane of a dimension's lanes is [`Dimension::uniform2`].
    #[test]
    fn uniform_lanes_equal_single_points(seed in any::<u64>(), pixel in any::<u32>(), dim in any::<u32>(), first in any::<u32>()) {
        let points = Dimension::new(&SampleKey { seed, frame: 3, pixel, sample: 9 }, dim);
        let index: [u32; N] = std::array::from_fn(|k| first.wrapping_add(k as u32));
        for level in levels() {
            let (x, y) = level.run(#[inline(always)] || points.uniform2_lanes(&index));
            for k in 0..N {
                let want = points.uniform2(index[k]);
                prop_assert_eq!((x[k].to_bits(), y[k].to_bits()), (want.x.to_bits(), want.y.to_bits()));
            }
        }
    }

    /// Every lane of [`square_points_in`] is [`square_point_in`], bit for bit, for any pattern,
    /// stratum grid (prime sizes give `n × 1` strips) and index, every lane below `n` or not.
    #[test]
    fn square_point_lanes_equal_single_points(
        pattern in patterns(),
        n in prop_oneof![1u32..300, Just(65_537), Just(1 << 20), Just(u32::MAX)],
        index in prop::array::uniform16(any::<u32>()),
        in_range in any::<bool>(),
        ux in prop::array::uniform16(unit()),
        uy in prop::array::uniform16(unit()),
    ) {
        let grid = strata(n);
        // Strata below `n` (as callers mostly pass them), or any index (reduced first).
        let index = if in_range { index.map(|i| i % n) } else { index };
        for level in levels() {
            let got = level.run(#[inline(always)] || square_points_in(pattern, grid, &index, &ux, &uy));
            for k in 0..N {
                let want = square_point_in(pattern, grid, index[k], Vec2::new(ux[k], uy[k]));
                prop_assert_eq!(
                    (got[k].x.to_bits(), got[k].y.to_bits()),
                    (want.x.to_bits(), want.y.to_bits()),
                    "{:?} {:?} n {} index {}", level, pattern, n, index[k]
                );
            }
        }
    }

    /// Every lane of an area light's lanes is [`Light::sample`], bit for bit, from shading
    /// points near and far, with and without falloff.
    #[test]
    fn light_lanes_equal_single_samples(
        corner in prop::array::uniform3(-100.0f32..100.0),
        p in prop::array::uniform3(-100.0f32..100.0),
        scale in prop_oneof![Just(1e-6f32), Just(1.0), Just(1e6)],
        st in prop::array::uniform16((unit(), unit())),
        inverse_square in any::<bool>(),
    ) {
        let falloff = if inverse_square { Falloff::InverseSquare } else { Falloff::None };
        let st = st.map(|(s, t)| Vec2::new(s, t));
        let corner = Vec3::from_array(corner) * scale;
        let p = Vec3::from_array(p) * scale;
        check_light(&rect(corner, Vec3::new(2.0, 0.1, 0.0) * scale, Vec3::new(0.0, 0.3, 2.0) * scale, falloff), p, &st);
        check_light(&disk(corner, 1.5 * scale, falloff), p, &st);
    }
}

/// The bits of every array of a packet.
fn packet_bits<const M: usize>(p: &RayPacket<M>) -> Vec<u32> {
    let axes = p.origin.iter().chain(&p.dir).chain(&p.inv_dir).flatten();
    axes.chain(&p.t_min)
        .chain(&p.t_max)
        .map(|v| v.to_bits())
        .chain(p.active.iter().map(|&a| a as u32))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// A packet of pinhole rays equals the packet of the same rays from [`Camera::ray`] put in
    /// lane by lane with [`RayPacket::set`], bit for bit, at every level: any camera, image
    /// size and points (pixel corners, the image's edges, points between).
    #[test]
    fn pinhole_lanes_equal_single_camera_rays(
        eye in prop::array::uniform3(-1e3f32..1e3),
        target in prop::array::uniform3(-1e3f32..1e3),
        fov_deg in 1.0f32..170.0,
        (width, height) in (1u32..4000, 1u32..4000),
        fraction in prop::array::uniform16((0.0f32..=1.0, 0.0f32..=1.0)),
        active in prop::array::uniform16(any::<bool>()),
        corners in any::<bool>(),
    ) {
        let (eye, target) = (Vec3::from_array(eye), Vec3::from_array(target));
        prop_assume!((target - eye).length() > 1e-2);
        let up = if (target - eye).normalize().y.abs() > 0.99 { Vec3::X } else { Vec3::Y };
        let camera = Camera::look_at(eye, target, up, fov_deg.to_radians());
        // Image points: whole pixel corners (`corners`), or anywhere in the image.
        let point = |(u, v): (f32, f32)| match corners {
            true => Vec2::new((u * width as f32).floor(), (v * height as f32).floor()),
            false => Vec2::new(u * width as f32, v * height as f32),
        };
        let points = fraction.map(point);
        let mut want = RayPacket::<N>::default();
        for i in (0..N).filter(|&i| active[i]) {
            want.set(i, &camera.ray(points[i].x, points[i].y, width, height), 0.0, f32::INFINITY);
        }
        for level in levels() {
            let got = level.run(#[inline(always)] || camera.pinhole_lanes(&points, &active, width, height));
            prop_assert_eq!(packet_bits(&got), packet_bits(&want), "{:?}", level);
        }
    }
}

/// A direction component: ordinary, zero of either sign, or so small its reciprocal is infinite.
fn component() -> impl Strategy<Value = f32> {
    prop_oneof![4 => -1.0f32..1.0, 1 => Just(0.0f32), 1 => Just(-0.0f32), 1 => Just(1e-40f32), 1 => Just(-1e-40f32)]
}

/// An origin component: anywhere around the box, or on one of its walls.
fn coordinate() -> impl Strategy<Value = f32> {
    prop_oneof![3 => -4.0f32..4.0, 1 => Just(-1.0f32), 1 => Just(2.0f32)]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1000, ..ProptestConfig::default() })]

    /// Clipping a packet's lanes to a box equals clipping each lane's ray alone: whether it
    /// meets the box and, where it does, the same range bits, at every level; including
    /// axis-parallel lanes, origins on the walls and directions whose reciprocal is infinite.
    #[test]
    fn clipped_lanes_equal_clipped_rays(
        origins in prop::array::uniform16(prop::array::uniform3(coordinate())),
        dirs in prop::array::uniform16(prop::array::uniform3(component())),
        ranges in prop::array::uniform16((prop_oneof![Just(0.0f32), 0.0f32..3.0], prop_oneof![Just(f32::INFINITY), 0.0f32..6.0])),
        live in prop::array::uniform16(any::<bool>()),
    ) {
        let aabb = penumbra::math::Aabb::new(Vec3::splat(-1.0), Vec3::splat(2.0));
        let mut packet = RayPacket::<N>::default();
        let mut t_max = [0.0f32; N];
        for i in 0..N {
            let d = Vec3::from_array(dirs[i]);
            let d = if d == Vec3::ZERO { Vec3::X } else { d };
            packet.set(i, &Ray::new(Vec3::from_array(origins[i]), d), ranges[i].0, 0.0);
            t_max[i] = ranges[i].1;
        }
        for level in levels() {
            let (meets, t0, t1) = level.run(#[inline(always)] || aabb.clip_lanes(&packet, &live, &t_max));
            for i in 0..N {
                let want = live[i].then(|| aabb.clip_ray(&packet.ray(i), Vec3::new(packet.inv_dir[0][i], packet.inv_dir[1][i], packet.inv_dir[2][i]), packet.t_min[i], t_max[i])).flatten();
                let got = meets[i].then_some((t0[i], t1[i]));
                prop_assert_eq!(got.map(|(a, b)| (a.to_bits(), b.to_bits())), want.map(|(a, b)| (a.to_bits(), b.to_bits())), "{:?} lane {}", level, i);
            }
        }
    }
}
