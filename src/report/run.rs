//! Running a report: the reference, then every distinct configuration of the sweep and of the
//! effect costs, rendered once per round in interleaved rounds (`A B C A B C …`); each point
//! gets the median time over the rounds, its rays, RMSE, PSNR, SSIM, image and heat map.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use super::sweep::{cheapest, SweepDesc};
use super::{EffectCost, Point, Reference, Report};
use crate::film::metrics::{error_heatmap, psnr, rmse, ssim};
use crate::film::{write_atomically, write_png, Film, OutputError};
use crate::scene::{spawn_world, SceneDesc};
use crate::script::{Animation, Script, ScriptError};
use crate::simd::SimdLevel;
use crate::store::SoaStore;
use crate::trace::{render, Effects, RenderSettings, RenderStats, TraceScene};
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
    /// The reference file cannot be used (not a PNG or EXR, unreadable, or tone-mapped in a
    /// way that cannot be undone).
    #[error("{path}: {message}")]
    Reference {
        /// The reference file.
        path: String,
        /// Why, and what to use instead.
        message: String,
    },
    /// A configuration the sweep asks for breaks a rule on what fields produce together (e.g. a
    /// sample count that makes a bright light's pixel sum overflow).
    #[error("sweep point `{label}`: {violation}")]
    Point {
        /// The configuration's label, e.g. `aa 4096`.
        label: String,
        /// The rule it breaks, at the scene field.
        violation: crate::scene::validate::Violation,
    },
    /// An image could not be encoded.
    #[error("{path}: cannot encode: {message}")]
    Encode {
        /// The file.
        path: String,
        /// Why.
        message: String,
    },
    /// The script that poses the scene failed (or does not define `fn frame(t)`).
    #[error(transparent)]
    Script(#[from] ScriptError),
}

/// A script frame a report measures: every configuration (the reference included) is the
/// scene as `script` leaves it at `frame`, stepped as `penumbra animate` steps it, so what
/// moves while the shutter is open is blurred. The script's output is dropped.
#[derive(Clone)]
pub struct ScriptFrame {
    /// The script (`fn frame(t)`, optionally `fn setup()`).
    pub script: Script,
    /// The frame (time `frame / fps`).
    pub frame: u32,
    /// Frames per second.
    pub fps: f64,
}

impl std::fmt::Debug for ScriptFrame {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ScriptFrame")
            .field("script", &self.script.file())
            .field("frame", &self.frame)
            .field("fps", &self.fps)
            .finish()
    }
}

/// Interleaved repetitions a report makes by default.
pub const DEFAULT_RUNS: usize = 3;

/// How a report runs.
#[derive(Debug, Clone)]
pub struct Options {
    /// Interleaved repetitions: each round renders every distinct configuration once, and a
    /// point's time is the median over the rounds.
    pub runs: usize,
    /// A reference image read instead of rendered (its film and a description of the file).
    pub reference: Option<(Film, String)>,
    /// How every render traces its rays (`--simd`; the same images at every level, so only
    /// the times depend on it).
    pub simd: SimdLevel,
    /// The script frame every configuration is posed at, if any (`--script`, `--frame`).
    pub script: Option<ScriptFrame>,
}

impl Default for Options {
    fn default() -> Self {
        Self { runs: DEFAULT_RUNS, reference: None, simd: SimdLevel::Auto, script: None }
    }
}

/// What the caller is told before each render: the label of the configuration rendered.
pub type Progress<'a> = &'a (dyn Fn(&str) + Sync);

/// The distinct configurations a report renders, and which one each sweep variant and each
/// effect cost uses. Two entries with the same effective scene share one configuration, so
/// a sweep that names a setting twice (or names the scene's own setting) renders it once.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Label and scene of each distinct configuration, in the order first named.
    pub configs: Vec<(String, SceneDesc)>,
    /// The configuration of each variant of the sweep, in sweep order.
    pub variants: Vec<usize>,
    /// Each measured effect: its axis and the configurations with its setting on and off.
    pub costs: Vec<(&'static str, usize, usize)>,
}

