//! Figures over named categories: bar charts and per-mode residual plots.

use super::common::{draw_err, series_colour, tick_label, NamedValues, DESC_SIZE, FONT, TICK_SIZE, TITLE_SIZE};
use crate::report::error::{ReportError, Result};
use crate::report::table::fmt_sig;
use plotters::coord::ranged1d::SegmentedCoord;
use plotters::prelude::*;

/// A category axis with segments `0..n` (plotters' segmented coordinate
/// over the *inclusive* integer range 0..=n-1).
fn categories(n: usize) -> SegmentedCoord<plotters::coord::types::RangedCoordi32> {
    (0..n as i32 - 1).into_segmented()
}

type CategoryChart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<SegmentedCoord<plotters::coord::types::RangedCoordi32>, plotters::coord::types::RangedCoordf64>,
>;

/// The frame both figures share: caption, a category x axis labelled by
/// `labels` (one per segment), a numeric y axis over `y`, mesh drawn.
fn category_chart<'a, 'b>(
    root: &'a DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    title: &str,
    y_label: &str,
    labels: &[String],
    y: std::ops::Range<f64>,
) -> Result<CategoryChart<'a, 'b>> {
    let n = labels.len();
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, TITLE_SIZE))
        .margin(12)
        .x_label_area_size(55)
        .y_label_area_size(80)
        .build_cartesian_2d(categories(n), y)
        .map_err(draw_err)?;
    let label = |v: &SegmentValue<i32>| match v {
        SegmentValue::CenterOf(i) => labels.get(*i as usize).cloned().unwrap_or_default(),
        _ => String::new(),
    };
    chart
        .configure_mesh()
        .disable_x_mesh()
        .light_line_style(WHITE.mix(0.0))
        .y_desc(y_label)
        .axis_desc_style((FONT, DESC_SIZE))
        .label_style((FONT, TICK_SIZE))
        .x_labels(n)
        .x_label_formatter(&label)
        .y_label_formatter(&tick_label)
        .draw()
        .map_err(draw_err)?;
    Ok(chart)
}

/// Spec of [`bar_chart`]: one bar per category, its value printed above it
/// (e.g. posterior probabilities of candidate model classes).
#[derive(Debug, Clone, PartialEq)]
pub struct BarChart {
    pub title: String,
    /// Value label with unit, e.g. `"P(M | data) (-)"`.
    pub y_label: String,
    pub categories: Vec<String>,
    pub values: Vec<f64>,
    /// Default: from min(0, values) to 1.1·max(0, values).
    pub y_range: Option<(f64, f64)>,
    pub size: (u32, u32),
}

impl Default for BarChart {
    fn default() -> Self {
        Self {
            title: String::new(),
            y_label: String::new(),
            categories: Vec::new(),
            values: Vec::new(),
            y_range: None,
            size: (700, 450),
        }
    }
}

/// Renders a [`BarChart`] as SVG text.
pub fn bar_chart(spec: &BarChart) -> Result<String> {
    let n = spec.categories.len();
    if n == 0 || spec.values.len() != n {
        return Err(ReportError::invalid(
            "bar chart",
            format!("{} values for {n} categories (need >= 1, equal)", spec.values.len()),
        ));
    }
    if let Some(v) = spec.values.iter().find(|v| !v.is_finite()) {
        return Err(ReportError::invalid("bar chart values", format!("{v} is not finite")));
    }
    let (y0, y1) = match spec.y_range {
        Some((a, b)) if a.is_finite() && b.is_finite() && a < b => (a, b),
        Some((a, b)) => {
            return Err(ReportError::invalid("bar chart y_range", format!("({a}, {b}) must be finite and increasing")))
        }
        None => {
            let lo = spec.values.iter().copied().fold(0.0, f64::min);
            let hi = spec.values.iter().copied().fold(0.0, f64::max);
            let (lo, hi) = (1.1 * lo, 1.1 * hi);
            if hi > lo {
                (lo, hi)
            } else {
                (0.0, 1.0)
            }
        }
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, spec.size).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        let mut chart = category_chart(&root, &spec.title, &spec.y_label, &spec.categories, y0..y1)?;
        chart
            .draw_series(spec.values.iter().enumerate().map(|(i, &v)| {
                let mut bar = Rectangle::new(
                    [(SegmentValue::Exact(i as i32), 0.0), (SegmentValue::Exact(i as i32 + 1), v)],
                    series_colour(0).filled(),
                );
                bar.set_margin(0, 0, 12, 12);
                bar
            }))
            .map_err(draw_err)?;
        chart
            .draw_series(spec.values.iter().enumerate().map(|(i, &v)| {
                Text::new(
                    fmt_sig(v, 3),
                    (SegmentValue::CenterOf(i as i32), v),
                    (FONT, TICK_SIZE).into_font().color(&BLACK).pos(plotters::style::text_anchor::Pos::new(
                        plotters::style::text_anchor::HPos::Center,
                        plotters::style::text_anchor::VPos::Bottom,
                    )),
                )
            }))
            .map_err(draw_err)?;
        root.present().map_err(draw_err)?;
    }
    Ok(svg)
}

