//! The effect-cost bar chart: each effect's median render time with the scene's setting and
//! with one sample (or off), side by side, with their ratio under each group.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::frame::{draw_legend, draw_no_data, with_legend, with_note, Mark};
use super::scale::format_number;
use super::{Drawn, FONT, GRID_BOLD, GRID_LIGHT, INK, MUTED, PALETTE};
use crate::report::Report;

/// The grouped bar chart of effect costs.
pub(super) fn draw_costs<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, report: &Report) -> Drawn<DB> {
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
