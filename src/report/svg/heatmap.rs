//! Heatmaps: a scalar field z(x, y) on a rectangular grid with a colour bar
//! (e.g. normalized ω_r and ζ_r over an e0a × Ω grid, paper Figs 1–3).

use super::common::{
    axes_mesh, draw_err, drawable, tick_label, with_chart, Axis, Scale, DESC_SIZE, FONT, TICK_SIZE, TITLE_SIZE,
};
use crate::report::error::{ReportError, Result};
use plotters::prelude::*;

/// Spec of [`heatmap`]. `z[j][i]` is the value at `(x[i], y[j])` (one row
/// per y value). Grid values must be strictly increasing; on a log axis the
/// cell edges are geometric midpoints. Non-finite z cells are drawn light grey.
#[derive(Debug, Clone, PartialEq)]
pub struct Heatmap {
    pub title: String,
    /// `range` is ignored: the axis spans the outer cell edges.
    pub x_axis: Axis,
    /// `range` is ignored: the axis spans the outer cell edges.
    pub y_axis: Axis,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<Vec<f64>>,
    /// Colour-bar label with unit, e.g. `"ω1/ω1' (-)"`.
    pub z_label: String,
    /// Colour scale limits; default: min and max of the finite z.
    pub z_range: Option<(f64, f64)>,
    pub size: (u32, u32),
}

impl Default for Heatmap {
    fn default() -> Self {
        Self {
            title: String::new(),
            x_axis: Axis::default(),
            y_axis: Axis::default(),
            x: Vec::new(),
            y: Vec::new(),
            z: Vec::new(),
            z_label: String::new(),
            z_range: None,
            size: (800, 560),
        }
    }
}

/// An approximation of matplotlib's perceptually uniform "viridis" colour
/// map: piecewise-linear through 9 of its samples, `t` clamped to [0, 1].
/// (Written here because plotters' `colormaps` feature is not enabled.)
pub fn viridis(t: f64) -> RGBColor {
    const ANCHORS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let pos = t * (ANCHORS.len() - 1) as f64;
    let k = (pos.floor() as usize).min(ANCHORS.len() - 2);
    let f = pos - k as f64;
    let lerp = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (ANCHORS[k], ANCHORS[k + 1]);
    RGBColor(lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2))
}

/// Cell edges around strictly increasing grid values (arithmetic or
/// geometric midpoints; the end cells are symmetric about their value).
fn cell_edges(v: &[f64], scale: Scale, what: &str) -> Result<Vec<f64>> {
    if v.is_empty() || v.iter().any(|&a| !drawable(a, scale)) || v.windows(2).any(|w| w[1] <= w[0]) {
        return Err(ReportError::invalid(
            what,
            "grid values must be non-empty, finite, strictly increasing (and > 0 on a log axis)",
        ));
    }
    type Map = fn(f64) -> f64;
    let (fwd, inv): (Map, Map) = match scale {
        Scale::Linear => (|a| a, |a| a),
        Scale::Log => (f64::log10, |a| 10f64.powf(a)),
    };
    let t: Vec<f64> = v.iter().map(|&a| fwd(a)).collect();
    let half = if t.len() > 1 { 0.5 * (t[1] - t[0]) } else { 0.5 };
    let half_end = if t.len() > 1 { 0.5 * (t[t.len() - 1] - t[t.len() - 2]) } else { 0.5 };
    let mut edges = vec![inv(t[0] - half)];
    edges.extend(t.windows(2).map(|w| inv(0.5 * (w[0] + w[1]))));
    edges.push(inv(t[t.len() - 1] + half_end));
    Ok(edges)
}

/// Renders a [`Heatmap`] as SVG text: the field on the left, a vertical
/// colour bar with its label on the right.
pub fn heatmap(spec: &Heatmap) -> Result<String> {
    let xe = cell_edges(&spec.x, spec.x_axis.scale, "heatmap x grid")?;
    let ye = cell_edges(&spec.y, spec.y_axis.scale, "heatmap y grid")?;
    if spec.z.len() != spec.y.len() || spec.z.iter().any(|row| row.len() != spec.x.len()) {
        return Err(ReportError::invalid(
            "heatmap z",
            format!("must have {} rows of {} values", spec.y.len(), spec.x.len()),
        ));
    }
    let (z0, z1) = match spec.z_range {
        Some((a, b)) if a.is_finite() && b.is_finite() && a < b => (a, b),
        Some((a, b)) => {
            return Err(ReportError::invalid("heatmap z_range", format!("({a}, {b}) must be finite and increasing")))
        }
        None => {
            let finite = spec.z.iter().flatten().copied().filter(|v| v.is_finite());
            let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)));
            if lo > hi {
                return Err(ReportError::invalid("heatmap z", "no finite values"));
            }
            if hi > lo {
                (lo, hi)
            } else {
                (lo - 0.5, hi + 0.5)
            }
        }
    };
    let colour = |v: f64| {
        if v.is_finite() {
            viridis((v - z0) / (z1 - z0))
        } else {
            RGBColor(220, 220, 220)
        }
    };
    let (w, h) = spec.size;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(draw_err)?;
        let root = root.titled(&spec.title, (FONT, TITLE_SIZE)).map_err(draw_err)?;
        let (main, bar) = root.split_horizontally(w.saturating_sub(130));
        let mut builder = ChartBuilder::on(&main);
        builder.margin(10).x_label_area_size(55).y_label_area_size(80);
        let xr = (xe[0], xe[xe.len() - 1]);
        let yr = (ye[0], ye[ye.len() - 1]);
        with_chart!(builder, spec.x_axis.scale, xr, spec.y_axis.scale, yr, |chart| {
            axes_mesh!(chart, spec.x_axis, spec.y_axis).disable_mesh().draw().map_err(draw_err)?;
            let (xe, ye, colour) = (&xe, &ye, &colour);
            let cells = spec.z.iter().enumerate().flat_map(|(j, row)| {
                row.iter()
                    .enumerate()
                    .map(move |(i, &v)| Rectangle::new([(xe[i], ye[j]), (xe[i + 1], ye[j + 1])], colour(v).filled()))
            });
            chart.draw_series(cells).map_err(draw_err)?;
        });
        let mut bar_chart = ChartBuilder::on(&bar)
            .margin_top(20)
            .margin_bottom(65)
            .margin_right(10)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..1.0, z0..z1)
            .map_err(draw_err)?;
        bar_chart
            .configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_desc(&spec.z_label)
            .axis_desc_style((FONT, DESC_SIZE))
            .label_style((FONT, TICK_SIZE))
            .y_label_formatter(&tick_label)
            .draw()
            .map_err(draw_err)?;
        const STEPS: usize = 128;
        let dz = (z1 - z0) / STEPS as f64;
        bar_chart
            .draw_series((0..STEPS).map(|k| {
                let a = z0 + k as f64 * dz;
                Rectangle::new([(0.0, a), (1.0, a + dz)], colour(a + 0.5 * dz).filled())
            }))
            .map_err(draw_err)?;
        root.present().map_err(draw_err)?;
    }
    Ok(svg)
}
