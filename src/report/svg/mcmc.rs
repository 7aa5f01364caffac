//! Sample figures: trace plots, marginal histograms and pair plots.

use super::common::{
    axis_range, draw_err, series_colour, thin_stride, tick_label, x_tick_count, Axis, NamedValues, DESC_SIZE, FONT,
    TICK_SIZE, TITLE_SIZE,
};
use crate::report::error::{ReportError, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

/// Default cap on drawn points per chain / scatter (deterministic thinning).
pub const DEFAULT_MAX_POINTS: usize = 4000;

/// Spec of [`trace_plot`]: one coloured line per chain, value against draw
/// index (the index is the draw's position in the full chain, also after
/// thinning), optional dashed reference value (e.g. the true parameter).
#[derive(Debug, Clone, PartialEq)]
pub struct TracePlot {
    pub title: String,
    /// Value label with unit, e.g. `"e0a (nm)"`.
    pub y_label: String,
    pub chains: Vec<NamedValues>,
    pub reference: Option<f64>,
    /// At most this many points are drawn per chain (every k-th draw); 0 = all.
    pub max_points: usize,
    pub size: (u32, u32),
}

impl Default for TracePlot {
    fn default() -> Self {
        Self {
            title: String::new(),
            y_label: String::new(),
            chains: Vec::new(),
            reference: None,
            max_points: DEFAULT_MAX_POINTS,
            size: (800, 400),
        }
    }
}

/// Renders a [`TracePlot`] as SVG text.
pub fn trace_plot(spec: &TracePlot) -> Result<String> {
    let n = spec.chains.iter().map(|c| c.values.len()).max().unwrap_or(0);
    if n == 0 {
        return Err(ReportError::invalid("trace plot", "no draws"));
    }
    let xr = (0.0, (n - 1).max(1) as f64);
    let yr = axis_range(
        &Axis::linear(""),
        spec.chains.iter().flat_map(|c| c.values.iter().copied()).chain(spec.reference),
        "trace plot values",
    )?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, spec.size).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&spec.title, (FONT, TITLE_SIZE))
            .margin(12)
            .x_label_area_size(55)
            .y_label_area_size(80)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
            .map_err(draw_err)?;
        chart
            .configure_mesh()
            .light_line_style(WHITE.mix(0.0))
            .x_desc("draw")
            .y_desc(&spec.y_label)
            .axis_desc_style((FONT, DESC_SIZE))
            .label_style((FONT, TICK_SIZE))
            .x_label_formatter(&tick_label)
            .y_label_formatter(&tick_label)
            .draw()
            .map_err(draw_err)?;
        for (k, c) in spec.chains.iter().enumerate() {
            let colour = series_colour(k);
            let stride = thin_stride(c.values.len(), spec.max_points);
            let pts =
                c.values.iter().enumerate().step_by(stride).filter(|(_, v)| v.is_finite()).map(|(i, &v)| (i as f64, v));
            chart
                .draw_series(LineSeries::new(pts, colour.stroke_width(1)))
                .map_err(draw_err)?
                .label(&c.name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
        }
        if let Some(r) = spec.reference.filter(|r| r.is_finite()) {
            chart
                .draw_series(DashedLineSeries::new(vec![(xr.0, r), (xr.1, r)], 6, 4, BLACK.stroke_width(2)))
                .map_err(draw_err)?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FONT, TICK_SIZE))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(draw_err)?;
        root.present().map_err(draw_err)?;
    }
    Ok(svg)
}

/// Spec of [`histogram`]: the marginal density of each group (e.g. Cases
/// 1A, 1B, 1C) as a density-normalized histogram on common bins (filled
/// lightly, outlined in the group colour), optional dashed reference value.
#[derive(Debug, Clone, PartialEq)]
pub struct HistogramPlot {
    pub title: String,
    /// Value label with unit, e.g. `"Ω (rad/s)"`.
    pub x_label: String,
    pub groups: Vec<NamedValues>,
    /// Number of equal-width bins over the pooled range (or `x_range`).
    pub bins: usize,
    pub reference: Option<f64>,
    /// Named vertical lines (e.g. "ours", "paper"), each in its own colour and
    /// listed in the legend.
    pub marks: Vec<(String, f64)>,
    pub x_range: Option<(f64, f64)>,
    pub size: (u32, u32),
}

