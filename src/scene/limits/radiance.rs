//! The radiance rule: what a pixel can sum ([`RadianceBudget`]) stays within
//! [`MAX_RADIANCE_SUM`], and the term to blame when it does not.

use glam::{DVec3, Vec3};

use super::PixelTerms;
use super::MAX_RADIANCE_SUM;
use crate::scene::error::number as num;
use crate::scene::locate::FieldPath;
use crate::scene::validate::Violation;

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
    pub fn of(terms: &PixelTerms) -> Self {
        let s = &terms.render;
        let mut parts = Vec::new();
        let camera = match s.adaptive {
            Some(_) => {
                parts.push("4 (settings.adaptive averages corners in fours)".to_owned());
                let mut n = 4.0;
                // A pixel corner takes all the lens samples.
                if terms.aperture > 0.0 {
                    parts.push(format!("camera.lens.samples {} (camera.aperture > 0)", s.lens.samples));
                    n *= f64::from(s.lens.samples);
                }
                n
            }
            None => {
                parts.push(format!("settings.aa.samples {}", s.aa.samples));
                let mut n = f64::from(s.aa.samples);
                if terms.aperture > 0.0 {
                    parts.push(format!("camera.lens.samples {} (camera.aperture > 0)", s.lens.samples));
                    n *= f64::from(s.lens.samples);
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
        let camera = match s.time.samples {
            1 => camera,
            n => {
                parts.push(format!("camera.time.samples {n}"));
                camera * f64::from(n)
            }
        };
        parts.push(format!("settings.glossy.samples {}", s.glossy.samples));
        parts.push(format!("(settings.max_depth {} + 1)", s.max_depth));
        let values = camera * f64::from(s.glossy.samples) * (f64::from(s.max_depth) + 1.0);
        let lights: DVec3 = terms.lights.iter().map(light_radiance).sum();
        let per_value = terms.background.as_dvec3() + terms.ambient.as_dvec3() + 2.0 * lights;
        Self { values, values_text: parts.join(" × "), per_value }
    }

    /// The largest sum, and its channel.
    pub fn worst(&self) -> (f64, usize) {
        let sums = self.per_value * self.values;
        (0..3).map(|c| (sums[c], c)).fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
    }
}

/// A light's colour × intensity, in 64-bit floats (it may overflow 32-bit ones).
fn light_radiance(&(colour, intensity): &(Vec3, f32)) -> DVec3 {
    colour.as_dvec3() * f64::from(intensity)
}

const CHANNELS: [&str; 3] = ["r", "g", "b"];

/// The radiance rule: a violation at the term that contributes most to the worst channel
/// (`settings.background`, `settings.ambient` or `lights[i].intensity` / `.colour`).
pub fn radiance_violation(terms: &PixelTerms) -> Option<Violation> {
    let budget = RadianceBudget::of(terms);
    let (sum, c) = budget.worst();
    if sum <= MAX_RADIANCE_SUM {
        return None;
    }
    let (background, ambient) = (f64::from(terms.background[c]), f64::from(terms.ambient[c]));
    let lights: Vec<f64> = terms.lights.iter().map(|l| light_radiance(l)[c]).collect();
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
        let (colour, intensity) = terms.lights[i];
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
