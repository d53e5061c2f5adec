//! Light sources in engine form: radiance already scaled by intensity.
//!
//! Point and directional lights are sampled once per shading point. Area lights (a
//! parallelogram or a disk) take `samples` points per pixel with their own pattern, shared
//! among the pixel's camera samples; shading averages the Phong terms and the visibility over
//! those points (each a point light with the light's radiance). Area lights are invisible to
//! camera, reflection and refraction rays unless `visible` ([`Light::hit`]), and then they show
//! their radiance; lights never cast shadows on each other.
//!
//! Light from point, spot and area lights can fall off with the square of the distance
//! ([`Falloff`]); without it (the default, as in classic Phong and POV-Ray) it does not.

use super::finite::clamp_radiance;
use crate::math::{unit_and_length, Ray, Vec2, Vec3};
use crate::sample::warp::concentric_disk;
use crate::sample::Pattern;

/// How the light from a light source weakens with distance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize, serde::Serialize)]
pub enum Falloff {
    /// It does not: every point receives the light's radiance (classic Phong, POV-Ray).
    #[default]
    None,
    /// Physical falloff: the radiance divided by the squared distance, so `colour ×
    /// intensity` is what arrives one unit away.
    InverseSquare,
}

impl Falloff {
    /// `radiance` as it arrives `dist` away (at most `f32::MAX` per channel).
    #[inline]
    pub fn apply(self, radiance: Vec3, dist: f32) -> Vec3 {
        match self {
            Falloff::None => radiance,
            Falloff::InverseSquare => clamp_radiance(radiance / (dist * dist)),
        }
    }
}

/// A light source.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Light {
    /// Point light.
    Point {
        /// Position.
        position: Vec3,
        /// Colour × intensity.
        radiance: Vec3,
        /// Distance falloff.
        falloff: Falloff,
    },
    /// A point light shining into a cone around `direction`, full inside `cos_inner` and
    /// fading smoothly to nothing at `cos_outer`.
    Spot {
        /// Position.
        position: Vec3,
        /// Unit direction the cone's axis points in.
        direction: Vec3,
        /// Cosine of the half-angle inside which the light is full.
        cos_inner: f32,
        /// Cosine of the half-angle outside which there is no light (≤ `cos_inner`).
        cos_outer: f32,
        /// Colour × intensity on the axis.
        radiance: Vec3,
        /// Distance falloff.
        falloff: Falloff,
    },
    /// Light from infinitely far away.
    Directional {
        /// Unit direction the light travels in.
        direction: Vec3,
        /// Colour × intensity.
        radiance: Vec3,
    },
    /// A parallelogram `corner + s·edge_u + t·edge_v`, s, t ∈ [0, 1], emitting to both sides.
    Rect {
        /// One corner.
        corner: Vec3,
        /// First edge from the corner.
        edge_u: Vec3,
        /// Second edge from the corner.
        edge_v: Vec3,
        /// Colour × intensity of the whole light.
        radiance: Vec3,
        /// Shadow rays per shading point.
        samples: u32,
        /// Placement of the samples.
        pattern: Pattern,
        /// Distance falloff (each sample from its own point).
        falloff: Falloff,
        /// Whether camera, reflection and refraction rays see the light.
        visible: bool,
    },
    /// A disk of `radius` around `centre`, spanned by the unit axes `axis_u`, `axis_v`.
    Disk {
        /// Centre.
        centre: Vec3,
        /// Unit vector in the disk's plane.
        axis_u: Vec3,
        /// Unit vector in the disk's plane, orthogonal to `axis_u`.
        axis_v: Vec3,
        /// Radius.
        radius: f32,
        /// Colour × intensity of the whole light.
        radiance: Vec3,
        /// Shadow rays per shading point.
        samples: u32,
        /// Placement of the samples.
        pattern: Pattern,
        /// Distance falloff (each sample from its own point).
        falloff: Falloff,
        /// Whether camera, reflection and refraction rays see the light.
        visible: bool,
    },
}

