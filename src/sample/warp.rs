//! Warps from the unit square onto the shapes distribution effects sample: the disk (lens,
//! area lights), the tent filter's footprint (anti-aliasing) and a cone of directions (glossy
//! and blurry surfaces), plus the orthonormal basis the cone is built in.
//!
//! All maps are deterministic functions of their input point, so stratification of the input
//! carries over to the output.

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// The largest `f32` below 1.
pub(crate) const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// Shirley–Chiu concentric map of `[0,1)²` onto the unit disk: area-preserving, no rejection.
///
/// Concentric squares map to concentric circles, so the square's boundary lands on the unit
/// circle and strata stay compact.
///
/// # Examples
/// ```
/// use penumbra::sample::warp::concentric_disk;
/// use glam::Vec2;
/// assert_eq!(concentric_disk(Vec2::splat(0.5)), Vec2::ZERO);
/// assert!((concentric_disk(Vec2::new(1.0, 0.5)).length() - 1.0).abs() < 1e-6);
/// ```
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, FRAC_PI_4 * (o.y / o.x))
    } else {
        (o.y, FRAC_PI_2 - FRAC_PI_4 * (o.x / o.y))
    };
    let (sin, cos) = theta.sin_cos();
    r * Vec2::new(cos, sin)
}

/// Inverse CDF of the tent filter of radius 1: maps `[0,1)` to `(-1, 1)` with density `1 - |x|`.
///
/// # Examples
/// ```
/// use penumbra::sample::warp::tent;
/// assert_eq!(tent(0.5), 0.0);
/// assert!(tent(0.0) > -1.0);
/// ```
pub fn tent(u: f32) -> f32 {
    let x = if u < 0.5 { (2.0 * u).sqrt() - 1.0 } else { 1.0 - (2.0 - 2.0 * u).max(0.0).sqrt() };
    x.clamp(-ONE_MINUS_EPSILON, ONE_MINUS_EPSILON)
}

/// Two unit vectors `(b1, b2)` with `(b1, b2, n)` a right-handed orthonormal basis, for unit `n`.
///
/// Duff et al. 2017, "Building an Orthonormal Basis, Revisited": branchless and continuous
/// except across `n.z = 0`'s sign flip, exact for `n = ±Z`.
pub fn orthonormal_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let b1 = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let b2 = Vec3::new(b, sign + n.y * n.y * a, -n.y);
    (b1, b2)
}