/// Spec of [`residual_plot`]: standardized residuals (e.g. (y_E − y)/sd per
/// mode ω1…ζ3) of several groups (e.g. "before" and "after" calibration),
/// one marker shape and colour per group, with a shaded ±`band` zone bounded
/// by dashed lines and a solid zero line.
#[derive(Debug, Clone, PartialEq)]
pub struct ResidualPlot {
    pub title: String,
    /// e.g. `"standardized residual (-)"`.
    pub y_label: String,
    /// One label per residual (per mode), e.g. `ω1`, …, `ζ3`.
    pub labels: Vec<String>,
    /// Each group has one value per label.
    pub groups: Vec<NamedValues>,
    /// Half-width of the shaded zone (2 for ±2 sd).
    pub band: f64,
    pub size: (u32, u32),
}

impl Default for ResidualPlot {
    fn default() -> Self {
        Self {
            title: String::new(),
            y_label: "standardized residual (-)".into(),
            labels: Vec::new(),
            groups: Vec::new(),
            band: 2.0,
            size: (750, 450),
        }
    }
}

/// Renders a [`ResidualPlot`] as SVG text.
pub fn residual_plot(spec: &ResidualPlot) -> Result<String> {
    let n = spec.labels.len();
    if n == 0 {
        return Err(ReportError::invalid("residual plot", "no labels"));
    }
    for g in &spec.groups {
        if g.values.len() != n {
            return Err(ReportError::invalid(
                format!("residual plot group `{}`", g.name),
                format!("{} values for {n} labels", g.values.len()),
            ));
        }
    }
    if !(spec.band.is_finite() && spec.band >= 0.0) {
        return Err(ReportError::invalid("residual plot band", format!("{} must be finite and >= 0", spec.band)));
    }
    let extent = spec
        .groups
        .iter()
        .flat_map(|g| g.values.iter())
        .filter(|v| v.is_finite())
        .fold(spec.band, |m, v| m.max(v.abs()));
    let extent = if extent > 0.0 { 1.15 * extent } else { 1.0 };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, spec.size).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        let mut chart = category_chart(&root, &spec.title, &spec.y_label, &spec.labels, -extent..extent)?;
        let (left, right) = (SegmentValue::Exact(0), SegmentValue::Exact(n as i32));
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(left.clone(), -spec.band), (right.clone(), spec.band)],
                RGBColor(160, 160, 160).mix(0.2).filled(),
            )))
            .map_err(draw_err)?;
        for b in [-spec.band, spec.band] {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(left.clone(), b), (right.clone(), b)],
                    6,
                    4,
                    BLACK.stroke_width(1),
                ))
                .map_err(draw_err)?;
        }
        chart.draw_series(LineSeries::new(vec![(left, 0.0), (right, 0.0)], BLACK.stroke_width(1))).map_err(draw_err)?;
        for (k, g) in spec.groups.iter().enumerate() {
            let colour = series_colour(k);
            let pts: Vec<(SegmentValue<i32>, f64)> = g
                .values
                .iter()
                .enumerate()
                .filter(|(_, v)| v.is_finite())
                .map(|(i, &v)| (SegmentValue::CenterOf(i as i32), v))
                .collect();
            // Marker shape cycles circle / triangle / cross so that groups
            // stay distinguishable where they overlap and in grey print.
            let series = match k % 3 {
                0 => chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 6, colour.filled()).into_dyn())),
                1 => chart.draw_series(pts.into_iter().map(|p| TriangleMarker::new(p, 7, colour.filled()).into_dyn())),
                _ => chart.draw_series(pts.into_iter().map(|p| Cross::new(p, 6, colour.stroke_width(2)).into_dyn())),
            }
            .map_err(draw_err)?;
            series.label(&g.name).legend(move |(x, y)| match k % 3 {
                0 => Circle::new((x + 10, y), 5, colour.filled()).into_dyn(),
                1 => TriangleMarker::new((x + 10, y), 6, colour.filled()).into_dyn(),
                _ => Cross::new((x + 10, y), 5, colour.stroke_width(2)).into_dyn(),
            });
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
        root.present().map_err(draw_err)?;
    }
    Ok(svg)
}
