//! The plots of a [`Report`]: error against time (with the Pareto front), error against rays,
//! and what each effect's sampling costs. Each plot is written twice with one stem, as an
//! 800×500 PNG and as an SVG, both atomically. PNG text is rasterised by `ab_glyph` from the
//! bundled DejaVu Sans (`assets/DejaVuSans.ttf`), so no system font library is needed; SVG text
//! names the `sans-serif` family and is drawn by the viewer (layout is measured with the same
//! bundled font).
//!
//! The legend stands in a column right of the axes, so it never covers a curve or a bar.
//!
//! PNG text goes through `raster`, which fixes plotters' glyph placement; `scale` makes the log
//! ticks and number labels.
//!
//! Error axes are logarithmic, so an RMSE of 0 (a variant equal to the reference) cannot be
//! drawn where it is: such points are drawn at half the smallest positive RMSE, and a note under
//! the plot says so. Points with no positive time or rays are left out, also with a note.
//! Degenerate data (no points, one point, equal times, no costs) never panics; with nothing to
//! draw the plot says "no data".

mod raster;
mod scale;

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{register_font, FontStyle};

use self::raster::Raster;
pub(crate) use self::scale::format_number;
use self::scale::{log_ticks, padded_log_range};
use super::{Point, Report};
use crate::film::{write_atomically, OutputError};

/// File stem of the error-against-time plot.
pub const ERROR_VS_TIME: &str = "error_vs_time";
/// File stem of the error-against-rays plot.
pub const RAYS_VS_ERROR: &str = "rays_vs_error";
/// File stem of the effect-cost bar chart.
pub const EFFECT_COSTS: &str = "effect_costs";
/// Width of every plot in pixels.
pub const WIDTH: u32 = 800;
/// Height of every plot in pixels.
pub const HEIGHT: u32 = 500;

/// The family every text style names; the bundled font is registered under it.
const FONT: &str = "sans-serif";
/// DejaVu Sans, under the Bitstream Vera licence (`assets/DejaVuSans-LICENSE.txt`).
static DEJAVU_SANS: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// Colour-blind-safe series colours (Okabe & Ito), in axis order.
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];
const INK: RGBColor = RGBColor(40, 40, 40);
const MUTED: RGBColor = RGBColor(100, 100, 100);
const FRONT: RGBColor = RGBColor(120, 120, 120);
const GRID_BOLD: RGBColor = RGBColor(218, 218, 218);
const GRID_LIGHT: RGBColor = RGBColor(240, 240, 240);

/// Why a plot could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The bundled font did not parse (a build problem, not a data one).
    #[error("the bundled font assets/DejaVuSans.ttf cannot be loaded")]
    Font,
    /// Plotters failed while drawing.
    #[error("{path}: cannot draw plot: {message}")]
    Draw {
        /// The plot being drawn.
        path: PathBuf,
        /// Plotters' message.
        message: String,
    },
    /// The PNG encoder rejected the image.
    #[error("{path}: cannot encode PNG: {source}")]
    Encode {
        /// The PNG being written.
        path: PathBuf,
        /// The cause.
        source: image::ImageError,
    },
    /// The file could not be written (the error names it).
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// Plots median render time against RMSE, log-log: one coloured series per sweep axis, joined
/// in sweep order, and the Pareto front as a dashed grey staircase with its points circled.
/// Writes `dir/error_vs_time.png` and `.svg` and returns their paths.
///
/// # Examples
/// ```no_run
/// # fn demo(report: &penumbra::report::Report) -> Result<(), penumbra::report::plot::PlotError> {
/// let written = penumbra::report::plot::error_vs_time(report, std::path::Path::new("out"))?;
/// assert!(written[0].ends_with("error_vs_time.png"));
/// # Ok(()) }
/// ```
pub fn error_vs_time(report: &Report, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
    write_plot(&Plot::ErrorVsTime(report), dir, ERROR_VS_TIME)
}

/// Plots total rays against RMSE, log-log, one series per sweep axis. Writes
/// `dir/rays_vs_error.png` and `.svg` and returns their paths.
pub fn rays_vs_error(report: &Report, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
    write_plot(&Plot::RaysVsError(report), dir, RAYS_VS_ERROR)
}

/// Bar chart of each effect's median render time with the scene's setting and with one sample
/// (or off), with the ratio under each group. Writes `dir/effect_costs.png` and `.svg` and
/// returns their paths.
pub fn effect_costs(report: &Report, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
    write_plot(&Plot::EffectCosts(report), dir, EFFECT_COSTS)
}