impl Light {
    /// The point a light is placed by: a point light's position, a rectangle's corner, a
    /// disk's centre; zero for directional lights.
    pub fn anchor(&self) -> Vec3 {
        match *self {
            Light::Point { position, .. } | Light::Spot { position, .. } => position,
            Light::Rect { corner, .. } => corner,
            Light::Disk { centre, .. } => centre,
            Light::Directional { .. } => Vec3::ZERO,
        }
    }

    /// The light's radiance (its colour × intensity).
    pub fn radiance(&self) -> Vec3 {
        match *self {
            Light::Point { radiance, .. }
            | Light::Spot { radiance, .. }
            | Light::Directional { radiance, .. }
            | Light::Rect { radiance, .. }
            | Light::Disk { radiance, .. } => radiance,
        }
    }

    /// The light with its radiance set to `to`.
    pub fn with_radiance(&self, to: Vec3) -> Self {
        let mut relit = *self;
        match &mut relit {
            Light::Point { radiance, .. }
            | Light::Spot { radiance, .. }
            | Light::Directional { radiance, .. }
            | Light::Rect { radiance, .. }
            | Light::Disk { radiance, .. } => *radiance = to,
        }
        relit
    }

    /// The light moved by `by` (directional lights do not move).
    pub fn translated(&self, by: Vec3) -> Self {
        let mut moved = *self;
        match &mut moved {
            Light::Point { position: p, .. }
            | Light::Spot { position: p, .. }
            | Light::Rect { corner: p, .. }
            | Light::Disk { centre: p, .. } => *p += by,
            Light::Directional { .. } => {}
        }
        moved
    }

    /// Unit direction from `p` towards a point light or directional light, the distance to it
    /// (∞ for directional) and the radiance arriving. For area lights, the direction to the
    /// centre and the whole radiance (used only where one representative sample is wanted).
    // Always inlined: returned through memory, the tuple's (x, y) and z were written by two
    // stores and read back by a load spanning both, which cannot be forwarded (a stall per call
    // on the packet path's shadow rays).
    #[inline(always)]
    pub fn towards(&self, p: Vec3) -> (Vec3, f32, Vec3) {
        match *self {
            Light::Point { position, radiance, falloff } => towards_point(p, position, radiance, falloff),
            Light::Spot { position, direction, cos_inner, cos_outer, radiance, falloff } => {
                let (to_light, dist, arriving) = towards_point(p, position, radiance, falloff);
                (to_light, dist, arriving * spot_factor(-to_light.dot(direction), cos_inner, cos_outer))
            }
            Light::Directional { direction, radiance } => {
                (-direction, f32::INFINITY, clamp_radiance(radiance))
            }
            Light::Rect { corner, edge_u, edge_v, radiance, falloff, .. } => {
                towards_point(p, corner + 0.5 * (edge_u + edge_v), radiance, falloff)
            }
            Light::Disk { centre, radiance, falloff, .. } => towards_point(p, centre, radiance, falloff),
        }
    }

    /// True for lights with an area (sampled with several shadow rays).
    #[inline]
    pub fn is_area(&self) -> bool {
        matches!(self, Light::Rect { .. } | Light::Disk { .. })
    }

    /// Samples per shading point (1 for point and directional lights).
    #[inline]
    pub fn samples(&self) -> u32 {
        match *self {
            Light::Rect { samples, .. } | Light::Disk { samples, .. } => samples.max(1),
            _ => 1,
        }
    }

    /// How the light's samples are placed over its area (jittered for point and directional
    /// lights, which take one).
    #[inline]
    pub fn pattern(&self) -> Pattern {
        match *self {
            Light::Rect { pattern, .. } | Light::Disk { pattern, .. } => pattern,
            _ => Pattern::Jittered,
        }
    }

    /// The point `st` of `[0, 1)²` (placed by the light's [`Self::pattern`] among the pixel's
    /// shadow samples) on an area light, as (direction from `p`, distance, the light's whole
    /// radiance). The caller averages over the samples it takes. Point and directional lights
    /// ignore `st`.
    #[inline]
    pub fn sample(&self, p: Vec3, st: Vec2) -> (Vec3, f32, Vec3) {
        match (*self, self.point(st)) {
            (Light::Rect { radiance, falloff, .. } | Light::Disk { radiance, falloff, .. }, Some(q)) => {
                towards_point(p, q, radiance, falloff)
            }
            _ => self.towards(p),
        }
    }

