//! Shared plain-data types and helpers of the SVG figures.

use crate::report::error::{ReportError, Result};
use crate::report::table::fmt_sig;
use plotters::style::RGBColor;

/// Axis scale.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Scale {
    #[default]
    Linear,
    /// Base-10 logarithmic; only positive values are drawn.
    Log,
}

/// An axis: label (with its unit, e.g. `"frequency (GHz)"`), scale and an
/// optional fixed range (otherwise taken from the data with a 5 % margin).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Axis {
    pub label: String,
    pub scale: Scale,
    pub range: Option<(f64, f64)>,
}

impl Axis {
    /// A linear axis with automatic range.
    pub fn linear(label: impl Into<String>) -> Self {
        Self { label: label.into(), scale: Scale::Linear, range: None }
    }
    /// A log-10 axis with automatic range.
    pub fn log(label: impl Into<String>) -> Self {
        Self { label: label.into(), scale: Scale::Log, range: None }
    }
    /// The same axis with a fixed range.
    pub fn with_range(mut self, lo: f64, hi: f64) -> Self {
        self.range = Some((lo, hi));
        self
    }
}

/// A named (x, y) series; `x` and `y` must have equal length.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Series {
    pub name: String,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
}

impl Series {
    pub fn new(name: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self { name: name.into(), x, y }
    }
}

/// A named list of values (a chain, a sample, residuals of one group, ...).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NamedValues {
    pub name: String,
    pub values: Vec<f64>,
}

impl NamedValues {
    pub fn new(name: impl Into<String>, values: Vec<f64>) -> Self {
        Self { name: name.into(), values }
    }
}

/// A dashed reference line across the whole plot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RefLine {
    /// y = value
    Horizontal(f64),
    /// x = value
    Vertical(f64),
}

/// The colour of the `i`-th series (Tableau 10, cycled).
pub(crate) fn series_colour(i: usize) -> RGBColor {
    const TABLEAU10: [(u8, u8, u8); 10] = [
        (31, 119, 180),
        (255, 127, 14),
        (44, 160, 44),
        (214, 39, 40),
        (148, 103, 189),
        (140, 86, 75),
        (227, 119, 194),
        (127, 127, 127),
        (188, 189, 34),
        (23, 190, 207),
    ];
    let (r, g, b) = TABLEAU10[i % TABLEAU10.len()];
    RGBColor(r, g, b)
}

pub(crate) const FONT: &str = "sans-serif";

/// Maps a plotters drawing error to [`ReportError::Drawing`].
pub(crate) fn draw_err<E: std::fmt::Debug>(e: E) -> ReportError {
    ReportError::Drawing(format!("{e:?}"))
}

/// Whether `v` can be drawn on an axis of this scale.
pub(crate) fn drawable(v: f64, scale: Scale) -> bool {
    v.is_finite() && (scale == Scale::Linear || v > 0.0)
}

/// The range of an axis: the fixed one if given (checked), else the span of
/// the drawable `values` widened by 5 % (linear) or 5 % of a decade-log span
/// (log). A degenerate span is widened to ±1 (linear) or a factor 10 (log).
pub(crate) fn axis_range(axis: &Axis, values: impl Iterator<Item = f64>, what: &str) -> Result<(f64, f64)> {
    if let Some((lo, hi)) = axis.range {
        let ok = drawable(lo, axis.scale) && drawable(hi, axis.scale) && lo < hi;
        return if ok {
            Ok((lo, hi))
        } else {
            Err(ReportError::invalid(
                what,
                format!("axis range ({lo}, {hi}) must be finite, increasing (and > 0 on a log axis)"),
            ))
        };
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.filter(|&v| drawable(v, axis.scale)) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return Err(ReportError::invalid(what, "no drawable (finite, and positive on a log axis) values"));
    }
    Ok(match axis.scale {
        Scale::Linear => {
            if hi - lo <= f64::EPSILON * lo.abs().max(hi.abs()) {
                (lo - 1.0, hi + 1.0)
            } else {
                let m = 0.05 * (hi - lo);
                (lo - m, hi + m)
            }
        }
        Scale::Log => {
            let (a, b) = (lo.log10(), hi.log10());
            if b - a < 1e-12 {
                (lo / 10.0, hi * 10.0)
            } else {
                let m = 0.05 * (b - a);
                (10f64.powf(a - m), 10f64.powf(b + m))
            }
        }
    })
}

