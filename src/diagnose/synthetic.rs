//! Seeded synthetic measured data with a known hidden effect, for testing the
//! diagnosis without telling it the truth.
//!
//! Base truth: a simply-supported SWCNT-like beam (L = 8 nm, d = 1 nm,
//! E = 1 TPa, ρ = 2300 kg/m³, 20 elements) with e0a ~ U[0.8, 1.2] nm,
//! Δ ~ U[0.3, 0.6], Ω ~ log-U[1e11, 1e12] rad/s; 4–6 modes; noise of 0.3 % on
//! ω and 3 % on ζ relative to the noise-free values (§4.2, eq. 37–38).
//! An effect (one of the four causes) is added at a magnitude that the base
//! model cannot absorb: the best base-model fit to the noise-free truth must
//! leave some observable ≥ [`MIN_SHIFT_SIGMA`] σ away. The generator checks
//! this by fitting the base model (multi-start Nelder–Mead) and grows the
//! magnitude ×1.5 (redrawing the effect's shape when a cap is reached) until true.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use crate::bayes::rng::{stream, Purpose};
use crate::bayes::Posterior;
use crate::beam::{BeamSpec, InternalVariable, PointMass, Support};
use crate::calibration::measured::MeasuredFile;
use crate::calibration::{DramSettings, MeasuredData, ModeObservation, ParameterSet};

use super::{model_posterior, Model, ModelClass, NominalScales};
use crate::bayes::map::map_estimate;
use crate::beam::{self, Mode};

/// Minimum misfit, in measurement sds, the hidden effect must leave in the best base fit.
pub const MIN_SHIFT_SIGMA: f64 = 5.0;
/// Relative measurement sds (§4.2): 0.3 % on ω, 3 % on ζ.
pub const OMEGA_REL_SD: f64 = 0.003;
pub const ZETA_REL_SD: f64 = 0.03;

/// A generated case.
#[derive(Debug, Clone)]
pub struct SyntheticCase {
    pub file: MeasuredFile,
    /// The hidden effect (`None`: clean truth).
    pub truth: Option<ModelClass>,
    pub truth_beam: BeamSpec,
    /// max_j |y0_j − ŷ_j(θ̂_base)| / σ_j of the best base fit to the noise-free truth.
    pub base_fit_max_z: f64,
}

impl SyntheticCase {
    pub fn data(&self) -> MeasuredData {
        MeasuredData::from_file(self.file.clone()).expect("generated data are valid")
    }
}

/// The nominal beam the diagnosis sees (geometry and material only).
pub fn nominal_beam() -> BeamSpec {
    BeamSpec::elastic(8.0, 1.0, 1.0e12, 2300.0, Support::SimplySupported, 20)
}

/// Effect drawn by seed: clean with probability 1/5, else one of the four causes.
pub fn draw_truth(seed: u64) -> Option<ModelClass> {
    let mut rng = stream(seed, Purpose::SyntheticEffect, [0, 0]);
    let k = rng.gen_range(0..5);
    (k < 4).then(|| ModelClass::CAUSES[k])
}

fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    rng.gen_range(lo.ln()..hi.ln()).exp()
}

/// Generates the case of `seed` with the given hidden effect (`None` = clean).
pub fn generate(seed: u64, effect: Option<ModelClass>) -> SyntheticCase {
    let mut rng = stream(seed, Purpose::SyntheticCase, [0, 0]);
    let n_modes = rng.gen_range(4..=6);
    'truth: loop {
        let mut truth = nominal_beam();
        truth.nonlocal_e0a_nm = rng.gen_range(0.8..1.2);
        truth.internal_variables =
            vec![InternalVariable { delta: rng.gen_range(0.3..0.6), omega_rad_s: log_uniform(&mut rng, 1e11, 1e12) }];
        let Ok(clean) = predict(&truth, n_modes) else { continue };
        let scales = NominalScales::of(&truth, n_modes).expect("nominal beam computes");
        if let Some(class) = effect {
            // (shape, magnitude, growth cap)
            let mut tries = 0;
            loop {
                tries += 1;
                if tries > 6 {
                    continue 'truth;
                }
                let (mut mag, cap) = match class {
                    ModelClass::ExtraRelaxation => (0.03, 1.0),
                    ModelClass::ViscousDamping => (0.002, 0.3),
                    ModelClass::SupportRotationalStiffness => (0.02, 100.0),
                    ModelClass::AttachedMass => (0.005, 1.0),
                };
                let shape = match class {
                    ModelClass::ExtraRelaxation => {
                        log_uniform(&mut rng, clean[0].omega_rad_s, clean[n_modes - 1].omega_rad_s)
                    }
                    ModelClass::AttachedMass => rng.gen_range(0.1..0.9) * truth.length_nm,
                    _ => 0.0,
                };
                while mag <= cap {
                    let b = with_effect(&truth, class, shape, mag, &scales);
                    if let Ok(y0) = predict(&b, n_modes) {
                        let z = base_fit_max_z(&y0, &truth, &scales, seed);
                        if z >= MIN_SHIFT_SIGMA {
                            return finish(seed, b, y0, Some(class), z, &mut rng);
                        }
                    }
                    mag *= 1.5;
                }
            }
        }
        let fit_z = base_fit_max_z(&clean, &truth, &scales, seed);
        return finish(seed, truth, clean, None, fit_z, &mut rng);
    }
}

