//! Viewable 8-bit renderings of AOV buffers, written as `{stem}.{aov}.png` next to a PNG image.
//!
//! - `depth`, `cost`: false colour of `value / max` through the Turbo colour ramp (Anton
//!   Mikhailov's 2019 colormap, as its published degree-5 polynomial fit in display space);
//!   `max` is stored as `penumbra.aov.depth.max` / `penumbra.aov.cost.max`. For depth it is
//!   twice the median finite depth (farther values take the top colour), so a floor
//!   running to the horizon does not flatten the rest. Background depth (+∞, or NaN) is black.
//! - `normal`: `n * 0.5 + 0.5` per component, stored as is (the usual normal-map encoding, no
//!   transfer curve), so (0.5, 0.5, 1) means facing +Z; background (no hit) is black.
//! - `albedo`: `kd` encoded with the sRGB curve, like a colour image.
//! - `object`: a colour per id from a hash of the id (hue, then saturation and value in bright
//!   ranges); id 0 (background) is black; the legend `1=name,2=name…` is stored as
//!   `penumbra.aov.object.legend`.
//!
//! Every file also gets `penumbra.aov` = its AOV name.

use super::aov::Aovs;
use super::exr_io::{legend, LEGEND_KEY};
use super::tonemap::linear_to_srgb;
use crate::math::Vec3;

/// One AOV rendered for viewing.
pub(crate) struct AovImage {
    /// The AOV name, used as the file-name infix.
    pub name: &'static str,
    /// 8-bit RGB samples, row-major.
    pub rgb: Vec<u8>,
    /// Metadata entries describing the scale.
    pub extra: Vec<(String, String)>,
}

/// The Turbo colour ramp at `t` (clamped to [0, 1]), as display (sRGB-encoded) RGB in [0, 1].
pub(crate) fn turbo(t: f32) -> [f32; 3] {
    // Degree-5 polynomial coefficients per channel, constant term first (Google, 2019).
    const R: [f64; 6] = [0.13572138, 4.61539260, -42.66032258, 132.13108234, -152.94239396, 59.28637943];
    const G: [f64; 6] = [0.09140261, 2.19418839, 4.84296658, -14.18503333, 4.27729857, 2.82956604];
    const B: [f64; 6] = [0.10667330, 12.64194608, -60.58204836, 110.36276771, -89.90310912, 27.34824973];
    let t = if t.is_nan() { 0.0 } else { f64::from(t.clamp(0.0, 1.0)) };
    [R, G, B].map(|c| c.iter().rev().fold(0.0, |acc, &k| acc * t + k).clamp(0.0, 1.0) as f32)
}

