//! Presentation utilities: plain data in, files out.
//!
//! This module knows nothing about beams or statistics; callers hand it
//! numbers and labels. It has three jobs, one submodule each:
//!
//! * [`svg`]: deterministic SVG figures (line plots with log axes, bands and
//!   reference lines; heatmaps with a colour bar; MCMC trace plots, marginal
//!   histograms, pair plots; bar charts; residual plots). Every function
//!   renders to a `String` so the caller can write the file atomically.
//! * [`table`]: a plain table rendered as Markdown or CSV, and number formatting.
//! * [`render`]: tera templates from a directory, and atomic writes of files
//!   and of whole output directories.
//! * [`inference_data`]: named arrays in named groups as a NetCDF-4 file (the
//!   layout ArviZ's `from_netcdf` reads).
//!
//! All fallible functions return [`ReportError`].
//!
//! # Files
//! `svg` (plotters figures), `table` (Markdown/CSV), `render` (tera, atomic output directories),
//! `inference_data` (NetCDF-4 for ArviZ); error type `ReportError`

pub mod error;
pub mod inference_data;
pub mod render;
pub mod svg;
pub mod table;

pub use error::{ReportError, Result};