/// The closed set of plots, dispatched by [`Plot::draw`].
enum Plot<'a> {
    ErrorVsTime(&'a Report),
    RaysVsError(&'a Report),
    EffectCosts(&'a Report),
}

/// What a drawing step returns on a backend.
type Drawn<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

impl Plot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        match *self {
            Plot::ErrorVsTime(r) => {
                let title = format!("Error vs time — {}", r.scene);
                draw_error_chart(root, r, &title, "median render time (s)", |p| p.seconds, true)
            }
            Plot::RaysVsError(r) => {
                let title = format!("Error vs rays — {}", r.scene);
                draw_error_chart(root, r, &title, "rays traced", |p| p.rays.total() as f64, false)
            }
            Plot::EffectCosts(r) => draw_costs(root, r),
        }
    }
}

/// Registers the bundled font under [`FONT`], once.
fn register_bundled_font() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| register_font(FONT, FontStyle::Normal, DEJAVU_SANS).is_ok());
    if ok {
        Ok(())
    } else {
        Err(PlotError::Font)
    }
}

/// Draws `plot` into a PNG and an SVG named `dir/stem.{png,svg}`, each written atomically.
fn write_plot(plot: &Plot, dir: &Path, stem: &str) -> Result<Vec<PathBuf>, PlotError> {
    register_bundled_font()?;
    let png_path = dir.join(format!("{stem}.png"));
    let svg_path = dir.join(format!("{stem}.svg"));
    let failed = |path: &Path, e: &dyn std::fmt::Display| PlotError::Draw {
        path: path.to_path_buf(),
        message: e.to_string(),
    };

    // PNG: rasterise into an RGB buffer, then encode it ourselves (plotters' encoder writes in
    // place, not atomically, and would pull in a second `image` version).
    let mut rgb = vec![0u8; WIDTH as usize * HEIGHT as usize * 3];
    {
        let bitmap = BitMapBackend::with_buffer(&mut rgb, (WIDTH, HEIGHT));
        let root = Raster::new(bitmap, DEJAVU_SANS).ok_or(PlotError::Font)?.into_drawing_area();
        plot.draw(&root).map_err(|e| failed(&png_path, &e))?;
        root.present().map_err(|e| failed(&png_path, &e))?;
    }
    let mut png = Vec::new();
    PngEncoder::new(&mut png)
        .write_image(&rgb, WIDTH, HEIGHT, ExtendedColorType::Rgb8)
        .map_err(|source| PlotError::Encode { path: png_path.clone(), source })?;
    write_atomically(&png_path, &png)?;

    // SVG: the same drawing into a string.
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
        plot.draw(&root).map_err(|e| failed(&svg_path, &e))?;
        root.present().map_err(|e| failed(&svg_path, &e))?;
    }
    write_atomically(&svg_path, svg.as_bytes())?;
    Ok(vec![png_path, svg_path])
}

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

/// Groups the drawable points by axis (and AA pattern); `None` when none is drawable.
fn error_data(report: &Report, x_of: impl Fn(&Point) -> f64) -> Option<ErrorData> {
    let drawable = |p: &Point| {
        let x = x_of(p);
        x.is_finite() && x > 0.0 && p.rmse.is_finite() && p.rmse >= 0.0
    };
    let smallest = report
        .points
        .iter()
        .filter(|p| drawable(p) && p.rmse > 0.0)
        .map(|p| p.rmse)
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
        let y = if p.rmse > 0.0 {
            p.rmse
        } else {
            zeros += 1;
            floor
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

/// Corners of marker shape `k` (circle, triangle, square, diamond, …) around (0, 0), in pixels.
fn marker_shape(k: usize) -> Vec<(i32, i32)> {
    match k % 4 {
        0 => (0..12)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / 12.0;
                ((4.5 * a.cos()).round() as i32, (4.5 * a.sin()).round() as i32)
            })
            .collect(),
        1 => vec![(0, -6), (5, 4), (-5, 4)],
        2 => vec![(-4, -4), (4, -4), (4, 4), (-4, 4)],
        _ => vec![(0, -6), (5, 0), (0, 6), (-5, 0)],
    }
}

