//! Delayed-rejection adaptive Metropolis (DRAM), §3.1 of the paper
//! (Haario, Laine, Mira & Saksman 2006), with any number of DR stages.
//!
//! * Stage 1 proposes θ1 ~ N(θn, C¹n) (eq. 27 with a symmetric q1).
//! * C¹n = C0 for n ≤ n0; afterwards C¹n = sd·Cov(θ_k … θ_{n−1}) + sd·λ·D,
//!   eq. (30), where k = `covariance_skip` states are ignored, adaptation starts at
//!   `adaptation_start`, and D = diag(C0) makes the regulariser λ relative to the
//!   parameter scales (an absolute λ·I is meaningless when Ω ~ 1e12 rad/s
//!   and Δ ~ 0.5 share one vector). The covariance is updated recursively
//!   (Welford's form of eq. 33) at every state.
//! * On rejection at stage i−1, stage i proposes θi ~ N(θn, γi·C¹n) (the
//!   proposals stay centred at the current state, as in the paper's
//!   q_i ~ N(θn, γi C¹n)), accepted with the general probability (29),
//!   whose reverse-path factors 1 − α_j(θi, θi−1, …) are evaluated by the
//!   recursive definition from cached log-densities: no extra model runs.
//! * Everything is in log space. A proposal outside the prior support or with
//!   a NaN/∞ model output has log π = −∞: it is rejected at that stage and
//!   counted in `rejected_invalid`.

use std::cell::RefCell;

use nalgebra::DMatrix;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;
use serde::{Deserialize, Serialize};

use crate::bayes::{Control, Posterior};
use crate::error::InputError;

/// Sampler settings; every field defaults to the paper's §4.2 value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DramSettings {
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
    /// Scaling sd of eq. (30); `None` (default) = 2.4²/d (Gelman, Roberts & Gilks 1996).
    #[serde(default)]
    pub adaptive_scale: Option<f64>,
    /// λ of eq. (30), relative to diag(C0) (default 1e-8).
    pub covariance_regularization: f64,
}

impl Default for DramSettings {
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
            adaptive_scale: None,
            covariance_regularization: 1e-8,
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

impl DramSettings {
    /// Checks every setting for a sampler of `dim` parameters (the one
    /// validation of the `sampler:` section; samplers assume it passed).
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
        if let Some(sd) = self.adaptive_scale {
            crate::error::positive(&f("adaptive_scale"), sd)?;
        }
        crate::error::non_negative(&f("covariance_regularization"), self.covariance_regularization)?;
        Ok(())
    }

    /// Number of DR stages (1 = plain adaptive Metropolis).
    pub fn stages(&self) -> usize {
        1 + self.dr_shrink_factors.len()
    }
}

/// One chain's output.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainOutput {
    /// All states θ0 … θ_{draws−1}, burn-in included.
    pub draws: Vec<Vec<f64>>,
    /// log π(θ | y) of every state.
    pub log_posterior: Vec<f64>,
    /// Proposals made at each DR stage.
    pub proposed: Vec<u64>,
    /// Proposals accepted at each DR stage.
    pub accepted: Vec<u64>,
    /// Proposals rejected because they left the support or the model failed.
    pub rejected_invalid: u64,
    /// Adapted covariances that were not positive definite (previous kept).
    pub covariance_failures: u64,
    /// Stage-1 proposal covariance at the end (row-major).
    pub final_covariance: Vec<f64>,
}

impl ChainOutput {
    /// Fraction of steps that ended by accepting at each stage.
    pub fn acceptance_per_stage(&self) -> Vec<f64> {
        let steps = self.draws.len().saturating_sub(1).max(1) as f64;
        self.accepted.iter().map(|&a| a as f64 / steps).collect()
    }
}

/// Gaussian random-walk proposal N(x0, γ·LLᵀ) for the current Cholesky factor
/// L (lower triangular, row-major d×d), with a scratch vector so that neither a
/// proposal nor a density costs an allocation (they run several times per step).
struct Proposal {
    d: usize,
    l: Vec<f64>,
    scratch: RefCell<Vec<f64>>,
}

/// Most DR stages + 1 (the validation allows 8 shrink factors): the longest path.
const MAX_PATH: usize = 10;

impl Proposal {
    fn from_lower(chol_l: &DMatrix<f64>) -> Self {
        let d = chol_l.nrows();
        let l = (0..d * d).map(|k| if k % d <= k / d { chol_l[(k / d, k % d)] } else { 0.0 }).collect();
        Proposal { d, l, scratch: RefCell::new(vec![0.0; d]) }
    }

