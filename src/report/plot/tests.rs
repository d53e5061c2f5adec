//! Tests of `src/report/plot.rs`.

use super::*;
use crate::report::{EffectCost, Point, Reference};
use crate::trace::RayCounts;

fn point(axis: &str, label: &str, seconds: f64, rays: u64, rmse: f64) -> Point {
    let psnr = if rmse > 0.0 { -20.0 * rmse.log10() } else { f64::INFINITY };
    let stem = label.replace(' ', "_");
    Point {
        axis: axis.into(),
        label: label.into(),
        params: vec![("samples".into(), label.rsplit(' ').next().unwrap_or("").into())],
        seconds,
        runs: 3,
        times: vec![seconds; 3],
        config: 0,
        rays: RayCounts { camera: rays / 2, shadow: rays - rays / 2, ..RayCounts::default() },
        rmse,
        estimated_rmse: None,
        psnr,
        ssim: 1.0 - rmse,
        image: format!("{stem}.png"),
        heatmap: format!("{stem}_heat.png"),
    }
}

/// Two axes of four points each (one equal to the reference), costs of two effects.
pub(crate) fn synthetic_report() -> Report {
    Report {
        scene: "scenes/cornell <glossy> & \"lens\".ron".into(),
        script: None,
        width: 320,
        height: 240,
        threads: 8,
        simd: crate::simd::SimdLevel::Avx2,
        reference: Reference {
            description: "aa 256 jittered, area_light 256".into(),
            seconds: 41.5,
            rays: RayCounts { camera: 19_660_800, area_shadow: 80_000_000, ..RayCounts::default() },
            image: "reference.png".into(),
        },
        points: vec![
            point("aa", "aa 1", 0.08, 76_800, 0.052),
            point("aa", "aa 4", 0.27, 307_200, 0.021),
            point("aa", "aa 16", 1.05, 1_228_800, 0.0094),
            point("aa", "aa 64", 4.1, 4_915_200, 0.0041),
            point("area_light", "area_light 4", 0.19, 400_000, 0.061),
            point("area_light", "area_light 16", 0.62, 1_600_000, 0.028),
            point("area_light", "area_light 64", 2.3, 6_400_000, 0.011),
            point("area_light", "area_light 256", 8.9, 25_600_000, 0.0),
        ],
        costs: vec![
            EffectCost { effect: "aa".into(), seconds_on: 1.05, seconds_off: 0.08 },
            EffectCost { effect: "area_light".into(), seconds_on: 2.3, seconds_off: 0.31 },
        ],
    }
}

/// One point and no costs.
pub(crate) fn degenerate_report() -> Report {
    let mut r = synthetic_report();
    r.points.truncate(1);
    r.costs.clear();
    r
}

fn check_written(paths: &[PathBuf], stem: &str, needles: &[&str]) {
    assert_eq!(paths.len(), 2);
    assert!(paths[0].ends_with(format!("{stem}.png")), "{paths:?}");
    assert!(paths[1].ends_with(format!("{stem}.svg")), "{paths:?}");
    assert_eq!(image::image_dimensions(&paths[0]).expect("PNG decodes"), (WIDTH, HEIGHT));
    let svg = std::fs::read_to_string(&paths[1]).expect("SVG is UTF-8");
    assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(80)]);
    assert!(svg.trim_end().ends_with("</svg>"));
    for needle in needles {
        assert!(svg.contains(needle), "{stem}.svg lacks {needle:?}");
    }
}

#[test]
fn every_plot_is_written_as_png_and_svg_with_labels_and_legend() {
    let dir = tempfile::tempdir().unwrap();
    let report = synthetic_report();
    let paths = error_vs_time(&report, dir.path()).unwrap();
    check_written(
        &paths,
        ERROR_VS_TIME,
        &[
            "median render time (s)",
            "RMSE against the reference",
            "Pareto front",
            "aa",
            "area_light",
            "Error vs time",
        ],
    );
    // The scene's name is escaped in the SVG.
    let svg = std::fs::read_to_string(&paths[1]).unwrap();
    assert!(svg.contains("&lt;glossy&gt; &amp;"), "scene name not escaped");
    assert!(svg.contains("RMSE 0 (equal to the reference), drawn at 0.002"), "no note on the RMSE-0 point");

    let paths = rays_vs_error(&report, dir.path()).unwrap();
    check_written(&paths, RAYS_VS_ERROR, &["rays traced", "RMSE against the reference", "aa", "area_light"]);
    let paths = effect_costs(&report, dir.path()).unwrap();
    check_written(
        &paths,
        EFFECT_COSTS,
        &["median render time (s)", "scene setting", "one sample / off", "aa (×13.1)", "area_light (×7.4)"],
    );
}

#[test]
fn the_estimate_plot_shows_the_noise_points_against_the_diagonal() {
    let dir = tempfile::tempdir().unwrap();
    let mut report = synthetic_report();
    // Without a noise axis there is nothing to plot.
    check_written(&estimate_vs_error(&report, dir.path()).unwrap(), ESTIMATE_VS_ERROR, &["no data"]);
    for (target, rmse, estimate) in [(0.02, 0.019, 0.021), (0.01, 0.011, 0.0095), (0.005, 0.0052, 0.0049)] {
        let mut p = point("noise", &format!("noise {target}"), 1.0, 1_000_000, rmse);
        p.estimated_rmse = Some(estimate);
        report.points.push(p);
    }
    check_written(
        &estimate_vs_error(&report, dir.path()).unwrap(),
        ESTIMATE_VS_ERROR,
        &[
            "RMSE against the reference",
            "estimated RMSE (noise-driven rounds)",
            "estimate = true",
            "noise",
            "8 variant(s) without an estimate or with RMSE 0 left out",
        ],
    );
}

