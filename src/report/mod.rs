//! Accuracy against time: render a high-sample reference, sweep the sample counts of the
//! effects a scene uses, and report each variant's error (RMSE, PSNR, SSIM) against its
//! render time and rays, with plots and a static HTML page.

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
            psnr: -20.0 * rmse.log10(),
            ssim: 1.0 - rmse,
            image: String::new(),
            heatmap: String::new(),
        }
    }

    #[test]
    fn the_pareto_front_keeps_only_undominated_points() {
        let report = Report {
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
            points: vec![
                point("aa", 1.0, 0.1),
                point("aa", 2.0, 0.05),
                point("lens", 1.5, 0.2),
                point("lens", 3.0, 0.05),
                point("adaptive", 0.5, 0.3),
            ],
            costs: vec![],
        };
        assert_eq!(report.pareto_front(), [4, 0, 1]);
        assert_eq!(report.axes(), ["aa", "lens", "adaptive"]);
    }
}
