//! The direct light of a camera packet's lanes, found together where every light is a point,
//! spot or directional light and the hit's material has no textures: each light's direction,
//! distance and falloff ([`Light::towards_lanes`]), the Phong bracket
//! ([`specular_power_lanes`]) and the sums are worked out lane by lane in vectors, with the
//! IEEE operations of [`point_lights`](super::phong::point_lights) in their order, so every
//! lane has the bits it has lit alone. A lane whose hit sends no reflected or refracted ray and
//! whose light lost nothing on its way in is finished here too (ambient and emission:
//! [`Lit::local`](super::integrator::Lit::local)); the others take their direct light on to the
//! single-lane path. Shadow rays the packet did not trace
//! ([`super::packet_tile::point_light_shadows`]) are traced here one by one.

use super::integrator::{bounces, own_light, ShadingPoint};
use super::light::{Light, TowardsLanes};
use super::packet::LANES;
use super::path::{CameraSample, ShadowHint};
use super::phong::{known, shadow, specular_power_lanes};
use super::scene::TraceScene;
use super::settings::RenderSettings;
use super::stats::RayCounts;
use crate::math::{Ray, RayPacket, Vec3, SHADOW_EPSILON};
use crate::simd::SimdLevel;
use crate::store::{Hit, PrimitiveStore};

/// Lane arrays, one per axis or channel.
type Lanes3 = [[f32; LANES]; 3];

/// A packet's lanes lit here: the direct light of each lane whose material has no textures,
/// and the colour of those among them that need nothing more.
pub(super) struct LocalLanes {
    /// Lanes whose direct light is `direct`.
    pub lit: [bool; LANES],
    /// Each `lit` lane's direct light from every light, as
    /// [`point_lights`](super::phong::point_lights) finds it.
    pub direct: [Vec3; LANES],
    /// Lanes shaded here, whose colour is `colour`: no ray leaves their hit, and their light
    /// lost nothing on its way in. The others are shaded one by one.
    pub done: [bool; LANES],
    /// The colours of the lanes `done`.
    pub colour: [Vec3; LANES],
}

/// What the lanes shaded together need of their hits, one array per axis or channel.
struct Gathered {
    point: Lanes3,
    normal: Lanes3,
    view: Lanes3,
    kd: Lanes3,
    ks: [f32; LANES],
    shininess: [f32; LANES],
    emission: Lanes3,
}

/// The direct light of a camera packet's lanes (`packet`, with each lane's `cameras` sample,
/// first hit and shading point) whose material has no textures, found together, and the
/// colour of those whose colour is their own light alone: in every lane, what
/// [`super::packet_tile`]'s single lane would find, with the same rays counted. `hints` are
/// the shadow transmittances the packet traced. In scenes with area lights or lights that
/// camera rays see, no lane is lit here.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(super) fn shade_local<S: PrimitiveStore>(
    (scene, settings): (&TraceScene<S>, &RenderSettings),
    level: SimdLevel,
    packet: &RayPacket<LANES>,
    cameras: &[Option<CameraSample>; LANES],
    hits: &[Option<Hit>; LANES],
    surfaces: &[Option<ShadingPoint>; LANES],
    hints: &[Option<ShadowHint>; LANES],
    rays: &mut RayCounts,
) -> LocalLanes {
    let mut out = LocalLanes {
        lit: [false; LANES],
        direct: [Vec3::ZERO; LANES],
        done: [false; LANES],
        colour: [Vec3::ZERO; LANES],
    };
    if scene.effects.visible_lights || scene.effects.area_lights {
        return out;
    }
    let zero = [[0.0; LANES]; 3];
    let mut g = Gathered {
        point: zero,
        normal: zero,
        view: zero,
        kd: zero,
        ks: [0.0; LANES],
        shininess: [0.0; LANES],
        emission: zero,
    };
    // Lanes lit here (`on`) and those also shaded here (`done`).
    let mut on = [false; LANES];
    let mut done = [false; LANES];
    let (max_depth, min_contribution) = (settings.max_depth, settings.min_contribution);
    for lane in 0..LANES {
        let (Some(_), Some(_), Some(shading)) = (cameras[lane], hits[lane], &surfaces[lane]) else {
            continue;
        };
        let m = scene.material(shading.sp.material);
        let ray = packet.ray(lane);
        // `Lit::new` takes an untextured material as it is, and its shading normal `ns`;
        // `Lit::local` leaves the colour as it is where the ray arrives from outside or the
        // material absorbs nothing.
        on[lane] = m.maps.is_empty();
        let kept = shading.entering | (m.absorption == Vec3::ZERO);
        let bounces = bounces((m, shading.ns, shading.entering), &ray, 0, 1.0, max_depth, min_contribution);
        done[lane] = on[lane] & kept & !bounces;
        for axis in 0..3 {
            g.point[axis][lane] = shading.sp.point[axis];
            g.normal[axis][lane] = shading.ns[axis];
            g.view[axis][lane] = -ray.dir[axis];
            g.kd[axis][lane] = m.kd[axis];
            g.emission[axis][lane] = m.emission[axis];
        }
        g.ks[lane] = m.ks;
        g.shininess[lane] = m.shininess;
    }
    if !on.iter().any(|&on| on) {
        return out;
    }
    let mut direct = zero;
    level.run(
        #[inline(always)]
        || {
            for (j, light) in scene.lights.iter().enumerate() {
                let t = towards(light, &g.point, &on);
                let n_dot_l = dot(&g.normal, &t.dir);
                // The shadow rays: traced in the packet, or now. A light behind the surface
                // sends none.
                let mut lit = [false; LANES];
                let mut pass = zero;
                for lane in 0..LANES {
                    if !on[lane] || n_dot_l[lane] <= 0.0 {
                        continue;
                    }
                    rays.shadow += 1;
                    let p = match known(hints[lane].as_ref(), j) {
                        Some(p) => p,
                        None => {
                            let Some(shading) = &surfaces[lane] else { continue };
                            let to_light = Vec3::new(t.dir[0][lane], t.dir[1][lane], t.dir[2][lane]);
                            let ray = Ray::new(shading.above, to_light);
                            shadow(scene, &ray, t.dist[lane] * (1.0 - SHADOW_EPSILON), 0.0, rays)
                        }
                    };
                    lit[lane] = p != Vec3::ZERO;
                    for axis in 0..3 {
                        pass[axis][lane] = p[axis];
                    }
                }
                add_phong(&mut direct, &g, &t, (&n_dot_l, &pass, &lit));
            }
        },
    );
    // The lanes finished here: `Lit::local` of their direct light.
    let ambient = scene.ambient;
    for lane in 0..LANES {
        let direct = Vec3::new(direct[0][lane], direct[1][lane], direct[2][lane]);
        out.direct[lane] = direct;
        if !done[lane] {
            continue;
        }
        let kd = Vec3::new(g.kd[0][lane], g.kd[1][lane], g.kd[2][lane]);
        let emission = Vec3::new(g.emission[0][lane], g.emission[1][lane], g.emission[2][lane]);
        out.colour[lane] = own_light(ambient, kd, direct, emission);
    }
    out.lit = on;
    out.done = done;
    out
}

