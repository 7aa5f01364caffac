//! Statistics only, beam-agnostic: priors, likelihoods, DRAM, TMCMC, MAP,
//! summaries and convergence diagnostics. It sees a log-density over a named
//! vector ([`Posterior`]) and nothing else.

pub mod chains;
pub mod control;
pub mod diagnostics;
pub mod dram;
pub mod error;
pub mod evidence;
pub mod importance;
pub mod laplace;
pub mod likelihood;
pub mod map;
pub mod posterior;
pub mod prior;
pub mod rng;
pub mod summary;
pub mod tmcmc;
pub mod transform;

pub use control::{Cancelled, Control, Controlled, Progress};
pub use error::BayesError;
pub use posterior::Posterior;
