//! The audit's verdict types (✓ reproduced, ≈ consistent, ✗ inconsistent,
//! with the replicate distribution behind a noise-dependent claim): plain
//! data that the audit produces and the results, the document and the
//! golden check read, in a file that imports none of them.

use serde::Serialize;

/// The three verdicts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    Reproduced,
    Consistent,
    Inconsistent,
}

impl Status {
    pub fn symbol(self) -> &'static str {
        match self {
            Status::Reproduced => "✓",
            Status::Consistent => "≈",
            Status::Inconsistent => "✗",
        }
    }
}

/// A noise-dependent statistic over the replicates (the data of its figure).
#[derive(Debug, Clone, Serialize)]
pub struct ReplicateStatistic {
    /// What the statistic is, with unit.
    pub label: String,
    /// Its value on every replicate whose fit succeeded.
    pub values: Vec<f64>,
    /// Whether the paper's statement holds on each of those replicates.
    pub holds: Vec<bool>,
    /// Our value (DRAM posterior on replicate 0).
    pub ours: f64,
    /// The paper's value, when it states a number.
    pub paper: Option<f64>,
    /// The boundary of the statement (e.g. 1 = interval edge), when it has one.
    pub threshold: Option<f64>,
    /// Whether the statement holds on our draw.
    pub ours_holds: bool,
    /// The value on the noise-free data.
    pub noise_free: Option<f64>,
    /// Replicates whose MAP/Laplace fit failed (left out).
    pub failed: usize,
}

/// One audit line.
#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    pub id: String,
    pub claim: String,
    pub source: String,
    pub reproduced: String,
    pub tolerance: String,
    pub status: Status,
    /// P(statement holds) over the replicates (yes/no claims), or the two-sided
    /// tail probability of the paper's number (numeric claims).
    pub probability: Option<f64>,
    /// Measured cause of a ≈ or ✗ (empty for ✓).
    pub cause: String,
    /// The replicate distribution, for noise-dependent claims.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub replicates: Option<ReplicateStatistic>,
}
