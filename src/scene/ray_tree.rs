//! How big a camera sample's ray tree can grow under a scene's materials and settings, and the
//! warnings a renderer prints before it starts when the budget of secondary rays
//! (`settings.max_secondary_rays`) would cut trees.
//!
//! Each hit below `settings.max_depth` spawns a reflection (`kr > 0`) and a refraction
//! (`kt > 0`) while the path weight (the product of the `kr` and `kt` along it) stays at or
//! above `settings.min_contribution`; the first bounce off a glossy material fans out into its
//! camera sample's share of `settings.glossy.samples` rays per branch. Glass with both `kr`
//! and `kt` therefore doubles the tree at every bounce: with `min_contribution: 0` and
//! `max_depth: 64` one camera sample would trace about 2^65 rays. The renderer cuts such a
//! tree at the budget (`trace::path::RayBudget`); these warnings say so before it
//! starts, naming the material and the fields to change.

use super::format::{MaterialDesc, SceneFile};

/// The most secondary rays one camera sample can trace when every ray it spawns hits a
/// material with reflectance `kr` and transmittance `kt`: each path of `a` reflections and `b`
/// refractions (`1 ≤ a + b ≤ max_depth`) whose weight `kr^a · kt^b` stays at or above
/// `min_contribution` is a ray, and the `first_bounce` rays of a glossy first bounce each start
/// such a tree. An upper bound for a scene made of this material; exact for a closed one.
///
/// # Examples
/// ```
/// use penumbra::scene::ray_tree::worst_case_rays;
/// // Glass in a closed room: the tree doubles at every bounce.
/// assert_eq!(worst_case_rays(0.5, 0.5, 0.0, 3, 1), 2.0 + 4.0 + 8.0);
/// // A mirror: one ray per bounce.
/// assert_eq!(worst_case_rays(0.9, 0.0, 0.0, 64, 1), 64.0);
/// // `min_contribution` prunes: 0.5^a · 0.5^b ≥ 0.2 only for paths of length ≤ 2.
/// assert_eq!(worst_case_rays(0.5, 0.5, 0.2, 64, 1), 2.0 + 4.0);
/// ```
pub fn worst_case_rays(kr: f32, kt: f32, min_contribution: f32, max_depth: u32, first_bounce: u32) -> f64 {
    let (kr, kt) = (f64::from(kr), f64::from(kt));
    // A hair below the threshold still counts: the renderer multiplies in f32, and the bound
    // must not miss a path that rounding keeps.
    let threshold = f64::from(min_contribution) * (1.0 - 1e-6);
    let mut total = 0.0;
    // `binomial[a]` is C(len, a) for the current path length `len`.
    let mut binomial = vec![1.0f64];
    for len in 1..=max_depth as usize {
        let mut next = vec![1.0f64; len + 1];
        for a in 1..len {
            next[a] = binomial[a - 1] + binomial[a];
        }
        binomial = next;
        let mut any = false;
        for (a, paths) in binomial.iter().enumerate() {
            let b = len - a;
            if (a > 0 && kr <= 0.0) || (b > 0 && kt <= 0.0) {
                continue;
            }
            if kr.powi(a as i32) * kt.powi(b as i32) >= threshold {
                total += paths;
                any = true;
            }
        }
        if !any {
            break; // Weights only fall with length: no longer path survives either.
        }
    }
    total * f64::from(first_bounce.max(1))
}

/// Camera samples per pixel the scene's settings give (adaptive corners count as one: each
/// takes the whole pixel's share of an effect).
fn camera_samples(desc: &SceneFile) -> u32 {
    if desc.settings.adaptive.is_some() {
        return 1;
    }
    let lens = if desc.camera.aperture > 0.0 { desc.camera.lens.samples.max(1) } else { 1 };
    desc.settings.aa.samples.max(1).saturating_mul(lens)
}

/// One warning per material that objects use whose ray tree can outgrow
/// `settings.max_secondary_rays`, each a single line naming the material and the settings
/// fields to change. Empty for every shipped scene.
///
/// # Examples
/// ```
/// use penumbra::scene::{default_scene, ray_tree::ray_tree_warnings};
/// assert!(ray_tree_warnings(&default_scene()).is_empty());
/// let mut desc = default_scene();
/// desc.settings.min_contribution = 0.0;
/// desc.settings.max_depth = 64;
/// let warnings = ray_tree_warnings(&desc);
/// assert!(warnings.iter().any(|w| w.contains("material `glass`") && w.contains("max_depth 64")));
/// ```
pub fn ray_tree_warnings(desc: &SceneFile) -> Vec<String> {
    let s = &desc.settings;
    let spp = camera_samples(desc);
    let used = |m: &MaterialDesc| desc.objects.iter().any(|o| o.material == m.name);
    let mut warnings = Vec::new();
    for m in desc.materials.iter().filter(|m| used(m)) {
        let glossy = m.glossiness > 0.0;
        let first_bounce = if glossy { s.glossy.samples.max(1).div_ceil(spp) } else { 1 };
        // Fresnel can move all of `kt` to the mirror (at grazing angles).
        let kt = m.kt.max_element();
        let kr = if m.fresnel { m.kr + kt } else { m.kr };
        let rays = worst_case_rays(kr, kt, s.min_contribution, s.max_depth, first_bounce);
        if rays <= f64::from(s.max_secondary_rays) {
            continue;
        }
        let fan = match glossy {
            true => format!(
                ", glossiness {} (settings.glossy.samples {} over {spp} camera sample(s) per pixel: {first_bounce} rays per branch at the first bounce)",
                m.glossiness, s.glossy.samples
            ),
            false => String::new(),
        };
        let growth = match kr > 0.0 && kt > 0.0 {
            true => format!(", doubling at every bounce (about 2^{:.0})", rays.log2()),
            false => String::new(),
        };
        warnings.push(format!(
            "material `{}` (kr {}, kt {}{fan}) with settings.min_contribution {} and settings.max_depth {} \
             can make one camera sample trace up to {} secondary rays{growth}; settings.max_secondary_rays {} \
             will cut such ray trees (--stats counts them): raise min_contribution, lower max_depth or raise \
             max_secondary_rays",
            shown(&m.name),
            m.kr,
            kt,
            s.min_contribution,
            s.max_depth,
            count(rays),
            s.max_secondary_rays,
        ));
    }
    warnings
}

