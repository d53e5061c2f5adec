//! Direct light with the Phong model: ambient is added by the caller; each light (or each
//! sample of an area light) adds `(kd·max(N·L, 0) + ks·max(R·V, 0)^shininess) × radiance ×
//! transmittance` of its shadow ray.

use super::light::Light;
use super::material::Material;
use super::packet::{shadow_passes, Origins, LANES, MIN_LANES};
use super::path::{EffectSamples, PathContext, ShadowHint};
use super::scene::TraceScene;
use super::stats::RayCounts;
use super::visibility::transmittance_at;
use crate::math::{reflect, Ray, RayPacket, Vec2, Vec3, SHADOW_EPSILON};
use crate::simd::SimdLevel;
use crate::store::{PrimitiveStore, TraversalCost};

/// A shading point: where it is, the normal on the side the ray arrived from, and the origin of
/// rays leaving on that side (shadow rays start there).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// Hit point.
    pub point: Vec3,
    /// Unit normal facing the incoming ray.
    pub normal: Vec3,
    /// Where rays leaving on the normal's side start: just beyond `point`'s error bound
    /// ([`crate::store::SurfacePoint::spawn`]).
    pub above: Vec3,
    /// The bound on `point`'s distance from the surface: a light closer than it is not seen.
    pub eps: f32,
}

/// The Phong bracket `kd·N·L + ks·(R·V)^shininess` for unit `to_light` with `N·L > 0`.
#[inline]
pub fn phong(m: &Material, normal: Vec3, view: Vec3, to_light: Vec3, n_dot_l: f32) -> Vec3 {
    let diffuse = m.kd * n_dot_l;
    if m.ks > 0.0 {
        // R·V of unit vectors is at most 1, but rounds a little above it at the highlight's
        // centre, where a huge shininess would raise it to +∞.
        let r_dot_v = reflect(-to_light, normal).dot(view).clamp(0.0, 1.0);
        diffuse + Vec3::splat(m.ks * specular_power(r_dot_v, m.shininess))
    } else {
        diffuse
    }
}

/// `x^s` for the Phong highlight, `x` in `[0, 1]`: by squaring in 64-bit floats for a whole
/// exponent (every accepted shininess up to [`crate::scene::rules::MAX_SHININESS`] that is an
/// integer), `libm`'s `powf` otherwise (the same bits on every CPU, unlike the system's).
#[inline]
pub fn specular_power(x: f32, s: f32) -> f32 {
    if whole_exponent(s) {
        let (mut base, mut n, mut acc) = (f64::from(x), s as u32, 1.0f64);
        while n != 0 {
            if n & 1 != 0 {
                acc *= base;
            }
            base *= base;
            n >>= 1;
        }
        acc as f32
    } else {
        libm::powf(x, s)
    }
}

/// Whether [`specular_power`] takes exponent `s` by squaring: a whole number no larger than
/// [`crate::scene::rules::MAX_SHININESS`].
#[inline(always)]
fn whole_exponent(s: f32) -> bool {
    s == s.trunc() && s <= crate::scene::rules::MAX_SHININESS
}

/// [`specular_power`]`(x[i], s[i])` in every lane whose exponent is whole (squared and
/// multiplied lane by lane: a lane whose exponent has run out of bits multiplies no more; the
/// same 64-bit products in the same order, so the same bits) and in the `wanted` lanes whose
/// exponent is not (`libm`'s `powf`, lane after lane); 1 in the others. Inline it into a
/// [`crate::simd::SimdLevel::run`] closure to get the level's vectors.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
pub fn specular_power_lanes<const N: usize>(x: &[f32; N], s: &[f32; N], wanted: &[bool; N]) -> [f32; N] {
    let mut whole = [false; N];
    let (mut base, mut n, mut acc) = ([0.0f64; N], [0u32; N], [1.0f64; N]);
    for i in 0..N {
        whole[i] = whole_exponent(s[i]);
        base[i] = f64::from(x[i]);
        n[i] = if whole[i] { s[i] as u32 } else { 0 };
    }
    let bits = u32::BITS - n.iter().fold(0, |all, &n| all | n).leading_zeros();
    for _ in 0..bits {
        for i in 0..N {
            if n[i] & 1 != 0 {
                acc[i] *= base[i];
            }
            base[i] *= base[i];
            n[i] >>= 1;
        }
    }
    let mut out = [0.0f32; N];
    for i in 0..N {
        out[i] = acc[i] as f32;
    }
    for i in 0..N {
        if wanted[i] && !whole[i] {
            out[i] = libm::powf(x[i], s[i]);
        }
    }
    out
}

