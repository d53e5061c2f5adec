//! Running a report: the reference, every variant of the sweep (median time of k renders,
//! rays, RMSE, PSNR, SSIM, images and heat maps) and each effect's cost.

use std::path::Path;
use std::time::Instant;

use super::sweep::{cheapest, SweepDesc, Variant};
use super::{EffectCost, Point, Reference, Report};
use crate::film::metrics::{error_heatmap, psnr, rmse, ssim};
use crate::film::{write_atomically, write_png, Film, OutputError};
use crate::scene::{spawn_world, SceneDesc};
use crate::trace::{render, Effects, RenderStats};
use crate::world::SceneWorld;

/// Errors of a report run.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Writing an image failed.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// The given reference does not fit the scene.
    #[error(
        "{path}: the reference is {found}, the report renders {expected}; use --width/--height to match"
    )]
    ReferenceSize {
        /// The reference file.
        path: String,
        /// Its size.
        found: String,
        /// The report's size.
        expected: String,
    },
    /// An image could not be encoded.
    #[error("{path}: cannot encode: {message}")]
    Encode {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
}

/// How a report runs.
#[derive(Debug, Clone)]
pub struct Options {
    /// Renders per point; the time is their median.
    pub runs: usize,
    /// A reference image read instead of rendered (its film and the file name).
    pub reference: Option<(Film, String)>,
}

/// What the caller is told before each render: a label and how many renders are done so far.
pub type Progress<'a> = &'a (dyn Fn(&str) + Sync);

/// The number of renders [`run`] makes, for progress bars.
pub fn render_count(desc: &SceneDesc, sweep: &SweepDesc, options: &Options) -> usize {
    let reference = usize::from(options.reference.is_none());
    let costs = cost_axes(desc, sweep).len();
    reference + sweep.variants().len() * options.runs + if costs > 0 { (costs + 1) * options.runs } else { 0 }
}

/// The effects of a scene description.
pub fn effects_of(desc: &SceneDesc) -> Effects {
    let mut world: SceneWorld = spawn_world(desc);
    world.update().effects
}

/// Renders `desc` `runs` times; the first film, its statistics and the median seconds.
fn timed(desc: &SceneDesc, runs: usize, label: &str, progress: Progress) -> (Film, RenderStats, f64) {
    let mut world: SceneWorld = spawn_world(desc);
    let snapshot = world.update();
    let settings = world.render_settings();
    let mut times = Vec::with_capacity(runs);
    let mut first = None;
    for _ in 0..runs.max(1) {
        progress(label);
        let started = Instant::now();
        let (film, stats) = render(&snapshot, &settings);
        times.push(started.elapsed().as_secs_f64());
        first.get_or_insert((film, stats));
    }
    times.sort_by(f64::total_cmp);
    let (film, stats) = first.expect("at least one run");
    (film, stats, times[times.len() / 2])
}

/// Axes whose cost is measured: those in the sweep that the scene's own settings use.
fn cost_axes(desc: &SceneDesc, sweep: &SweepDesc) -> Vec<&'static str> {
    let effects = effects_of(desc);
    let mut axes: Vec<&'static str> = Vec::new();
    for axis in sweep.axes.iter().map(|a| a.name()) {
        let used = match axis {
            "aa" => desc.settings.adaptive.is_none() && desc.settings.aa.samples > 1,
            "adaptive" => desc.settings.adaptive.is_some(),
            "area_light" => effects.area_lights,
            "glossy" => effects.glossy || effects.blurry,
            "lens" => effects.lens && desc.camera.lens.samples > 1,
            _ => false,
        };
        if used && !axes.contains(&axis) {
            axes.push(axis);
        }
    }
    axes
}

/// File-name part of a label: `aa 16 jittered` → `aa-16-jittered`.
fn slug(label: &str) -> String {
    label.chars().map(|c| if c.is_ascii_alphanumeric() || c == '.' { c } else { '-' }).collect()
}

fn write_heatmap(image: &Film, reference: &Film, path: &Path) -> Result<(), ReportError> {
    let encode = |message: String| ReportError::Encode { path: path.display().to_string(), message };
    let (heat, _) = error_heatmap(image, reference).ok_or_else(|| encode("sizes differ".into()))?;
    let mut png = Vec::new();
    heat.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| encode(e.to_string()))?;
    Ok(write_atomically(path, &png)?)
}

