//! Accuracy against time: render a high-sample reference, sweep the sample counts of the
//! effects a scene uses, and report each variant's error (RMSE, PSNR, SSIM) against its
//! render time and rays, with plots and a static HTML page.
//!
//! This module owns the sweep description ([`sweep`]: axes, variants, the reference's
//! settings), the high-sample reference ([`reference`](mod@reference)), running every variant and measuring
//! it ([`run`]), the plots ([`plot`]) and the page ([`html`]). It is behind the `reports`
//! feature; it reads scenes and renders through the library's public API.

pub mod html;
pub mod plot;
pub mod reference;
pub mod run;
pub mod sweep;

use serde::Serialize;

use crate::simd::SimdLevel;
use crate::trace::RayCounts;

/// One rendered variant of the sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Point {
    /// The sweep axis it belongs to: `aa`, `adaptive`, `area_light`, `glossy` or `lens` (the
    /// effect names `penumbra render --samples` takes).
    pub axis: String,
    /// Short human label, e.g. `aa 16 jittered`.
    pub label: String,
    /// Parameter names and values, e.g. `[("samples", "16"), ("pattern", "jittered")]`.
    pub params: Vec<(String, String)>,
    /// Median wall time of the render in seconds, over interleaved rounds.
    pub seconds: f64,
    /// Renders the median was taken over (one per round).
    pub runs: usize,
    /// The time of each render in seconds, round by round.
    pub times: Vec<f64>,
    /// Index of the distinct configuration rendered: points with equal settings (a setting
    /// listed twice, or the scene's own setting on several axes) share one render and its time.
    pub config: usize,
    /// Rays by kind (of one render).
    pub rays: RayCounts,
    /// Root-mean-square error against the reference (linear RGB).
    pub rmse: f64,
    /// The renderer's own estimate of that error, for noise-driven sampling (`None` elsewhere).
    pub estimated_rmse: Option<f64>,
    /// PSNR in dB (infinite for an image equal to the reference; `"inf"` in JSON).
    #[serde(serialize_with = "finite_or_inf")]
    pub psnr: f64,
    /// Mean SSIM on luminance against the reference, in [-1, 1].
    pub ssim: f64,
    /// The variant's image, a PNG file name relative to the report folder.
    pub image: String,
    /// Its error heat map against the reference, a PNG file name relative to the report folder.
    pub heatmap: String,
}

/// A SIMD level as its name (`avx2`), as `--simd` takes it.
fn simd_name<S: serde::Serializer>(level: &SimdLevel, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(level.name())
}

/// A float as a JSON number, or the string `"inf"` when infinite (JSON has no infinity).
fn finite_or_inf<S: serde::Serializer>(value: &f64, s: S) -> Result<S::Ok, S::Error> {
    match value.is_infinite() {
        true => s.serialize_str(if *value > 0.0 { "inf" } else { "-inf" }),
        false => s.serialize_f64(*value),
    }
}

/// What an effect's sampling costs at the scene's own settings: the median time with the
/// scene's sample count and with a single sample (or the effect off).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EffectCost {
    /// The axis name (`aa`, `area_light`, `glossy`, `lens`, `adaptive`).
    pub effect: String,
    /// Median seconds with the scene's setting.
    pub seconds_on: f64,
    /// Median seconds with one sample (or off).
    pub seconds_off: f64,
}

/// The reference image a report measures against.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reference {
    /// How it was made, e.g. `aa 256 jittered, lens 64, area_light 256, glossy 256`, or the
    /// file it was read from.
    pub description: String,
    /// Seconds it took (0 when read from a file).
    pub seconds: f64,
    /// Its rays (zero when read from a file).
    pub rays: RayCounts,
    /// PNG file name relative to the report folder.
    pub image: String,
}

/// What the best fixed pattern needs for an adaptive point's RMSE, read off its curve.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FixedAt {
    /// The AA pattern, e.g. `jittered`.
    pub pattern: String,
    /// Rays or seconds at the adaptive point's RMSE, interpolated log-log between the two AA
    /// points of the pattern around it.
    pub value: f64,
    /// That over the adaptive point's rays or seconds: how many times more the fixed render
    /// needs (above 1: the adaptive point saves).
    pub ratio: f64,
}

