//! Statistics only, beam-agnostic: priors, likelihoods, DRAM, TMCMC, MAP,
//! summaries and convergence diagnostics. It sees a log-density over a named
//! vector ([`Posterior`]) and nothing else.

pub mod posterior;
pub mod prior;

pub use posterior::Posterior;
