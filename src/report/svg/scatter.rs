//! Scatter plots: named point groups, one colour and marker each (e.g. a
//! stabilisation diagram: pole frequency vs model order, grouped by class),
//! with dashed reference lines.

use super::common::{
    axes_mesh, axis_range, drawable, same_len, series_colour, with_chart, Axis, RefLine, Series, FONT, TICK_SIZE,
    TITLE_SIZE,
};
use crate::report::error::Result;
use plotters::prelude::*;

/// Spec of [`scatter_plot`]: group `i` is drawn in colour `i` with marker
/// `i mod 3` (filled circle, cross, hollow circle).
#[derive(Debug, Clone, PartialEq)]
pub struct ScatterPlot {
    pub title: String,
    pub x_axis: Axis,
    pub y_axis: Axis,
    pub groups: Vec<Series>,
    pub ref_lines: Vec<RefLine>,
    pub size: (u32, u32),
}

impl Default for ScatterPlot {
    fn default() -> Self {
        Self {
            title: String::new(),
            x_axis: Axis::default(),
            y_axis: Axis::default(),
            groups: Vec::new(),
            ref_lines: Vec::new(),
            size: (800, 500),
        }
    }
}

/// Renders a [`ScatterPlot`] as SVG text.
pub fn scatter_plot(spec: &ScatterPlot) -> Result<String> {
    for g in &spec.groups {
        same_len(&format!("group `{}`", g.name), g.x.len(), g.y.len())?;
    }
    let ref_x = spec.ref_lines.iter().filter_map(|r| if let RefLine::Vertical(v) = r { Some(*v) } else { None });
    let ref_y = spec.ref_lines.iter().filter_map(|r| if let RefLine::Horizontal(v) = r { Some(*v) } else { None });
    let xr = axis_range(&spec.x_axis, spec.groups.iter().flat_map(|g| g.x.iter().copied()).chain(ref_x), "scatter x")?;
    let yr = axis_range(&spec.y_axis, spec.groups.iter().flat_map(|g| g.y.iter().copied()).chain(ref_y), "scatter y")?;
    let (xs, ys) = (spec.x_axis.scale, spec.y_axis.scale);
    let keep = |x: f64, y: f64| drawable(x, xs) && drawable(y, ys);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, spec.size).into_drawing_area();
        root.fill(&WHITE).map_err(super::common::draw_err)?;
        let mut builder = ChartBuilder::on(&root);
        builder.caption(&spec.title, (FONT, TITLE_SIZE)).margin(12).x_label_area_size(55).y_label_area_size(80);
        with_chart!(builder, xs, xr, ys, yr, |chart| {
            axes_mesh!(chart, spec.x_axis, spec.y_axis).light_line_style(WHITE.mix(0.0)).draw().map_err(draw_err)?;
            for r in &spec.ref_lines {
                let line = match *r {
                    RefLine::Horizontal(v) => vec![(xr.0, v), (xr.1, v)],
                    RefLine::Vertical(v) => vec![(v, yr.0), (v, yr.1)],
                };
                if line.iter().all(|&(x, y)| keep(x, y)) {
                    chart.draw_series(DashedLineSeries::new(line, 6, 4, BLACK.stroke_width(1))).map_err(draw_err)?;
                }
            }
            for (i, g) in spec.groups.iter().enumerate() {
                let colour = series_colour(i);
                let pts: Vec<(f64, f64)> =
                    g.x.iter().zip(&g.y).map(|(&x, &y)| (x, y)).filter(|&(x, y)| keep(x, y)).collect();
                let marker = i % 3;
                let drawn = chart
                    .draw_series(pts.into_iter().map(move |p| -> DynElement<'static, SVGBackend, (f64, f64)> {
                        match marker {
                            0 => Circle::new(p, 3, colour.filled()).into_dyn(),
                            1 => Cross::new(p, 3, colour.stroke_width(1)).into_dyn(),
                            _ => Circle::new(p, 3, colour.stroke_width(1)).into_dyn(),
                        }
                    }))
                    .map_err(draw_err)?;
                drawn.label(&g.name).legend(move |(x, y)| Circle::new((x + 10, y), 3, colour.filled()));
            }
            if !spec.groups.is_empty() {
                chart
                    .configure_series_labels()
                    .position(SeriesLabelPosition::UpperRight)
                    .label_font((FONT, TICK_SIZE))
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .draw()
                    .map_err(draw_err)?;
            }
        });
        root.present().map_err(super::common::draw_err)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_are_drawn_and_mismatched_lengths_refused() {
        let spec = ScatterPlot {
            groups: vec![
                Series::new("stable", vec![1.0, 2.0], vec![4.0, 6.0]),
                Series::new("new", vec![3.0], vec![8.0]),
            ],
            ..ScatterPlot::default()
        };
        let svg = scatter_plot(&spec).unwrap();
        assert!(svg.contains("stable") && svg.contains("new"));
        let bad = ScatterPlot { groups: vec![Series::new("x", vec![1.0], vec![])], ..ScatterPlot::default() };
        assert!(scatter_plot(&bad).is_err());
    }
}
