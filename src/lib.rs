//! nanobeam: nonlocal viscoelastic Euler–Bernoulli nanobeams — forward model,
//! Bayesian calibration (DRAM, TMCMC), model diagnosis and the reproduction of
//! the source paper. See ARCHITECTURE.md for the map and the data flow.
//!
//! Data flows one way: spec -> [`beam`] -> [`calibration`] (posterior) ->
//! [`bayes`] (samplers) -> results -> [`report`].

// `!(x > 0.0)` is this crate's idiom for "not a positive number, NaN included":
// the partial_cmp spelling clippy suggests hides exactly that intent.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Public docs link the private helper that does the work (e.g. `global_map`,
// `combine` in diagnose::evidence) so a maintainer can follow them; the links resolve in
// `cargo doc --document-private-items`, the build this crate's docs are read in.
#![allow(rustdoc::private_intra_doc_links)]

pub mod bayes;
pub mod beam;
pub mod calibration;
pub mod cli;
pub mod diagnose;
pub mod error;
pub mod identify;
pub mod report;
pub mod reproduce;
