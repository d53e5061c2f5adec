//! The rules on what fields produce together, checked once each field has passed its own rule
//! in [`super::validate`] (and the meshes are loaded):
//!
//! - **World-space extent.** Every object's bounds, after its transform (radius × scale,
//!   vertices, box corners and mesh bounds scaled, rotated and translated), and every area
//!   light's corners lie within ±[`MAX_COORDINATE`]: each coordinate is fine alone, but a
//!   sphere of radius 1e17 scaled by 1e3 is not.
//! - **Lens.** Every lens point (`position` ± `aperture`) and the focus point (`position` +
//!   `focus_distance` along the view) lie within ±[`MAX_COORDINATE`], so the lens maths
//!   stays finite.
//! - **Camera samples.** A pixel's camera samples, `settings.aa.samples` ×
//!   `camera.lens.samples` (with an aperture) × `camera.time.samples`, are at most
//!   [`MAX_CAMERA_SAMPLES`], so every sample has a 32-bit index. Time samples count whether or
//!   not anything moves: what moves comes from a script, after this check.
//! - **Radiance.** The radiance a pixel can sum, [`RadianceBudget::values`] ×
//!   [`RadianceBudget::per_value`], is at most [`MAX_RADIANCE_SUM`] in every channel.
//!
//! [`check`] applies them to a scene, in document order (camera, settings and lights,
//! objects); the script API applies the same functions to each write, and the command line to
//! the scene with its overrides applied.

use glam::{DQuat, DVec3, Vec3};

use super::error::{number as num, SceneError};
use super::format::{CameraDesc, LightDesc, ObjectDesc, SceneDesc, ShapeDesc, TransformDesc};
use super::locate::{position_of, FieldPath, Segment};
use super::mesh::MeshLibrary;
use super::rules::MAX_COORDINATE;
use super::validate::Violation;

/// Largest radiance a pixel may sum, in any channel, before dividing by its sample count.
/// Film sums are 32-bit floats (largest ≈ 3.4e38); 1e29 leaves room for the Phong bracket
/// (≤ 2: `kd` ≤ 1 plus `ks` ≤ 1 times a highlight that [`super::rules::MAX_SHININESS`]
/// keeps ≤ 1.01), for an exposure of up to 2^30 in tone mapping, and for 10⁸ lights.
pub const MAX_RADIANCE_SUM: f64 = 1e29;

/// Largest number of camera samples a pixel may take: AA positions × lens points × times
/// (4096², what AA and lens samples at their largest already make).
pub const MAX_CAMERA_SAMPLES: u64 = 1 << 24;

/// Checks the combined rules on a validated scene whose meshes are loaded; the first
/// violation in document order.
///
/// # Examples
/// ```
/// use penumbra::scene::{default_scene, limits::check};
/// let mut scene = default_scene();
/// assert!(check(&scene).is_ok());
/// scene.camera.aperture = 1e30;
/// assert_eq!(check(&scene).unwrap_err().path.to_string(), "camera.aperture");
/// ```
pub fn check(scene: &SceneDesc) -> Result<(), Violation> {
    let root = FieldPath::root();
    if let Some(v) = lens_violation(&scene.camera) {
        return Err(under(&root.clone().field("camera"), v));
    }
    if let Some(v) = camera_samples_violation(scene) {
        return Err(v);
    }
    if let Some(v) = radiance_violation(scene) {
        return Err(v);
    }
    for (i, light) in scene.lights.iter().enumerate() {
        if let Some(v) = light_extent_violation(light) {
            return Err(under(&root.clone().field("lights").index(i), v));
        }
    }
    for (i, object) in scene.objects.iter().enumerate() {
        if let Some(v) = object_violation(object, &scene.meshes) {
            return Err(under(&root.clone().field("objects").index(i), v));
        }
    }
    Ok(())
}

/// [`check`] as a [`SceneError`] located in `text` (the scene's source, named `origin`).
pub fn check_located(scene: &SceneDesc, text: &str, origin: &str) -> Result<(), SceneError> {
    check(scene).map_err(|v| located(v, text, origin))
}

/// A violation as a [`SceneError`]: at its field in `text`, or at the nearest enclosing field
/// the text has (a field the command line set may be absent from the file).
pub fn located(v: Violation, text: &str, origin: &str) -> SceneError {
    let segments = v.path.segments();
    let (line, col) = (0..=segments.len())
        .rev()
        .find_map(|n| position_of(text, &path_of(&segments[..n])))
        .unwrap_or((1, 1));
    SceneError::Invalid { path: origin.to_owned(), line, col, field: v.path.to_string(), rule: v.rule }
}