    /// C0 = diag(sd²): its Cholesky factor is diag(sd) exactly, so no
    /// factorisation (which would fail when sd² underflows to 0) is needed.
    fn diagonal(sd: &[f64]) -> Self {
        let d = sd.len();
        let mut l = vec![0.0; d * d];
        sd.iter().enumerate().for_each(|(i, s)| l[i * d + i] = *s);
        Proposal { d, l, scratch: RefCell::new(vec![0.0; d]) }
    }

    /// Cholesky of a row-major covariance, or `None` if it is not positive definite.
    fn from_covariance(c: &[f64], d: usize) -> Option<Self> {
        let mut l = c.to_vec();
        cholesky_in_place(&mut l, d).then(|| Proposal { d, l, scratch: RefCell::new(vec![0.0; d]) })
    }

    /// out = x0 + scale·L z.
    fn step(&self, x0: &[f64], z: &[f64], scale: f64, out: &mut Vec<f64>) {
        out.clear();
        out.extend((0..self.d).map(|i| {
            let row = &self.l[i * self.d..i * self.d + i + 1];
            x0[i] + scale * row.iter().zip(z).map(|(a, b)| a * b).sum::<f64>()
        }));
    }

    /// Quadratic form (x − x0)ᵀ (LLᵀ)⁻¹ (x − x0) by forward substitution
    /// (∞ when L is singular, as nalgebra's triangular solve reports it).
    fn mahalanobis2(&self, x0: &[f64], x: &[f64]) -> f64 {
        let d = self.d;
        let mut y = self.scratch.borrow_mut();
        let mut sum = 0.0;
        for i in 0..d {
            let row = &self.l[i * d..i * d + i];
            let acc = (x[i] - x0[i]) - row.iter().zip(y.iter()).map(|(a, b)| a * b).sum::<f64>();
            let diag = self.l[i * d + i];
            if diag == 0.0 {
                return f64::INFINITY;
            }
            y[i] = acc / diag;
            sum += y[i] * y[i];
        }
        sum
    }
}

/// In-place Cholesky factor (lower, row-major) of a symmetric d×d matrix read
/// from its lower triangle; `false` when a pivot is not positive (or NaN).
/// Hand-written because it runs at every adapted step: nalgebra's `Cholesky`
/// consumes (so allocates) its matrix, and for the d ≤ ~20 of a calibration
/// the allocation costs more than the O(d³/6) arithmetic.
fn cholesky_in_place(a: &mut [f64], d: usize) -> bool {
    for j in 0..d {
        let mut diag = a[j * d + j];
        for k in 0..j {
            diag -= a[j * d + k] * a[j * d + k];
        }
        if !(diag > 0.0) {
            return false;
        }
        let ljj = diag.sqrt();
        a[j * d + j] = ljj;
        for i in j + 1..d {
            let mut v = a[i * d + j];
            for k in 0..j {
                v -= a[i * d + k] * a[j * d + k];
            }
            a[i * d + j] = v / ljj;
        }
        for k in j + 1..d {
            a[j * d + k] = 0.0;
        }
    }
    true
}

/// log q_j(from → to) up to the stage constant −½ log det(γj C), which
/// cancels between the numerator and denominator of eq. (29).
fn log_q(prop: &Proposal, gamma: f64, from: &[f64], to: &[f64]) -> f64 {
    -0.5 * prop.mahalanobis2(from, to) / gamma
}

/// Acceptance probability α_i of eq. (29) for the path y0 → y1 → … → yi
/// (`path[k]` indexes into `points`/`log_pi`, at most 10 long), with stage scales `gammas`
/// (γ1 = 1 first). Recursive: the reverse-path factors are α's of shorter
/// reversed paths. Exposed for the detailed-balance test.
pub fn dr_acceptance(
    points: &[Vec<f64>],
    log_pi: &[f64],
    path: &[usize],
    gammas: &[f64],
    chol_l: &DMatrix<f64>,
) -> f64 {
    let prop = Proposal::from_lower(chol_l);
    alpha(points, log_pi, path, gammas, &prop)
}