/// The truth with the effect at `mag` (relative units of [`super::classes`]).
fn with_effect(base: &BeamSpec, class: ModelClass, shape: f64, mag: f64, s: &NominalScales) -> BeamSpec {
    let mut b = base.clone();
    match class {
        ModelClass::ExtraRelaxation => b.internal_variables.push(InternalVariable { delta: mag, omega_rad_s: shape }),
        ModelClass::ViscousDamping => b.viscous_damping_n_s_m2 = 2.0 * s.rho_a_kg_m * s.omega_1_rad_s * mag,
        ModelClass::SupportRotationalStiffness => b.support_rotational_stiffness_n_m_rad = mag * s.ei_n_m2 / s.length_m,
        ModelClass::AttachedMass => {
            b.point_mass = Some(PointMass { mass_kg: mag * s.rho_a_kg_m * s.length_m, x_nm: shape })
        }
    }
    b
}

/// The first `n_modes` modes of `beam`.
fn predict(beam: &BeamSpec, n_modes: usize) -> Result<Vec<Mode>, beam::BeamError> {
    beam::modal(beam, n_modes).map(|r| r.modes)
}

fn observations(y: &[Mode]) -> Vec<ModeObservation> {
    y.iter()
        .enumerate()
        .map(|(r, m)| ModeObservation {
            mode: r + 1,
            omega_rad_s: m.omega_rad_s,
            omega_sd_rad_s: OMEGA_REL_SD * m.omega_rad_s,
            zeta: m.zeta,
            zeta_sd: ZETA_REL_SD * m.zeta,
        })
        .collect()
}

/// Best base-model fit to noise-free `y0`: 128 prior draws plus the truth's
/// own base parameters screened, Nelder–Mead from the best 3; returns the
/// largest standardized residual.
fn base_fit_max_z(y0: &[Mode], truth: &BeamSpec, s: &NominalScales, seed: u64) -> f64 {
    let post = model_posterior(&Model::BASE, &ParameterSet::paper_n1(), &nominal_beam(), &observations(y0), s);
    let mut rng = stream(seed, Purpose::SyntheticBaseFit, [0, 0]);
    let iv = truth.internal_variables[0];
    let mut starts = vec![vec![truth.nonlocal_e0a_nm, iv.delta, iv.omega_rad_s]];
    starts.extend((0..128).map(|_| post.sample_prior(&mut rng)));
    let mut scored: Vec<(f64, Vec<f64>)> = starts.into_iter().map(|u| (post.log_posterior(&u), u)).collect();
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    let sd = [0.05, 0.05, 0.05e12];
    let best = scored
        .iter()
        .take(3)
        .map(|(_, u)| map_estimate(&post, u, &sd, 600))
        .max_by(|a, b| a.log_posterior.total_cmp(&b.log_posterior))
        .expect("starts");
    let Some(fit) = post.inner().predict(&post.to_inner(&best.theta)) else { return f64::INFINITY };
    let obs = post.inner();
    obs.observed().iter().zip(obs.sd()).zip(&fit).map(|((y, sd), f)| ((y - f) / sd).abs()).fold(0.0, f64::max)
}

fn finish(
    seed: u64,
    truth: BeamSpec,
    y0: Vec<Mode>,
    effect: Option<ModelClass>,
    z: f64,
    rng: &mut ChaCha8Rng,
) -> SyntheticCase {
    let mut modes = observations(&y0);
    for m in &mut modes {
        let e1: f64 = StandardNormal.sample(rng);
        let e2: f64 = StandardNormal.sample(rng);
        m.omega_rad_s += e1 * m.omega_sd_rad_s;
        m.zeta += e2 * m.zeta_sd;
    }
    let file = MeasuredFile {
        beam: nominal_beam(),
        modes,
        held_out_modes: vec![],
        parameters: None,
        sampler: Some(DramSettings { seed, ..DramSettings::default() }),
    };
    SyntheticCase { file, truth: effect, truth_beam: truth, base_fit_max_z: z }
}