    /// The point `st` of `[0, 1)²` on an area light; `None` for point and directional lights.
    #[inline(always)]
    fn point(&self, st: Vec2) -> Option<Vec3> {
        match *self {
            Light::Rect { corner, edge_u, edge_v, .. } => Some(corner + st.x * edge_u + st.y * edge_v),
            Light::Disk { centre, axis_u, axis_v, radius, .. } => {
                let d = concentric_disk(st) * radius;
                Some(centre + d.x * axis_u + d.y * axis_v)
            }
            _ => None,
        }
    }

    /// [`Self::sample`]'s directions and distances from `p` for the points `st` of an area
    /// light, worked out lane by lane so that the lanes' square roots and divisions share
    /// instructions: in every lane that is `ok`, the same bits as [`Self::sample`]. A lane is
    /// not `ok` where its point is so near `p`, or so far, that [`Self::sample`] takes its safe
    /// path ([`LightLanes::sample`] then takes that). Point and directional lights give no
    /// lane `ok`. Inline it into a [`crate::simd::SimdLevel::run`] closure to get the level's
    /// vectors.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
    pub fn sample_lanes<const N: usize>(&self, p: Vec3, st: &[Vec2; N]) -> LightLanes<N> {
        let mut out = LightLanes { dir: [[0.0; N]; 3], dist: [0.0; N], ok: [false; N] };
        let mut to = [[0.0f32; N]; 3];
        for (lane, &st) in st.iter().enumerate() {
            let Some(q) = self.point(st) else { return out };
            for axis in 0..3 {
                to[axis][lane] = q[axis] - p[axis];
            }
        }
        for lane in 0..N {
            let [x, y, z] = [to[0][lane], to[1][lane], to[2][lane]];
            // `Vec3::length` and `Vec3 / f32`, in the same order.
            let dist = (x * x + y * y + z * z).sqrt();
            out.dist[lane] = dist;
            out.ok[lane] = dist.is_finite() && dist >= TINY_DISTANCE;
            for axis in 0..3 {
                out.dir[axis][lane] = to[axis][lane] / dist;
            }
        }
        out
    }

    /// [`Self::towards`] from the points `p` (one array per axis) of a point, spot or
    /// directional light, worked out lane by lane so that the lanes' square roots, divisions and
    /// falloffs share instructions: in every lane that is `ok`, the same bits as
    /// [`Self::towards`]. A lane is not `ok` where the light is so near its point, or so far,
    /// that [`Self::towards`] takes its safe path; area lights give no lane `ok`. Inline it into
    /// a [`crate::simd::SimdLevel::run`] closure to get the level's vectors.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
    pub fn towards_lanes<const N: usize>(&self, p: &[[f32; N]; 3]) -> TowardsLanes<N> {
        let mut out =
            TowardsLanes { dir: [[0.0; N]; 3], dist: [0.0; N], radiance: [[0.0; N]; 3], ok: [false; N] };
        let (position, radiance, falloff) = match *self {
            Light::Point { position, radiance, falloff }
            | Light::Spot { position, radiance, falloff, .. } => {
                (position, clamp_radiance(radiance), falloff)
            }
            Light::Directional { direction, radiance } => {
                let (to_light, radiance) = (-direction, clamp_radiance(radiance));
                for axis in 0..3 {
                    out.dir[axis] = [to_light[axis]; N];
                    out.radiance[axis] = [radiance[axis]; N];
                }
                return TowardsLanes { dist: [f32::INFINITY; N], ok: [true; N], ..out };
            }
            Light::Rect { .. } | Light::Disk { .. } => return out,
        };
        for lane in 0..N {
            // `towards_point`: `Vec3::length`, `Vec3 / f32` and `Falloff::apply`, in the same order.
            let to = [position.x - p[0][lane], position.y - p[1][lane], position.z - p[2][lane]];
            let dist = (to[0] * to[0] + to[1] * to[1] + to[2] * to[2]).sqrt();
            out.dist[lane] = dist;
            out.ok[lane] = dist.is_finite() && dist >= TINY_DISTANCE;
            for axis in 0..3 {
                out.dir[axis][lane] = to[axis] / dist;
            }
            let square = dist * dist;
            for axis in 0..3 {
                out.radiance[axis][lane] = match falloff {
                    Falloff::None => radiance[axis],
                    Falloff::InverseSquare => {
                        let r = radiance[axis] / square;
                        if r > f32::MAX {
                            f32::MAX
                        } else {
                            r
                        }
                    }
                };
            }
        }
        if let Light::Spot { direction, cos_inner, cos_outer, .. } = *self {
            for lane in 0..N {
                // `-to_light.dot(direction)`: the dot product, negated.
                let [x, y, z] = [out.dir[0][lane], out.dir[1][lane], out.dir[2][lane]];
                let cos = -(x * direction.x + y * direction.y + z * direction.z);
                let factor = spot_factor(cos, cos_inner, cos_outer);
                for axis in 0..3 {
                    out.radiance[axis][lane] *= factor;
                }
            }
        }
        out
    }