/// A direction uniform over the solid angle of the cone of `half_angle` radians around unit
/// `axis` (`half_angle` in `[0, π/2]`; values outside `[0, π]` are clamped).
///
/// `u.x` picks `cos θ` uniformly in `[cos half_angle, 1]`, `u.y` the azimuth. A zero
/// half-angle returns `axis` exactly, so a perfect mirror needs no special case.
///
/// # Examples
/// ```
/// use penumbra::sample::warp::cone;
/// use glam::{Vec2, Vec3};
/// let d = cone(Vec3::Y, 0.2, Vec2::new(0.3, 0.8));
/// assert!(d.dot(Vec3::Y) >= 0.2f32.cos() - 1e-6);
/// assert_eq!(cone(Vec3::Y, 0.0, Vec2::new(0.3, 0.8)), Vec3::Y);
/// ```
pub fn cone(axis: Vec3, half_angle: f32, u: Vec2) -> Vec3 {
    let half_angle = half_angle.clamp(0.0, PI);
    if half_angle == 0.0 {
        return axis;
    }
    // 1 - cos α = 2 sin²(α/2), accurate for narrow cones.
    let one_minus_cos_max = 2.0 * (0.5 * half_angle).sin().powi(2);
    let one_minus_cos = u.x * one_minus_cos_max;
    let cos_theta = 1.0 - one_minus_cos;
    // sin²θ = (1 - cos θ)(1 + cos θ), again without cancellation.
    let sin_theta = (one_minus_cos * (2.0 - one_minus_cos)).max(0.0).sqrt();
    let (sin_phi, cos_phi) = (2.0 * PI * u.y).sin_cos();
    let (b1, b2) = orthonormal_basis(axis);
    b1 * (sin_theta * cos_phi) + b2 * (sin_theta * sin_phi) + axis * cos_theta
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::rng::{uniform, uniform2, SampleKey};

    fn key(pixel: u32) -> SampleKey {
        SampleKey { seed: 31, frame: 0, pixel, sample: 0 }
    }

    /// A uniformly distributed unit vector (for test inputs).
    fn unit_vector(i: u32) -> Vec3 {
        let u = uniform2(&key(i), 7, 0);
        let z = 1.0 - 2.0 * u.x;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let (s, c) = (2.0 * PI * u.y).sin_cos();
        Vec3::new(r * c, r * s, z).normalize()
    }

    fn chi_square(bins: &[u32], expected: &[f64]) -> f64 {
        bins.iter().zip(expected).map(|(&b, &e)| (f64::from(b) - e).powi(2) / e).sum()
    }

    #[test]
    fn concentric_map_sends_the_square_boundary_onto_the_unit_circle() {
        for k in 0..=256 {
            let t = (k as f32 / 256.0).min(ONE_MINUS_EPSILON);
            for u in [
                Vec2::new(t, 0.0),
                Vec2::new(0.0, t),
                Vec2::new(t, ONE_MINUS_EPSILON),
                Vec2::new(ONE_MINUS_EPSILON, t),
            ] {
                let p = concentric_disk(u);
                assert!((p.length() - 1.0).abs() < 1e-6, "{u} -> {p}");
            }
        }
        assert_eq!(concentric_disk(Vec2::splat(0.5)), Vec2::ZERO);
    }

    #[test]
    fn concentric_map_stays_inside_the_unit_disk() {
        for i in 0..100_000 {
            let p = concentric_disk(uniform2(&key(i), 0, 0));
            assert!(p.length_squared() <= 1.0 + 1e-6, "{p}");
        }
    }

    #[test]
    fn tent_samples_stay_in_the_open_interval_and_follow_the_tent_density() {
        const N: u32 = 200_000;
        const BINS: usize = 20;
        // χ² critical value for 19 degrees of freedom at p = 0.001.
        const CHI2_CRIT: f64 = 43.82;
        for u in [0.0, 0.25, 0.5, 0.75, ONE_MINUS_EPSILON] {
            let x = tent(u);
            assert!(x > -1.0 && x < 1.0, "tent({u}) = {x}");
        }
        let mut bins = [0u32; BINS];
        for i in 0..N {
            let x = tent(uniform(&key(i), 0, 0));
            let b = (((x + 1.0) * 0.5 * BINS as f32) as usize).min(BINS - 1);
            bins[b] += 1;
        }
        // Probability of bin [a, b]: the tent CDF difference.
        let cdf = |x: f64| {
            if x < 0.0 {
                0.5 * (1.0 + x).powi(2)
            } else {
                1.0 - 0.5 * (1.0 - x).powi(2)
            }
        };
        let expected: Vec<f64> = (0..BINS)
            .map(|b| {
                let lo = -1.0 + 2.0 * b as f64 / BINS as f64;
                let hi = lo + 2.0 / BINS as f64;
                f64::from(N) * (cdf(hi) - cdf(lo))
            })
            .collect();
        let chi2 = chi_square(&bins, &expected);
        assert!(chi2 < CHI2_CRIT, "chi2 {chi2}, bins {bins:?}");
    }

    #[test]
    fn orthonormal_basis_is_orthonormal_and_right_handed_for_many_normals() {
        let mut normals: Vec<Vec3> = (0..10_000).map(unit_vector).collect();
        normals.extend([
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
            Vec3::new(0.0, 1e-4, -1.0).normalize(),
            Vec3::new(1e-7, 0.0, -1.0).normalize(),
        ]);
        for n in normals {
            let (b1, b2) = orthonormal_basis(n);
            for (what, v) in [
                ("|b1|", b1.length() - 1.0),
                ("|b2|", b2.length() - 1.0),
                ("b1.b2", b1.dot(b2)),
                ("b1.n", b1.dot(n)),
                ("b2.n", b2.dot(n)),
            ] {
                assert!(v.abs() < 1e-5, "{n}: {what} = {v}");
            }
            assert!((b1.cross(b2) - n).length() < 1e-5, "{n}: not right-handed");
        }
    }

    #[test]
    fn cone_with_zero_half_angle_returns_the_axis_exactly() {
        for i in 0..100 {
            let axis = unit_vector(i);
            assert_eq!(cone(axis, 0.0, uniform2(&key(i), 1, 0)), axis);
        }
    }

    #[test]
    fn cone_directions_lie_inside_the_half_angle_and_average_to_the_axis() {
        const N: u32 = 20_000;
        let mut axes: Vec<Vec3> = (0..4).map(unit_vector).collect();
        axes.extend([Vec3::Z, Vec3::NEG_Z, Vec3::X]);
        for axis in axes {
            for half_angle in [0.01f32, 0.1, 0.5, 1.0, FRAC_PI_2] {
                let cos_max = half_angle.cos();
                // Accumulate in f64: an f32 sum of 20k near-equal vectors rounds the same way
                // every time and drifts by ~1e-4.
                let mut sum = glam::DVec3::ZERO;
                for i in 0..N {
                    let d = cone(axis, half_angle, uniform2(&key(i), 2, 0));
                    assert!((d.length() - 1.0).abs() < 1e-5);
                    assert!(d.dot(axis) >= cos_max - 1e-5, "{axis} {half_angle}: {d}");
                    sum += d.as_dvec3();
                }
                // The mean's lateral error is ≈ half_angle / (2√N) per axis; 0.03 · half_angle
                // is over 5σ at N = 20k.
                let angle = sum.normalize().angle_between(axis.as_dvec3());
                assert!(angle < 0.03 * f64::from(half_angle) + 1e-6, "{axis} {half_angle}: {angle}");
            }
        }
    }

    #[test]
    fn cone_cosines_are_uniform_between_cos_half_angle_and_one() {
        const N: u32 = 64_000;
        const BINS: usize = 16;
        // χ² critical value for 15 degrees of freedom at p = 0.001.
        const CHI2_CRIT: f64 = 37.70;
        let axis = unit_vector(3);
        for half_angle in [0.1f32, 0.7, FRAC_PI_2] {
            // Measure 1 - cos θ in f64 as 2 sin²(θ/2) = |d - axis|²/2, exact for narrow cones.
            let width = 2.0 * (0.5 * f64::from(half_angle)).sin().powi(2);
            let mut bins = [0u32; BINS];
            for i in 0..N {
                let d = cone(axis, half_angle, uniform2(&key(i), 3, 0));
                let t = 0.5 * f64::from((d - axis).length_squared()) / width;
                bins[((t * BINS as f64) as usize).min(BINS - 1)] += 1;
            }
            let expected = [f64::from(N) / BINS as f64; BINS];
            let chi2 = chi_square(&bins, &expected);
            assert!(chi2 < CHI2_CRIT, "{half_angle}: chi2 {chi2}, bins {bins:?}");
        }
    }
}