/// Light arriving directly from every light source, Phong-weighted and shadowed.
/// An area light's samples are a per-pixel budget shared among the pixel's camera samples
/// (stratified across them); each traces one shadow ray.
pub fn direct_light<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    m: &Material,
    s: &Surface,
    view: Vec3,
    ctx: &mut PathContext<'_>,
) -> Vec3 {
    let mut colour = Vec3::ZERO;
    let hint = ctx.shadow_hint.take();
    for (j, light) in scene.lights.iter().enumerate() {
        if light.is_area() {
            colour += area_light(scene, light, m, s, view, ctx);
        } else if let Some(lit) =
            point_light(scene, light, (m, s, view), known(hint.as_ref(), j), ctx.time, ctx.rays)
        {
            colour += lit;
        }
    }
    colour
}

/// [`direct_light`] in a scene whose lights are all point, spot or directional lights (none
/// sampled), at time 0: needs no path context. `hint` holds the shadow transmittances already
/// traced in a packet; the other shadow rays are traced here. Inlined into its one caller
/// (a packet's lane), so `view` stays in registers: passed through memory, it was read with a
/// wider load than the stores that had just written it, a stall the CPU cannot forward.
#[inline(always)]
pub(crate) fn point_lights<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    m: &Material,
    s: &Surface,
    view: Vec3,
    hint: Option<&ShadowHint>,
    rays: &mut RayCounts,
) -> Vec3 {
    let mut colour = Vec3::ZERO;
    for (j, light) in scene.lights.iter().enumerate() {
        debug_assert!(!light.is_area(), "area lights are sampled through a path context");
        if let Some(lit) = point_light(scene, light, (m, s, view), known(hint, j), 0.0, rays) {
            colour += lit;
        }
    }
    colour
}

/// Light `j`'s shadow transmittance in `hint`, where it was traced in a packet.
#[inline]
pub(super) fn known(hint: Option<&ShadowHint>, j: usize) -> Option<Vec3> {
    hint.and_then(|h| h.get(j).copied().flatten())
}

/// What point, spot or directional light `light` adds to the surface `s` of material `m` seen
/// from `view` (`None` for nothing: the surface faces away, or the light is blocked): its shadow
/// ray's transmittance is `known`, or traced at time `time`.
#[inline(always)]
fn point_light<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    light: &Light,
    (m, s, view): (&Material, &Surface, Vec3),
    known: Option<Vec3>,
    time: f32,
    rays: &mut RayCounts,
) -> Option<Vec3> {
    let (to_light, dist, radiance) = light.towards(s.point);
    let n_dot_l = s.normal.dot(to_light);
    if n_dot_l <= 0.0 {
        return None;
    }
    rays.shadow += 1;
    // Traced already in a packet (its cost recorded there), or now.
    let pass = match known {
        Some(pass) => pass,
        None => shadow(scene, &Ray::new(s.above, to_light), dist * (1.0 - SHADOW_EPSILON), time, rays),
    };
    (pass != Vec3::ZERO).then(|| radiance * pass * phong(m, s.normal, view, to_light, n_dot_l))
}

/// The samples of one area light, each a point light of `radiance / samples`.
fn area_light<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    light: &Light,
    m: &Material,
    s: &Surface,
    view: Vec3,
    ctx: &mut PathContext<'_>,
) -> Vec3 {
    let samples = ctx.effect_samples(light.samples(), light.pattern());
    // Each sample stands for `1 / count` of the light as this camera sample sees it.
    let share = 1.0 / samples.taken() as f32;
    if let Some(level) = ctx.packets.filter(|_| samples.taken() as usize >= MIN_LANES) {
        return area_light_packets(scene, light, m, s, view, samples, share, level, ctx);
    }
    let mut colour = Vec3::ZERO;
    for st in samples {
        let (to_light, dist, radiance) = light.sample(s.point, st);
        let n_dot_l = s.normal.dot(to_light);
        if n_dot_l <= 0.0 || dist <= s.eps {
            continue;
        }
        ctx.rays.area_shadow += 1;
        let pass =
            shadow(scene, &Ray::new(s.above, to_light), dist * (1.0 - SHADOW_EPSILON), ctx.time, ctx.rays);
        if pass != Vec3::ZERO {
            colour += radiance * (pass * share) * phong(m, s.normal, view, to_light, n_dot_l);
        }
    }
    colour
}

