//! The beam posterior: priors of the named parameters times the Gaussian
//! likelihood of the measured modal data, eqs. (24), (26), (38), (41).
//!
//! y = [ω_1 … ω_M, ζ_1 … ζ_M] (eq. 36 for any listed modes), followed by the
//! relative amplitudes of any mode scans ([`ModeScan`], not in the paper);
//! the measurement covariance is diagonal with the file's standard
//! deviations, scaled by β² when `beta_squared` is a parameter (eq. 41; the
//! scans' too). A θ the forward model cannot evaluate (invalid beam, a
//! requested mode overdamped or missing, numerical failure) has likelihood
//! zero: log L = −∞.

use rand::RngCore;

use crate::bayes::likelihood::DiagonalGaussian;
use crate::bayes::prior::Prior;
use crate::bayes::Posterior;
use crate::beam::{self, BeamSpec};
use crate::calibration::measured::ModeScan;
pub use crate::calibration::measured::{observables, scan_observables, Observable, Quantity};
use crate::calibration::{MeasuredData, ModeObservation, ParameterSet, Target};

thread_local! {
    /// The scratch beam of [`BeamPosterior::with_beam_at`] (one per thread).
    static SCRATCH_BEAM: std::cell::RefCell<Option<BeamSpec>> = const { std::cell::RefCell::new(None) };
}

/// Posterior over the parameter set for one measured-data file.
#[derive(Debug, Clone)]
pub struct BeamPosterior {
    base: BeamSpec,
    params: ParameterSet,
    /// Fitted modes (their numbers, 1-based).
    modes: Vec<usize>,
    observables: Vec<Observable>,
    observed: Vec<f64>,
    sd: Vec<f64>,
    /// Mode scans fitted after the modes' ω and ζ (empty: the paper's model).
    scans: Vec<ModeScan>,
    /// Highest mode number the forward model must return.
    n_modes: usize,
    beta_squared: Option<usize>,
    /// The likelihood with its normalising constant computed once (it runs at every proposal).
    likelihood: DiagonalGaussian,
    /// Internal variables whose Ω agree within this log ratio are one relaxation
    /// written twice; see [`Self::with_distinct_relaxations`]. 0 = no constraint.
    min_relaxation_log_ratio: f64,
    /// Σ −ln(upper − lower) when every prior is uniform: log π(θ) inside the
    /// support, the same terms summed in the same order as [`Posterior::log_prior`]
    /// computes them (so the same bits), without a logarithm per parameter per
    /// proposal.
    uniform_log_prior: Option<f64>,
    /// θ indices (Δᵢ, Ωᵢ) of internal variables that are exchangeable (both
    /// sampled, the same priors as every other one here): empty unless two or
    /// more are. See [`Posterior::relabel`].
    exchangeable: Vec<[usize; 2]>,
    /// θ indices [i, j] held to θ_i ≥ θ_j (a folded prior; see [`Self::with_ordered_pair`]).
    ordered: Option<[usize; 2]>,
}

impl BeamPosterior {
    /// Posterior for the fitted `modes` of `data` with parameter set `params`.
    pub fn new(data: &MeasuredData, params: ParameterSet) -> Self {
        Self::from_parts(&data.beam, &data.modes, params).with_scans(&data.mode_scans)
    }

    pub fn from_parts(base: &BeamSpec, observations: &[ModeObservation], params: ParameterSet) -> Self {
        let observables = observables(observations);
        let observed: Vec<f64> = observables.iter().map(|o| o.value).collect();
        let sd: Vec<f64> = observables.iter().map(|o| o.sd).collect();
        let likelihood = DiagonalGaussian::new(&observed, &sd);
        let beta_squared = params.beta_squared_index();
        let uniform_log_prior = params
            .params
            .iter()
            .map(|p| match p.prior {
                Prior::Uniform { lower, upper } => Some(-(upper - lower).ln()),
                _ => None,
            })
            .collect::<Option<Vec<f64>>>()
            .map(|terms| terms.into_iter().sum::<f64>());
        Self {
            uniform_log_prior,
            exchangeable: exchangeable_relaxations(&params),
            base: base.clone(),
            modes: observations.iter().map(|m| m.mode).collect(),
            n_modes: observations.iter().map(|m| m.mode).max().unwrap_or(1),
            observables,
            observed,
            sd,
            scans: Vec::new(),
            params,
            beta_squared,
            likelihood,
            min_relaxation_log_ratio: 0.0,
            ordered: None,
        }
    }