/// [`check`] on a scene the command line has changed: `flags` pairs a field it set (e.g.
/// `settings.aa.samples`) with the flag that set it (`--samples aa=4096`), and every flag whose
/// field the rule names is added to the message. `text` is the scene's source, named `origin`.
pub fn check_overrides(
    desc: &SceneDesc,
    text: &str,
    origin: &str,
    flags: &[(String, String)],
) -> Result<(), SceneError> {
    let Err(mut v) = check(desc) else { return Ok(()) };
    let named: Vec<String> = flags
        .iter()
        .filter(|(field, _)| {
            v.rule.contains(field.as_str()) || v.path.to_string().starts_with(field.as_str())
        })
        .map(|(field, flag)| format!("{field} from `{flag}`"))
        .collect();
    if !named.is_empty() {
        v.rule = format!("{} (the command line set {})", v.rule, named.join(", "));
    }
    Err(located(v, text, origin))
}

fn path_of(segments: &[Segment]) -> FieldPath {
    segments.iter().fold(FieldPath::root(), |p, s| match s {
        Segment::Field(name) => p.field(name),
        Segment::Index(i) => p.index(*i),
    })
}

/// `v` with its path put under `path`.
fn under(path: &FieldPath, v: Violation) -> Violation {
    let mut segments = path.segments().to_vec();
    segments.extend_from_slice(v.path.segments());
    Violation { path: path_of(&segments), rule: v.rule }
}

fn violation(path: &str, rule: String) -> Violation {
    Violation { path: FieldPath::parse(path).unwrap_or_default(), rule }
}

/// Whether `value`, as the engine's 32-bit float, lies within ±[`MAX_COORDINATE`].
fn within(value: f64) -> bool {
    (value as f32).abs() <= MAX_COORDINATE
}

/// The first axis and value of `p` beyond ±[`MAX_COORDINATE`].
fn beyond(p: DVec3) -> Option<(&'static str, f64)> {
    ["x", "y", "z"].into_iter().zip(p.to_array()).find(|&(_, c)| !within(c))
}

// ---------------------------------------------------------------------------------------
// Lens
// ---------------------------------------------------------------------------------------

/// The lens rule for a camera whose fields are each valid; the path is relative to the camera
/// (`aperture`, `focus_distance`).
pub fn lens_violation(camera: &CameraDesc) -> Option<Violation> {
    let position = camera.position;
    let aperture = f64::from(camera.aperture);
    if aperture > 0.0 {
        let reach = position.abs() + DVec3::splat(aperture);
        if let Some((axis, c)) = beyond(reach) {
            let rule = format!(
                "the lens must lie within ±{MAX_COORDINATE:e} (`position` ± `aperture` on every axis), \
                 but |position.{axis}| + aperture = {}; got aperture {}",
                num(c),
                num(camera.aperture.into())
            );
            return Some(violation("aperture", rule));
        }
    }
    if let Some(distance) = camera.focus_distance {
        let forward = (camera.look_at - position).normalize_or_zero();
        let focus = position + forward * f64::from(distance);
        if let Some((axis, c)) = beyond(focus) {
            let rule = format!(
                "the focus point `position + focus_distance × view direction` must lie within \
                 ±{MAX_COORDINATE:e}, but its {axis} is {}; got focus_distance {}",
                num(c),
                num(distance.into())
            );
            return Some(violation("focus_distance", rule));
        }
    }
    None
}

/// The camera-samples rule: `settings.aa.samples` × `camera.lens.samples` (with an aperture)
/// × `camera.time.samples` ≤ [`MAX_CAMERA_SAMPLES`], reported at `camera.time.samples` (the
/// only factor that can push the product past it). Adaptive renders trace at most
/// `camera.time.samples` rays per lattice point, so only the time samples count there.
pub fn camera_samples_violation(scene: &SceneDesc) -> Option<Violation> {
    let camera = &scene.camera;
    let lens = if camera.aperture > 0.0 { u64::from(camera.lens.samples) } else { 1 };
    let per_position = match scene.settings.adaptive {
        Some(_) => 1,
        None => u64::from(scene.settings.aa.samples) * lens,
    };
    let n = per_position * u64::from(camera.time.samples);
    (n > MAX_CAMERA_SAMPLES).then(|| {
        let rule = format!(
            "a pixel takes settings.aa.samples {} × camera.lens.samples {lens} (with camera.aperture > 0) \
             × camera.time.samples {} = {n} camera samples, more than {MAX_CAMERA_SAMPLES}; lower one of them",
            scene.settings.aa.samples, camera.time.samples
        );
        violation("camera.time.samples", rule)
    })
}

