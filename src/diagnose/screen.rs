//! Screening of the models with the most causes (the pairs at the default
//! [`DiagnoseSettings::max_causes`]): an upper bound on a model's evidence
//! from its best likelihood, and the rule that says when that bound is too
//! low for the model to change any decision of the diagnosis, so that its
//! full evidence ([`super::evidence`]) need not be computed.
//!
//! # The bound
//! For a prior that integrates to at most one (every prior of
//! `bayes::prior` is a normalised density, restricted at most to a subset of
//! its support, and the sampling coordinates of `bayes::transform` carry
//! their Jacobian), Z = ∫ L π dθ ≤ sup L · ∫ π dθ ≤ sup L, so
//! ln Z ≤ ln L_max. A search finds some ln L̂ ≤ ln L_max: the bound is only
//! as good as the optimiser. [`likelihood_max`] searches from the MAPs of the
//! model's sub-models (each with one cause fewer, whose full evidences are
//! computed first), where a model that adds a cause to a fitting sub-model
//! peaks, with [`SCREEN_POINTS`] prior draws of the parameters it adds; the
//! strict bound is ln L̂ + [`OPTIMISER_MARGIN_NATS`].
//!
//! That bound gives away the Occam factor, the prior volume the posterior
//! does not fill: 20–30 nats on a 5–7-parameter pair of a 5-mode file, so it
//! screens only the pairs that misfit by far more. The Laplace evidence at
//! the same optimum keeps the Occam factor; it is no bound (it misses other
//! modes' mass and non-Gaussian tails), so it is used with a measured margin,
//! [`LAPLACE_MARGIN_NATS`], and the bound used is the lower of the two
//! ([`Bound::log_evidence_bound`]). Every computed pair records both against
//! its full evidence ([`Check`]), and the hidden suite asserts that neither
//! margin was ever needed in full.

//! # The rule
//! A screened model with bound b changes no decision of the search
//! (`search::search`, rules 1–3) and of the verdict (`verdict`) when
//! ([`Reach::harmless`]):
//! 1. it cannot be selected: b < ln Z(it without c) + threshold for some
//!    cause c (then it is not selectable, rule 1), or b is below both the
//!    bar rule 2 sets for its number of causes (the selection of fewer
//!    causes + threshold) and the floor of the misfit fallback (the
//!    selection after rule 2 − margin, rule 3);
//! 2. and it cannot be listed as an alternative: b ≤ ln Z(selected) −
//!    margin; alternatives are what undecide a cause
//!    (`decided_causes`) and what the next measurement separates, so this
//!    covers those too; or, when the base is selected (no alternatives), it
//!    cannot be the model the gain is assessed for: b < the best evidence
//!    of the models computed.
//!
//! Both keep b below the best evidence computed, so the bar a flagged model
//! must reach to be replicated (`search::Problem::run`) is not raised by it
//! either. What it does change is a number: the posterior model
//! probabilities are normalised over the models whose evidence was
//! computed; each screened model's probability relative to the most
//! probable one is below e^(b − ln Z_max).
//!
//! The search first computes the full evidence of every model whose bound
//! reaches the best evidence of fewer causes less the margin, then selects,
//! then checks every screened model against the rule at that selection;
//! those that fail it get their full evidence too, and the selection is
//! redone, until none fails. The models computed, and so every number, are
//! functions of the input and seed alone.

use rayon::prelude::*;
use serde::Serialize;

use crate::bayes::laplace::laplace_log_evidence_with_step;
use crate::bayes::map::polish_best;
use crate::bayes::posterior::Counted;
use crate::bayes::rng::{child_seed, stream, Purpose};
use crate::bayes::Posterior;

use super::classes::{ClassPosterior, Model};
use super::evidence::ModelRun;
use super::settings::DiagnoseSettings;

/// Prior draws of the parameters a model adds to each sub-model, screened
/// by likelihood at that sub-model's MAP, and how many of the best are
/// polished by Nelder–Mead: as the nested MAP search of `bayes::evidence`
/// (500 and 2), whose starts these are.
pub const SCREEN_POINTS: usize = 500;
pub const SCREEN_KEEP: usize = 2;

/// Added to the best log-likelihood the search found before it is used as
/// the bound on ln Z: 15 nats. The search's optimum is a lower bound of the
/// true maximum, and on pairs with several modes by construction (two
/// relaxations; a relaxation and a point mass) the likelihood at the full
/// evidence's MAP was seen 6.4 and 9.9 nats above it ([`Check`];
/// `tests/diagnose_hidden.md`, "Screening", records the largest shortfall
/// on every case measured); 15 keeps 5 nats above the worst seen.
pub const OPTIMISER_MARGIN_NATS: f64 = 15.0;