    /// Folds the prior of two parameters with the same prior onto θ_i ≥ θ_j
    /// (`pair` = [i, j]): outside the prior density is 0, inside it is twice
    /// the unfolded one (the density of the ordered pair of two i.i.d.
    /// draws), so the evidence of a likelihood symmetric under the swap is
    /// unchanged while the sampler sees one of the two mirror peaks. The
    /// caller asserts the symmetry (`diagnose`: the two end springs of a
    /// beam whose data cannot tell it from its mirror image).
    pub fn with_ordered_pair(mut self, pair: [usize; 2]) -> Self {
        debug_assert_eq!(self.params.params[pair[0]].prior, self.params.params[pair[1]].prior);
        self.ordered = Some(pair);
        self
    }

    /// Fits `scans` too: their relative amplitudes join y after the modes'
    /// ω and ζ, at one FRF factorisation per scan and proposal
    /// ([`relative_amplitudes`]). Each scan's mode must be a fitted one
    /// (`MeasuredData` validates it; a scan of another mode has no
    /// likelihood: −∞).
    pub fn with_scans(mut self, scans: &[ModeScan]) -> Self {
        if scans.is_empty() {
            return self;
        }
        let extra = scan_observables(scans);
        self.observed.extend(extra.iter().map(|o| o.value));
        self.sd.extend(extra.iter().map(|o| o.sd));
        self.observables.extend(extra);
        self.likelihood = DiagonalGaussian::new(&self.observed, &self.sd);
        self.scans = scans.to_vec();
        self
    }

    /// Restricts the model to internal variables whose relaxation rates differ
    /// by more than `log_ratio` in |ln(Ωᵢ/Ωⱼ)|: θ outside gets zero likelihood.
    /// Two variables with Ωᵢ = Ωⱼ are exactly one with Δᵢ + Δⱼ (eq. 8), so the
    /// excluded sliver only relabels models the rest of the space already
    /// holds; it is also where the poles of the coupled model cluster into
    /// nearly defective sets that the pole solvers resolve slowly (seconds
    /// instead of microseconds). The evidence loses the prior mass of the
    /// sliver: for a log-uniform Ω over a range of R nats, ≈ 2·log_ratio/R.
    pub fn with_distinct_relaxations(mut self, log_ratio: f64) -> Self {
        self.min_relaxation_log_ratio = log_ratio;
        self
    }

    fn relaxations_distinct(&self, beam: &BeamSpec) -> bool {
        let ivs = &beam.internal_variables;
        ivs.iter().enumerate().all(|(i, a)| {
            ivs[i + 1..].iter().all(|b| (a.omega_rad_s / b.omega_rad_s).ln().abs() > self.min_relaxation_log_ratio)
        })
    }

    pub fn parameters(&self) -> &ParameterSet {
        &self.params
    }

    pub fn base_beam(&self) -> &BeamSpec {
        &self.base
    }

    /// The beam that θ describes.
    pub fn beam_at(&self, theta: &[f64]) -> BeamSpec {
        self.params.apply(&self.base, theta)
    }

