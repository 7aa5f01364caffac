//! Deterministic SVG figures (plotters, SVG backend), rendered to `String`.
//!
//! Each function takes a plain-data spec struct and returns the SVG text, so
//! the caller decides where to write it (see
//! [`write_file_atomically`](crate::report::render::write_file_atomically)).
//! Text is laid out with plotters' built-in font-size estimate (no system
//! fonts are read), so the same spec always gives byte-identical output.
//!
//! Non-finite values are skipped (and non-positive ones on a log axis); a
//! figure whose data has nothing left to draw is an
//! [`InvalidData`](crate::report::ReportError::InvalidData) error.
//!
//! | function | figure |
//! |---|---|
//! | [`line_plot`] | named (x, y) series, log axes, band, grey realizations, reference lines |
//! | [`heatmap()`] | scalar field z(x, y) on a grid, colour bar |
//! | [`trace_plot`] | MCMC chains: draw index vs value, reference line |
//! | [`histogram`] | marginal densities of sample groups, reference line |
//! | [`pair_plot`] | d×d grid: histograms on the diagonal, scatter below |
//! | [`bar_chart`] | one value per category (e.g. class probabilities) |
//! | [`residual_plot`] | standardized residual per mode, several groups, ±band |
//! | [`scatter_plot`] | point groups with markers (stabilisation diagram) |

mod categorical;
mod common;
mod heatmap;
mod line;
mod mcmc;
mod scatter;

pub use categorical::{bar_chart, residual_plot, BarChart, ResidualPlot};
pub use common::{Axis, NamedValues, RefLine, Scale, Series};
pub use heatmap::{heatmap, viridis, Heatmap};
pub use line::{line_plot, Band, LinePlot};
pub use mcmc::{histogram, pair_plot, trace_plot, HistogramPlot, PairPlot, TracePlot};
pub use scatter::{scatter_plot, ScatterPlot};
