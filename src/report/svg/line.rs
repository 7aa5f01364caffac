//! Line plots: named series, optional log axes, a shaded band (e.g. a 99 %
//! envelope, drawn with dashed edges), thin grey realizations and dashed
//! reference lines.

use super::common::{
    axes_mesh, axis_range, drawable, same_len, series_colour, with_chart, Axis, RefLine, Series, FONT, TICK_SIZE,
    TITLE_SIZE,
};
use crate::report::error::Result;
use plotters::prelude::*;

/// A shaded band between `lower` and `upper`, both sampled at `x`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Band {
    /// Legend entry of the band.
    pub name: String,
    pub x: Vec<f64>,
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
}

/// Spec of [`line_plot`]. Drawing order: band, realizations, series,
/// reference lines; the legend lists the band and the named series.
#[derive(Debug, Clone, PartialEq)]
pub struct LinePlot {
    pub title: String,
    pub x_axis: Axis,
    pub y_axis: Axis,
    /// Coloured, 2 px, in the legend.
    pub series: Vec<Series>,
    /// Thin light-grey lines, not in the legend (names are ignored).
    pub realizations: Vec<Series>,
    pub band: Option<Band>,
    pub ref_lines: Vec<RefLine>,
    /// Width and height in pixels.
    pub size: (u32, u32),
}

impl Default for LinePlot {
    fn default() -> Self {
        Self {
            title: String::new(),
            x_axis: Axis::default(),
            y_axis: Axis::default(),
            series: Vec::new(),
            realizations: Vec::new(),
            band: None,
            ref_lines: Vec::new(),
            size: (800, 500),
        }
    }
}

/// Renders a [`LinePlot`] as SVG text.
pub fn line_plot(spec: &LinePlot) -> Result<String> {
    for s in spec.series.iter().chain(&spec.realizations) {
        same_len(&format!("series `{}`", s.name), s.x.len(), s.y.len())?;
    }
    if let Some(b) = &spec.band {
        same_len(&format!("band `{}` lower", b.name), b.x.len(), b.lower.len())?;
        same_len(&format!("band `{}` upper", b.name), b.x.len(), b.upper.len())?;
    }
    let all_series = || spec.series.iter().chain(&spec.realizations);
    let band_x = spec.band.iter().flat_map(|b| b.x.iter().copied());
    let band_y = spec.band.iter().flat_map(|b| b.lower.iter().chain(&b.upper).copied());
    let ref_x = spec.ref_lines.iter().filter_map(|r| match r {
        RefLine::Vertical(v) => Some(*v),
        RefLine::Horizontal(_) => None,
    });
    let ref_y = spec.ref_lines.iter().filter_map(|r| match r {
        RefLine::Horizontal(v) => Some(*v),
        RefLine::Vertical(_) => None,
    });
    let xr = axis_range(
        &spec.x_axis,
        all_series().flat_map(|s| s.x.iter().copied()).chain(band_x).chain(ref_x),
        "line plot x axis",
    )?;
    let yr = axis_range(
        &spec.y_axis,
        all_series().flat_map(|s| s.y.iter().copied()).chain(band_y).chain(ref_y),
        "line plot y axis",
    )?;
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
            if let Some(b) = &spec.band {
                let upper: Vec<(f64, f64)> =
                    b.x.iter().zip(&b.upper).map(|(&x, &y)| (x, y)).filter(|&(x, y)| keep(x, y)).collect();
                let lower: Vec<(f64, f64)> =
                    b.x.iter().zip(&b.lower).map(|(&x, &y)| (x, y)).filter(|&(x, y)| keep(x, y)).collect();
                let polygon: Vec<(f64, f64)> = upper.iter().chain(lower.iter().rev()).copied().collect();
                let fill = RGBColor(160, 160, 160).mix(0.3);
                chart
                    .draw_series(std::iter::once(Polygon::new(polygon, fill.filled())))
                    .map_err(draw_err)?
                    .label(&b.name)
                    .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 20, y + 5)], fill.filled()));
                for edge in [upper, lower] {
                    chart.draw_series(DashedLineSeries::new(edge, 6, 4, BLACK.stroke_width(1))).map_err(draw_err)?;
                }
            }
            for r in &spec.realizations {
                let pts: Vec<(f64, f64)> =
                    r.x.iter().zip(&r.y).map(|(&x, &y)| (x, y)).filter(|&(x, y)| keep(x, y)).collect();
                chart.draw_series(LineSeries::new(pts, RGBColor(190, 190, 190).stroke_width(1))).map_err(draw_err)?;
            }
            for (i, s) in spec.series.iter().enumerate() {
                let colour = series_colour(i);
                let pts: Vec<(f64, f64)> =
                    s.x.iter().zip(&s.y).map(|(&x, &y)| (x, y)).filter(|&(x, y)| keep(x, y)).collect();
                chart
                    .draw_series(LineSeries::new(pts, colour.stroke_width(2)))
                    .map_err(draw_err)?
                    .label(&s.name)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
            }
            for r in &spec.ref_lines {
                let line = match *r {
                    RefLine::Horizontal(v) => vec![(xr.0, v), (xr.1, v)],
                    RefLine::Vertical(v) => vec![(v, yr.0), (v, yr.1)],
                };
                if line.iter().all(|&(x, y)| keep(x, y)) {
                    chart.draw_series(DashedLineSeries::new(line, 6, 4, BLACK.stroke_width(1))).map_err(draw_err)?;
                }
            }
            if !spec.series.is_empty() || spec.band.is_some() {
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