    /// `f` of [`Self::beam_at`]`(theta)`, built in this thread's scratch beam
    /// instead of a fresh clone (its allocation, copy and free). The scratch is reset to the
    /// base field by field before θ is applied, so it holds exactly
    /// `beam_at(theta)` whatever posterior used it before; a re-entrant call
    /// falls back to the clone.
    fn with_beam_at<R>(&self, theta: &[f64], f: impl FnOnce(&BeamSpec) -> R) -> R {
        SCRATCH_BEAM.with(|cell| match cell.try_borrow_mut() {
            Ok(mut slot) => {
                let mut ivs = slot.take().map(|b| b.internal_variables).unwrap_or_default();
                ivs.clear();
                ivs.extend_from_slice(&self.base.internal_variables);
                // every other field is Copy: if a heap field is ever added to
                // BeamSpec this stops compiling instead of sharing stale data
                let beam = slot.insert(BeamSpec { internal_variables: ivs, ..*self.base_beam() });
                self.params.apply_in_place(beam, theta);
                f(beam)
            }
            Err(_) => f(&self.beam_at(theta)),
        })
    }

    /// β at θ (1 when β² is not calibrated).
    pub fn beta_at(&self, theta: &[f64]) -> f64 {
        self.beta_squared.map_or(1.0, |i| theta[i].sqrt())
    }

    /// Predicted [ω…, ζ…] of the fitted modes at θ, then the relative
    /// amplitudes of the fitted scans (in y's order), or `None` when the
    /// model fails (invalid beam, a requested mode missing, numerical failure).
    pub fn predict(&self, theta: &[f64]) -> Option<Vec<f64>> {
        let beam = self.beam_at(theta);
        if self.scans.is_empty() {
            return predict_modes(&beam, &self.modes, self.n_modes);
        }
        self.predict_with_scans(&beam)
    }

    /// [ω…, ζ…, scan amplitudes…] of `beam`: the modes' ω and ζ by the fast
    /// path, then one FRF factorisation per scan at its mode's ω (a fitted
    /// mode's, validated with the file).
    fn predict_with_scans(&self, beam: &BeamSpec) -> Option<Vec<f64>> {
        let mut y = vec![0.0; 2 * self.modes.len()];
        if !beam::modal_observables(beam, &self.modes, self.n_modes, &mut y).ok()? {
            return None;
        }
        let omega_of = |n: usize| self.modes.iter().position(|&m| m == n).map(|k| y[k]);
        let amplitudes = relative_amplitudes(beam, &self.scans, omega_of)?;
        y.extend(amplitudes);
        Some(y)
    }

    /// The fitted mode scans.
    pub fn scans(&self) -> &[ModeScan] {
        &self.scans
    }

    /// Highest mode number the forward model computes.
    pub fn max_mode(&self) -> usize {
        self.n_modes
    }

    /// The fitted (1-based, physical) mode numbers.
    pub fn fitted_modes(&self) -> &[usize] {
        &self.modes
    }

    pub fn observed(&self) -> &[f64] {
        &self.observed
    }

    /// The fitted observables in the order of [`Self::observed`].
    pub fn observables(&self) -> &[Observable] {
        &self.observables
    }

    pub fn sd(&self) -> &[f64] {
        &self.sd
    }
}

/// The relative amplitudes of every point of `scans`, scan by scan, on
/// `beam` whose mode n has natural frequency `omega_of(n)` (rad/s): at ω_n,
/// |H(ω_n; drive, x)| over the largest among the scan's points
/// ([`relative_to_peak`]). `None` when a scanned mode's ω is unknown or the
/// response cannot be solved.
pub fn relative_amplitudes(
    beam: &BeamSpec,
    scans: &[ModeScan],
    omega_of: impl Fn(usize) -> Option<f64>,
) -> Option<Vec<f64>> {
    let mut out = Vec::with_capacity(scans.iter().map(|s| s.points.len()).sum());
    for s in scans {
        let xs: Vec<f64> = s.points.iter().map(|p| p.x_nm).collect();
        let h = beam::frf_points(beam, s.drive_x_nm, &xs, &[omega_of(s.mode)?]).ok()?;
        out.extend(relative_to_peak(&h[0])?);
    }
    Some(out)
}

/// |h_k| / max_k |h_k|; `None` when the largest is zero or not finite.
pub fn relative_to_peak(h: &[num_complex::Complex64]) -> Option<Vec<f64>> {
    let amp: Vec<f64> = h.iter().map(|z| z.norm()).collect();
    let peak = amp.iter().copied().fold(0.0, f64::max);
    (peak > 0.0 && peak.is_finite()).then(|| amp.iter().map(|v| v / peak).collect())
}