/// Added to the Laplace evidence at the screening search's optimum before
/// it is used as a bound on ln Z: 20 nats. Not a bound by itself: the
/// Laplace evidence misses the mass of other modes and of non-Gaussian
/// tails, and sits at a less exact optimum than the evidence's own. On the
/// pairs of the hidden suite's CI cases the full ln Z exceeded the Laplace
/// evidence at its own MAP by at most 2.85 nats and the screening Laplace
/// evidence by at most 2.6; the screening optimum can fall short of the
/// full MAP by as much as [`OPTIMISER_MARGIN_NATS`] covers, so this margin
/// keeps that one's room above the Laplace error. Every computed pair's
/// ln Z − this Laplace evidence is recorded ([`Check`];
/// `tests/diagnose_hidden.md`, "Screening").
pub const LAPLACE_MARGIN_NATS: f64 = 20.0;

/// How far, in nats, a model's evidence bound ([`Bound::log_evidence_bound`])
/// must lie below a layer's reference evidence for its own evidence to be
/// estimated at a quarter of the TMCMC samples ([`HOPELESS_SAMPLE_DIVISOR`]):
/// 20. The reference (`search::Problem::run_layer`) is the best evidence
/// computed of a model selectable by rule 1 when it beats the base's by the
/// threshold, else the base's.
///
/// Why that changes no decision (threshold 3, margin 3, the defaults):
/// rule 2 of the search ends at most a threshold below the reference (a
/// better model of more causes replaces the selection only when it beats it
/// by the threshold), and rule 3 moves down by at most the margin, so every
/// decision the model could take part in (selected, the misfit fallback, an
/// alternative, the gain's model) needs ln Z ≥ reference − threshold −
/// 2·margin = reference − 9, 11 nats above any model hopeless by this
/// constant. The one place its value enters is rule 1 of a model P that adds
/// a cause to it: ln Z(P) − ln Z(it) ≥ the threshold, where P matters only
/// at ln Z(P) ≥ reference − 9; the difference is then above 11 nats, and the
/// cheaper estimate would have to overestimate ln Z by 8 nats to flip it.
/// TMCMC's ln Ẑ is biased low, not high (Jensen on an unbiased Ẑ), and the
/// bound caps it. What it costs: the evidence's se, reported with it, is
/// about twice the full run's.
pub const HOPELESS_NATS: f64 = 20.0;

/// The TMCMC samples of a hopeless model ([`HOPELESS_NATS`]) are the
/// diagnosis's samples divided by this (at least `DiagnoseSettings::MIN_SAMPLES`).
pub const HOPELESS_SAMPLE_DIVISOR: usize = 4;

/// What the screening search found for one model.
#[derive(Debug, Clone)]
pub struct Bound {
    pub model: Model,
    /// The log-likelihood at the best optimum found (a lower bound of the maximum).
    pub log_likelihood_max_found: f64,
    /// The Laplace evidence there (`None` when the Hessian is not positive
    /// definite at any step, or the optimum sits on a prior bound).
    pub log_evidence_laplace: Option<f64>,
    /// Forward solves the search spent.
    pub forward_evaluations: u64,
    /// The best optimum found (sampling coordinates) and the simplex steps
    /// of its search, one per coordinate (the scales of the Laplace
    /// evidence there): where the model's evidence from an optimum starts
    /// (`evidence::run_from_optimum`). `None` when no search found a finite posterior.
    pub optimum: Option<(Vec<f64>, Vec<f64>)>,
}

impl Bound {
    /// The bound used on ln Z: the best log-likelihood found plus
    /// [`OPTIMISER_MARGIN_NATS`] (ln Z ≤ ln L_max), or the Laplace evidence
    /// plus [`LAPLACE_MARGIN_NATS`] (a measured margin) when that is lower.
    pub fn log_evidence_bound(&self) -> f64 {
        let strict = self.log_likelihood_max_found + OPTIMISER_MARGIN_NATS;
        self.log_evidence_laplace.map_or(strict, |l| strict.min(l + LAPLACE_MARGIN_NATS))
    }
}