impl Default for HistogramPlot {
    fn default() -> Self {
        Self {
            title: String::new(),
            x_label: String::new(),
            groups: Vec::new(),
            bins: 40,
            reference: None,
            marks: Vec::new(),
            x_range: None,
            size: (800, 450),
        }
    }
}

/// Density histogram of `values` on `bins` equal bins over `[lo, hi]`:
/// count / (n_in_range · width). Values outside the range are not counted
/// (and not in n). Returns the bin heights.
pub(crate) fn density(values: &[f64], lo: f64, hi: f64, bins: usize) -> Vec<f64> {
    let width = (hi - lo) / bins as f64;
    let mut counts = vec![0usize; bins];
    let mut n = 0usize;
    for &v in values.iter().filter(|v| v.is_finite() && **v >= lo && **v <= hi) {
        let k = (((v - lo) / width) as usize).min(bins - 1);
        counts[k] += 1;
        n += 1;
    }
    counts.iter().map(|&c| if n == 0 { 0.0 } else { c as f64 / (n as f64 * width) }).collect()
}

/// The pooled finite range of several lists, or an explicit one.
fn pooled_range<'a>(
    lists: impl Iterator<Item = &'a [f64]>,
    explicit: Option<(f64, f64)>,
    what: &str,
) -> Result<(f64, f64)> {
    let axis = Axis { range: explicit, ..Axis::linear("") };
    let (lo, hi) = axis_range(&axis, lists.flat_map(|l| l.iter().copied()), what)?;
    // axis_range adds a 5 % margin; the histogram spans the data itself.
    Ok(if explicit.is_some() { (lo, hi) } else { (lo + (hi - lo) / 22.0, hi - (hi - lo) / 22.0) })
}

/// Draws step-outlined density histograms on `area` (shared by
/// [`histogram`] and the diagonal of [`pair_plot`]).
#[allow(clippy::too_many_arguments)] // private helper; a spec struct would only rename these
fn draw_histograms<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    groups: &[&[f64]],
    names: Option<&[String]>,
    (lo, hi): (f64, f64),
    bins: usize,
    reference: Option<f64>,
    marks: &[(String, f64)],
    x_label: &str,
    caption: Option<&str>,
    font: (u32, u32),
) -> Result<()> {
    let bins = bins.max(1);
    let heights: Vec<Vec<f64>> = groups.iter().map(|g| density(g, lo, hi, bins)).collect();
    let top = heights.iter().flatten().copied().fold(0.0, f64::max);
    let top = if top > 0.0 { 1.08 * top } else { 1.0 };
    let mut builder = ChartBuilder::on(area);
    if let Some(c) = caption {
        builder.caption(c, (FONT, TITLE_SIZE));
    }
    let plot_width = area.dim_in_pixel().0.saturating_sub(font.0 * 3 + 20 + 16);
    let mut chart = builder
        .margin(8)
        .x_label_area_size(font.0 * 2 + 10)
        .y_label_area_size(font.0 * 3 + 20)
        .build_cartesian_2d(lo..hi, 0.0..top)
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(x_label)
        .y_desc("density")
        .axis_desc_style((FONT, font.0))
        .label_style((FONT, font.1))
        .x_labels(x_tick_count((lo, hi), plot_width, font.1))
        .y_labels(4)
        .x_label_formatter(&tick_label)
        .y_label_formatter(&tick_label)
        .draw()
        .map_err(draw_err)?;
    let width = (hi - lo) / bins as f64;
    for (k, h) in heights.iter().enumerate() {
        let colour = series_colour(k);
        let mut step = vec![(lo, 0.0)];
        for (b, &v) in h.iter().enumerate() {
            step.push((lo + b as f64 * width, v));
            step.push((lo + (b + 1) as f64 * width, v));
        }
        step.push((hi, 0.0));
        chart.draw_series(std::iter::once(Polygon::new(step.clone(), colour.mix(0.15).filled()))).map_err(draw_err)?;
        let outline = chart.draw_series(LineSeries::new(step, colour.stroke_width(2))).map_err(draw_err)?;
        if let Some(names) = names {
            outline
                .label(&names[k])
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
        }
    }
    if let Some(r) = reference.filter(|r| r.is_finite()) {
        chart
            .draw_series(DashedLineSeries::new(vec![(r, 0.0), (r, top)], 6, 4, BLACK.stroke_width(2)))
            .map_err(draw_err)?;
    }
    for (k, (name, x)) in marks.iter().enumerate().filter(|(_, (_, x))| x.is_finite()) {
        let colour = series_colour(groups.len() + k);
        chart
            .draw_series(std::iter::once(PathElement::new(vec![(*x, 0.0), (*x, top)], colour.stroke_width(3))))
            .map_err(draw_err)?
            .label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3)));
    }
    if names.is_some() || !marks.is_empty() {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font((FONT, font.1))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(draw_err)?;
    }
    Ok(())
}

