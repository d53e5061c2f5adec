//! The log-log error plots, RMSE against render time (with the Pareto front) and against rays,
//! and the noise-driven mode's estimated RMSE against its true RMSE (with the line where they
//! are equal): the points grouped into one series per sweep axis, zero values drawn at a floor
//! with an arrow, and points without a positive x (or without a y) left out.

use std::ops::Range;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::frame::{draw_legend, draw_no_data, with_legend, with_note, Mark};
use super::scale::{format_number, log_ticks, padded_log_range};
use super::{marker_shape, Drawn, FONT, FRONT, GRID_BOLD, GRID_LIGHT, INK, MUTED, PALETTE};
use crate::report::{Point, Report};

/// One axis's points, ready for log-log axes.
struct Series {
    name: String,
    /// (x, y, index into `report.points`), in sweep order.
    points: Vec<(f64, f64, usize)>,
}

/// The points of a log-log error plot, with what had to be adjusted to draw them.
struct ErrorData {
    series: Vec<Series>,
    x: Range<f64>,
    y: Range<f64>,
    /// Where RMSE-0 points are drawn, if there are any.
    zero_at: Option<f64>,
    /// Points left out for a non-positive or non-finite x or RMSE.
    left_out: usize,
}

/// What one log-log chart plots of each point.
pub(super) struct Axes<X, Y> {
    /// The x axis's description.
    pub x_desc: &'static str,
    /// The y axis's description.
    pub y_desc: &'static str,
    /// A point's x; points without a positive, finite one are left out.
    pub x_of: X,
    /// A point's y (`None`: not plotted); zero is drawn at a floor with an arrow.
    pub y_of: Y,
    /// What the note calls a y of zero.
    pub zero: &'static str,
    /// What the note calls the points left out.
    pub left_out: &'static str,
    /// Draw the Pareto front of (seconds, RMSE), which only makes sense when x is the time.
    pub front: bool,
    /// Draw the line y = x.
    pub diagonal: bool,
}

/// The axes of an RMSE plot against `x_of`.
pub(super) fn rmse_against(
    x_desc: &'static str,
    x_of: impl Fn(&Point) -> f64,
    front: bool,
) -> Axes<impl Fn(&Point) -> f64, impl Fn(&Point) -> Option<f64>> {
    Axes {
        x_desc,
        y_desc: "RMSE against the reference",
        x_of,
        y_of: |p: &Point| Some(p.rmse),
        zero: "RMSE 0 (equal to the reference)",
        left_out: "variant(s) without a positive value",
        front,
        diagonal: false,
    }
}

/// Groups the drawable points by axis (and AA pattern); `None` when none is drawable.
fn error_data(
    report: &Report,
    x_of: impl Fn(&Point) -> f64,
    y_of: impl Fn(&Point) -> Option<f64>,
) -> Option<ErrorData> {
    let drawable = |p: &Point| {
        let x = x_of(p);
        x.is_finite() && x > 0.0 && y_of(p).is_some_and(|y| y.is_finite() && y >= 0.0)
    };
    let smallest = report
        .points
        .iter()
        .filter(|p| drawable(p))
        .filter_map(&y_of)
        .filter(|&y| y > 0.0)
        .fold(f64::INFINITY, f64::min);
    // With no positive RMSE at all, any level will do: there is nothing to compare with.
    let floor = if smallest.is_finite() { smallest / 2.0 } else { 1e-3 };

    let mut series: Vec<Series> = Vec::new();
    let (mut left_out, mut zeros) = (0, 0);
    for (i, p) in report.points.iter().enumerate() {
        if !drawable(p) {
            left_out += 1;
            continue;
        }
        let y = match y_of(p) {
            Some(y) if y > 0.0 => y,
            _ => {
                zeros += 1;
                floor
            }
        };
        // One curve per axis, and per pattern where the axis sweeps patterns too.
        let name = match p.params.iter().find(|(k, _)| k == "pattern") {
            Some((_, pattern)) => format!("{} {pattern}", p.axis),
            None => p.axis.clone(),
        };
        match series.iter_mut().find(|s| s.name == name) {
            Some(s) => s.points.push((x_of(p), y, i)),
            None => series.push(Series { name, points: vec![(x_of(p), y, i)] }),
        }
    }
    let all = || series.iter().flat_map(|s| s.points.iter());
    let x = padded_log_range(all().map(|p| p.0))?;
    let mut y = padded_log_range(all().map(|p| p.1))?;
    if zeros > 0 {
        // Room under the lowest points for the arrows that mark RMSE 0.
        y.start = y.start.min(floor / 10f64.powf(0.25));
    }
    Some(ErrorData { series, x, y, zero_at: (zeros > 0).then_some(floor), left_out })
}

