//! The glue between physics and statistics: the measured-data file, named
//! parameters mapped onto a beam, and the beam posterior that the samplers see.

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
