//! The glue between physics and statistics: the measured-data file, named
//! parameters mapped onto a beam, and the beam posterior that the samplers see.
//!
//! # Files
//! `measured` (the measured-data file: modes, held-out modes, mode scans, and its observables:
//! `Observable`, a mode's ω or ζ or a scan point's relative amplitude), `parameters` (names → beam
//! fields), `posterior` (`BeamPosterior`: THE beam posterior; relative amplitudes through
//! `beam::frf_points`), `run` (`calibrate`: overdispersed starts → chains → health checks → summary
//! → MAP; `SamplingError`), `output` (chains.csv, summary.json, InferenceData, SVGs), `identified`
//! (identified modes → numbered measured-data file), `numbering` (the physical numbering over the
//! base model's whole prior: the elastic modes interpolated over (e0a, shear), the N = 1
//! relaxation and the section in closed form, the numberings' grid search and local refinement);
//! the `sampler:` section is `bayes::dram::DramSettings`

pub mod identified;
pub mod measured;
pub mod numbering;
pub mod output;
pub mod parameters;
pub mod posterior;
pub mod run;

pub use crate::bayes::dram::DramSettings;
pub use measured::{observables, MeasuredData, ModeObservation, ModeScan, Observable, Quantity, ScanPoint};
pub use parameters::{Parameter, ParameterSet, Target};
pub use posterior::BeamPosterior;
pub use run::{calibrate, calibrate_posterior, CalibrateOptions, CalibrationResult, SamplingError};