    /// True for an area light that camera, reflection and refraction rays see.
    #[inline]
    pub fn is_visible(&self) -> bool {
        matches!(self, Light::Rect { visible: true, .. } | Light::Disk { visible: true, .. })
    }

    /// Where `ray` meets a visible light within `(0, t_max)` (`t` in units of the direction's
    /// length), and the radiance it sees there: the light's colour × intensity, from either
    /// side. `None` for lights that are not visible.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: f32) -> Option<(f32, Vec3)> {
        match *self {
            Light::Rect { corner, edge_u, edge_v, radiance, visible: true, .. } => {
                let n = edge_u.cross(edge_v);
                let t = plane_t(ray, corner, n, t_max)?;
                // q = s·edge_u + r·edge_v: s n = q × edge_v, r n = edge_u × q.
                let q = ray.at(t) - corner;
                let nn = n.dot(n);
                let s = q.cross(edge_v).dot(n) / nn;
                let r = edge_u.cross(q).dot(n) / nn;
                ((0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&r)).then(|| (t, clamp_radiance(radiance)))
            }
            Light::Disk { centre, axis_u, axis_v, radius, radiance, visible: true, .. } => {
                let t = plane_t(ray, centre, axis_u.cross(axis_v), t_max)?;
                let q = ray.at(t) - centre;
                (q.length_squared() <= radius * radius).then(|| (t, clamp_radiance(radiance)))
            }
            _ => None,
        }
    }
}

/// The ray parameter where `ray` crosses the plane through `p` with normal `n`, if that is in
/// `(0, t_max)`; `None` for a ray parallel to the plane.
#[inline]
fn plane_t(ray: &Ray, p: Vec3, n: Vec3, t_max: f32) -> Option<f32> {
    let denom = ray.dir.dot(n);
    if denom == 0.0 {
        return None;
    }
    let t = (p - ray.origin).dot(n) / denom;
    (t > 0.0 && t < t_max).then_some(t)
}

/// How much of a spot light's radiance leaves in a direction whose cosine with the axis is
/// `cos`: 1 inside the inner cone, 0 outside the outer one, a smoothstep between.
#[inline]
pub fn spot_factor(cos: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    if cos >= cos_inner {
        return 1.0;
    }
    if cos <= cos_outer {
        return 0.0;
    }
    let x = (cos - cos_outer) / (cos_inner - cos_outer);
    x * x * (3.0 - 2.0 * x)
}

/// Directions and distances from a point to `N` points of an area light, lane by lane
/// ([`Light::sample_lanes`]).
#[derive(Debug, Clone, Copy)]
pub struct LightLanes<const N: usize> {
    /// Unit directions towards the light points, one array per axis.
    pub dir: [[f32; N]; 3],
    /// Distances to the light points.
    pub dist: [f32; N],
    /// Lanes whose direction and distance are [`Light::sample`]'s.
    pub ok: [bool; N],
}

