//! The `sampler:` section of a measured-data file: DRAM settings (§3.1, §4.2)
//! plus the number of chains and the seed.

use serde::{Deserialize, Serialize};

use crate::error::InputError;

/// Sampler settings; every field defaults to the paper's §4.2 value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SamplerSpec {
    /// States drawn per chain, burn-in included (paper: 20 000).
    pub draws_per_chain: usize,
    /// Leading states discarded from every summary (paper: 5 000).
    pub burn_in: usize,
    /// Non-adaptation period n0 with proposal C0, eq. (30) (paper: 4 000).
    pub nonadaptive_draws: usize,
    /// State at which adaptation starts (paper: 4 000).
    pub adaptation_start: usize,
    /// The adapted covariance ignores the first this-many states (paper: 3 000).
    pub covariance_skip: usize,
    /// Delayed-rejection shrink factors γ2, γ3, ... on the covariance of the
    /// stage-1 proposal (paper: two stages, γ1 = 0.1 → `[0.1]`).
    pub dr_shrink_factors: Vec<f64>,
    /// Independent chains, run in parallel (≥ 4 for split-R̂).
    pub chains: usize,
    /// Master seed: chain c uses the stream (seed, c).
    pub seed: u64,
    /// Prior draws screened by the multi-start optimiser that places the chains.
    pub multistart_points: usize,
}

impl Default for SamplerSpec {
    fn default() -> Self {
        Self {
            draws_per_chain: 20_000,
            burn_in: 5_000,
            nonadaptive_draws: 4_000,
            adaptation_start: 4_000,
            covariance_skip: 3_000,
            dr_shrink_factors: vec![0.1],
            chains: 4,
            seed: 20_201_228,
            multistart_points: 256,
        }
    }
}

impl SamplerSpec {
    pub fn validate(&self, _dim: usize) -> Result<(), InputError> {
        let f = |name: &str| format!("sampler.{name}");
        if self.draws_per_chain == 0 {
            return Err(InputError::new(f("draws_per_chain"), 0, ">= 1"));
        }
        if self.burn_in >= self.draws_per_chain {
            return Err(InputError::new(
                f("burn_in"),
                self.burn_in,
                format!("< draws_per_chain = {}", self.draws_per_chain),
            ));
        }
        if self.covariance_skip > self.adaptation_start {
            return Err(InputError::new(
                f("covariance_skip"),
                self.covariance_skip,
                format!("<= adaptation_start = {}", self.adaptation_start),
            ));
        }
        for (i, &g) in self.dr_shrink_factors.iter().enumerate() {
            if !(g.is_finite() && g > 0.0 && g <= 1.0) {
                return Err(InputError::new(format!("sampler.dr_shrink_factors[{i}]"), g, "0 < gamma <= 1"));
            }
        }
        if self.chains == 0 || self.chains > 64 {
            return Err(InputError::new(f("chains"), self.chains, "1..=64 (>= 4 for split-R-hat)"));
        }
        if self.multistart_points == 0 {
            return Err(InputError::new(f("multistart_points"), 0, ">= 1"));
        }
        Ok(())
    }
}