/// Tick label: three significant digits, trailing zeros of the fraction
/// dropped (`0.00100` -> `0.001`, `10.0` -> `10`, `1.00e13` -> `1e13`).
pub(crate) fn tick_label(v: &f64) -> String {
    let s = fmt_sig(*v, 3);
    let (mantissa, exponent) = match s.split_once('e') {
        Some((m, e)) => (m.to_string(), format!("e{e}")),
        None => (s, String::new()),
    };
    let mantissa = if mantissa.contains('.') {
        mantissa.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        mantissa
    };
    format!("{mantissa}{exponent}")
}

/// Most tick labels a log-10 axis gets from [`log_ticks`].
pub(crate) const MAX_LOG_TICKS: usize = 8;

/// Tick positions of a log-10 axis over `[lo, hi]` (0 < lo < hi), chosen here
/// rather than by plotters: its log coordinate drops every key point within
/// `f64::EPSILON` of zero in absolute value (it takes them for its zero
/// point, `LogCoord::is_inf` in plotters 0.3.7), so an axis of PSD values
/// (1e-35 m²·s/rad) got no tick and no number at all.
///
/// Whole decades inside the range, thinned to every s-th decade (s the
/// smallest stride leaving at most [`MAX_LOG_TICKS`], aligned to multiples of
/// s so that the labels read 1e-40, 1e-36, …); a range holding fewer than two
/// decades gets the 1-2-5 multiples, then 1…9; a range narrower than
/// that gets three geometrically spaced points rounded to three significant
/// digits. Every position is parsed from its decimal text (`"5e-35"`), so the
/// tick sits at exactly the number its label prints.
pub(crate) fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let inside = |v: &f64| *v >= lo && *v <= hi;
    let (a, b) = (lo.log10().floor() as i32 - 1, hi.log10().ceil() as i32 + 1);
    let number = |m: u32, k: i32| format!("{m}e{k}").parse::<f64>().unwrap_or(f64::NAN);
    let decades: Vec<(i32, f64)> = (a..=b).map(|k| (k, number(1, k))).filter(|(_, v)| inside(v)).collect();
    if decades.len() >= 2 {
        let stride = decades.len().div_ceil(MAX_LOG_TICKS) as i32;
        let aligned: Vec<f64> = decades.iter().filter(|(k, _)| k.rem_euclid(stride) == 0).map(|&(_, v)| v).collect();
        if aligned.len() >= 2 {
            return aligned;
        }
        return decades.iter().step_by(stride as usize).map(|&(_, v)| v).collect();
    }
    for multiples in [&[1, 2, 5][..], &[1, 2, 3, 4, 5, 6, 7, 8, 9]] {
        let ticks: Vec<f64> =
            (a..=b).flat_map(|k| multiples.iter().map(move |&m| number(m, k))).filter(inside).collect();
        if ticks.len() >= 2 {
            return ticks;
        }
    }
    let ratio = hi / lo;
    [0.1, 0.5, 0.9].iter().filter_map(|f| fmt_sig(lo * ratio.powf(*f), 3).parse::<f64>().ok()).filter(inside).collect()
}

/// How many x-axis tick labels fit side by side in `width_px` without
/// overlapping (2..=5). Plotters' SVG text is about 0.6·size px per character
/// (its built-in estimate, no font is read); a label is sized by the longest
/// of the range's end labels and followed by a one-character gap. Ω axes of
/// pair plots ("4.08e11" in a 200 px cell) need 2–3 ticks, not 5.
pub(crate) fn x_tick_count(range: (f64, f64), width_px: u32, font_size: u32) -> usize {
    let chars =
        [range.0, range.1, 0.5 * (range.0 + range.1)].iter().map(|v| tick_label(v).chars().count()).max().unwrap_or(1);
    let per_label = 0.6 * font_size as f64 * (chars + 1) as f64;
    ((width_px as f64 / per_label).floor() as usize).clamp(2, 5)
}

/// Font sizes (plotters' size units; its SVG text is about 0.65 of this in px).
pub(crate) const TITLE_SIZE: u32 = 26;
pub(crate) const DESC_SIZE: u32 = 20;
pub(crate) const TICK_SIZE: u32 = 17;

/// Every `stride`-th index so that at most `max_points` remain (all if
/// `max_points` is 0). Deterministic thinning for long chains.
pub(crate) fn thin_stride(len: usize, max_points: usize) -> usize {
    if max_points == 0 || len <= max_points {
        1
    } else {
        len.div_ceil(max_points)
    }
}

