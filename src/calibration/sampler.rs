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

/// Memory budget for the stored chains (bytes). A stored state costs
/// `state_bytes(dim)`; `calibrate` holds every state once in the chains and
/// once more in the post-burn-in copy that the summaries read.
pub const MAX_CHAIN_MEMORY_BYTES: f64 = 2.0 * 1024.0 * 1024.0 * 1024.0;

/// Bytes per stored state of a `dim`-parameter chain: a `Vec<f64>` (24-byte
/// header + 8·dim heap bytes + ~16 bytes allocator overhead) and its log
/// posterior (8), twice (chains + the kept copy).
pub fn state_bytes(dim: usize) -> f64 {
    2.0 * (24.0 + 8.0 * dim as f64 + 16.0 + 8.0)
}

/// Least post-burn-in draws per chain: the rank-normalised split-R̂ and the
/// bulk/tail ESS split each chain in halves and need a few draws in each
/// tail quantile (5 %) of each half: 2 × 20 = 40 keeps them finite.
pub const MIN_KEPT_DRAWS: usize = 40;

impl SamplerSpec {
    pub fn validate(&self, dim: usize) -> Result<(), InputError> {
        let f = |name: &str| format!("sampler.{name}");
        if self.chains < 2 || self.chains > 64 {
            return Err(InputError::new(
                f("chains"),
                self.chains,
                "2..=64 (R-hat compares chains; >= 4 recommended for split-R-hat)",
            ));
        }
        let max_draws = (MAX_CHAIN_MEMORY_BYTES / (state_bytes(dim.max(1)) * self.chains as f64)).floor() as usize;
        if self.draws_per_chain > max_draws {
            return Err(InputError::new(
                f("draws_per_chain"),
                self.draws_per_chain,
                format!(
                    "<= {max_draws} (the {} chains of {dim} parameters must fit in {} GiB)",
                    self.chains,
                    MAX_CHAIN_MEMORY_BYTES / 1024f64.powi(3)
                ),
            ));
        }
        if self.draws_per_chain < self.burn_in + MIN_KEPT_DRAWS {
            return Err(InputError::new(
                f("draws_per_chain"),
                self.draws_per_chain,
                format!(
                    ">= burn_in + {MIN_KEPT_DRAWS} = {} (draws kept for the diagnostics)",
                    self.burn_in + MIN_KEPT_DRAWS
                ),
            ));
        }
        if self.nonadaptive_draws >= self.draws_per_chain {
            return Err(InputError::new(
                f("nonadaptive_draws"),
                self.nonadaptive_draws,
                format!("< draws_per_chain = {} (otherwise adaptation never starts)", self.draws_per_chain),
            ));
        }
        if self.adaptation_start >= self.draws_per_chain {
            return Err(InputError::new(
                f("adaptation_start"),
                self.adaptation_start,
                format!("< draws_per_chain = {} (otherwise adaptation never starts)", self.draws_per_chain),
            ));
        }
        if self.covariance_skip > self.adaptation_start {
            return Err(InputError::new(
                f("covariance_skip"),
                self.covariance_skip,
                format!("<= adaptation_start = {}", self.adaptation_start),
            ));
        }
        if self.dr_shrink_factors.len() > 8 {
            return Err(InputError::new(
                f("dr_shrink_factors"),
                format!("({} factors)", self.dr_shrink_factors.len()),
                "at most 8 (each stage costs one model run; the acceptance recursion is exponential in stages)",
            ));
        }
        for (i, &g) in self.dr_shrink_factors.iter().enumerate() {
            if !(g.is_finite() && (1e-6..=1.0).contains(&g)) {
                return Err(InputError::new(
                    format!("sampler.dr_shrink_factors[{i}]"),
                    crate::error::fmt_num(g),
                    "1e-6 <= gamma <= 1 (gamma * sd^2 must stay a normal number)",
                ));
            }
        }
        if self.multistart_points == 0 || self.multistart_points > 100_000 {
            return Err(InputError::new(f("multistart_points"), self.multistart_points, "1..=100000"));
        }
        Ok(())
    }
}