/// Renders a [`HistogramPlot`] as SVG text.
pub fn histogram(spec: &HistogramPlot) -> Result<String> {
    if spec.bins == 0 {
        return Err(ReportError::invalid("histogram bins", "must be >= 1"));
    }
    let lists: Vec<&[f64]> = spec.groups.iter().map(|g| g.values.as_slice()).collect();
    let marks: Vec<f64> = spec.marks.iter().map(|m| m.1).collect();
    let range = pooled_range(
        lists
            .iter()
            .copied()
            .chain(spec.reference.as_slice().iter().map(std::slice::from_ref))
            .chain(std::iter::once(marks.as_slice())),
        spec.x_range,
        "histogram values",
    )?;
    let names: Vec<String> = spec.groups.iter().map(|g| g.name.clone()).collect();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, spec.size).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        draw_histograms(
            &root,
            &lists,
            Some(&names),
            range,
            spec.bins,
            spec.reference,
            &spec.marks,
            &spec.x_label,
            Some(&spec.title),
            (DESC_SIZE, TICK_SIZE),
        )?;
        root.present().map_err(draw_err)?;
    }
    Ok(svg)
}

/// Spec of [`pair_plot`]: `columns[p]` holds the draws of parameter `p`
/// (all columns of equal length). The d×d grid shows the histogram of
/// parameter i on the diagonal and the scatter of (parameter j, parameter i)
/// below it (j < i); the upper triangle is blank. Reference values, when
/// given, are dashed lines on the diagonal and black crosses in the scatters.
#[derive(Debug, Clone, PartialEq)]
pub struct PairPlot {
    pub title: String,
    /// Parameter labels with units, one per column.
    pub names: Vec<String>,
    pub columns: Vec<Vec<f64>>,
    pub reference: Option<Vec<f64>>,
    pub bins: usize,
    /// At most this many scatter points (every k-th draw); 0 = all.
    pub max_points: usize,
    /// Side of one grid cell in pixels.
    pub cell_size: u32,
}

impl Default for PairPlot {
    fn default() -> Self {
        Self {
            title: String::new(),
            names: Vec::new(),
            columns: Vec::new(),
            reference: None,
            bins: 30,
            max_points: DEFAULT_MAX_POINTS,
            cell_size: 240,
        }
    }
}

/// One below-diagonal cell of a pair plot: column `x` against column `y`.
struct Cell<'a> {
    x: usize,
    y: usize,
    ranges: ((f64, f64), (f64, f64)),
    stride: usize,
    font: (u32, u32),
    x_label: &'a str,
}