/// A log-log chart of `axes`' y against its x, one series per axis.
pub(super) fn draw_error_chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    report: &Report,
    title: &str,
    axes: &Axes<impl Fn(&Point) -> f64, impl Fn(&Point) -> Option<f64>>,
) -> Drawn<DB> {
    let Some(data) = error_data(report, &axes.x_of, &axes.y_of) else {
        let why = match axes.diagonal {
            true => "no variant has an estimated error (the noise axis gives them)",
            false => "no variant has a positive value and a finite RMSE",
        };
        return draw_no_data(root, title, why);
    };
    let mut notes = Vec::new();
    if let Some(at) = data.zero_at {
        notes.push(format!("↓ {}, drawn at {}", axes.zero, format_number(at)));
    }
    if data.left_out > 0 {
        notes.push(format!("{} {} left out", data.left_out, axes.left_out));
    }
    let area = with_note(root, &notes.join("; "))?;
    let (area, legend) = with_legend(&area, title)?;

    let (xb, xl) = log_ticks(&data.x);
    let (yb, yl) = log_ticks(&data.y);
    let mut chart = ChartBuilder::on(&area)
        .margin(14)
        .margin_top(4)
        .x_label_area_size(46)
        .y_label_area_size(62)
        .build_cartesian_2d(
            data.x.clone().log_scale().with_key_points(xb).with_light_points(xl),
            data.y.clone().log_scale().with_key_points(yb).with_light_points(yl),
        )?;
    chart
        .configure_mesh()
        .x_desc(axes.x_desc)
        .y_desc(axes.y_desc)
        .x_label_formatter(&|v| format_number(*v))
        .y_label_formatter(&|v| format_number(*v))
        .label_style((FONT, 13).into_font().color(&INK))
        .axis_desc_style((FONT, 15).into_font().color(&INK))
        .bold_line_style(GRID_BOLD)
        .light_line_style(GRID_LIGHT)
        .axis_style(MUTED)
        .draw()?;

    // The Pareto front or the diagonal first, so that the series are drawn over it.
    let mut entries = Vec::new();
    if axes.diagonal {
        let (lo, hi) = (data.x.start.max(data.y.start), data.x.end.min(data.y.end));
        if lo < hi {
            let style = FRONT.stroke_width(2);
            chart.draw_series(DashedLineSeries::new([(lo, lo), (hi, hi)], 7, 5, style))?;
            entries.push(("estimate = true".to_owned(), Mark::Front));
        }
    }
    if axes.front {
        let points: Vec<(f64, f64)> = report
            .pareto_front()
            .into_iter()
            .filter_map(|i| data.series.iter().flat_map(|s| &s.points).find(|p| p.2 == i))
            .map(|p| (p.0, p.1))
            .collect();
        if !points.is_empty() {
            let mut steps = vec![points[0]];
            for w in points.windows(2) {
                steps.push((w[1].0, w[0].1));
                steps.push(w[1]);
            }
            let style = FRONT.stroke_width(2);
            chart.draw_series(DashedLineSeries::new(steps, 7, 5, style))?;
            entries.push(("Pareto front".to_owned(), Mark::Front));
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 9, FRONT.stroke_width(2))))?;
        }
    }

    for (k, s) in data.series.iter().enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        let line = colour.stroke_width(2);
        let shape = marker_shape(k);
        chart.draw_series(LineSeries::new(s.points.iter().map(|p| (p.0, p.1)), line))?;
        entries.push((s.name.clone(), Mark::Series(k)));
        chart.draw_series(
            s.points
                .iter()
                .map(|p| EmptyElement::at((p.0, p.1)) + Polygon::new(shape.clone(), colour.filled())),
        )?;
        // An arrow down from each point drawn above its true RMSE of 0.
        let zeros =
            s.points.iter().filter(|p| report.points.get(p.2).and_then(&axes.y_of).is_some_and(|y| y <= 0.0));
        chart.draw_series(zeros.map(|p| {
            EmptyElement::at((p.0, p.1))
                + PathElement::new(vec![(0, 8), (0, 17)], line)
                + Polygon::new(vec![(-4, 15), (4, 15), (0, 22)], colour.filled())
        }))?;
    }

    draw_legend(&legend, &entries)
}