/// [ω…, ζ…] for the given 1-based modes of `beam`.
pub fn predict_modes(beam: &BeamSpec, modes: &[usize], n_modes: usize) -> Option<Vec<f64>> {
    let result = beam::modal(beam, n_modes).ok()?;
    let mut y = vec![0.0; 2 * modes.len()];
    for (k, &m) in modes.iter().enumerate() {
        let mode = result.mode(m)?;
        y[k] = mode.omega_rad_s;
        y[modes.len() + k] = mode.zeta;
    }
    Some(y)
}

/// The (Δᵢ, Ωᵢ) index pairs of θ when at least two internal variables have
/// both sampled with the same priors as each other: eq. (8) sums over the
/// variables, so relabelling them leaves the model and the prior unchanged.
/// Empty otherwise (one variable, or priors that tell them apart).
fn exchangeable_relaxations(params: &ParameterSet) -> Vec<[usize; 2]> {
    let find = |t: Target| params.params.iter().position(|p| p.target == t);
    let mut pairs = Vec::new();
    for i in 0.. {
        match (find(Target::Delta(i)), find(Target::Omega(i))) {
            (Some(d), Some(o)) => pairs.push([d, o]),
            _ => break,
        }
    }
    let prior = |k: usize| params.params[k].prior;
    let same = pairs.iter().all(|&[d, o]| prior(d) == prior(pairs[0][0]) && prior(o) == prior(pairs[0][1]));
    if pairs.len() >= 2 && same {
        pairs
    } else {
        Vec::new()
    }
}

impl Posterior for BeamPosterior {
    fn names(&self) -> Vec<String> {
        self.params.names()
    }

    /// Exchangeable internal variables in ascending Ω (the fastest-relaxing last).
    fn relabel(&self, theta: &mut [f64]) {
        if self.exchangeable.is_empty() {
            return;
        }
        let mut pairs: Vec<(f64, f64)> = self.exchangeable.iter().map(|&[d, o]| (theta[d], theta[o])).collect();
        pairs.sort_by(|a, b| a.1.total_cmp(&b.1));
        for (&[d, o], (delta, omega)) in self.exchangeable.iter().zip(pairs) {
            theta[d] = delta;
            theta[o] = omega;
        }
    }

    fn dim(&self) -> usize {
        self.params.len()
    }

    fn log_prior(&self, theta: &[f64]) -> f64 {
        let fold = match self.ordered {
            Some([i, j]) if theta[i] < theta[j] => return f64::NEG_INFINITY,
            Some(_) => std::f64::consts::LN_2,
            None => 0.0,
        };
        if let Some(lp) = self.uniform_log_prior {
            // Prior::ln_pdf of a uniform: −ln(upper − lower) inside, −∞ outside
            return if self.params.params.iter().zip(theta).all(|(p, &x)| p.prior.in_support(x)) {
                lp + fold
            } else {
                f64::NEG_INFINITY
            };
        }
        self.params.params.iter().zip(theta).map(|(p, &x)| p.prior.ln_pdf(x)).sum::<f64>() + fold
    }