/// Scatter of the thinned draws of two columns, the reference as a cross; the
/// x tick count fits the cell ([`x_tick_count`]) so long labels (Ω) do not overlap.
fn scatter_cell<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, spec: &PairPlot, c: &Cell) -> Result<()> {
    let ((xr, yr), font) = (c.ranges, c.font);
    let plot_width = area.dim_in_pixel().0.saturating_sub(font.0 * 3 + 20 + 16);
    let mut chart = ChartBuilder::on(area)
        .margin(8)
        .x_label_area_size(font.0 * 2 + 10)
        .y_label_area_size(font.0 * 3 + 20)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(draw_err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(c.x_label)
        .y_desc(if c.x == 0 { spec.names[c.y].as_str() } else { "" })
        .axis_desc_style((FONT, font.0))
        .label_style((FONT, font.1))
        .x_labels(x_tick_count(xr, plot_width, font.1))
        .y_labels(5)
        .x_label_formatter(&tick_label)
        .y_label_formatter(&tick_label)
        .draw()
        .map_err(draw_err)?;
    let (cx, cy) = (&spec.columns[c.x], &spec.columns[c.y]);
    let pts = (0..cx.len()).step_by(c.stride).map(|k| (cx[k], cy[k])).filter(|(x, y)| x.is_finite() && y.is_finite());
    chart.draw_series(pts.map(|p| Circle::new(p, 1, series_colour(0).mix(0.35).filled()))).map_err(draw_err)?;
    if let Some(r) = &spec.reference {
        chart.draw_series(std::iter::once(Cross::new((r[c.x], r[c.y]), 6, BLACK.stroke_width(2)))).map_err(draw_err)?;
    }
    Ok(())
}

/// Renders a [`PairPlot`] as SVG text.
pub fn pair_plot(spec: &PairPlot) -> Result<String> {
    let d = spec.columns.len();
    if d == 0 || spec.names.len() != d {
        return Err(ReportError::invalid(
            "pair plot",
            format!("{} names for {d} columns (need >= 1, equal)", spec.names.len()),
        ));
    }
    let n = spec.columns[0].len();
    for (p, c) in spec.columns.iter().enumerate() {
        if c.len() != n {
            return Err(ReportError::invalid(
                format!("pair plot column `{}`", spec.names[p]),
                format!("{} draws, first column has {n}", c.len()),
            ));
        }
    }
    if let Some(r) = &spec.reference {
        if r.len() != d {
            return Err(ReportError::invalid("pair plot reference", format!("{} values for {d} columns", r.len())));
        }
    }
    let bins = spec.bins.max(1);
    let ranges: Vec<(f64, f64)> = (0..d)
        .map(|p| {
            let r = spec.reference.as_ref().map(|r| r[p]);
            pooled_range(
                std::iter::once(spec.columns[p].as_slice()).chain(r.as_slice().iter().map(std::slice::from_ref)),
                None,
                &format!("pair plot column `{}`", spec.names[p]),
            )
        })
        .collect::<Result<_>>()?;
    let stride = thin_stride(n, spec.max_points);
    let side = spec.cell_size * d as u32;
    let font = ((spec.cell_size / 14).max(10), (spec.cell_size / 17).max(9));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (side, side + 40)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        let root = root.titled(&spec.title, (FONT, TITLE_SIZE)).map_err(draw_err)?;
        let cells = root.split_evenly((d, d));
        for i in 0..d {
            for j in 0..d {
                let area = &cells[i * d + j];
                let x_label = if i == d - 1 { spec.names[j].as_str() } else { "" };
                if i == j {
                    let r = spec.reference.as_ref().map(|r| r[i]);
                    draw_histograms(area, &[&spec.columns[i]], None, ranges[i], bins, r, &[], x_label, None, font)?;
                } else if j < i {
                    let cell = Cell { x: j, y: i, ranges: (ranges[j], ranges[i]), stride, font, x_label };
                    scatter_cell(area, spec, &cell)?;
                }
            }
        }
        root.present().map_err(draw_err)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::density;

    #[test]
    fn density_integrates_to_one_over_the_range() {
        let values: Vec<f64> = (0..1000).map(|i| ((i * 37) % 101) as f64 / 10.0).collect();
        let (lo, hi, bins) = (0.0, 10.0, 17);
        let h = density(&values, lo, hi, bins);
        let integral: f64 = h.iter().sum::<f64>() * (hi - lo) / bins as f64;
        // 17 additions of O(1) terms: round-off far below 1e-12.
        assert!((integral - 1.0).abs() < 1e-12, "{integral}");
        // Values outside the range are not counted: a narrower range still integrates to 1.
        let h = density(&values, 2.0, 3.0, 4);
        assert!((h.iter().sum::<f64>() * 0.25 - 1.0).abs() < 1e-12);
    }
}