// ---------------------------------------------------------------------------------------
// Radiance
// ---------------------------------------------------------------------------------------

/// What bounds the radiance a pixel sums: how many values it adds up, and how large each can
/// be per channel.
#[derive(Debug, Clone, PartialEq)]
pub struct RadianceBudget {
    /// Values a pixel adds before dividing: camera samples × glossy rays × ray-tree levels.
    pub values: f64,
    /// How `values` is made, naming the fields, e.g. `settings.aa.samples 4 × ...`.
    pub values_text: String,
    /// The largest radiance one value can carry, per channel: background + ambient + 2 × the
    /// sum of the lights' colour × intensity.
    pub per_value: DVec3,
}

impl RadianceBudget {
    /// The budget of `scene` (its settings, camera and lights).
    pub fn of(scene: &SceneDesc) -> Self {
        let s = &scene.settings;
        let mut parts = Vec::new();
        let camera = match s.adaptive {
            Some(_) => {
                parts.push("4 (settings.adaptive averages corners in fours)".to_owned());
                4.0
            }
            None => {
                parts.push(format!("settings.aa.samples {}", s.aa.samples));
                let mut n = f64::from(s.aa.samples);
                if scene.camera.aperture > 0.0 {
                    parts.push(format!(
                        "camera.lens.samples {} (camera.aperture > 0)",
                        scene.camera.lens.samples
                    ));
                    n *= f64::from(scene.camera.lens.samples);
                }
                if let Some(noise) = &s.noise {
                    // Pixels sum whole batches; the last may pass max_samples by up to one batch.
                    let batches = noise.max_samples.div_ceil(s.aa.samples).max(2);
                    parts.push(format!(
                        "{batches} batches (settings.noise.max_samples {})",
                        noise.max_samples
                    ));
                    n *= f64::from(batches);
                }
                n
            }
        };
        // Time samples multiply the camera samples (and a lattice point's) where something moves.
        let camera = match scene.camera.time.samples {
            1 => camera,
            n => {
                parts.push(format!("camera.time.samples {n}"));
                camera * f64::from(n)
            }
        };
        parts.push(format!("settings.glossy.samples {}", s.glossy.samples));
        parts.push(format!("(settings.max_depth {} + 1)", s.max_depth));
        let values = camera * f64::from(s.glossy.samples) * (f64::from(s.max_depth) + 1.0);
        let lights: DVec3 = scene.lights.iter().map(light_radiance).sum();
        let per_value = s.background.as_dvec3() + s.ambient.as_dvec3() + 2.0 * lights;
        Self { values, values_text: parts.join(" × "), per_value }
    }

    /// The largest sum, and its channel.
    pub fn worst(&self) -> (f64, usize) {
        let sums = self.per_value * self.values;
        (0..3).map(|c| (sums[c], c)).fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
    }
}

/// A light's colour × intensity, in 64-bit floats (it may overflow 32-bit ones).
fn light_radiance(light: &LightDesc) -> DVec3 {
    let (colour, intensity) = light_terms(light);
    colour.as_dvec3() * f64::from(intensity)
}

fn light_terms(light: &LightDesc) -> (Vec3, f32) {
    match *light {
        LightDesc::Point { colour, intensity, .. }
        | LightDesc::Spot { colour, intensity, .. }
        | LightDesc::Directional { colour, intensity, .. }
        | LightDesc::Rect { colour, intensity, .. }
        | LightDesc::Disk { colour, intensity, .. } => (colour, intensity),
    }
}

const CHANNELS: [&str; 3] = ["r", "g", "b"];