/// Runs the report for scene `desc` (named `scene` in the report) into folder `out` (which
/// must exist): images and heat maps there, the figures returned.
pub fn run(
    desc: &SceneDesc,
    scene: &str,
    sweep: &SweepDesc,
    options: &Options,
    out: &Path,
    progress: Progress,
) -> Result<Report, ReportError> {
    let effects = effects_of(desc);
    let (width, height) = (desc.camera.width, desc.camera.height);
    let reference = match &options.reference {
        Some((film, file)) => {
            if (film.width, film.height) != (width, height) {
                return Err(ReportError::ReferenceSize {
                    path: file.clone(),
                    found: format!("{}x{}", film.width, film.height),
                    expected: format!("{width}x{height}"),
                });
            }
            write_png(film, &out.join("reference.png"))?;
            let info = Reference {
                description: format!("read from {file}"),
                seconds: 0.0,
                rays: Default::default(),
                image: "reference.png".into(),
            };
            (film.clone(), info)
        }
        None => {
            let (film, stats, seconds) = timed(&sweep.reference.apply(desc), 1, "reference", progress);
            write_png(&film, &out.join("reference.png"))?;
            let info = Reference {
                description: sweep.reference.describe(&effects),
                seconds,
                rays: stats.rays,
                image: "reference.png".into(),
            };
            (film, info)
        }
    };
    let (reference_film, reference_info) = reference;

    let mut points = Vec::new();
    for (i, variant) in sweep.variants().iter().enumerate() {
        points.push(measure(i, variant, desc, &reference_film, options.runs, out, progress)?);
    }

    let mut costs = Vec::new();
    let axes = cost_axes(desc, sweep);
    if !axes.is_empty() {
        let (_, _, seconds_on) = timed(desc, options.runs, "scene as is", progress);
        for axis in axes {
            let off = cheapest(axis, desc).expect("cost axes are known");
            let (_, _, seconds_off) = timed(&off, options.runs, &format!("{axis} off"), progress);
            costs.push(EffectCost { effect: axis.into(), seconds_on, seconds_off });
        }
    }
    Ok(Report {
        scene: scene.to_owned(),
        width,
        height,
        threads: rayon::current_num_threads(),
        reference: reference_info,
        points,
        costs,
    })
}

fn measure(
    index: usize,
    variant: &Variant,
    desc: &SceneDesc,
    reference: &Film,
    runs: usize,
    out: &Path,
    progress: Progress,
) -> Result<Point, ReportError> {
    let label = variant.label();
    let (film, stats, seconds) = timed(&variant.apply(desc), runs, &label, progress);
    let stem = format!("{index:02}-{}", slug(&label));
    let (image, heatmap) = (format!("{stem}.png"), format!("{stem}.heat.png"));
    write_png(&film, &out.join(&image))?;
    write_heatmap(&film, reference, &out.join(&heatmap))?;
    let same_size = "sizes checked above";
    Ok(Point {
        axis: variant.axis.to_owned(),
        label,
        params: variant.params(),
        seconds,
        runs: runs.max(1),
        rays: stats.rays,
        rmse: rmse(&film, reference).expect(same_size),
        psnr: psnr(&film, reference).expect(same_size),
        ssim: ssim(&film, reference).expect(same_size),
        image,
        heatmap,
    })
}

/// `results.csv`: a row per point.
pub fn csv(report: &Report) -> String {
    let kinds = crate::trace::RayCounts::default().kinds().map(|(k, _)| format!("rays_{k}"));
    let mut out = format!(
        "axis,label,params,seconds,runs,rays_total,rmse,psnr,ssim,pareto,image,heatmap,{}\n",
        kinds.join(",")
    );
    let front = report.pareto_front();
    for (i, p) in report.points.iter().enumerate() {
        let params: Vec<String> = p.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
        let psnr = if p.psnr.is_infinite() { "inf".to_owned() } else { format!("{:.4}", p.psnr) };
        out += &format!(
            "{},{},{},{:.6},{},{},{:.6e},{psnr},{:.6},{},{},{},{}\n",
            p.axis,
            p.label,
            params.join(" "),
            p.seconds,
            p.runs,
            p.rays.total(),
            p.rmse,
            p.ssim,
            front.contains(&i),
            p.image,
            p.heatmap,
            p.rays.kinds().map(|(_, n)| n.to_string()).join(",")
        );
    }
    out
}