/// [`Light::towards`] from the `on` lanes' points: [`Light::towards_lanes`], and
/// [`Light::towards`] itself in the lanes where that takes its safe path.
#[inline(always)]
fn towards(light: &Light, point: &Lanes3, on: &[bool; LANES]) -> TowardsLanes<LANES> {
    let mut t = light.towards_lanes(point);
    for lane in 0..LANES {
        if on[lane] && !t.ok[lane] {
            let (dir, dist, radiance) =
                light.towards(Vec3::new(point[0][lane], point[1][lane], point[2][lane]));
            for axis in 0..3 {
                t.dir[axis][lane] = dir[axis];
                t.radiance[axis][lane] = radiance[axis];
            }
            t.dist[lane] = dist;
        }
    }
    t
}

/// `a · b` lane by lane, as `Vec3::dot` adds the products.
#[inline(always)]
fn dot(a: &Lanes3, b: &Lanes3) -> [f32; LANES] {
    let mut out = [0.0; LANES];
    for (i, out) in out.iter_mut().enumerate() {
        *out = a[0][i] * b[0][i] + a[1][i] * b[1][i] + a[2][i] * b[2][i];
    }
    out
}

/// Adds one light's Phong term to `direct` in the `lit` lanes: `radiance · pass ·
/// (kd·N·L + ks·(R·V)^shininess)`, as `point_light` and `phong` work it out for one lane.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lane arrays indexed by lane
fn add_phong(
    direct: &mut Lanes3,
    g: &Gathered,
    t: &TowardsLanes<LANES>,
    (n_dot_l, pass, lit): (&[f32; LANES], &Lanes3, &[bool; LANES]),
) {
    // R = reflect(-L, N) = d - (2 (d·N)) N with d = -L; R·V clamped to [0, 1] as `f32::clamp`
    // does (a NaN stays).
    let mut r_dot_v = [0.0f32; LANES];
    let mut wanted = [false; LANES];
    for i in 0..LANES {
        let d = [-t.dir[0][i], -t.dir[1][i], -t.dir[2][i]];
        let n = [g.normal[0][i], g.normal[1][i], g.normal[2][i]];
        let k = 2.0 * (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
        let r = [d[0] - k * n[0], d[1] - k * n[1], d[2] - k * n[2]];
        let x = r[0] * g.view[0][i] + r[1] * g.view[1][i] + r[2] * g.view[2][i];
        let x = if x < 0.0 { 0.0 } else { x };
        r_dot_v[i] = if x > 1.0 { 1.0 } else { x };
        wanted[i] = lit[i] && g.ks[i] > 0.0;
    }
    let power = specular_power_lanes(&r_dot_v, &g.shininess, &wanted);
    for i in 0..LANES {
        let specular = g.ks[i] * power[i];
        for c in 0..3 {
            let diffuse = g.kd[c][i] * n_dot_l[i];
            let phong = if g.ks[i] > 0.0 { diffuse + specular } else { diffuse };
            let term = t.radiance[c][i] * pass[c][i] * phong;
            if lit[i] {
                direct[c][i] += term;
            }
        }
    }
}