/// The radiance rule: a violation at the term that contributes most to the worst channel
/// (`settings.background`, `settings.ambient` or `lights[i].intensity` / `.colour`).
pub fn radiance_violation(scene: &SceneDesc) -> Option<Violation> {
    let budget = RadianceBudget::of(scene);
    let (sum, c) = budget.worst();
    if sum <= MAX_RADIANCE_SUM {
        return None;
    }
    let s = &scene.settings;
    let (background, ambient) = (f64::from(s.background[c]), f64::from(s.ambient[c]));
    let lights: Vec<f64> = scene.lights.iter().map(|l| light_radiance(l)[c]).collect();
    let light_sum: f64 = lights.iter().sum();
    let channel = CHANNELS[c];
    let budget_text = format!(
        "a pixel sums {} values ({}), each up to background + ambient + 2 × Σ lights' colour × \
         intensity = {} + {} + 2 × {} in {channel}, and {} × {} = {} must stay ≤ {MAX_RADIANCE_SUM:e} \
         (32-bit film sums overflow at 3.4e38)",
        num(budget.values),
        budget.values_text,
        num(background),
        num(ambient),
        num(light_sum),
        num(budget.values),
        num(budget.per_value[c]),
        num(sum),
    );
    let brightest = lights.iter().copied().enumerate().fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    let (path, what) = if 2.0 * brightest.1 >= background.max(ambient) {
        let (i, radiance) = brightest;
        let (colour, intensity) = light_terms(&scene.lights[i]);
        let field = if intensity >= colour.max_element() { "intensity" } else { "colour" };
        let path = FieldPath::root().field("lights").index(i).field(field);
        let (colour, intensity, radiance) = (num(colour[c].into()), num(intensity.into()), num(radiance));
        (path, format!("colour × intensity = {colour} × {intensity} = {radiance} in {channel} is too bright"))
    } else if background >= ambient {
        let path = FieldPath::root().field("settings").field("background");
        (path, format!("{channel} = {} is too bright", num(background)))
    } else {
        let path = FieldPath::root().field("settings").field("ambient");
        (path, format!("{channel} = {} is too bright", num(ambient)))
    };
    Some(Violation { path, rule: format!("{what}: {budget_text}") })
}

// ---------------------------------------------------------------------------------------
// World-space extent
// ---------------------------------------------------------------------------------------

/// Where a shape lies in object space, as the extent rule sees it.
#[derive(Debug, Clone, PartialEq)]
pub enum Extent {
    /// A sphere: under a uniform scale its world bounds are the moved centre ± radius × |scale|.
    Ball {
        /// Centre.
        centre: DVec3,
        /// Radius.
        radius: f64,
    },
    /// These points' world images bound the shape (vertices, or a box's eight corners).
    Points(Vec<DVec3>),
    /// An infinite plane: only its point is placed.
    Plane(DVec3),
}

impl Extent {
    /// The extent of `shape`; a mesh's is its bounds' corners (`None` if it is not loaded).
    pub fn of(shape: &ShapeDesc, meshes: &MeshLibrary) -> Option<Self> {
        Some(match shape {
            ShapeDesc::Sphere { centre, radius } => {
                Self::Ball { centre: *centre, radius: f64::from(*radius) }
            }
            ShapeDesc::Plane { point, .. } => Self::Plane(*point),
            ShapeDesc::Triangle { vertices } => Self::Points(vertices.to_vec()),
            ShapeDesc::Polygon { vertices } => Self::Points(vertices.clone()),
            ShapeDesc::Cuboid { min, max } => Self::corners(*min, *max),
            ShapeDesc::Mesh { .. } => {
                let (_, asset) = meshes.get_key(shape.mesh_key()?)?;
                let b = asset.data.bounds;
                Self::corners(b.min.as_dvec3(), b.max.as_dvec3())
            }
        })
    }

    /// The eight corners of the box `min..max`.
    pub fn corners(min: DVec3, max: DVec3) -> Self {
        let pick = |i: usize| {
            DVec3::new(
                if i & 1 == 0 { min.x } else { max.x },
                if i & 2 == 0 { min.y } else { max.y },
                if i & 4 == 0 { min.z } else { max.z },
            )
        };
        Self::Points((0..8).map(pick).collect())
    }

    /// World-space bounds under `placement` (scale, then rotate X, Y, Z, then translate).
    pub fn world_bounds(&self, placement: &Placement) -> (DVec3, DVec3) {
        let rotation = placement.rotation();
        let place = |p: DVec3| rotation * (placement.scale * p) + placement.translate;
        match self {
            Self::Ball { centre, radius } => {
                let c = place(*centre);
                let r = DVec3::splat(radius * placement.scale.abs().max_element());
                (c - r, c + r)
            }
            Self::Points(points) => points
                .iter()
                .map(|p| place(*p))
                .fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| {
                    (lo.min(p), hi.max(p))
                }),
            Self::Plane(point) => (place(*point), place(*point)),
        }
    }
}

/// An object's placement in 64-bit floats, as [`TransformDesc`] gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Translation.
    pub translate: DVec3,
    /// Rotation in degrees about X, then Y, then Z.
    pub rotate_deg: DVec3,
    /// Per-axis scale.
    pub scale: DVec3,
}

impl Placement {
    /// The placement a scene transform describes.
    pub fn of(t: &TransformDesc) -> Self {
        Self { translate: t.translate, rotate_deg: t.rotate_deg.as_dvec3(), scale: t.scale.as_dvec3() }
    }

