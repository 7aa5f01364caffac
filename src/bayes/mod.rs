//! Statistics only, beam-agnostic: priors, likelihoods, DRAM, TMCMC, MAP,
//! summaries and convergence diagnostics. It sees a log-density over a named
//! vector ([`Posterior`]) and nothing else.
//!
//! # Files
//! `Posterior` (log prior + log likelihood over a named vector), `transform` (`Reparameterized`:
//! sampling in ln x with the Jacobian), `prior`, `likelihood` (Gaussian, β² of eq. 41), `dram`
//! (n-stage DRAM, eq. 27–33; `DramSettings`, the one sampler settings type, validated by
//! `validate(dim)` when the measured file is read, again at `calibrate_posterior`, and by
//! `run_chain`/`run_chains` themselves, which also check `c0_sd` and the starts), `chains` (rayon,
//! one keyed stream per chain), `map` (argmin Nelder–Mead, multi-start), `tmcmc` (evidence),
//! `laplace`, `importance` (evidence by defensive-mixture importance sampling), `evidence` (the
//! combined evidence estimator: TMCMC, MAP searches, Laplace, the importance check, posterior draws
//! resampled when TMCMC's population missed the MAP, replicates of a run that missed the peak and
//! the rule for them; `EvidenceSettings`), `diagnostics` (rank R̂, bulk/tail ESS, IAT), `summary`,
//! `rng` (the seed scheme), `control` (`Control`: a caller's cancellation flag, polled by DRAM at
//! every step and TMCMC at every stage and sample, and its `Progress` sink; `Controlled`: a
//! posterior whose likelihood reads the flag at every evaluation, for the MAP searches, Laplace
//! Hessians and importance batches; changes no number); error type `BayesError`

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
