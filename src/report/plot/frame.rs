//! What surrounds every chart: the title, the legend column right of the axes (so that the
//! legend never covers data), the note under the plot and the "no data" plate.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{marker_shape, Drawn, FONT, FRONT, GRID_BOLD, HEIGHT, INK, MUTED, PALETTE, WIDTH};

/// Width in pixels of the legend column right of every plot's axes.
pub const LEGEND_WIDTH: u32 = 160;

/// What a legend entry shows beside its name.
pub(super) enum Mark {
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
pub(super) fn with_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<(DrawingArea<DB, Shift>, DrawingArea<DB, Shift>), DrawingAreaErrorKind<DB::ErrorType>> {
    let below = area.titled(title, (FONT, 22).into_font().color(&INK))?;
    let width = below.dim_in_pixel().0;
    Ok(below.split_horizontally(width.saturating_sub(LEGEND_WIDTH)))
}

/// Draws the legend `entries` (name and mark) top-down in `column`.
pub(super) fn draw_legend<DB: DrawingBackend>(
    column: &DrawingArea<DB, Shift>,
    entries: &[(String, Mark)],
) -> Drawn<DB> {
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
pub(super) fn with_note<DB: DrawingBackend>(
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
pub(super) fn draw_no_data<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    why: &str,
) -> Drawn<DB> {
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
