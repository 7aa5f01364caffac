//! `cargo xtask reproduce --check`: compares a run's results with the committed
//! golden results (`golden/reproduce-quick.json`, `golden/reproduce-full.json`).
//!
//! A golden file holds, per quantity, the value and its Monte Carlo standard
//! error at the time it was accepted; the check fails when
//!
//!   |x − x_golden| > K · √(se² + se_golden²),   K = 4,
//!
//! i.e. when the difference of two independent Monte Carlo estimates exceeds 4
//! of its own standard deviations (two-sided P ≈ 6e-5 per quantity for a
//! Gaussian error, so a run with ~100 quantities drifts by chance with P ≈ 0.6 %).
//! The runs are deterministic, so on an unchanged code base the difference is
//! exactly 0; the tolerance says how far a code change may move a Monte Carlo
//! estimate before it counts as a drift (a change of seed or chain layout moves
//! it by O(1) standard errors). Quantities without a Monte Carlo error
//! (reconstruction, forward model) have se = relative 1e-9 of their value plus
//! 1e-12: they are exact up to floating-point reassociation. Every audit verdict
//! that changes is a drift too.
//!
//! Quantities and their standard errors:
//! * case posterior mean: sd/√ESS_bulk;
//! * case posterior sd: sd/√(2·ESS_bulk) (Gaussian-approximation se of an sd);
//! * case CI95 endpoints: sd·√(p(1−p))/(φ(z_p)·√ESS_tail) at p = 0.025, i.e.
//!   ≈ 2.9·sd/√ESS_tail (se of a quantile through the normal density);
//! * Case-3 log evidence: TMCMC's own se;
//! * replicate probabilities P: binomial √(P(1−P)/R), floored at 1/R.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::reproduce::results::Results;
use crate::reproduce::verdict::Status;

/// Drift threshold in standard errors of the difference (module doc).
pub const K_SIGMA: f64 = 4.0;

/// One quantity of a golden file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quantity {
    pub value: f64,
    /// Monte Carlo standard error (or the floating-point floor).
    pub se: f64,
}

/// The golden results: quantities by name, verdicts by claim id.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Golden {
    pub quick: bool,
    pub quantities: BTreeMap<String, Quantity>,
    pub verdicts: BTreeMap<String, Status>,
}

/// A golden file that cannot be used (exit 2).
#[derive(Debug, thiserror::Error)]
pub enum GoldenError {
    #[error("invalid golden file = {path}: allowed an existing JSON file written by `cargo xtask reproduce --bless` ({reason})")]
    Unreadable { path: String, reason: String },
    #[error("invalid golden file = {path}: allowed a run with quick = {expected} (it holds quick = {found})")]
    WrongMode { path: String, expected: bool, found: bool },
}

impl Golden {
    /// The golden file's text.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("golden serialises") + "\n"
    }
}

fn exact(x: f64) -> Quantity {
    Quantity { value: x, se: 1e-9 * x.abs() + 1e-12 }
}

/// The quantities and verdicts of a run.
pub fn golden_of(r: &Results) -> Golden {
    let mut q = BTreeMap::new();
    q.insert("reconstruction.table_1.length_nm".into(), exact(r.reconstruction.table_1.length_nm));
    for (n, v) in &r.reconstruction.table_4_fit.parameters {
        q.insert(format!("reconstruction.table_4.{n}"), exact(*v));
    }
    for (n, v) in &r.reconstruction.table_9_fit.parameters {
        q.insert(format!("reconstruction.table_9.{n}"), exact(*v));
    }
    for row in &r.table_2 {
        q.insert(format!("table_2.mode_{}.omega_rad_s", row.mode), exact(row.omega_rad_s));
    }
    for c in &r.cases {
        for p in &c.parameters {
            let s = &p.summary;
            let key = |what: &str| format!("case_{}.{}.{what}", c.id, s.name);
            let ess = s.ess_bulk.max(1.0);
            let ess_tail = s.ess_tail.max(1.0);
            q.insert(key("mean"), Quantity { value: s.mean, se: s.sd / ess.sqrt() });
            q.insert(key("sd"), Quantity { value: s.sd, se: s.sd / (2.0 * ess).sqrt() });
            // se of the 2.5 % quantile: √(p(1−p))/φ(1.96) = 0.156/0.0584 ≈ 2.67 sd units per √ESS.
            let se_q = 2.67 * s.sd / ess_tail.sqrt();
            q.insert(key("ci95_lower"), Quantity { value: s.ci95[0], se: se_q });
            q.insert(key("ci95_upper"), Quantity { value: s.ci95[1], se: se_q });
        }
    }
    if let Some(e) = &r.case_3_evidence {
        q.insert(
            "case_3_evidence.log_evidence_n1_beta".into(),
            Quantity { value: e.log_evidence_n1_beta, se: e.log_evidence_n1_beta_se },
        );
        q.insert(
            "case_3_evidence.log_evidence_n2".into(),
            Quantity { value: e.log_evidence_n2, se: e.log_evidence_n2_se },
        );
    }
    for v in &r.audit {
        if let (Some(p), Some(s)) = (v.probability, &v.replicates) {
            let n = s.values.len().max(1) as f64;
            q.insert(
                format!("audit.{}.probability", v.id),
                Quantity { value: p, se: (p * (1.0 - p) / n).sqrt().max(1.0 / n) },
            );
        }
    }
    let verdicts = r.audit.iter().map(|v| (v.id.clone(), v.status)).collect();
    Golden { quick: r.quick, quantities: q, verdicts }
}