/// The equal-error saving of one adaptive point (corner or noise-driven) against fixed AA.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Saving {
    /// The point's label, e.g. `noise 0.01`.
    pub label: String,
    /// Its RMSE, rays and median seconds.
    pub rmse: f64,
    /// Its rays.
    pub rays: u64,
    /// Its median seconds.
    pub seconds: f64,
    /// The pattern needing the fewest rays for that RMSE; `None` when the RMSE lies outside
    /// every fixed pattern's curve.
    pub fixed_rays: Option<FixedAt>,
    /// The pattern needing the least time for that RMSE.
    pub fixed_seconds: Option<FixedAt>,
}

/// `y` at `x` on the log-log polyline through `points` (x, y), between the two consecutive
/// points whose x values bracket it; `None` outside.
fn log_log_at(points: &[(f64, f64)], x: f64) -> Option<f64> {
    points.windows(2).find_map(|w| {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        let (lo, hi) = (x0.min(x1), x0.max(x1));
        if !(x > 0.0 && lo > 0.0 && y0 > 0.0 && y1 > 0.0 && (lo..=hi).contains(&x)) {
            return None;
        }
        if x0 == x1 {
            return Some(y0.min(y1));
        }
        let t = (x.ln() - x0.ln()) / (x1.ln() - x0.ln());
        Some((y0.ln() + t * (y1.ln() - y0.ln())).exp())
    })
}

/// A whole report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// The scene, as given on the command line.
    pub scene: String,
    /// The script frame every render was posed at, e.g. `scripts/motion.rhai, frame 6 at 24
    /// fps`; `None` when the scene was rendered as loaded.
    pub script: Option<String>,
    /// Image size in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Worker threads.
    pub threads: usize,
    /// The SIMD level every render traced its rays with (`--simd`, resolved: never `auto`).
    #[serde(serialize_with = "simd_name")]
    pub simd: SimdLevel,
    /// The reference.
    pub reference: Reference,
    /// Every variant, grouped by axis in sweep order.
    pub points: Vec<Point>,
    /// The cost of each effect's sampling.
    pub costs: Vec<EffectCost>,
}

impl Report {
    /// The axes present, in the order their points first appear.
    pub fn axes(&self) -> Vec<&str> {
        let mut axes: Vec<&str> = Vec::new();
        for p in &self.points {
            if !axes.contains(&p.axis.as_str()) {
                axes.push(&p.axis);
            }
        }
        axes
    }

    /// The equal-error saving of every adaptive and noise-driven point against the `aa` axis:
    /// for each AA pattern, its points in order of samples form a curve of rays (and seconds)
    /// against RMSE, read log-log at the point's RMSE; the pattern needing least is the best.
    pub fn savings(&self) -> Vec<Saving> {
        let mut patterns: Vec<&str> = Vec::new();
        let fixed: Vec<(&str, &Point)> = self
            .points
            .iter()
            .filter(|p| p.axis == "aa")
            .map(|p| {
                let pattern = p.params.iter().find(|(k, _)| k == "pattern").map_or("", |(_, v)| v.as_str());
                if !patterns.contains(&pattern) {
                    patterns.push(pattern);
                }
                (pattern, p)
            })
            .collect();
        let best = |p: &Point, of: fn(&Point) -> f64| -> Option<FixedAt> {
            patterns
                .iter()
                .filter_map(|&pattern| {
                    // In order of rays (the sample count), so noisy times cannot reorder it.
                    let mut points: Vec<&Point> =
                        fixed.iter().filter(|(q, _)| *q == pattern).map(|&(_, f)| f).collect();
                    points.sort_by_key(|f| f.rays.total());
                    let curve: Vec<(f64, f64)> = points.iter().map(|f| (f.rmse, of(f))).collect();
                    let value = log_log_at(&curve, p.rmse)?;
                    Some(FixedAt {
                        pattern: pattern.to_owned(),
                        value,
                        ratio: value / of(p).max(f64::MIN_POSITIVE),
                    })
                })
                .min_by(|a, b| a.value.total_cmp(&b.value))
        };
        self.points
            .iter()
            .filter(|p| p.axis == "adaptive" || p.axis == "noise")
            .map(|p| Saving {
                label: p.label.clone(),
                rmse: p.rmse,
                rays: p.rays.total(),
                seconds: p.seconds,
                fixed_rays: best(p, |f| f.rays.total() as f64),
                fixed_seconds: best(p, |f| f.seconds),
            })
            .collect()
    }