/// [`area_light`] with the shadow rays traced in packets of [`LANES`] (they share an origin):
/// the same samples, rays and sums in the same order, so the same bits. The sample points
/// ([`EffectSamples::fill`]), the directions to them ([`Light::sample_lanes`]) and the
/// packet's reciprocal directions are worked out [`LANES`] at a time.
#[allow(clippy::too_many_arguments)]
fn area_light_packets<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    light: &Light,
    m: &Material,
    s: &Surface,
    view: Vec3,
    mut samples: EffectSamples,
    share: f32,
    level: SimdLevel,
    ctx: &mut PathContext<'_>,
) -> Vec3 {
    let mut colour = Vec3::ZERO;
    let mut packet = RayPacket::<LANES>::default();
    // Each lane's direction to the light, the radiance arriving and N·L.
    let mut lit = [(Vec3::ZERO, Vec3::ZERO, 0.0f32); LANES];
    let mut lanes = 0;
    // Whether `packet` was traced and must be cleared before it takes new lanes.
    let mut traced = false;
    while samples.taken() > 0 {
        let mut st = [Vec2::ZERO; LANES];
        let (count, towards, n_dot_l) = level.run(
            #[inline(always)]
            || {
                let count = samples.fill(&mut st);
                let towards = light.sample_lanes(s.point, &st);
                // `Vec3::dot` lane by lane, in its order.
                let n = s.normal;
                let d = &towards.dir;
                let n_dot_l: [f32; LANES] =
                    std::array::from_fn(|i| n.x * d[0][i] + n.y * d[1][i] + n.z * d[2][i]);
                (count, towards, n_dot_l)
            },
        );
        // The common case, a whole packet's worth of samples that all light the point, fills the
        // packet at once: every lane is set here but the reciprocals, which `add_lit` works out.
        let lights = |i: usize| towards.ok[i] && !(n_dot_l[i] <= 0.0 || towards.dist[i] <= s.eps);
        if lanes == 0 && count == LANES && (0..LANES).all(lights) {
            for axis in 0..3 {
                packet.origin[axis] = [s.above[axis]; LANES];
                packet.dir[axis] = towards.dir[axis];
            }
            packet.t_min = [0.0; LANES];
            packet.t_max = towards.dist.map(|dist| dist * (1.0 - SHADOW_EPSILON));
            packet.active = [true; LANES];
            let radiances = towards.radiances(light);
            for (lane, lit) in lit.iter_mut().enumerate() {
                let to_light = Vec3::new(towards.dir[0][lane], towards.dir[1][lane], towards.dir[2][lane]);
                *lit = (to_light, radiances[lane], n_dot_l[lane]);
            }
            add_lit(scene, &mut packet, &lit, (m, s, view, share), level, ctx, &mut colour);
            traced = true;
            continue;
        }
        for (lane, &st) in st.iter().enumerate().take(count) {
            let (to_light, dist, radiance) = towards.sample(lane, light, s.point, st);
            let n_dot_l = if towards.ok[lane] { n_dot_l[lane] } else { s.normal.dot(to_light) };
            if n_dot_l <= 0.0 || dist <= s.eps {
                continue;
            }
            if traced {
                (packet, traced) = (RayPacket::default(), false);
            }
            packet.put(lanes, &Ray::new(s.above, to_light), 0.0, dist * (1.0 - SHADOW_EPSILON));
            lit[lanes] = (to_light, radiance, n_dot_l);
            lanes += 1;
            if lanes == LANES {
                add_lit(scene, &mut packet, &lit[..lanes], (m, s, view, share), level, ctx, &mut colour);
                (traced, lanes) = (true, 0);
            }
        }
    }
    if lanes > 0 {
        add_lit(scene, &mut packet, &lit[..lanes], (m, s, view, share), level, ctx, &mut colour);
    }
    colour
}

/// Adds to `colour` the light a packet of area-light shadow rays (`packet`, whose lanes'
/// directions, radiance and N·L are `lit`) brings to the surface `s` of material `m` seen from
/// `view`, each lane `share` of the light: lane by lane, in lane order.
#[inline]
fn add_lit<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    packet: &mut RayPacket<LANES>,
    lit: &[(Vec3, Vec3, f32)],
    (m, s, view, share): (&Material, &Surface, Vec3, f32),
    level: SimdLevel,
    ctx: &mut PathContext<'_>,
    colour: &mut Vec3,
) {
    ctx.rays.area_shadow += lit.len() as u64;
    let mut cost = TraversalCost::default();
    let pass = level.run(
        #[inline(always)]
        || {
            packet.reciprocals();
            // The rays of one shading point.
            shadow_passes(scene, packet, Origins::Shared, &mut cost)
        },
    );
    ctx.rays.traversal.record_many(cost.per_ray(lit.len() as u32), lit.len() as u64);
    for (lane, &(to_light, radiance, n_dot_l)) in lit.iter().enumerate() {
        if pass[lane] != Vec3::ZERO {
            *colour += radiance * (pass[lane] * share) * phong(m, s.normal, view, to_light, n_dot_l);
        }
    }
}