/// A display colour in [0, 1] to 8 bits.
fn to_u8(v: f32) -> u8 {
    (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// A well-mixed 32-bit hash (MurmurHash3's finaliser over a Weyl step).
fn hash32(id: u32) -> u32 {
    let mut x = id.wrapping_mul(0x9E37_79B9);
    x ^= x >> 16;
    x = x.wrapping_mul(0x85EB_CA6B);
    x ^= x >> 13;
    x = x.wrapping_mul(0xC2B2_AE35);
    x ^ (x >> 16)
}

/// The display colour of object `id`: black for 0, else a bright colour from the id's hash.
pub(crate) fn object_colour(id: u32) -> [u8; 3] {
    if id == 0 {
        return [0, 0, 0];
    }
    let h = hash32(id);
    let hue = (h & 0xFFFF) as f32 / 65536.0;
    let sat = 0.55 + 0.45 * ((h >> 16) & 0xFF) as f32 / 255.0;
    let val = 0.7 + 0.3 * (h >> 24) as f32 / 255.0;
    hsv_to_rgb(hue, sat, val).map(to_u8)
}

/// HSV (all in [0, 1]) to RGB.
fn hsv_to_rgb(h: f32, s: f32, v: f32) -> [f32; 3] {
    let k = |n: f32| {
        let k = (n + h * 6.0) % 6.0;
        v - v * s * k.min(4.0 - k).clamp(0.0, 1.0)
    };
    [k(5.0), k(3.0), k(1.0)]
}

/// Scalar values through the Turbo ramp scaled by `max` (non-finite values black).
/// Twice the median of the finite values (a floor plane reaching the horizon would otherwise
/// squeeze every nearer depth into the bottom of the ramp), or their maximum if that is less.
pub(crate) fn robust_max(values: &[f32]) -> f32 {
    let mut finite: Vec<f32> = values.iter().copied().filter(|v| v.is_finite()).collect();
    if finite.is_empty() {
        return 0.0;
    }
    finite.sort_by(f32::total_cmp);
    let median = finite[(finite.len() - 1) / 2];
    (2.0 * median).min(finite[finite.len() - 1]).max(0.0)
}

fn false_colour(values: impl Iterator<Item = f32>, max: f32) -> Vec<u8> {
    values
        .flat_map(|v| {
            if !v.is_finite() {
                [0, 0, 0]
            } else {
                let t = if max > 0.0 { v / max } else { 0.0 };
                turbo(t).map(to_u8)
            }
        })
        .collect()
}

/// Entries `penumbra.aov` = `name` plus `extra`.
fn entries(name: &str, extra: &[(&str, String)]) -> Vec<(String, String)> {
    std::iter::once(("penumbra.aov".to_owned(), name.to_owned()))
        .chain(extra.iter().map(|(k, v)| ((*k).to_owned(), v.clone())))
        .collect()
}

/// Renders every AOV buffer present, in the order depth, normal, albedo, object, cost.
pub(crate) fn aov_images(aovs: &Aovs) -> Vec<AovImage> {
    let mut out = Vec::new();
    if let Some(depth) = &aovs.depth {
        let max = robust_max(depth);
        let extra = [("penumbra.aov.depth.max", max.to_string()), ("penumbra.aov.colormap", "turbo".into())];
        let rgb = false_colour(depth.iter().copied(), max);
        out.push(AovImage { name: "depth", rgb, extra: entries("depth", &extra) });
    }
    if let Some(normal) = &aovs.normal {
        // Background pixels (no hit: a zero normal) are black, not mid-grey.
        let encode = |n: &Vec3| if *n == Vec3::ZERO { Vec3::ZERO } else { *n * 0.5 + Vec3::splat(0.5) };
        let rgb = normal.iter().flat_map(|n| encode(n).to_array().map(to_u8)).collect();
        let extra = [("penumbra.aov.normal.encoding", "rgb = n * 0.5 + 0.5; background black".to_owned())];
        out.push(AovImage { name: "normal", rgb, extra: entries("normal", &extra) });
    }
    if let Some(albedo) = &aovs.albedo {
        let rgb = albedo.iter().flat_map(|c| c.to_array().map(|v| to_u8(linear_to_srgb(v)))).collect();
        out.push(AovImage { name: "albedo", rgb, extra: entries("albedo", &[]) });
    }
    if let Some(object) = &aovs.object {
        let rgb = object.iter().flat_map(|&id| object_colour(id)).collect();
        let extra = [(LEGEND_KEY, legend(&aovs.object_names))];
        out.push(AovImage { name: "object", rgb, extra: entries("object", &extra) });
    }
    if let Some(cost) = &aovs.cost {
        let max = cost.iter().copied().max().unwrap_or(0);
        let extra = [("penumbra.aov.cost.max", max.to_string()), ("penumbra.aov.colormap", "turbo".into())];
        let rgb = false_colour(cost.iter().map(|&c| c as f32), max as f32);
        out.push(AovImage { name: "cost", rgb, extra: entries("cost", &extra) });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::AovSet;

    #[test]
    fn turbo_runs_from_dark_blue_through_green_to_dark_red() {
        let [r, g, b] = turbo(0.0);
        assert!(r.max(g).max(b) < 0.2, "{r} {g} {b}");
        let [r, g, b] = turbo(0.15);
        assert!(b > 0.8 && b > r && b > g, "{r} {g} {b}");
        let [r, g, b] = turbo(0.5);
        assert!(g > 0.8 && g > r && g > b, "{r} {g} {b}");
        let [r, g, b] = turbo(1.0);
        assert!(r > 0.4 && g < 0.1 && b < 0.1, "{r} {g} {b}");
        assert_eq!(turbo(-3.0), turbo(0.0));
        assert_eq!(turbo(f32::NAN), turbo(0.0));
    }

    #[test]
    fn object_colours_are_black_for_background_and_distinct_otherwise() {
        assert_eq!(object_colour(0), [0, 0, 0]);
        let colours: Vec<_> = (1..=64).map(object_colour).collect();
        for (i, c) in colours.iter().enumerate() {
            assert!(c.iter().any(|&v| v > 100), "id {} too dark: {c:?}", i + 1);
            assert!(!colours[..i].contains(c), "id {} repeats {c:?}", i + 1);
        }
    }

    #[test]
    fn the_depth_scale_ignores_a_few_far_outliers() {
        let mut depths: Vec<f32> = (0..100).map(|i| i as f32 / 10.0).collect();
        depths[99] = 1e6; // a floor at the horizon
        depths.push(f32::INFINITY);
        assert_eq!(robust_max(&depths), 9.8, "twice the median 4.9");
        assert_eq!(robust_max(&[1.0, 1.5]), 1.5, "never above the largest depth");
        assert_eq!(robust_max(&[f32::INFINITY]), 0.0);
    }

    #[test]
    fn depth_and_cost_scale_by_their_maximum() {
        let set = AovSet { depth: true, cost: true, object: true, ..Default::default() };
        let mut aovs = Aovs::new(set, 3, 1);
        aovs.depth = Some(vec![1.0, 4.0, f32::INFINITY]);
        aovs.cost = Some(vec![0, 5, 10]);
        aovs.object = Some(vec![0, 1, 2]);
        aovs.object_names = vec!["floor".into(), "ball".into()];
        let images = aov_images(&aovs);
        let names: Vec<_> = images.iter().map(|i| i.name).collect();
        assert_eq!(names, ["depth", "object", "cost"]);
        let depth = &images[0];
        assert!(depth.extra.contains(&("penumbra.aov.depth.max".into(), "2".into())), "twice the median");
        assert_eq!(depth.rgb[3..6], turbo(1.0).map(to_u8));
        assert_eq!(depth.rgb[6..9], [0, 0, 0]);
        assert!(images[1].extra.contains(&(LEGEND_KEY.into(), "1=floor,2=ball".into())));
        let cost = &images[2];
        assert!(cost.extra.contains(&("penumbra.aov.cost.max".into(), "10".into())));
        assert_eq!(cost.rgb[3..6], turbo(0.5).map(to_u8));
    }
}