/// The plan of a report on `desc` (whose effects, as posed, are `effects`) with `sweep`.
pub fn plan(desc: &SceneDesc, effects: &Effects, sweep: &SweepDesc) -> Plan {
    let mut configs: Vec<(String, SceneDesc)> = Vec::new();
    let mut add = |label: String, scene: SceneDesc| match configs.iter().position(|(_, s)| *s == scene) {
        Some(i) => i,
        None => {
            configs.push((label, scene));
            configs.len() - 1
        }
    };
    let variants = sweep.variants().iter().map(|v| add(v.label(), v.apply(desc))).collect();
    let axes = cost_axes(desc, effects, sweep);
    let mut costs = Vec::new();
    if !axes.is_empty() {
        let on = add("scene as is".into(), desc.clone());
        for axis in axes {
            // `cost_axes` only returns axes that `cheapest` knows.
            let off = cheapest(axis, desc).unwrap_or_else(|| desc.clone());
            costs.push((axis, on, add(format!("{axis} off"), off)));
        }
    }
    Plan { configs, variants, costs }
}

/// The order of `runs` interleaved rounds over `configs` configurations: every configuration
/// once per round (`0 1 2 0 1 2 …`), so a slow spell of the machine affects every
/// configuration alike instead of whichever happened to run then.
pub fn schedule(configs: usize, runs: usize) -> Vec<usize> {
    (0..runs.max(1)).flat_map(|_| 0..configs).collect()
}