/// Transmittance of a shadow ray (per colour channel), its traversal cost counted.
#[inline]
pub(super) fn shadow<S: PrimitiveStore>(
    scene: &TraceScene<S>,
    ray: &Ray,
    t_max: f32,
    time: f32,
    rays: &mut RayCounts,
) -> Vec3 {
    let mut cost = TraversalCost::default();
    let pass = transmittance_at(scene, ray, t_max, time, &mut cost);
    rays.traversal.record(cost);
    pass
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`specular_power_lanes`] has [`specular_power`]'s bits in every lane that is whole or
    /// wanted: exponents of every size up to the largest accepted, fractional ones, and bases
    /// at 0, 1, −0 and NaN, lanes of different exponents side by side.
    #[test]
    fn specular_powers_lane_by_lane_have_the_single_powers_bits() {
        use rand::{RngExt, SeedableRng};
        const N: usize = 16;
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let max = crate::scene::rules::MAX_SHININESS;
        let mut compared = 0;
        for _ in 0..2000 {
            let x: [f32; N] = std::array::from_fn(|_| match rng.random_range(0..12) {
                0 => 0.0,
                1 => 1.0,
                2 => -0.0,
                3 => f32::NAN,
                _ => rng.random_range(0.0..=1.0),
            });
            let s: [f32; N] = std::array::from_fn(|_| match rng.random_range(0..6) {
                0 => rng.random_range(0.0..=max).round(),
                1 => rng.random_range(0..=64) as f32,
                2 => max,
                3 => rng.random_range(0.0..max),
                _ => rng.random_range(0.0..300.0f32).round(),
            });
            let wanted: [bool; N] = std::array::from_fn(|_| rng.random_range(0..4) != 0);
            let got = specular_power_lanes(&x, &s, &wanted);
            for i in 0..N {
                if s[i] == s[i].trunc() || wanted[i] {
                    assert_eq!(got[i].to_bits(), specular_power(x[i], s[i]).to_bits(), "{}^{}", x[i], s[i]);
                    compared += 1;
                }
            }
        }
        assert!(compared > 25_000, "{compared}");
    }

    #[test]
    fn a_huge_shininess_gives_a_highlight_of_at_most_ks() {
        let m = Material { kd: Vec3::splat(0.2), ks: 0.5, shininess: 1e9, ..Material::default() };
        // The viewer on the mirror direction: R·V rounds to just above 1 for some of these.
        let mut above_one = 0;
        for k in 0..2000 {
            let a = k as f32 * 1e-4;
            let normal = Vec3::new(a.sin(), a.cos(), 0.0).normalize();
            let to_light = Vec3::new(0.3 * a, 1.0, 0.1).normalize();
            let view = reflect(-to_light, normal).normalize();
            above_one += u32::from(reflect(-to_light, normal).dot(view) > 1.0);
            let c = phong(&m, normal, view, to_light, normal.dot(to_light).max(0.0));
            assert!(c.is_finite() && c.max_element() <= 0.2 + 0.5 + 1e-6, "{k}: {c}");
        }
        assert!(above_one > 0, "no case rounds R·V above 1; the test would prove nothing");
    }

    /// Whole exponents agree with the exact power (`f64::powf` of the same base: libm's
    /// logarithm and exponential, not repeated products, with an error far below an `f32` ulp)
    /// to within one ulp, down to and through underflow; `0^0` is 1 as
    /// for `powf`, and a fractional exponent is `powf`.
    #[test]
    fn the_specular_power_is_the_power_to_within_an_ulp() {
        let ulp = |v: f32| f32::from_bits(v.to_bits() + 1) - v;
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut underflowed = 0;
        for k in 0..20_000 {
            let x = if k % 7 == 0 { 1.0 - next() * 1e-3 } else { next() };
            let s = (next() * next() * 1e4).floor();
            let got = specular_power(x, s);
            let exact = f64::from(x).powf(f64::from(s));
            let expected = exact as f32;
            underflowed += u32::from(expected == 0.0);
            assert!((got - expected).abs() <= ulp(expected), "{x}^{s}: {got} vs {expected} ({exact:e})");
        }
        assert!(underflowed > 0, "no case underflows; the test would miss that range");
        assert_eq!(specular_power(0.0, 0.0), 1.0);
        assert_eq!(specular_power(0.0, 3.0), 0.0);
        assert_eq!(specular_power(1.0, 1e4), 1.0);
        assert_eq!(specular_power(0.7, 2.5), libm::powf(0.7, 2.5));
    }
}