/// A log-log chart of RMSE against `x_of`, one series per axis; `front` adds the Pareto front
/// of (seconds, RMSE), which only makes sense when x is the time.
fn draw_error_chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    report: &Report,
    title: &str,
    x_desc: &str,
    x_of: impl Fn(&Point) -> f64,
    front: bool,
) -> Drawn<DB> {
    let Some(data) = error_data(report, &x_of) else {
        return draw_no_data(root, title, "no variant has a positive value and a finite RMSE");
    };
    let mut notes = Vec::new();
    if let Some(at) = data.zero_at {
        notes.push(format!("↓ RMSE 0 (equal to the reference), drawn at {}", format_number(at)));
    }
    if data.left_out > 0 {
        notes.push(format!("{} variant(s) without a positive value left out", data.left_out));
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
        .x_desc(x_desc)
        .y_desc("RMSE against the reference")
        .x_label_formatter(&|v| format_number(*v))
        .y_label_formatter(&|v| format_number(*v))
        .label_style((FONT, 13).into_font().color(&INK))
        .axis_desc_style((FONT, 15).into_font().color(&INK))
        .bold_line_style(GRID_BOLD)
        .light_line_style(GRID_LIGHT)
        .axis_style(MUTED)
        .draw()?;

    // The Pareto front first, so that the series are drawn over it.
    let mut entries = Vec::new();
    if front {
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
        let zeros = s.points.iter().filter(|p| report.points.get(p.2).is_some_and(|q| q.rmse <= 0.0));
        chart.draw_series(zeros.map(|p| {
            EmptyElement::at((p.0, p.1))
                + PathElement::new(vec![(0, 8), (0, 17)], line)
                + Polygon::new(vec![(-4, 15), (4, 15), (0, 22)], colour.filled())
        }))?;
    }

    draw_legend(&legend, &entries)
}

/// The grouped bar chart of effect costs.
fn draw_costs<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, report: &Report) -> Drawn<DB> {
    let title = format!("Effect costs — {}", report.scene);
    let costs: Vec<_> = report
        .costs
        .iter()
        .filter(|c| c.seconds_on.is_finite() && c.seconds_off.is_finite())
        .map(|c| (c.effect.as_str(), c.seconds_on.max(0.0), c.seconds_off.max(0.0)))
        .collect();
    if costs.is_empty() {
        return draw_no_data(root, &title, "no effect costs were measured");
    }
    let max = costs.iter().map(|c| c.1.max(c.2)).fold(0.0, f64::max);
    let (unit, scale) = if max < 1.0 { ("ms", 1e3) } else { ("s", 1.0) };
    let top = if max > 0.0 { max * scale * 1.3 } else { 1.0 };
    let n = costs.len() as u32;
    let labels: Vec<String> = costs
        .iter()
        .map(
            |&(effect, on, off)| {
                if off > 0.0 {
                    format!("{effect} (×{:.1})", on / off)
                } else {
                    effect.to_string()
                }
            },
        )
        .collect();

    let area = with_note(root, "ratio in brackets: time with the scene's setting / time with one sample")?;
    let (area, legend) = with_legend(&area, &title)?;
    let mut chart = ChartBuilder::on(&area)
        .margin(14)
        .margin_top(4)
        .x_label_area_size(46)
        .y_label_area_size(62)
        .build_cartesian_2d((0..n - 1).into_segmented(), 0.0..top)?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(costs.len() + 1)
        .max_light_lines(1)
        .x_desc("effect")
        .y_desc(format!("median render time ({unit})"))
        .x_label_formatter(&|v| match v {
            SegmentValue::CenterOf(i) => labels.get(*i as usize).cloned().unwrap_or_default(),
            _ => String::new(),
        })
        .y_label_formatter(&|v| format_number(*v))
        .label_style((FONT, 13).into_font().color(&INK))
        .axis_desc_style((FONT, 15).into_font().color(&INK))
        .bold_line_style(GRID_BOLD)
        .light_line_style(GRID_LIGHT)
        .axis_style(MUTED)
        .draw()?;

    // Bars: the left half of each group's segment is the scene's setting, the right half one
    // sample, with a gap of `outer` pixels to the group's edges and `inner` between the bars.
    let segment = chart.plotting_area().dim_in_pixel().0 as f64 / f64::from(n);
    let outer = (segment * 0.14).round() as u32;
    let inner = (segment * 0.01).round().max(1.0) as u32;
    let bar_centre = ((segment / 2.0 - f64::from(outer) - f64::from(inner)) / 2.0) as i32;
    let value_style =
        TextStyle::from((FONT, 12).into_font()).color(&INK).pos(Pos::new(HPos::Center, VPos::Bottom));
    let [on_colour, off_colour] = [PALETTE[0], RGBColor(160, 190, 214)];
    let mut entries = Vec::new();
    for (half, colour, name) in [(0, on_colour, "scene setting"), (1, off_colour, "one sample / off")] {
        entries.push((name.to_owned(), Mark::Bar(colour)));
        chart.draw_series(costs.iter().enumerate().map(|(i, c)| {
            let i = i as u32;
            let v = if half == 0 { c.1 } else { c.2 } * scale;
            let (from, to, margin) = if half == 0 {
                (SegmentValue::Exact(i), SegmentValue::CenterOf(i), (outer, inner))
            } else {
                (SegmentValue::CenterOf(i), SegmentValue::Exact(i + 1), (inner, outer))
            };
            let mut bar = Rectangle::new([(from, v), (to, 0.0)], colour.filled());
            bar.set_margin(0, 0, margin.0, margin.1);
            bar
        }))?;
        chart.draw_series(costs.iter().enumerate().map(|(i, c)| {
            let v = if half == 0 { c.1 } else { c.2 } * scale;
            let dx = if half == 0 { -bar_centre - inner as i32 } else { bar_centre + inner as i32 };
            EmptyElement::at((SegmentValue::CenterOf(i as u32), v))
                + Text::new(format_number(v), (dx, -3), value_style.clone())
        }))?;
    }

    draw_legend(&legend, &entries)
}

