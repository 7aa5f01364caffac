//! The crate's one seed scheme: every random stream is a ChaCha8 generator
//! keyed by (master seed, purpose, two indices).
//!
//! The 32-byte ChaCha key is the four little-endian words
//! `[seed, purpose, index[0], index[1]]`, so distinct tuples give
//! independent streams and a stream never depends on which thread, or in which
//! order, it is drawn. Nested work (a TMCMC run per model class, a DRAM chain
//! per noise replicate) keys its own streams with a child seed from
//! [`child_seed`]: the same function one level down.

use rand::{RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// What a random stream is for: the second word of its key. The indices that
/// go with each purpose are documented on the variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u64)]
pub enum Purpose {
    /// DRAM chain `[chain, 0]`.
    Chain = 1,
    /// Start point of DRAM chain `[chain, 0]` (jitter or overdispersed draw).
    ChainStart = 2,
    /// Prior points screened by a multi-start optimiser `[run, 0]`.
    MultiStart = 3,
    /// TMCMC prior sample `[0, sample]`.
    TmcmcPrior = 4,
    /// TMCMC resampling of stage `[stage, 0]`.
    TmcmcResample = 5,
    /// TMCMC Metropolis moves of `[stage, sample]`.
    TmcmcMove = 6,
    /// Child seed of one model class in a diagnosis `[class, 0]`; of its
    /// evidence bound's search (`diagnose::screen`) `[class, 1]`.
    ModelClass = 7,
    /// Hidden-effect generator of the tests (`tests/synthetic/mod.rs`, not shipped): which effect a case carries `[0, 0]`.
    SyntheticEffect = 8,
    /// Hidden-effect generator: the truth and its noise `[0, 0]`.
    SyntheticCase = 9,
    /// Hidden-effect generator: start points of the base fit that sizes an effect `[0, 0]`, of
    /// the fit of catalogue model k (the generator's `catalogue_models` order) to a foreign effect `[1 + k, 0]`.
    SyntheticBaseFit = 10,
    /// Measurement noise of synthetic reference data `[case, replicate]`.
    MeasurementNoise = 11,
    /// Prior draws stored beside a calibration (InferenceData `prior` group) `[0, 0]`.
    PriorDraws = 12,
    /// Replicate r ≥ 1 of a model's TMCMC run when the first missed the peak `[r, 0]`.
    EvidenceReplicate = 13,
    /// Draw `[i, 0]` of an importance-sampling evidence (`bayes::importance`).
    ImportanceDraw = 14,
    /// The uniform of a systematic resample of importance draws `[0, 0]` (`bayes::importance`).
    ImportanceResample = 15,
    /// Prior points screened by a diagnosed model's global MAP search `[0, 0]` (`diagnose::evidence`).
    GlobalMapSearch = 16,
    /// Prior draws of the parameters a diagnosed model adds to its `[k, 0]`-th
    /// sub-model, screened at that sub-model's MAP (`diagnose::evidence`; and
    /// by likelihood, under the evidence-bound seed, in `diagnose::screen`).
    NestedMapSearch = 17,
    /// Prior draws of the parameters a diagnosed model adds to its `[k, 0]`-th
    /// sub-model, paired with that sub-model's posterior draws in the
    /// population of an evidence from an optimum (`diagnose::evidence`).
    ImportancePopulation = 18,
    /// Prior draws of the parameters a diagnosed model adds to the sub-model
    /// whose posterior draws start its TMCMC run (`diagnose::evidence`), one
    /// stream `[0, 0]` drawn in sample order.
    NestedStart = 19,
}

/// The stream keyed by `(seed, purpose, index)`.
pub fn stream(seed: u64, purpose: Purpose, index: [u64; 2]) -> ChaCha8Rng {
    let mut key = [0u8; 32];
    for (k, w) in [seed, purpose as u64, index[0], index[1]].iter().enumerate() {
        key[8 * k..8 * k + 8].copy_from_slice(&w.to_le_bytes());
    }
    ChaCha8Rng::from_seed(key)
}

/// A master seed for nested work, drawn from the stream `(seed, purpose, index)`.
pub fn child_seed(seed: u64, purpose: Purpose, index: [u64; 2]) -> u64 {
    stream(seed, purpose, index).next_u64()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_differ_by_every_key_word_and_repeat_for_the_same_key() {
        let first = |s, p, i| stream(s, p, i).next_u64();
        let base = first(1, Purpose::Chain, [0, 0]);
        assert_eq!(base, first(1, Purpose::Chain, [0, 0]));
        for other in [
            first(2, Purpose::Chain, [0, 0]),
            first(1, Purpose::ChainStart, [0, 0]),
            first(1, Purpose::Chain, [1, 0]),
            first(1, Purpose::Chain, [0, 1]),
        ] {
            assert_ne!(base, other);
        }
    }
}