/// Reads a golden file; a missing or malformed one is a [`GoldenError`].
pub fn load_golden(path: &Path, quick: bool) -> Result<Golden, GoldenError> {
    let p = path.display().to_string();
    let text = std::fs::read_to_string(path)
        .map_err(|e| GoldenError::Unreadable { path: p.clone(), reason: e.to_string() })?;
    let g: Golden =
        serde_json::from_str(&text).map_err(|e| GoldenError::Unreadable { path: p.clone(), reason: e.to_string() })?;
    if g.quick != quick {
        return Err(GoldenError::WrongMode { path: p, expected: quick, found: g.quick });
    }
    Ok(g)
}

/// Every drift of `run` against `golden`, one line each ("" = none).
pub fn compare(run: &Golden, golden: &Golden) -> Vec<String> {
    let mut drifts = Vec::new();
    for (name, g) in &golden.quantities {
        match run.quantities.get(name) {
            None => drifts.push(format!("{name}: missing from this run (golden {})", g.value)),
            Some(x) => {
                let se = (x.se * x.se + g.se * g.se).sqrt();
                let d = x.value - g.value;
                let ok = if se > 0.0 && se.is_finite() { d.abs() <= K_SIGMA * se } else { d == 0.0 };
                if !ok || !x.value.is_finite() {
                    drifts.push(format!(
                        "{name}: {} vs golden {} (Δ = {d:+.4e} = {:+.1} σ; tolerance {K_SIGMA} σ, σ = {se:.3e})",
                        x.value,
                        g.value,
                        d / se
                    ));
                }
            }
        }
    }
    for name in run.quantities.keys().filter(|n| !golden.quantities.contains_key(*n)) {
        drifts.push(format!("{name}: new in this run (not in the golden file)"));
    }
    for (id, g) in &golden.verdicts {
        match run.verdicts.get(id) {
            Some(s) if s == g => {}
            Some(s) => drifts.push(format!("audit verdict {id}: {} vs golden {}", s.symbol(), g.symbol())),
            None => drifts.push(format!("audit verdict {id}: missing from this run (golden {})", g.symbol())),
        }
    }
    for id in run.verdicts.keys().filter(|n| !golden.verdicts.contains_key(*n)) {
        drifts.push(format!("audit verdict {id}: new in this run"));
    }
    drifts
}

#[cfg(test)]
mod tests {
    use super::*;

    fn golden(mean: f64, status: Status) -> Golden {
        Golden {
            quick: true,
            quantities: [("case_1A.delta.mean".to_string(), Quantity { value: mean, se: 0.01 })].into(),
            verdicts: [("case_1a_covers_truth".to_string(), status)].into(),
        }
    }

    #[test]
    fn drift_is_measured_in_units_of_the_difference_se() {
        let g = golden(0.5, Status::Reproduced);
        assert!(compare(&g, &g).is_empty());
        // √(0.01² + 0.01²) = 0.01414: 0.05 away is 3.5 σ (inside), 0.06 is 4.2 σ (drift).
        assert!(compare(&golden(0.55, Status::Reproduced), &g).is_empty());
        let d = compare(&golden(0.56, Status::Reproduced), &g);
        assert_eq!(d.len(), 1);
        assert!(d[0].contains("+4.2 σ"), "{}", d[0]);
    }

    #[test]
    fn a_changed_verdict_is_a_drift() {
        let d = compare(&golden(0.5, Status::Consistent), &golden(0.5, Status::Reproduced));
        assert_eq!(d, vec!["audit verdict case_1a_covers_truth: ≈ vs golden ✓".to_string()]);
    }

    #[test]
    fn missing_malformed_and_wrong_mode_golden_files_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("reproduce-quick.json");
        assert!(load_golden(&p, true).unwrap_err().to_string().contains("reproduce-quick.json"));
        std::fs::write(&p, "{").unwrap();
        assert!(load_golden(&p, true).unwrap_err().to_string().starts_with("invalid golden file ="));
        std::fs::write(&p, golden(0.5, Status::Reproduced).to_json()).unwrap();
        assert!(load_golden(&p, true).is_ok());
        assert!(matches!(load_golden(&p, false), Err(GoldenError::WrongMode { .. })));
    }
}