fn alpha(points: &[Vec<f64>], log_pi: &[f64], path: &[usize], gammas: &[f64], prop: &Proposal) -> f64 {
    let i = path.len() - 1;
    let (y0, yi) = (path[0], path[i]);
    if log_pi[yi] == f64::NEG_INFINITY {
        return 0.0;
    }
    if log_pi[y0] == f64::NEG_INFINITY {
        return 1.0;
    }
    // At every stage i the last factors, q_i(yi → y0) in the numerator and
    // q_i(y0 → yi) in the denominator, are the same Gaussian density of
    // ±(yi − y0), bitwise (the forward substitution of a negated vector is the
    // negated result, exactly), so they cancel in eq. (29) and are skipped
    // (skipping the stage-1 pair and, at stage 2, the stage-2 pair halves
    // log_q's calls). At stage 1 nothing else
    // is left: α1 = min(1, π(y1)/π(y0)) (Metropolis).
    if i == 1 {
        let log_ratio = log_pi[yi] - log_pi[y0];
        return if log_ratio.is_nan() {
            0.0
        } else if log_ratio >= 0.0 {
            1.0
        } else {
            log_ratio.exp()
        };
    }
    // Reverse path: yi → y_{i−1} → … → y0 (on the stack: no allocation per step).
    let mut reverse = [0usize; MAX_PATH];
    path.iter().rev().zip(reverse.iter_mut()).for_each(|(p, r)| *r = *p);
    let reverse = &reverse[..path.len()];
    let mut log_num = log_pi[yi];
    let mut log_den = log_pi[y0];
    for j in 1..i {
        // Stage-j proposal density: centred at the path's start (j = i cancels, above).
        log_num += log_q(prop, gammas[j - 1], &points[yi], &points[reverse[j]]);
        log_den += log_q(prop, gammas[j - 1], &points[y0], &points[path[j]]);
        let a_rev = alpha(points, log_pi, &reverse[..=j], gammas, prop);
        let a_fwd = alpha(points, log_pi, &path[..=j], gammas, prop);
        if a_rev >= 1.0 {
            return 0.0;
        }
        log_num += (1.0 - a_rev).ln();
        log_den += (1.0 - a_fwd).ln();
    }
    let log_ratio = log_num - log_den;
    if log_ratio.is_nan() {
        0.0
    } else if log_ratio >= 0.0 {
        1.0
    } else {
        log_ratio.exp()
    }
}

/// Running mean and scatter matrix (Welford), the recursive form of eq. (33),
/// in flat row-major buffers (no allocation per state).
struct RunningCovariance {
    n: usize,
    d: usize,
    mean: Vec<f64>,
    delta: Vec<f64>,
    scatter: Vec<f64>,
}

impl RunningCovariance {
    fn new(d: usize) -> Self {
        Self { n: 0, d, mean: vec![0.0; d], delta: vec![0.0; d], scatter: vec![0.0; d * d] }
    }

    fn push(&mut self, x: &[f64]) {
        self.n += 1;
        let n = self.n as f64;
        for ((delta, mean), xi) in self.delta.iter_mut().zip(self.mean.iter_mut()).zip(x) {
            *delta = xi - *mean;
            *mean += *delta / n;
        }
        let d = self.d;
        for (i, (xi, mean)) in x.iter().zip(&self.mean).enumerate() {
            let delta2 = xi - mean;
            for (j, delta) in self.delta.iter().enumerate() {
                // scatter += δ δ₂ᵀ, entry (j, i) += δ_j δ₂_i
                self.scatter[j * d + i] += delta * delta2;
            }
        }
    }

    /// sd·(sample covariance, eq. 31, divisor n − 1) + regulariser, row-major.
    fn proposal_covariance(&self, sd: f64, regulariser: &[f64], out: &mut [f64]) -> bool {
        if self.n < 2 {
            return false;
        }
        let div = self.n as f64 - 1.0;
        for ((o, s), r) in out.iter_mut().zip(&self.scatter).zip(regulariser) {
            *o = s / div * sd + r;
        }
        true
    }
}

