//! The plots of a [`Report`]: error against time (with the Pareto front), error against rays,
//! what each effect's sampling costs, and the noise-driven mode's estimated error against its
//! true error. Each plot is written twice with one stem, as an
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
//!
//! `error_chart` draws the three log-log error plots, `costs` the bar chart and `frame` what
//! surrounds every chart: the title, the legend column, the note under the axes and the
//! "no data" plate.

mod costs;
mod error_chart;
mod frame;
mod raster;
mod scale;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use image::codecs::png::PngEncoder;
use image::{ExtendedColorType, ImageEncoder};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

use self::costs::draw_costs;
use self::error_chart::{draw_error_chart, rmse_against, Axes};
pub use self::frame::LEGEND_WIDTH;
use self::raster::Raster;
pub(crate) use self::scale::format_number;
use super::{Point, Report};
use crate::film::{write_atomically, OutputError};

/// File stem of the error-against-time plot.
pub const ERROR_VS_TIME: &str = "error_vs_time";
/// File stem of the error-against-rays plot.
pub const RAYS_VS_ERROR: &str = "rays_vs_error";
/// File stem of the effect-cost bar chart.
pub const EFFECT_COSTS: &str = "effect_costs";
/// File stem of the noise-driven mode's estimated-against-true error plot.
pub const ESTIMATE_VS_ERROR: &str = "estimate_vs_error";
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

/// Plots the noise-driven mode's estimated RMSE (what its rounds decided by) against its true
/// RMSE, log-log, with the line where they are equal; variants without an estimate are left
/// out. Writes `dir/estimate_vs_error.png` and `.svg` and returns their paths.
pub fn estimate_vs_error(report: &Report, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
    write_plot(&Plot::EstimateVsError(report), dir, ESTIMATE_VS_ERROR)
}

/// The closed set of plots, dispatched by [`Plot::draw`].
enum Plot<'a> {
    ErrorVsTime(&'a Report),
    RaysVsError(&'a Report),
    EffectCosts(&'a Report),
    EstimateVsError(&'a Report),
}

/// What a drawing step returns on a backend.
type Drawn<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

impl Plot<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        root.fill(&WHITE)?;
        match *self {
            Plot::ErrorVsTime(r) => {
                let title = format!("Error vs time — {}", r.scene);
                draw_error_chart(
                    root,
                    r,
                    &title,
                    &rmse_against("median render time (s)", |p| p.seconds, true),
                )
            }
            Plot::RaysVsError(r) => {
                let title = format!("Error vs rays — {}", r.scene);
                let axes = rmse_against("rays traced", |p| p.rays.total() as f64, false);
                draw_error_chart(root, r, &title, &axes)
            }
            Plot::EffectCosts(r) => draw_costs(root, r),
            Plot::EstimateVsError(r) => {
                let title = format!("Estimated vs true error — {}", r.scene);
                let axes = Axes {
                    x_desc: "RMSE against the reference",
                    y_desc: "estimated RMSE (noise-driven rounds)",
                    x_of: |p: &Point| p.rmse,
                    y_of: |p: &Point| p.estimated_rmse,
                    zero: "an estimate of 0",
                    left_out: "variant(s) without an estimate or with RMSE 0",
                    front: false,
                    diagonal: true,
                };
                draw_error_chart(root, r, &title, &axes)
            }
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

#[cfg(test)]
pub(crate) mod tests;