/// The median of `times` (the mean of the middle two for an even count; 0 when empty).
pub fn median(times: &[f64]) -> f64 {
    let mut sorted = times.to_vec();
    sorted.sort_by(f64::total_cmp);
    match sorted.len() {
        0 => 0.0,
        n if n % 2 == 1 => sorted[n / 2],
        n => (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0,
    }
}

/// The number of renders [`run`] makes, for progress bars.
pub fn render_count(desc: &SceneDesc, effects: &Effects, sweep: &SweepDesc, options: &Options) -> usize {
    let reference = usize::from(options.reference.is_none());
    reference + plan(desc, effects, sweep).configs.len() * options.runs.max(1)
}

/// The effects of a scene description, posed at `script`'s frame when given (motion comes
/// only from a script).
pub fn effects_of(desc: &SceneDesc, script: Option<&ScriptFrame>) -> Result<Effects, ReportError> {
    Ok(prepare(desc, SimdLevel::Scalar, script)?.0.effects)
}

/// A scene ready to render: its snapshot and settings.
type Prepared = (Arc<TraceScene<SoaStore>>, RenderSettings);

/// `desc` ready to render, its rays traced at `simd`: spawned as it is, or posed at the
/// script's frame (with its shutter's motion).
fn prepare(desc: &SceneDesc, simd: SimdLevel, script: Option<&ScriptFrame>) -> Result<Prepared, ReportError> {
    let Some(s) = script else {
        let mut world: SceneWorld = spawn_world(desc);
        let snapshot = world.update();
        return Ok((snapshot, RenderSettings { simd, ..world.render_settings() }));
    };
    let mut animation: Animation = Animation::with_output(desc, &s.script, s.fps, false)?;
    let snapshot = animation.step_to(s.frame)?;
    Ok((snapshot, RenderSettings { simd, ..animation.world().world().render_settings() }))
}

/// Axes whose cost is measured: those in the sweep that the scene's own settings use.
fn cost_axes(desc: &SceneDesc, effects: &Effects, sweep: &SweepDesc) -> Vec<&'static str> {
    let mut axes: Vec<&'static str> = Vec::new();
    for axis in sweep.axes.iter().map(|a| a.name()) {
        let used = match axis {
            "aa" => desc.settings.adaptive.is_none() && desc.settings.aa.samples > 1,
            "adaptive" => desc.settings.adaptive.is_some(),
            "noise" => desc.settings.noise.is_some(),
            "area_light" => effects.area_lights,
            "glossy" => effects.glossy || effects.blurry,
            "lens" => effects.lens && desc.camera.lens.samples > 1,
            "time" => effects.motion,
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

/// What the first render of a configuration gave: its rays and, when a variant uses it, its
/// error against the reference and its image files.
struct Measured {
    stats: RenderStats,
    rmse: f64,
    psnr: f64,
    ssim: f64,
    image: String,
    heatmap: String,
}

/// Runs the report for scene `desc` (named `scene` in the report) into folder `out` (which
/// must exist): images and heat maps there, the figures returned. The reference is rendered
/// (or taken from `options`) first; then `options.runs` rounds each render every distinct
/// configuration of [`plan`] once, in [`schedule`] order.
pub fn run(
    desc: &SceneDesc,
    scene: &str,
    sweep: &SweepDesc,
    options: &Options,
    out: &Path,
    progress: Progress,
) -> Result<Report, ReportError> {
    let script = options.script.as_ref();
    let effects = effects_of(desc, script)?;
    let (width, height) = (desc.camera.width, desc.camera.height);
    // Every configuration obeys the scene's combined rules before anything renders.
    let reference_scene = ("reference".to_owned(), sweep.reference.apply(desc));
    let plan = plan(desc, &effects, sweep);
    for (label, scene) in std::iter::once(&reference_scene).chain(&plan.configs) {
        crate::scene::limits::check(scene)
            .map_err(|violation| ReportError::Point { label: label.clone(), violation })?;
    }
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
            let (snapshot, settings) = prepare(&reference_scene.1, options.simd, script)?;
            progress("reference");
            let started = Instant::now();
            let (film, stats) = render(&snapshot, &settings);
            let seconds = started.elapsed().as_secs_f64();
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

    // The image files of a configuration are named after the first variant that uses it.
    let variants = sweep.variants();
    let mut stems: Vec<Option<String>> = vec![None; plan.configs.len()];
    for (i, (&c, variant)) in plan.variants.iter().zip(&variants).enumerate() {
        stems[c].get_or_insert_with(|| format!("{i:02}-{}", slug(&variant.label())));
    }
    let prepared: Vec<Prepared> =
        plan.configs.iter().map(|(_, d)| prepare(d, options.simd, script)).collect::<Result<_, _>>()?;
    let mut times = vec![Vec::with_capacity(options.runs.max(1)); plan.configs.len()];
    let mut measured: Vec<Option<Measured>> = (0..plan.configs.len()).map(|_| None).collect();
    for c in schedule(plan.configs.len(), options.runs) {
        progress(&plan.configs[c].0);
        let (snapshot, settings) = &prepared[c];
        let started = Instant::now();
        let (film, stats) = render(snapshot, settings);
        times[c].push(started.elapsed().as_secs_f64());
        if measured[c].is_none() {
            measured[c] = Some(measure(film, stats, stems[c].as_deref(), &reference_film, out)?);
        }
    }

    let mut points = Vec::new();
    for (variant, &c) in variants.iter().zip(&plan.variants) {
        let Some(m) = &measured[c] else { continue };
        points.push(Point {
            axis: variant.axis.to_owned(),
            label: variant.label(),
            params: variant.params(),
            seconds: median(&times[c]),
            runs: times[c].len(),
            times: times[c].clone(),
            config: c,
            rays: m.stats.rays,
            rmse: m.rmse,
            estimated_rmse: (m.stats.noise.rounds > 0).then_some(m.stats.noise.estimated_rmse),
            psnr: m.psnr,
            ssim: m.ssim,
            image: m.image.clone(),
            heatmap: m.heatmap.clone(),
        });
    }
    let costs = plan
        .costs
        .iter()
        .map(|&(axis, on, off)| EffectCost {
            effect: axis.into(),
            seconds_on: median(&times[on]),
            seconds_off: median(&times[off]),
        })
        .collect();
    Ok(Report {
        scene: scene.to_owned(),
        script: script.map(|s| format!("{}, frame {} at {} fps", s.script.file(), s.frame, s.fps)),
        width,
        height,
        threads: rayon::current_num_threads(),
        simd: options.simd.resolve(),
        reference: reference_info,
        points,
        costs,
    })
}

/// The rays of a configuration's first render and, where `stem` names its files, its error
/// against the reference, its image and its heat map.
fn measure(
    film: Film,
    stats: RenderStats,
    stem: Option<&str>,
    reference: &Film,
    out: &Path,
) -> Result<Measured, ReportError> {
    let Some(stem) = stem else {
        return Ok(Measured {
            stats,
            rmse: 0.0,
            psnr: 0.0,
            ssim: 0.0,
            image: String::new(),
            heatmap: String::new(),
        });
    };
    let (image, heatmap) = (format!("{stem}.png"), format!("{stem}.heat.png"));
    write_png(&film, &out.join(&image))?;
    write_heatmap(&film, reference, &out.join(&heatmap))?;
    let sizes = |path: &str| ReportError::Encode { path: path.to_owned(), message: "sizes differ".into() };
    Ok(Measured {
        stats,
        rmse: rmse(&film, reference).ok_or_else(|| sizes(&image))?,
        psnr: psnr(&film, reference).ok_or_else(|| sizes(&image))?,
        ssim: ssim(&film, reference).ok_or_else(|| sizes(&image))?,
        image,
        heatmap,
    })
}

/// `results.csv`: a row per point.
pub fn csv(report: &Report) -> String {
    let kinds = crate::trace::RayCounts::default().kinds().map(|(k, _)| format!("rays_{k}"));
    let mut out = format!(
        "axis,label,params,seconds,runs,config,rays_total,rmse,estimated_rmse,psnr,ssim,pareto,image,heatmap,{}\n",
        kinds.join(",")
    );
    let front = report.pareto_front();
    for (i, p) in report.points.iter().enumerate() {
        let params: Vec<String> = p.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
        let psnr = if p.psnr.is_infinite() { "inf".to_owned() } else { format!("{:.4}", p.psnr) };
        out += &format!(
            "{},{},{},{:.6},{},{},{},{:.6e},{},{psnr},{:.6},{},{},{},{}\n",
            p.axis,
            p.label,
            params.join(" "),
            p.seconds,
            p.runs,
            p.config,
            p.rays.total(),
            p.rmse,
            p.estimated_rmse.map_or(String::new(), |e| format!("{e:.6e}")),
            p.ssim,
            front.contains(&i),
            p.image,
            p.heatmap,
            p.rays.kinds().map(|(_, n)| n.to_string()).join(",")
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::parse_scene;

    const SCENE: &str = r#"Scene(
        camera: (position: (0, 1, -4), look_at: (0, 0.5, 0), fov_deg: 40, width: 8, height: 6),
        settings: (aa: (samples: 2)),
        materials: [(name: "m", kd: (0.8, 0.8, 0.8))],
        lights: [Rect(corner: (-1, 3, -1), edge_u: (2, 0, 0), edge_v: (0, 0, 2), samples: 4)],
        objects: [(name: "ball", shape: Sphere(centre: (0, 0.5, 0), radius: 0.5), material: "m")],
    )"#;

    #[test]
    fn rounds_render_every_configuration_once_each() {
        assert_eq!(schedule(3, 2), [0, 1, 2, 0, 1, 2]);
        assert_eq!(schedule(2, 0), [0, 1], "at least one round");
        assert_eq!(median(&[0.287, 0.122, 0.125]), 0.125);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(median(&[]), 0.0);
    }

    #[test]
    fn equal_settings_share_one_configuration() {
        let desc = parse_scene(SCENE, "s.ron").unwrap();
        let sweep =
            SweepDesc::parse("Sweep(axes: [Aa(samples: [2, 2, 8]), AreaLight(samples: [4, 16])])", "w.ron")
                .unwrap();
        let plan = plan(&desc, &effects_of(&desc, None).unwrap(), &sweep);
        // aa 2 jittered is the scene as is, and so is area_light 4 (the light's own count).
        assert_eq!(plan.variants, [0, 0, 1, 0, 2]);
        let labels: Vec<&str> = plan.configs.iter().map(|(l, _)| l.as_str()).collect();
        assert_eq!(labels, ["aa 2 jittered", "aa 8 jittered", "area_light 16", "aa off", "area_light off"]);
        assert_eq!(plan.costs, [("aa", 0, 3), ("area_light", 0, 4)]);
        let options = Options { runs: 3, ..Options::default() };
        assert_eq!(render_count(&desc, &effects_of(&desc, None).unwrap(), &sweep, &options), 1 + 5 * 3);
    }
}