/// The x of every `<text>` whose content is `label`, and the right end of the axes (the
/// largest x of the grid and axis `<line>`s) in an SVG written by plotters.
fn text_x_and_axes_end(svg: &str, label: &str) -> (Vec<f64>, f64) {
    let attr = |tag: &str, name: &str| -> Option<f64> {
        let start = tag.find(&format!(" {name}=\""))? + name.len() + 3;
        tag[start..].split('"').next()?.parse().ok()
    };
    let texts = svg
        .split("<text")
        .skip(1)
        .filter(|t| {
            t.split_once('>').is_some_and(|(_, rest)| rest.trim_start().starts_with(&format!("{label}\n")))
        })
        .filter_map(|t| attr(t, "x"))
        .collect();
    let end =
        svg.split("<line").skip(1).flat_map(|l| [attr(l, "x1"), attr(l, "x2")]).flatten().fold(0.0, f64::max);
    (texts, end)
}

#[test]
fn legends_sit_right_of_the_axes_never_over_the_data() {
    let dir = tempfile::tempdir().unwrap();
    let report = synthetic_report();
    let plots = [
        (error_vs_time(&report, dir.path()).unwrap(), vec!["Pareto front", "aa", "area_light"]),
        (rays_vs_error(&report, dir.path()).unwrap(), vec!["aa", "area_light"]),
        (effect_costs(&report, dir.path()).unwrap(), vec!["scene setting", "one sample / off"]),
    ];
    for (paths, labels) in plots {
        let svg = std::fs::read_to_string(&paths[1]).unwrap();
        for label in labels {
            let (xs, axes_end) = text_x_and_axes_end(&svg, label);
            assert!(axes_end > 400.0, "{}: no axes found", paths[1].display());
            assert!(
                !xs.is_empty() && xs.iter().all(|&x| x > axes_end),
                "{}: legend `{label}` at x {xs:?}, axes end at {axes_end}",
                paths[1].display()
            );
        }
    }
}

#[test]
fn degenerate_reports_render_without_panicking() {
    let dir = tempfile::tempdir().unwrap();
    let one = degenerate_report();
    check_written(&error_vs_time(&one, dir.path()).unwrap(), ERROR_VS_TIME, &["aa"]);
    check_written(&rays_vs_error(&one, dir.path()).unwrap(), RAYS_VS_ERROR, &["aa"]);
    check_written(&effect_costs(&one, dir.path()).unwrap(), EFFECT_COSTS, &["no data"]);

    // No points at all, equal times, zero and non-finite values.
    let mut odd = synthetic_report();
    odd.points.clear();
    check_written(&error_vs_time(&odd, dir.path()).unwrap(), ERROR_VS_TIME, &["no data"]);
    odd = synthetic_report();
    for p in &mut odd.points {
        p.seconds = 1.0;
        p.rmse = 0.0;
    }
    odd.points[0].seconds = f64::NAN;
    odd.points[1].rays = RayCounts::default();
    odd.costs[0].seconds_on = 0.0;
    odd.costs[0].seconds_off = 0.0;
    check_written(&error_vs_time(&odd, dir.path()).unwrap(), ERROR_VS_TIME, &["left out"]);
    check_written(&rays_vs_error(&odd, dir.path()).unwrap(), RAYS_VS_ERROR, &["left out"]);
    check_written(&effect_costs(&odd, dir.path()).unwrap(), EFFECT_COSTS, &["area_light"]);
}

/// A tool, not a test: writes the plots of the synthetic report for a person to look at,
/// into `$PENUMBRA_PLOT_DIR` (default `target/inspect`). Run it with
/// `cargo test --release --lib plots_can_be_written_for_inspection -- --ignored`.
#[test]
#[ignore = "writes files for inspection; asserts nothing"]
fn plots_can_be_written_for_inspection() {
    let dir =
        std::env::var_os("PENUMBRA_PLOT_DIR").map_or_else(|| PathBuf::from("target/inspect"), PathBuf::from);
    std::fs::create_dir_all(&dir).unwrap();
    let report = synthetic_report();
    error_vs_time(&report, &dir).unwrap();
    rays_vs_error(&report, &dir).unwrap();
    effect_costs(&report, &dir).unwrap();
    let one = dir.join("degenerate");
    std::fs::create_dir_all(&one).unwrap();
    error_vs_time(&degenerate_report(), &one).unwrap();
    effect_costs(&degenerate_report(), &one).unwrap();

    // Five axes, five fast effects.
    let wide = dir.join("wide");
    std::fs::create_dir_all(&wide).unwrap();
    let mut many = synthetic_report();
    for (k, axis) in ["adaptive", "glossy", "lens"].into_iter().enumerate() {
        for j in 0..4 {
            let s = 0.05 * (k + 1) as f64 * 3f64.powi(j);
            many.points.push(point(
                axis,
                &format!("{axis} {j}"),
                s,
                (s * 4e6) as u64,
                0.08 / (k as f64 + 1.5) / 2f64.powi(j),
            ));
        }
    }
    many.costs = ["aa", "adaptive", "area_light", "glossy", "lens"]
        .iter()
        .enumerate()
        .map(|(k, e)| EffectCost {
            effect: e.to_string(),
            seconds_on: 0.1 + 0.15 * k as f64,
            seconds_off: 0.04,
        })
        .collect();
    error_vs_time(&many, &wide).unwrap();
    rays_vs_error(&many, &wide).unwrap();
    effect_costs(&many, &wide).unwrap();
}