    fn rotation(&self) -> DQuat {
        let r = self.rotate_deg * (std::f64::consts::PI / 180.0);
        DQuat::from_rotation_z(r.z) * DQuat::from_rotation_y(r.y) * DQuat::from_rotation_x(r.x)
    }
}

/// The rule every object's placed bounds obey.
pub fn extent_rule() -> String {
    format!(
        "an object's world-space bounds (its shape × scale, rotated, then translated) must lie within \
         ±{MAX_COORDINATE:e}"
    )
}

/// Which part of an object puts it beyond the limit, and the first coordinate beyond it;
/// `None` when its placed bounds lie within ±[`MAX_COORDINATE`].
///
/// The part is `translate` when the object fits before it is moved, `scale` when the scale
/// enlarges it (|scale| > 1 on some axis), else `shape` (the shape alone is too large).
pub fn extent_excess(extent: &Extent, placement: &Placement) -> Option<(&'static str, &'static str, f64)> {
    let (lo, hi) = extent.world_bounds(placement);
    let (axis, value) = beyond(lo).or_else(|| beyond(hi))?;
    let unmoved = Placement { translate: DVec3::ZERO, ..*placement };
    let (ulo, uhi) = extent.world_bounds(&unmoved);
    let part = if beyond(ulo).is_none() && beyond(uhi).is_none() {
        "translate"
    } else if placement.scale.abs().max_element() > 1.0 {
        "scale"
    } else {
        "shape"
    };
    Some((part, axis, value))
}

/// A short account of how the shape reaches that far: `radius 1e17 × scale 1000`.
fn extent_account(object: &ObjectDesc) -> String {
    let t = &object.transform;
    let scale = t.scale.abs().max_element();
    match &object.shape {
        ShapeDesc::Sphere { radius, .. } => {
            format!("radius {} × scale {}", num(f64::from(*radius)), num(f64::from(scale)))
        }
        ShapeDesc::Plane { .. } => "the plane's point × transform".to_owned(),
        ShapeDesc::Triangle { .. } | ShapeDesc::Polygon { .. } => "its vertices × transform".to_owned(),
        ShapeDesc::Cuboid { .. } => "its box corners × transform".to_owned(),
        ShapeDesc::Mesh { .. } => "its mesh bounds × transform".to_owned(),
    }
}

/// The extent rule for one object, with a path relative to it.
pub fn object_violation(object: &ObjectDesc, meshes: &MeshLibrary) -> Option<Violation> {
    let extent = Extent::of(&object.shape, meshes)?;
    let (part, axis, value) = extent_excess(&extent, &Placement::of(&object.transform))?;
    let path = match (part, &object.shape) {
        ("translate", _) => "transform.translate",
        ("scale", _) => "transform.scale",
        (_, ShapeDesc::Sphere { .. }) => "shape.radius",
        (_, ShapeDesc::Mesh { .. }) => "shape.file",
        (_, ShapeDesc::Cuboid { .. }) => "shape.max",
        (_, ShapeDesc::Plane { .. }) => "shape.point",
        _ => "shape.vertices",
    };
    let rule =
        format!("{}: {} puts the object at {axis} = {}", extent_rule(), extent_account(object), num(value));
    Some(violation(path, rule))
}

/// The extent rule for an area light (its corners, or its centre ± radius); the path is
/// relative to the light.
pub fn light_extent_violation(light: &LightDesc) -> Option<Violation> {
    match *light {
        LightDesc::Rect { corner, edge_u, edge_v, .. } => {
            let (c, u, v) = (corner, edge_u.as_dvec3(), edge_v.as_dvec3());
            for (field, p) in [("edge_u", c + u), ("edge_v", c + v), ("edge_v", c + u + v)] {
                if let Some((axis, value)) = beyond(p) {
                    let rule = format!(
                        "the light's corners (`corner` + `edge_u` + `edge_v`) must lie within \
                         ±{MAX_COORDINATE:e}, but one is at {axis} = {}",
                        num(value)
                    );
                    return Some(violation(field, rule));
                }
            }
            None
        }
        LightDesc::Disk { centre, radius, .. } => {
            let reach = centre.abs() + DVec3::splat(f64::from(radius));
            let (axis, value) = beyond(reach)?;
            let rule = format!(
                "the disk (`centre` ± `radius`) must lie within ±{MAX_COORDINATE:e}, but it reaches \
                 |{axis}| = {}",
                num(value)
            );
            Some(violation("radius", rule))
        }
        LightDesc::Point { .. } | LightDesc::Spot { .. } | LightDesc::Directional { .. } => None,
    }
}

#[cfg(test)]
mod tests;
