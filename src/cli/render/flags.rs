//! The value parsers of the rendering options (`--samples aa=16`, `--pattern lens=grid`,
//! `--adaptive 0.05:4`, `--shutter 0:0.5`, …): each refuses a bad value with a message that
//! says what is allowed.

use penumbra::camera::Shutter;
use penumbra::film::ToneOperator;
use penumbra::sample::Pattern;
use penumbra::scene;

/// An effect whose sampling the command line can set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Effect {
    Aa,
    Lens,
    Shadow,
    Glossy,
    Time,
}

pub(super) fn split_effect(s: &str) -> Result<(Effect, &str), String> {
    let (effect, value) = s.split_once('=').ok_or_else(|| format!("expected EFFECT=VALUE, got `{s}`"))?;
    let effect = match effect {
        "aa" => Effect::Aa,
        "lens" => Effect::Lens,
        // `area_light` as in reports and sweep files; `shadow` is its older spelling.
        "area_light" | "shadow" => Effect::Shadow,
        "glossy" => Effect::Glossy,
        "time" => Effect::Time,
        other => {
            return Err(format!("unknown effect `{other}`; expected aa, lens, area_light, glossy or time"))
        }
    };
    Ok((effect, value))
}

pub(super) fn parse_samples(s: &str) -> Result<(Effect, u32), String> {
    let (effect, value) = split_effect(s)?;
    match value.parse::<u32>() {
        Ok(n) if (1..=4096).contains(&n) => Ok((effect, n)),
        _ => Err(format!("sample count must be a whole number in 1..=4096, got `{value}`")),
    }
}

pub(super) fn parse_pattern(s: &str) -> Result<(Effect, Pattern), String> {
    let (effect, value) = split_effect(s)?;
    let pattern = match value {
        "grid" => Pattern::Grid,
        "random" => Pattern::Random,
        "jittered" => Pattern::Jittered,
        other => return Err(format!("unknown pattern `{other}`; expected grid, random or jittered")),
    };
    Ok((effect, pattern))
}

pub(super) fn parse_adaptive(s: &str) -> Result<(f32, u32), String> {
    let (threshold, depth) = s.split_once(':').unwrap_or((s, "3"));
    let threshold = threshold.parse::<f32>().ok().filter(|t| t.is_finite() && *t >= 0.0);
    let depth = depth.parse::<u32>().ok().filter(|d| (1..=6).contains(d));
    match (threshold, depth) {
        (Some(t), Some(d)) => Ok((t, d)),
        _ => Err(format!(
            "expected a threshold ≥ 0 and an optional depth in 1..=6 (`0.05` or `0.05:4`), got `{s}`"
        )),
    }
}

/// `--shutter`: a shutter interval, or `none` for an instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShutterFlag(pub Option<(f32, f32)>);

/// Parses `--shutter OPEN:CLOSE|none`.
pub fn parse_shutter(s: &str) -> Result<ShutterFlag, String> {
    if s == "none" {
        return Ok(ShutterFlag(None));
    }
    let number = |t: &str| t.trim().parse::<f32>().ok().filter(|x| x.is_finite());
    let Some((open, close)) = s.split_once(':').and_then(|(a, b)| Some((number(a)?, number(b)?))) else {
        return Err(format!(
            "expected OPEN:CLOSE (fractions of the frame interval, e.g. `0:0.5`) or `none`, got `{s}`"
        ));
    };
    Shutter::new(open, close).map(|_| ShutterFlag(Some((open, close))))
}

pub(super) fn parse_target_error(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(e) if (0.0..=1.0).contains(&e) => Ok(e),
        _ => Err(format!(
            "expected a target error in [0, 1] (display units; 0.01 is about 2.5/255), got `{s}`"
        )),
    }
}

pub(super) fn parse_time_limit(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(t),
        _ => Err(format!("expected a time limit in seconds, finite and > 0, got `{s}`")),
    }
}

pub(super) fn parse_noise_samples(s: &str) -> Result<(u32, u32), String> {
    let max = scene::validate::MAX_NOISE_SAMPLES;
    let parsed = s
        .split_once(':')
        .and_then(|(a, b)| Some((a.trim().parse::<u32>().ok()?, b.trim().parse::<u32>().ok()?)));
    match parsed {
        Some((lo, hi)) if 1 <= lo && lo <= hi && hi <= max => Ok((lo, hi)),
        _ => {
            Err(format!("expected MIN:MAX camera samples per pixel with 1 <= MIN <= MAX <= {max}, got `{s}`"))
        }
    }
}

pub(super) fn parse_aperture(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(r) if r.is_finite() && r >= 0.0 => Ok(r),
        _ => Err(format!("aperture must be a finite number ≥ 0, got `{s}`")),
    }
}

pub(super) fn parse_operator(s: &str) -> Result<ToneOperator, String> {
    match s {
        "clamp" => Ok(ToneOperator::Clamp),
        "reinhard" => Ok(ToneOperator::Reinhard),
        "aces" => Ok(ToneOperator::Aces),
        other => Err(format!("unknown tone operator `{other}`; expected clamp, reinhard or aces")),
    }
}

pub(super) fn parse_exposure(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(e) if e.is_finite() && e.abs() <= 30.0 => Ok(e),
        _ => Err(format!("exposure must be a number of stops in [-30, 30], got `{s}`")),
    }
}

pub(super) fn parse_white(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(w) if w.is_finite() && w > 0.0 => Ok(w),
        _ => Err(format!("white point must be a finite number > 0, got `{s}`")),
    }
}