/// A name on one line: control characters escaped, cut to 60 characters.
fn shown(name: &str) -> String {
    let mut out: String = name.chars().take(60).flat_map(char::escape_debug).collect();
    if name.chars().nth(60).is_some() {
        out.push('…');
    }
    out
}

/// A ray count: whole below a million, in scientific notation above.
fn count(rays: f64) -> String {
    if rays < 1e6 {
        format!("{rays:.0}")
    } else {
        format!("{rays:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse_scene;

    #[test]
    fn a_doubling_tree_under_no_pruning_has_two_to_the_depth_plus_one_minus_two_rays() {
        assert_eq!(worst_case_rays(0.5, 0.5, 0.0, 10, 1), 2f64.powi(11) - 2.0);
        let deep = worst_case_rays(0.5, 0.5, 0.0, 64, 1);
        assert!((deep / 2f64.powi(65) - 1.0).abs() < 1e-12, "{deep}");
        assert_eq!(worst_case_rays(0.0, 0.0, 0.0, 64, 1), 0.0);
        assert_eq!(worst_case_rays(0.5, 0.5, 0.0, 0, 8), 0.0);
    }

    #[test]
    fn a_glossy_first_bounce_multiplies_every_path() {
        assert_eq!(worst_case_rays(0.8, 0.0, 0.0, 5, 16), 16.0 * 5.0);
    }

    #[test]
    fn min_contribution_bounds_the_tree_even_at_depth_64() {
        // 0.5^len ≥ 1e-3 for len ≤ 9: 2 + 4 + … + 512.
        assert_eq!(worst_case_rays(0.5, 0.5, 1e-3, 64, 1), 2f64.powi(10) - 2.0);
    }

    fn glass_scene(settings: &str) -> String {
        format!(
            "Scene(camera: (position: (0, 0, 0), look_at: (0, 0, 1), fov_deg: 60, width: 4, height: 4),
               settings: ({settings}),
               materials: [(name: \"glass\", kd: (0, 0, 0), kr: 0.5, kt: 0.5),
                           (name: \"unused\", kd: (0, 0, 0), kr: 0.5, kt: 0.5)],
               objects: [(shape: Sphere(centre: (0, 0, 0), radius: 2), material: \"glass\")])"
        )
    }

    #[test]
    fn exponential_settings_warn_once_naming_the_material_and_fields() {
        let desc = parse_scene(&glass_scene("min_contribution: 0, max_depth: 64"), "test.ron").unwrap();
        let warnings = ray_tree_warnings(&desc);
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        let w = &warnings[0];
        for part in [
            "material `glass`",
            "settings.min_contribution 0",
            "settings.max_depth 64",
            "3.69e19",
            "2^65",
            "settings.max_secondary_rays 1024",
        ] {
            assert!(w.contains(part), "`{part}` missing from {w}");
        }
        assert!(!w.contains('\n'));
    }

    #[test]
    fn a_budget_that_holds_the_tree_or_pruning_silences_the_warning() {
        for settings in [
            "min_contribution: 0, max_depth: 9",
            "min_contribution: 0.001, max_depth: 64",
            "min_contribution: 0, max_depth: 12, max_secondary_rays: 8190",
        ] {
            let desc = parse_scene(&glass_scene(settings), "test.ron").unwrap();
            assert_eq!(ray_tree_warnings(&desc), Vec::<String>::new(), "{settings}");
        }
        let desc = parse_scene(
            &glass_scene("min_contribution: 0, max_depth: 12, max_secondary_rays: 8189"),
            "test.ron",
        );
        assert_eq!(ray_tree_warnings(&desc.unwrap()).len(), 1);
    }

    #[test]
    fn a_wide_glossy_fan_warns_even_without_refraction() {
        let text =
            "Scene(camera: (position: (0, 0, 0), look_at: (0, 0, 1), fov_deg: 60, width: 4, height: 4),
               settings: (glossy: (samples: 4096), aa: (samples: 2)),
               materials: [(name: \"brushed\\nmetal\", kd: (0, 0, 0), kr: 0.9, glossiness: 0.2)],
               objects: [(shape: Sphere(centre: (0, 0, 0), radius: 2), material: \"brushed\\nmetal\")])";
        let warnings = ray_tree_warnings(&parse_scene(text, "test.ron").unwrap());
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        // 2048 rays at the first bounce, then one per bounce down to depth 5.
        assert!(warnings[0].contains("up to 10240 secondary rays"), "{}", warnings[0]);
        assert!(warnings[0].contains("material `brushed\\nmetal`"), "{}", warnings[0]);
        assert!(!warnings[0].contains("doubling"));
    }
}