    /// Indices of the points on the Pareto front of (seconds, rmse): no other point is both
    /// faster and more accurate. Sorted by time.
    pub fn pareto_front(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.points.len()).collect();
        order.sort_by(|&a, &b| {
            let (pa, pb) = (&self.points[a], &self.points[b]);
            pa.seconds.total_cmp(&pb.seconds).then(pa.rmse.total_cmp(&pb.rmse))
        });
        let mut front = Vec::new();
        let mut best = f64::INFINITY;
        for i in order {
            if self.points[i].rmse < best {
                best = self.points[i].rmse;
                front.push(i);
            }
        }
        front
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(axis: &str, seconds: f64, rmse: f64) -> Point {
        Point {
            axis: axis.into(),
            label: format!("{axis} {seconds}"),
            params: vec![],
            seconds,
            runs: 1,
            times: vec![seconds],
            config: 0,
            rays: RayCounts::default(),
            rmse,
            estimated_rmse: None,
            psnr: -20.0 * rmse.log10(),
            ssim: 1.0 - rmse,
            image: String::new(),
            heatmap: String::new(),
        }
    }

    fn report_of(points: Vec<Point>) -> Report {
        Report {
            scene: "s".into(),
            script: None,
            width: 1,
            height: 1,
            threads: 1,
            simd: SimdLevel::Scalar,
            reference: Reference {
                description: String::new(),
                seconds: 0.0,
                rays: RayCounts::default(),
                image: String::new(),
            },
            points,
            costs: vec![],
        }
    }

    #[test]
    fn the_pareto_front_keeps_only_undominated_points() {
        let report = report_of(vec![
            point("aa", 1.0, 0.1),
            point("aa", 2.0, 0.05),
            point("lens", 1.5, 0.2),
            point("lens", 3.0, 0.05),
            point("adaptive", 0.5, 0.3),
        ]);
        assert_eq!(report.pareto_front(), [4, 0, 1]);
        assert_eq!(report.axes(), ["aa", "lens", "adaptive"]);
    }

    #[test]
    fn savings_read_the_fixed_curve_log_log_at_the_adaptive_rmse() {
        let fixed = |seconds: f64, rmse: f64, rays: u64| {
            let mut p = point("aa", seconds, rmse);
            p.params = vec![("samples".into(), rays.to_string()), ("pattern".into(), "jittered".into())];
            p.rays.camera = rays;
            p
        };
        let mut adaptive = point("noise", 0.5, 0.02);
        adaptive.rays.camera = 100;
        let mut outside = point("adaptive", 0.1, 0.5);
        outside.rays.camera = 10;
        // rays 100 → 0.04, 400 → 0.01: rays ∝ rmse^-1 here, so 0.02 needs 200 rays.
        let report = report_of(vec![fixed(1.0, 0.04, 100), fixed(4.0, 0.01, 400), adaptive, outside]);
        let savings = report.savings();
        assert_eq!(savings.len(), 2);
        let rays = savings[0].fixed_rays.as_ref().expect("0.02 lies on the curve");
        assert_eq!(rays.pattern, "jittered");
        assert!((rays.value - 200.0).abs() < 1e-9 && (rays.ratio - 2.0).abs() < 1e-12, "{rays:?}");
        let seconds = savings[0].fixed_seconds.as_ref().unwrap();
        assert!((seconds.value - 2.0).abs() < 1e-9 && (seconds.ratio - 4.0).abs() < 1e-9, "{seconds:?}");
        assert_eq!(savings[1].fixed_rays, None, "an RMSE no fixed point brackets");
        assert_eq!(log_log_at(&[(0.04, 100.0), (0.01, 400.0)], 0.005), None);
    }
}