impl<const N: usize> LightLanes<N> {
    /// [`Light::sample`]`(p, st)` for lane `lane`, whose point is `st`, of the lanes `light`
    /// gave for `p`: the lane's direction and distance where it is `ok`, the whole sample taken
    /// again where it is not.
    #[inline]
    pub fn sample(&self, lane: usize, light: &Light, p: Vec3, st: Vec2) -> (Vec3, f32, Vec3) {
        match *light {
            Light::Rect { radiance, falloff, .. } | Light::Disk { radiance, falloff, .. }
                if self.ok[lane] =>
            {
                let dir = Vec3::new(self.dir[0][lane], self.dir[1][lane], self.dir[2][lane]);
                let dist = self.dist[lane];
                (dir, dist, falloff.apply(clamp_radiance(radiance), dist))
            }
            _ => light.sample(p, st),
        }
    }

    /// The radiance arriving in every lane from an area light `light` (zero for other lights):
    /// in the lanes that are `ok`, [`Self::sample`]'s third part.
    #[inline]
    pub fn radiances(&self, light: &Light) -> [Vec3; N] {
        match *light {
            Light::Rect { radiance, falloff, .. } | Light::Disk { radiance, falloff, .. } => {
                let radiance = clamp_radiance(radiance);
                self.dist.map(|dist| falloff.apply(radiance, dist))
            }
            _ => [Vec3::ZERO; N],
        }
    }
}

/// Directions, distances and arriving radiance from `N` points to a point, spot or
/// directional light, lane by lane ([`Light::towards_lanes`]).
#[derive(Debug, Clone, Copy)]
pub struct TowardsLanes<const N: usize> {
    /// Unit directions towards the light, one array per axis.
    pub dir: [[f32; N]; 3],
    /// Distances to the light (∞ for a directional light).
    pub dist: [f32; N],
    /// The radiance arriving, one array per channel.
    pub radiance: [[f32; N]; 3],
    /// Lanes whose direction, distance and radiance are [`Light::towards`]'s.
    pub ok: [bool; N],
}

/// Below this distance to a light, `to / |to|` loses precision: [`unit_and_length`] takes over.
const TINY_DISTANCE: f32 = 1e-18;