/// The screening search of `posterior` from the MAPs of `sub_models`
/// (module doc): per sub-model k, its MAP fills the shared parameters (by
/// name), [`SCREEN_POINTS`] prior draws (stream `(seed, NestedMapSearch, [k,
/// 0])`) the added ones, and the [`SCREEN_KEEP`] best are polished by
/// Nelder–Mead on the posterior; simplex steps: the sub-model's posterior sd
/// for a shared parameter, a tenth of the prior draws' sd for an added one.
/// At the best optimum: the log-likelihood (a lower bound of ln L_max) and
/// the Laplace evidence (FD steps 0.05, else 0.01 or 0.002 of those sds, as
/// the evidence's own Laplace). −∞ and `None` without sub-models or a finite
/// posterior.
pub fn likelihood_max(
    model: Model,
    posterior: &ClassPosterior,
    sub_models: &[&ModelRun],
    s: &DiagnoseSettings,
    seed: u64,
) -> Bound {
    let counted = Counted::new(posterior);
    let names = posterior.names();
    let best = sub_models
        .iter()
        .enumerate()
        .filter_map(|(k, sub)| {
            let sub_names = sub.posterior.names();
            let shared: Vec<Option<usize>> = names.iter().map(|n| sub_names.iter().position(|m| m == n)).collect();
            let mut rng = stream(seed, Purpose::NestedMapSearch, [k as u64, 0]);
            let draws: Vec<Vec<f64>> = (0..SCREEN_POINTS).map(|_| counted.sample_prior(&mut rng)).collect();
            let starts: Vec<Vec<f64>> = draws
                .iter()
                .map(|d| shared.iter().zip(d).map(|(j, &x)| j.map_or(x, |j| sub.map[j])).collect())
                .collect();
            let scales: Vec<f64> = shared
                .iter()
                .enumerate()
                .map(|(i, j)| match j {
                    Some(j) => sd(sub.draws.iter().map(|u| u[*j])),
                    None => 0.1 * sd(draws.iter().map(|u| u[i])),
                })
                .map(|s| if s > 0.0 && s.is_finite() { s } else { 1e-3 })
                .collect();
            polish_best(&counted, &scales, starts, SCREEN_KEEP, s.map_iters).into_iter().next().map(|m| (m, scales))
        })
        .max_by(|a, b| a.0.log_posterior.total_cmp(&b.0.log_posterior));
    let (log_likelihood_max_found, log_evidence_laplace, optimum) = match best {
        Some((m, scales)) => (
            counted.log_likelihood(&m.theta),
            [0.05, 0.01, 0.002]
                .into_iter()
                .find_map(|h| laplace_log_evidence_with_step(&counted, &m.theta, &scales, h).ok())
                .map(|l| l.log_evidence)
                .filter(|l| l.is_finite()),
            m.log_posterior.is_finite().then_some((m.theta, scales)),
        ),
        None => (f64::NEG_INFINITY, None, None),
    };
    Bound { model, log_likelihood_max_found, log_evidence_laplace, forward_evaluations: counted.count(), optimum }
}

/// For a model of the top layer whose evidence was computed: how the
/// screening search's best log-likelihood compares with the likelihood at
/// the full evidence's MAP (found by other searches: a lower bound of the
/// maximum too). The second above the first is a shortfall of the search
/// that [`OPTIMISER_MARGIN_NATS`] must cover.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Check {
    pub extension: String,
    pub log_likelihood_max_found: f64,
    pub log_likelihood_at_map: f64,
    /// The screening search's Laplace evidence and the model's full ln Z:
    /// the second above the first is what [`LAPLACE_MARGIN_NATS`] must cover.
    pub log_evidence_laplace: Option<f64>,
    pub log_evidence: f64,
}

/// A model whose evidence was not computed: its evidence bound is below
/// every value at which it could change a decision (module doc).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ScreenedModel {
    pub extension: String,
    pub causes: Vec<String>,
    /// The log-likelihood at the screening search's best optimum (a lower bound of the maximum).
    pub log_likelihood_max_found: f64,
    /// The Laplace evidence there.
    pub log_evidence_laplace: Option<f64>,
    /// The bound on ln Z used ([`Bound::log_evidence_bound`]).
    pub log_evidence_bound: f64,
    /// `log_evidence_bound` − ln Z(base): a bound on the model's ln B.
    pub log_bayes_factor_bound: f64,
    /// The least bound at which the model could have changed a decision
    /// (selection, alternatives, the gain's model): `log_evidence_bound` lies below it.
    pub log_evidence_needed: f64,
    /// Forward solves of the screening search.
    pub forward_evaluations: u64,
    /// Why it was not computed: "screened: cannot reach the leader".
    pub reason: String,
}

/// The screening searches of `models` in parallel, gathered in their order;
/// each keyed by `(seed, ModelClass, [model key, 1])` (index 0 keys the
/// model's evidence).
pub(super) fn bounds(
    models: &[(Model, ClassPosterior, Vec<&ModelRun>, u64)],
    s: &DiagnoseSettings,
    seed: u64,
) -> Vec<Bound> {
    models
        .par_iter()
        .map(|(m, posterior, subs, key)| {
            let seed = child_seed(seed, Purpose::ModelClass, [*key, 1]);
            likelihood_max(m.clone(), posterior, subs, s, seed)
        })
        .collect()
}

/// Sample sd of `v` (0 for fewer than two values).
fn sd(v: impl Iterator<Item = f64>) -> f64 {
    let v: Vec<f64> = v.collect();
    if v.len() < 2 {
        return 0.0;
    }
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (v.len() - 1) as f64).sqrt()
}

/// What a screened model would have to reach to change a decision, at one
/// selection (module doc, "The rule").
#[derive(Debug, Clone, Copy)]
pub(super) struct Reach {
    /// The bound at or above which the model could be selected (rule 1:
    /// the best of its sub-models + threshold; else rules 2 and 3).
    pub(super) select: f64,
    /// The bound above which the model could be listed as an alternative
    /// (ln Z(selected) − margin), or, with the base selected, be the model the
    /// gain is assessed for (the best evidence computed).
    pub(super) list: f64,
}

impl Reach {
    /// The least bound at which the model could change a decision.
    pub(super) fn needed(&self) -> f64 {
        self.select.min(self.list)
    }

    /// A model with evidence bound `b` changes no decision.
    pub(super) fn harmless(&self, b: f64) -> bool {
        b < self.needed()
    }
}