/// Runs one DRAM chain from `start` with initial proposal standard
/// deviations `c0_sd` (C0 = diag(c0_sd²)). With a `control`, its progress
/// advances every 256 states (and by the remainder at the end), and the chain
/// stops after the state at which it finds the control cancelled, returning
/// the states so far: the caller, who cancelled, checks the control and
/// discards them ([`crate::bayes::control`]).
///
/// The settings are checked here ([`DramSettings::validate`]), not assumed:
/// this is public, and a caller that skipped the check would otherwise get
/// whatever unchecked settings produce (a burn-in beyond the chain, a
/// shrink factor of 0). So are the inputs' shapes: `c0_sd` must have one positive finite sd per
/// parameter and `start` must be finite. Every such error is an
/// [`InputError`] naming the field (recoverable: fix the input).
pub fn run_chain(
    post: &dyn Posterior,
    settings: &DramSettings,
    c0_sd: &[f64],
    start: &[f64],
    rng: &mut ChaCha8Rng,
    control: Option<&Control>,
) -> Result<ChainOutput, InputError> {
    check_chain_inputs(settings, c0_sd, start)?;
    let d = start.len();
    let stages = settings.stages();
    let gammas: Vec<f64> = std::iter::once(1.0).chain(settings.dr_shrink_factors.iter().copied()).collect();
    let scales: Vec<f64> = gammas.iter().map(|g| g.sqrt()).collect();
    let sd = settings.adaptive_scale.unwrap_or(2.4 * 2.4 / d as f64);
    let c0: Vec<f64> = (0..d * d).map(|k| if k % d == k / d { c0_sd[k / d] * c0_sd[k / d] } else { 0.0 }).collect();
    let regulariser: Vec<f64> = c0.iter().map(|c| c * (sd * settings.covariance_regularization)).collect();
    // Cholesky of diag(sd²) where it exists; diag(sd) itself when sd² underflows
    // and the factorisation fails.
    let mut proposal = Proposal::from_covariance(&c0, d).unwrap_or_else(|| Proposal::diagonal(c0_sd));
    let mut current_cov = c0;
    let (mut trial, mut trial_l) = (vec![0.0; d * d], vec![0.0; d * d]);

    let mut out = ChainOutput {
        draws: Vec::with_capacity(settings.draws_per_chain),
        log_posterior: Vec::with_capacity(settings.draws_per_chain),
        proposed: vec![0; stages],
        accepted: vec![0; stages],
        rejected_invalid: 0,
        covariance_failures: 0,
        final_covariance: Vec::new(),
    };
    let mut theta = start.to_vec();
    let mut lp = post.log_posterior(&theta);
    let mut running = RunningCovariance::new(d);
    // points[0] = θn, points[k] = the stage-k candidate (buffers reused every step)
    let mut points: Vec<Vec<f64>> = vec![Vec::with_capacity(d); stages + 1];
    let mut log_pi: Vec<f64> = Vec::with_capacity(stages + 1);
    let path: Vec<usize> = (0..=stages).collect();
    let mut z = vec![0.0; d];

    for n in 0..settings.draws_per_chain {
        if n > 0 {
            // One DRAM step from θ_{n−1}.
            points[0].clone_from(&theta);
            log_pi.clear();
            log_pi.push(lp);
            for stage in 0..stages {
                z.iter_mut().for_each(|v| *v = rng.sample::<f64, _>(StandardNormal));
                proposal.step(&theta, &z, scales[stage], &mut points[stage + 1]);
                let lc = post.log_posterior(&points[stage + 1]);
                out.proposed[stage] += 1;
                if !lc.is_finite() {
                    out.rejected_invalid += 1;
                }
                log_pi.push(if lc.is_nan() { f64::NEG_INFINITY } else { lc });
                let a = alpha(&points[..stage + 2], &log_pi, &path[..stage + 2], &gammas, &proposal);
                if a > 0.0 && rng.gen::<f64>() < a {
                    theta.clone_from(&points[stage + 1]);
                    lp = log_pi[stage + 1];
                    out.accepted[stage] += 1;
                    break;
                }
            }
        }
        out.draws.push(theta.clone());
        out.log_posterior.push(lp);

        // Adaptation, eq. (30): the covariance of states cov_skip … n.
        if n >= settings.covariance_skip {
            running.push(&theta);
        }
        if n + 1 > settings.nonadaptive_draws
            && n + 1 >= settings.adaptation_start
            && running.proposal_covariance(sd, &regulariser, &mut trial)
        {
            trial_l.copy_from_slice(&trial);
            if cholesky_in_place(&mut trial_l, d) {
                std::mem::swap(&mut proposal.l, &mut trial_l);
                std::mem::swap(&mut current_cov, &mut trial);
            } else {
                // not positive definite: the previous proposal is kept
                out.covariance_failures += 1;
            }
        }
        if let Some(control) = control {
            if n % 256 == 255 {
                control.advance(256);
            }
            if control.is_cancelled() {
                break;
            }
        }
    }
    if let Some(control) = control {
        control.advance((out.draws.len() % 256) as u64);
    }
    // row-major C¹ (symmetric up to rounding: the Welford scatter is not)
    out.final_covariance = current_cov;
    Ok(out)
}

/// The checks of [`run_chain`] (also [`crate::bayes::chains::run_chains`]'s,
/// for every start before any chain runs).
pub(crate) fn check_chain_inputs(settings: &DramSettings, c0_sd: &[f64], start: &[f64]) -> Result<(), InputError> {
    let d = start.len();
    settings.validate(d)?;
    if d == 0 {
        return Err(InputError::new("start", "(0 parameters)", "at least 1 parameter"));
    }
    if c0_sd.len() != d {
        return Err(InputError::new(
            "c0_sd",
            format!("({} entries)", c0_sd.len()),
            format!("one proposal sd per parameter ({d})"),
        ));
    }
    for (i, &sd) in c0_sd.iter().enumerate() {
        crate::error::positive(&format!("c0_sd[{i}]"), sd)?;
    }
    if let Some(i) = start.iter().position(|x| !x.is_finite()) {
        return Err(InputError::new(format!("start[{i}]"), crate::error::fmt_num(start[i]), "finite"));
    }
    Ok(())
}