/// Width in pixels of the legend column right of every plot's axes.
pub const LEGEND_WIDTH: u32 = 160;

/// What a legend entry shows beside its name.
enum Mark {
    /// The Pareto front: a dashed grey line through a circle.
    Front,
    /// Series `k`: its colour's line and marker shape.
    Series(usize),
    /// A bar of this colour.
    Bar(RGBColor),
}

/// Writes `title` over the whole width of `area` and splits what is under it into the
/// chart's area and a [`LEGEND_WIDTH`] column on the right for the legend, so that the legend
/// never covers data.
#[allow(clippy::type_complexity)]
fn with_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<(DrawingArea<DB, Shift>, DrawingArea<DB, Shift>), DrawingAreaErrorKind<DB::ErrorType>> {
    let below = area.titled(title, (FONT, 22).into_font().color(&INK))?;
    let width = below.dim_in_pixel().0;
    Ok(below.split_horizontally(width.saturating_sub(LEGEND_WIDTH)))
}

/// Draws the legend `entries` (name and mark) top-down in `column`.
fn draw_legend<DB: DrawingBackend>(column: &DrawingArea<DB, Shift>, entries: &[(String, Mark)]) -> Drawn<DB> {
    let style = TextStyle::from((FONT, 14).into_font()).color(&INK).pos(Pos::new(HPos::Left, VPos::Center));
    for (row, (name, mark)) in entries.iter().enumerate() {
        let (x, y) = (16, 14 + 24 * row as i32);
        match mark {
            Mark::Front => {
                let line = FRONT.stroke_width(2);
                column.draw(
                    &(EmptyElement::at((x, y))
                        + PathElement::new(vec![(-12, 0), (-4, 0)], line)
                        + PathElement::new(vec![(4, 0), (12, 0)], line)
                        + Circle::new((0, 0), 6, line)),
                )?;
            }
            Mark::Series(k) => {
                let colour = PALETTE[k % PALETTE.len()];
                column.draw(
                    &(EmptyElement::at((x, y))
                        + PathElement::new(vec![(-12, 0), (12, 0)], colour.stroke_width(2))
                        + Polygon::new(marker_shape(*k), colour.filled())),
                )?;
            }
            Mark::Bar(colour) => {
                column.draw(&Rectangle::new([(x - 7, y - 6), (x + 7, y + 6)], colour.filled()))?
            }
        }
        column.draw(&Text::new(name.clone(), (x + 20, y), style.clone()))?;
    }
    Ok(())
}

/// Writes `note` in small grey type under the plot and returns the area above it (all of
/// `root` when the note is empty).
fn with_note<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    note: &str,
) -> Result<DrawingArea<DB, Shift>, DrawingAreaErrorKind<DB::ErrorType>> {
    if note.is_empty() {
        return Ok(root.clone());
    }
    let (upper, lower) = root.split_vertically(HEIGHT - 22);
    let style = TextStyle::from((FONT, 12).into_font()).color(&MUTED).pos(Pos::new(HPos::Right, VPos::Top));
    lower.draw(&Text::new(note.to_string(), (WIDTH as i32 - 28, 2), style))?;
    Ok(upper)
}

/// A plot with only its title, "no data" and why.
fn draw_no_data<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, title: &str, why: &str) -> Drawn<DB> {
    let area = root.titled(title, (FONT, 22).into_font().color(&INK))?;
    let (w, h) = area.dim_in_pixel();
    let (cx, cy) = (w as i32 / 2, h as i32 / 2);
    area.draw(&Rectangle::new([(40, 30), (w as i32 - 40, h as i32 - 40)], GRID_BOLD.stroke_width(1)))?;
    let centred = |size: u32| {
        TextStyle::from((FONT, size).into_font()).color(&MUTED).pos(Pos::new(HPos::Center, VPos::Center))
    };
    area.draw(&Text::new("no data", (cx, cy - 14), centred(28)))?;
    area.draw(&Text::new(why.to_string(), (cx, cy + 18), centred(14)))?;
    Ok(())
}

#[cfg(test)]
pub(crate) mod tests;