/// Checks that two paired lists have equal length.
pub(crate) fn same_len(what: &str, a: usize, b: usize) -> Result<()> {
    if a == b {
        Ok(())
    } else {
        Err(ReportError::invalid(what, format!("paired lists have different lengths ({a} vs {b})")))
    }
}

/// Builds a 2-D cartesian chart whose axes are linear or log as given, and
/// runs `$body` with the chart bound to `$chart`. A macro (not a generic
/// function) because plotters' linear and log coordinates are different
/// types; the body is compiled once per combination.
macro_rules! with_chart {
    ($builder:expr, $xs:expr, $xr:expr, $ys:expr, $yr:expr, |$chart:ident| $body:block) => {{
        use plotters::coord::combinators::{BindKeyPoints, IntoLogRange};
        use $crate::report::svg::common::{draw_err, log_ticks, Scale};
        let (x0, x1) = $xr;
        let (y0, y1) = $yr;
        match ($xs, $ys) {
            (Scale::Linear, Scale::Linear) => {
                let mut $chart = $builder.build_cartesian_2d(x0..x1, y0..y1).map_err(draw_err)?;
                $body
            }
            (Scale::Log, Scale::Linear) => {
                let x = (x0..x1).log_scale().with_key_points(log_ticks(x0, x1));
                let mut $chart = $builder.build_cartesian_2d(x, y0..y1).map_err(draw_err)?;
                $body
            }
            (Scale::Linear, Scale::Log) => {
                let y = (y0..y1).log_scale().with_key_points(log_ticks(y0, y1));
                let mut $chart = $builder.build_cartesian_2d(x0..x1, y).map_err(draw_err)?;
                $body
            }
            (Scale::Log, Scale::Log) => {
                let x = (x0..x1).log_scale().with_key_points(log_ticks(x0, x1));
                let y = (y0..y1).log_scale().with_key_points(log_ticks(y0, y1));
                let mut $chart = $builder.build_cartesian_2d(x, y).map_err(draw_err)?;
                $body
            }
        }
    }};
}
pub(crate) use with_chart;

/// The mesh builder of an (x, y) chart with the house axis style: axis
/// descriptions from the two [`Axis`] labels, the house fonts and the tick
/// formatter. The caller adds grid options and calls `draw()`. A macro for the
/// same reason as [`with_chart`]: the chart's coordinate type varies.
macro_rules! axes_mesh {
    ($chart:ident, $x_axis:expr, $y_axis:expr) => {
        $chart
            .configure_mesh()
            .x_desc(&$x_axis.label)
            .y_desc(&$y_axis.label)
            .axis_desc_style(($crate::report::svg::common::FONT, $crate::report::svg::common::DESC_SIZE))
            .label_style(($crate::report::svg::common::FONT, $crate::report::svg::common::TICK_SIZE))
            .x_label_formatter(&$crate::report::svg::common::tick_label)
            .y_label_formatter(&$crate::report::svg::common::tick_label)
    };
}
pub(crate) use axes_mesh;

#[cfg(test)]
mod tick_tests {
    use super::*;

    #[test]
    fn log_ticks_label_tiny_values_and_stay_few() {
        // A thermal PSD in m²·s/rad: every decade inside, as exact decimals.
        assert_eq!(log_ticks(3e-39, 2e-34), vec![1e-38, 1e-37, 1e-36, 1e-35, 1e-34]);
        // Twenty decades: every third, aligned, at most MAX_LOG_TICKS.
        let wide = log_ticks(1e-20, 1e0);
        assert!(wide.len() >= 2 && wide.len() <= MAX_LOG_TICKS, "{wide:?}");
        assert_eq!(wide[0], 1e-18);
        // Less than two decades: 1-2-5; a narrow range: points inside it.
        assert_eq!(log_ticks(1.5e11, 6e11), vec![2e11, 5e11]);
        let narrow = log_ticks(4.0e11, 4.2e11);
        assert!(narrow.len() >= 2 && narrow.iter().all(|v| (4.0e11..=4.2e11).contains(v)), "{narrow:?}");
    }

    #[test]
    fn x_ticks_of_a_narrow_omega_axis_fit_their_cell() {
        // A 180 px pair-plot cell with 12-unit tick text: "4.08e11" labels.
        let n = x_tick_count((3.9e11, 4.25e11), 180, 12);
        let width = 0.6 * 12.0 * 8.0; // 7 characters + gap
        assert!(n as f64 * width <= 180.0, "{n} labels of {width} px");
        assert!(n >= 2);
        // A wide axis with short labels keeps five.
        assert_eq!(x_tick_count((0.0, 1.0), 700, 17), 5);
    }
}
