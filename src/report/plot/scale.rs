//! Scales for the plots: padded log ranges, 1-2-5 log ticks that always give labels (plotters'
//! own log key points skip ranges inside one decade), and short number labels.

use std::ops::Range;

/// The log-scale range covering `values` (all positive and finite) with a margin of 8 % of the
/// span on each side, and at least 0.6 decades in all so that one value still gets ticks.
pub(super) fn padded_log_range(values: impl Iterator<Item = f64>) -> Option<Range<f64>> {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !(lo.is_finite() && lo > 0.0 && hi.is_finite()) {
        return None;
    }
    let span = (hi / lo).log10();
    let pad = (span * 0.08).max((0.6 - span) / 2.0).max(0.1);
    let f = 10f64.powf(pad);
    Some(lo / f..hi * f)
}

/// Tick values for a log axis: the sparsest of decades, 1-2-5 or 1-2-3-5 per decade (or every
/// value of 1..9) giving at least four ticks (wide ranges use every k-th decade), and light
/// grid values at 1..9 per decade.
pub(super) fn log_ticks(range: &Range<f64>) -> (Vec<f64>, Vec<f64>) {
    let (d0, d1) = (range.start.log10().floor() as i32, range.end.log10().ceil() as i32);
    let decades = d1.saturating_sub(d0).max(1);
    let step = (decades + 7) / 8;
    let inside = |v: &f64| *v >= range.start && *v <= range.end;
    let values = |mantissas: &[f64], step: i32| -> Vec<f64> {
        (d0..=d1)
            .filter(|d| (d - d0) % step == 0)
            .flat_map(|d| mantissas.iter().map(move |m| m * 10f64.powi(d)))
            .filter(inside)
            .collect()
    };
    let tiers: [&[f64]; 4] =
        [&[1.0], &[1.0, 2.0, 5.0], &[1.0, 2.0, 3.0, 5.0], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]];
    let mut bold = Vec::new();
    for (k, tier) in tiers.iter().enumerate() {
        bold = values(tier, if k == 0 { step } else { 1 });
        if bold.len() >= 4 {
            break;
        }
    }
    let light = if decades <= 12 {
        values(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0], 1)
    } else {
        values(&[1.0], 1)
    };
    (bold, light)
}

/// A short, readable number: up to three significant digits, trailing zeros dropped; `k`, `M`,
/// `G`, `T` from a thousand up, scientific below 0.001.
pub(crate) fn format_number(v: f64) -> String {
    if !v.is_finite() {
        return if v.is_nan() {
            "–".into()
        } else if v > 0.0 {
            "∞".into()
        } else {
            "−∞".into()
        };
    }
    let a = v.abs();
    if a == 0.0 {
        return "0".into();
    }
    let trim = |s: String| -> String {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if a >= 999.5 {
        let (scale, suffix) = [(1e12, "T"), (1e9, "G"), (1e6, "M"), (1e3, "k")]
            .into_iter()
            .find(|(s, _)| a >= *s * 0.9995)
            .unwrap_or((1e3, "k"));
        if a / scale >= 999.5 && suffix == "T" {
            return trim(format!("{v:.2e}"));
        }
        return format!("{}{suffix}", format_number(v / scale));
    }
    if a < 1e-3 {
        let s = format!("{v:.2e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        return format!("{}e{exponent}", trim(mantissa.to_string()));
    }
    let decimals = (2 - a.log10().floor() as i32).clamp(0, 5) as usize;
    trim(format!("{v:.decimals$}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_ticks_always_give_labels() {
        for range in [0.79..1.26, 0.5..2.0, 0.07..5.0, 1e-4..1e9, 3e3..4e3] {
            let (bold, light) = log_ticks(&range);
            assert!(bold.len() >= 2, "{range:?}: {bold:?}");
            assert!(bold.len() <= 12, "{range:?}: {bold:?}");
            assert!(bold.iter().chain(&light).all(|v| (range.start..=range.end).contains(v)), "{range:?}");
        }
        let r = padded_log_range([2.0].into_iter()).unwrap();
        assert!(r.start < 2.0 && r.end > 2.0 && (r.end / r.start).log10() >= 0.59);
        assert!(padded_log_range(std::iter::empty()).is_none());
    }

    #[test]
    fn numbers_are_short() {
        let cases = [
            (0.0, "0"),
            (1.0, "1"),
            (0.5, "0.5"),
            (0.0123, "0.0123"),
            (1.5, "1.5"),
            (12.34, "12.3"),
            (999.0, "999"),
            (1000.0, "1k"),
            (2e5, "200k"),
            (1_228_800.0, "1.23M"),
            (0.0002, "2e-4"),
            (0.000123, "1.23e-4"),
            (f64::INFINITY, "∞"),
        ];
        for (v, s) in cases {
            assert_eq!(format_number(v), s, "{v}");
        }
    }
}