    fn log_likelihood(&self, theta: &[f64]) -> f64 {
        if self.min_relaxation_log_ratio > 0.0 && !self.relaxations_distinct(&self.beam_at(theta)) {
            return f64::NEG_INFINITY;
        }
        if !self.scans.is_empty() {
            return match self.with_beam_at(theta, |beam| self.predict_with_scans(beam)) {
                Some(pred) => self.likelihood.log_likelihood(&pred, self.beta_at(theta)),
                None => f64::NEG_INFINITY,
            };
        }
        // the prediction on the stack for up to 32 modes (no allocation per proposal)
        let mut stack = [0.0; 64];
        let mut heap = Vec::new();
        let n = 2 * self.modes.len();
        let pred: &mut [f64] = if n <= stack.len() {
            &mut stack[..n]
        } else {
            heap.resize(n, 0.0);
            &mut heap
        };
        match self.with_beam_at(theta, |beam| beam::modal_observables(beam, &self.modes, self.n_modes, pred)) {
            Ok(true) => self.likelihood.log_likelihood(pred, self.beta_at(theta)),
            _ => f64::NEG_INFINITY,
        }
    }

    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
        let mut theta: Vec<f64> = self.params.params.iter().map(|p| p.prior.sample(rng)).collect();
        if let Some([i, j]) = self.ordered {
            if theta[i] < theta[j] {
                theta.swap(i, j);
            }
        }
        theta
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn data(second_omega_upper: f64) -> MeasuredData {
        MeasuredData::from_yaml(&format!(
            "beam: {{ length_nm: 8.0, diameter_nm: 1.0, youngs_modulus_pa: 1.0e12, density_kg_m3: 2300.0, \
             support: simply-supported, elements: 20, internal_variables: [{{ delta: 0.3, omega_rad_s: 1.0e11 }}, \
             {{ delta: 0.2, omega_rad_s: 1.0e12 }}] }}
modes:
  - {{ mode: 1, omega_rad_s: 8.9e11, omega_sd_rad_s: 2.7e9, zeta: 0.048, zeta_sd: 0.0015 }}
  - {{ mode: 2, omega_rad_s: 3.0e12, omega_sd_rad_s: 9.0e9, zeta: 0.016, zeta_sd: 0.0005 }}
  - {{ mode: 3, omega_rad_s: 5.5e12, omega_sd_rad_s: 1.6e10, zeta: 0.008, zeta_sd: 0.00025 }}
parameters:
  delta: {{ prior: {{ dist: uniform, lower: 0.0, upper: 1.0 }}, proposal_sd: 0.01 }}
  omega_rad_s: {{ prior: {{ dist: uniform, lower: 0.0, upper: 1.0e13 }}, proposal_sd: 1.0e10 }}
  nonlocal_e0a_nm: {{ prior: {{ dist: uniform, lower: 0.0, upper: 2.0 }}, proposal_sd: 0.01 }}
  delta_2: {{ prior: {{ dist: uniform, lower: 0.0, upper: 1.0 }}, proposal_sd: 0.01 }}
  omega_2_rad_s: {{ prior: {{ dist: uniform, lower: 0.0, upper: {second_omega_upper:e} }}, proposal_sd: 1.0e10 }}
sampler: {{ draws_per_chain: 2000, burn_in: 500, nonadaptive_draws: 200, adaptation_start: 200, covariance_skip: 100, chains: 2, seed: 1 }}
"
        ))
        .expect("valid test data")
    }

    /// Two relaxations with the same priors are put in ascending Ω, Δ moving
    /// with its Ω; the swap leaves log π unchanged (the model sums over them).
    #[test]
    fn exchangeable_relaxations_are_relabelled_in_ascending_omega() {
        let d = data(1.0e13);
        let post = BeamPosterior::new(&d, d.parameters.clone());
        // θ = [Δ₁, Ω₁, e0a, Δ₂, Ω₂] with Ω₁ > Ω₂
        let theta = vec![0.2, 2.0e12, 0.8, 0.4, 3.0e11];
        let mut relabelled = theta.clone();
        post.relabel(&mut relabelled);
        assert_eq!(relabelled, vec![0.4, 3.0e11, 0.8, 0.2, 2.0e12]);
        let (a, b) = (post.log_posterior(&theta), post.log_posterior(&relabelled));
        assert!(a.is_finite() && a == b, "{a} vs {b}");
    }

    /// Different priors tell the variables apart: no relabelling.
    #[test]
    fn relaxations_with_different_priors_keep_their_labels() {
        let d = data(5.0e12);
        let post = BeamPosterior::new(&d, d.parameters.clone());
        let mut theta = vec![0.2, 2.0e12, 0.8, 0.4, 3.0e11];
        post.relabel(&mut theta);
        assert_eq!(theta, vec![0.2, 2.0e12, 0.8, 0.4, 3.0e11]);
    }
}