/// Direction and distance from `p` to a point of a light, and the radiance arriving (at most
/// `f32::MAX` per channel, after `falloff`). Safe at any distance: far points (where `|to|²` overflows) and
/// near ones (where it underflows) are handled on a scaled vector, and a light exactly at `p`
/// gives a zero direction, which every caller skips as facing away.
#[inline]
fn towards_point(p: Vec3, position: Vec3, radiance: Vec3, falloff: Falloff) -> (Vec3, f32, Vec3) {
    let to = position - p;
    let dist = to.length();
    let radiance = clamp_radiance(radiance);
    if dist.is_finite() && dist >= TINY_DISTANCE {
        return (to / dist, dist, falloff.apply(radiance, dist));
    }
    match unit_and_length(to) {
        Some((dir, dist)) => (dir, dist, falloff.apply(radiance, dist)),
        None => (Vec3::ZERO, 0.0, radiance),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every lane `ok` has [`Light::towards`]'s bits, and the lanes not `ok` are exactly those
    /// where it takes its safe path: points at the light, a hair from it, ordinary and far, for
    /// point lights with and without falloff, spots, directional and area lights.
    #[test]
    fn light_lanes_towards_give_the_single_points_bits() {
        use rand::{RngExt, SeedableRng};
        const N: usize = 16;
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let position = Vec3::new(0.5, 3.0, -1.0);
        let radiance = Vec3::new(2.0, 1.0, 3e38);
        let lights = [
            Light::Point { position, radiance, falloff: Falloff::None },
            Light::Point { position, radiance, falloff: Falloff::InverseSquare },
            Light::Spot {
                position,
                direction: Vec3::new(0.1, -1.0, 0.2).normalize(),
                cos_inner: 0.95,
                cos_outer: 0.8,
                radiance,
                falloff: Falloff::InverseSquare,
            },
            Light::Directional { direction: Vec3::new(0.3, -1.0, 0.1).normalize(), radiance },
            Light::Disk {
                centre: position,
                axis_u: Vec3::X,
                axis_v: Vec3::Z,
                radius: 1.0,
                radiance,
                samples: 4,
                pattern: Pattern::Jittered,
                falloff: Falloff::None,
                visible: false,
            },
        ];
        let (mut ok, mut safe) = (0, 0);
        for round in 0..400 {
            let points: [Vec3; N] = std::array::from_fn(|lane| match (round + lane) % 5 {
                0 => position,
                1 => position + Vec3::new(1e-20, -3e-20, 2e-20),
                2 => position + Vec3::splat(rng.random_range(-1e-17f32..1e-17)),
                3 => Vec3::new(rng.random_range(-1e18..1e18), rng.random_range(-1e18..1e18), 0.0),
                _ => Vec3::new(
                    rng.random_range(-4.0..4.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-4.0..4.0),
                ),
            });
            let lanes = [0, 1, 2].map(|axis| points.map(|p| p[axis]));
            for light in &lights {
                let got = light.towards_lanes(&lanes);
                for (lane, &p) in points.iter().enumerate() {
                    let (dir, dist, arriving) = light.towards(p);
                    let fast = match *light {
                        Light::Point { .. } | Light::Spot { .. } => {
                            let d = (position - p).length();
                            d.is_finite() && d >= TINY_DISTANCE
                        }
                        Light::Directional { .. } => true,
                        _ => false,
                    };
                    assert_eq!(got.ok[lane], fast, "{light:?} from {p}");
                    if !fast {
                        safe += 1;
                        continue;
                    }
                    ok += 1;
                    let lane_of = |a: &[[f32; N]; 3]| [0, 1, 2].map(|axis| a[axis][lane].to_bits());
                    assert_eq!(lane_of(&got.dir), dir.to_array().map(f32::to_bits), "{light:?} from {p}");
                    assert_eq!(got.dist[lane].to_bits(), dist.to_bits(), "{light:?} from {p}");
                    assert_eq!(
                        lane_of(&got.radiance),
                        arriving.to_array().map(f32::to_bits),
                        "{light:?} from {p}"
                    );
                }
            }
        }
        assert!(ok > 10_000 && safe > 5_000, "{ok} lanes ok, {safe} safe");
    }

    #[test]
    fn towards_a_point_is_finite_near_far_and_at_the_light() {
        let one = Vec3::ONE;
        let (d, dist, _) =
            towards_point(Vec3::new(-1e30, 0.0, 0.0), Vec3::new(1e30, 0.0, 0.0), one, Falloff::None);
        assert_eq!((d, dist), (Vec3::X, 2e30));
        let (d, dist, _) = towards_point(Vec3::ZERO, Vec3::new(0.0, 3e-25, 4e-25), one, Falloff::None);
        assert!((d - Vec3::new(0.0, 0.6, 0.8)).length() < 1e-6 && (dist - 5e-25).abs() < 1e-30);
        let (d, dist, _) = towards_point(Vec3::splat(1e7), Vec3::splat(1e7), one, Falloff::None);
        assert_eq!((d, dist), (Vec3::ZERO, 0.0));
        // An ordinary distance keeps the plain bits.
        let to = Vec3::new(1.0, 2.0, -2.5);
        assert_eq!(towards_point(Vec3::ZERO, to, one, Falloff::None).0, to / to.length());
    }

    #[test]
    fn radiance_beyond_the_largest_float_arrives_as_the_largest_float() {
        let light = Light::Point {
            position: Vec3::Y,
            radiance: Vec3::new(f32::INFINITY, 3e38, 0.0),
            falloff: Falloff::None,
        };
        assert_eq!(light.towards(Vec3::ZERO).2, Vec3::new(f32::MAX, 3e38, 0.0));
        let sun = Light::Directional { direction: -Vec3::Y, radiance: Vec3::splat(f32::INFINITY) };
        assert_eq!(sun.towards(Vec3::ZERO), (Vec3::Y, f32::INFINITY, Vec3::splat(f32::MAX)));
    }

    #[test]
    fn inverse_square_falloff_matches_the_analytic_value_and_none_keeps_the_radiance() {
        let radiance = Vec3::new(8.0, 4.0, 2.0);
        for dist in [0.5f32, 1.0, 2.0, 3.0, 100.0] {
            let light = Light::Point {
                position: Vec3::new(0.0, dist, 0.0),
                radiance,
                falloff: Falloff::InverseSquare,
            };
            let (_, d, arriving) = light.towards(Vec3::ZERO);
            assert_eq!(d, dist);
            let expected = radiance / (dist * dist);
            assert!((arriving - expected).abs().max_element() <= 1e-6 * expected.max_element(), "{dist}");
            let plain =
                Light::Point { position: Vec3::new(0.0, dist, 0.0), radiance, falloff: Falloff::None };
            assert_eq!(plain.towards(Vec3::ZERO).2, radiance);
        }
    }

    #[test]
    fn a_spot_light_is_full_inside_its_inner_cone_dark_outside_and_smooth_between() {
        let spot = Light::Spot {
            position: Vec3::new(0.0, 10.0, 0.0),
            direction: -Vec3::Y,
            cos_inner: 20f32.to_radians().cos(),
            cos_outer: 30f32.to_radians().cos(),
            radiance: Vec3::ONE,
            falloff: Falloff::None,
        };
        let at = |deg: f32| spot.towards(Vec3::new(10.0 * deg.to_radians().tan(), 0.0, 0.0)).2.x;
        assert_eq!(at(0.0), 1.0);
        assert_eq!(at(19.0), 1.0);
        assert_eq!(at(31.0), 0.0);
        let mid = at(25.0);
        assert!(mid > 0.1 && mid < 0.9, "{mid}");
        assert!(at(22.0) > mid && mid > at(28.0), "fades monotonically");
        assert_eq!(spot_factor(0.5, 0.8, 0.2), 0.5, "the smoothstep's middle");
    }

    #[test]
    fn a_visible_rect_or_disk_is_hit_inside_and_missed_outside_and_invisible_ones_never() {
        let rect = Light::Rect {
            corner: Vec3::new(-1.0, 2.0, -0.5),
            edge_u: Vec3::new(2.0, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 0.0, 1.0),
            radiance: Vec3::new(3.0, 2.0, 1.0),
            samples: 4,
            pattern: Pattern::Jittered,
            falloff: Falloff::None,
            visible: true,
        };
        let up = |x: f32, z: f32| Ray::new(Vec3::new(x, 0.0, z), Vec3::Y);
        assert_eq!(rect.hit(&up(0.0, 0.0), f32::INFINITY), Some((2.0, Vec3::new(3.0, 2.0, 1.0))));
        assert_eq!(rect.hit(&up(0.99, 0.49), f32::INFINITY).map(|h| h.0), Some(2.0));
        assert_eq!(rect.hit(&up(1.01, 0.0), f32::INFINITY), None);
        assert_eq!(rect.hit(&up(0.0, 0.51), f32::INFINITY), None);
        assert_eq!(rect.hit(&up(0.0, 0.0), 1.5), None, "beyond t_max");
        assert_eq!(rect.hit(&Ray::new(Vec3::new(0.0, 3.0, 0.0), Vec3::Y), f32::INFINITY), None, "behind");
        // Seen from above too, and with a direction of another length (t in its units).
        assert_eq!(
            rect.hit(&Ray::new(Vec3::new(0.0, 6.0, 0.0), -4.0 * Vec3::Y), f32::INFINITY).map(|h| h.0),
            Some(1.0)
        );
        let mut hidden = rect;
        if let Light::Rect { visible, .. } = &mut hidden {
            *visible = false;
        }
        assert_eq!(hidden.hit(&up(0.0, 0.0), f32::INFINITY), None);
        let disk = Light::Disk {
            centre: Vec3::new(0.0, 2.0, 0.0),
            axis_u: Vec3::X,
            axis_v: Vec3::Z,
            radius: 0.5,
            radiance: Vec3::ONE,
            samples: 4,
            pattern: Pattern::Jittered,
            falloff: Falloff::None,
            visible: true,
        };
        assert_eq!(disk.hit(&up(0.3, 0.3), f32::INFINITY).map(|h| h.0), Some(2.0));
        assert_eq!(disk.hit(&up(0.4, 0.4), f32::INFINITY), None, "inside the square, outside the disk");
    }
}
