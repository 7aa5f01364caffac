//! Several DRAM chains in parallel (rayon), deterministic for any thread count:
//! chain c draws from ChaCha8 stream c of the master seed, and results are
//! gathered in chain order.

use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use crate::bayes::dram::{check_chain_inputs, run_chain, ChainOutput, DramSettings};
use crate::bayes::rng::{stream, Purpose};
use crate::bayes::{Control, Posterior};
use crate::error::InputError;

/// The RNG of chain `chain` under master seed `seed`: the keyed stream
/// `(seed, Chain, [chain, 0])` of [`crate::bayes::rng`].
pub fn chain_rng(seed: u64, chain: usize) -> ChaCha8Rng {
    stream(seed, Purpose::Chain, [chain as u64, 0])
}

/// Runs one chain per start state; `control` receives the states' progress
/// and can stop every chain early ([`run_chain`]: the caller then discards
/// the chains).
/// Every start is checked as [`crate::bayes::dram::run_chain`] checks its one
/// before any chain runs (so a bad start fails fast, not after the others).
pub fn run_chains(
    post: &dyn Posterior,
    settings: &DramSettings,
    c0_sd: &[f64],
    starts: &[Vec<f64>],
    seed: u64,
    control: Option<&Control>,
) -> Result<Vec<ChainOutput>, InputError> {
    for start in starts {
        check_chain_inputs(settings, c0_sd, start)?;
    }
    starts
        .par_iter()
        .enumerate()
        .map(|(c, start)| {
            let mut rng = chain_rng(seed, c);
            run_chain(post, settings, c0_sd, start, &mut rng, control)
        })
        .collect()
}

/// Pooled acceptance fraction per DR stage over all chains.
pub fn pooled_acceptance(chains: &[ChainOutput]) -> Vec<f64> {
    let stages = chains.first().map_or(0, |c| c.accepted.len());
    let steps: f64 = chains.iter().map(|c| c.draws.len().saturating_sub(1) as f64).sum::<f64>().max(1.0);
    (0..stages).map(|s| chains.iter().map(|c| c.accepted[s] as f64).sum::<f64>() / steps).collect()
}
