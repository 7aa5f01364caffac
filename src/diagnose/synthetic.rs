//! Seeded synthetic measured data with known hidden effects, for testing the
//! diagnosis without telling it the truth.
//!
//! Base truth: a simply-supported SWCNT-like beam (L = 8 nm, d = 1 nm,
//! E = 1 TPa, ρ = 2300 kg/m³, 20 elements) with e0a ~ U[0.8, 1.2] nm,
//! Δ ~ U[0.3, 0.6], Ω ~ log-U[1e11, 1e12] rad/s; 4–6 modes; noise of 0.3 % on
//! ω and 3 % on ζ relative to the noise-free values (§4.2, eq. 37–38).
//! Hidden: any set of the six catalogue causes, or a [`Foreign`] effect that
//! no class models. Each effect is sized, alone on the truth, so that the
//! base model cannot absorb it: the best base-model fit to the noise-free
//! data must leave some observable ≥ [`MIN_SHIFT_SIGMA`] σ away. The
//! generator checks this by fitting the base model (multi-start
//! Nelder–Mead) and grows the magnitude ×1.5 (redrawing the effect's shape
//! when a cap is reached) until true; the case then carries all its effects.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use crate::bayes::rng::{stream, Purpose};
use crate::bayes::Posterior;
use crate::beam::{BeamSpec, InternalVariable, PointMass, ShearDeformation, Support};
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

/// An effect no candidate class models (the open-world part of the tests).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Foreign {
    /// One end clamped, the other pinned, while the nominal beam is simply
    /// supported: the support spring class acts on both ends alike, so an
    /// asymmetric support is outside it (β_nL ≈ (n + ¼)π instead of nπ).
    ClampedEnd,
    /// A uniform adsorbate coating: mass per length ρA(1 + ε) with the
    /// stiffness unchanged, so every frequency drops by the same factor
    /// 1/√(1 + ε), which no class (all change modes unequally) reproduces.
    Coating,
}

impl Foreign {
    pub const ALL: [Foreign; 2] = [Foreign::ClampedEnd, Foreign::Coating];

    pub fn name(self) -> &'static str {
        match self {
            Foreign::ClampedEnd => "clamped-end",
            Foreign::Coating => "coating",
        }
    }
}

/// What a synthetic case hides: any number of catalogue causes and at most one foreign effect.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Hidden {
    pub causes: Vec<ModelClass>,
    pub foreign: Option<Foreign>,
}

impl Hidden {
    pub fn clean() -> Self {
        Self::default()
    }

    pub fn causes(causes: &[ModelClass]) -> Self {
        Self { causes: causes.to_vec(), foreign: None }
    }

    pub fn foreign(f: Foreign) -> Self {
        Self { causes: vec![], foreign: Some(f) }
    }

    /// `none`, the causes joined by `+`, or `foreign:<name>`.
    pub fn label(&self) -> String {
        match (self.foreign, self.causes.is_empty()) {
            (Some(f), _) => format!("foreign:{}", f.name()),
            (None, true) => "none".into(),
            (None, false) => self.causes.iter().map(|c| c.name()).collect::<Vec<_>>().join("+"),
        }
    }
}

/// A generated case.
#[derive(Debug, Clone)]
pub struct SyntheticCase {
    pub file: MeasuredFile,
    /// The hidden effects.
    pub hidden: Hidden,
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

/// Effect drawn by seed: clean with probability 1/7, else one of the six causes.
pub fn draw_truth(seed: u64) -> Option<ModelClass> {
    let mut rng = stream(seed, Purpose::SyntheticEffect, [0, 0]);
    let k = rng.gen_range(0..=ModelClass::CAUSES.len());
    ModelClass::CAUSES.get(k).copied()
}

fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    rng.gen_range(lo.ln()..hi.ln()).exp()
}

/// Generates the case of `seed` with one hidden cause or none.
pub fn generate(seed: u64, effect: Option<ModelClass>) -> SyntheticCase {
    generate_hidden(seed, &Hidden { causes: effect.into_iter().collect(), foreign: None })
}

/// Starting magnitude and growth cap of each effect, in the relative units of [`with_effect`].
fn magnitude_range(effect: Effect) -> (f64, f64) {
    match effect {
        Effect::Cause(ModelClass::ExtraRelaxation) => (0.03, 1.0),
        Effect::Cause(ModelClass::ViscousDamping) => (0.002, 0.3),
        Effect::Cause(ModelClass::SupportRotationalStiffness) => (0.02, 100.0),
        Effect::Cause(ModelClass::AttachedMass) => (0.005, 1.0),
        // |N|/|N_cr|: tension up to 2, compression up to 0.5 (the class's prior)
        Effect::Cause(ModelClass::AxialForce) => (0.02, 2.0),
        // 1/κ from κ = 1 down to the prior's 0.3
        Effect::Cause(ModelClass::ShearDeformation) => (1.0, 1.0 / 0.3),
        Effect::Foreign(Foreign::ClampedEnd) => (1.0, 1.0),
        Effect::Foreign(Foreign::Coating) => (0.005, 0.5),
    }
}

/// One effect to hide.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Effect {
    Cause(ModelClass),
    Foreign(Foreign),
}

/// Draws the shape of an effect (position, relaxation time, sign; 0 when it has none).
fn draw_shape(effect: Effect, clean: &[Mode], length_nm: f64, rng: &mut ChaCha8Rng) -> f64 {
    match effect {
        Effect::Cause(ModelClass::ExtraRelaxation) => {
            log_uniform(rng, clean[0].omega_rad_s, clean[clean.len() - 1].omega_rad_s)
        }
        Effect::Cause(ModelClass::AttachedMass) => rng.gen_range(0.1..0.9) * length_nm,
        // tension twice as likely as compression
        Effect::Cause(ModelClass::AxialForce) => {
            if rng.gen_range(0..3) < 2 {
                1.0
            } else {
                -1.0
            }
        }
        _ => 0.0,
    }
}

/// Generates the case of `seed` hiding `hidden`. Every effect alone is grown
/// until the best base fit misses some observable by ≥ [`MIN_SHIFT_SIGMA`];
/// the case then carries all of them at once.
pub fn generate_hidden(seed: u64, hidden: &Hidden) -> SyntheticCase {
    let mut rng = stream(seed, Purpose::SyntheticCase, [0, 0]);
    let n_modes = rng.gen_range(4..=6);
    let effects: Vec<Effect> =
        hidden.causes.iter().map(|&c| Effect::Cause(c)).chain(hidden.foreign.map(Effect::Foreign)).collect();
    'truth: loop {
        let mut truth = nominal_beam();
        truth.nonlocal_e0a_nm = rng.gen_range(0.8..1.2);
        truth.internal_variables =
            vec![InternalVariable { delta: rng.gen_range(0.3..0.6), omega_rad_s: log_uniform(&mut rng, 1e11, 1e12) }];
        let Ok(clean) = predict(&truth, n_modes) else { continue };
        let scales = NominalScales::of(&truth, n_modes).expect("nominal beam computes");
        let mut combined = truth.clone();
        for &effect in &effects {
            let Some((shape, mag)) = visible_effect(seed, effect, &truth, &clean, &scales, &mut rng) else {
                continue 'truth;
            };
            combined = with_effect(&combined, effect, shape, mag, &scales);
        }
        let Ok(y0) = predict(&combined, n_modes) else { continue };
        let z = base_fit_max_z(&y0, &truth, &scales, seed);
        return finish(seed, combined, y0, hidden.clone(), z, &mut rng);
    }
}

/// (shape, magnitude) of `effect` on `truth` that the base model cannot
/// absorb, growing the magnitude ×1.5 up to its cap and redrawing the shape
/// (at most 6 times) when the cap is reached; `None` gives up on this truth.
fn visible_effect(
    seed: u64,
    effect: Effect,
    truth: &BeamSpec,
    clean: &[Mode],
    scales: &NominalScales,
    rng: &mut ChaCha8Rng,
) -> Option<(f64, f64)> {
    for _ in 0..6 {
        let (mut mag, cap) = magnitude_range(effect);
        let shape = draw_shape(effect, clean, truth.length_nm, rng);
        // compression is capped at half the buckling load (the class prior)
        let cap = if shape < 0.0 { cap.min(0.5) } else { cap };
        while mag <= cap * (1.0 + 1e-12) {
            let b = with_effect(truth, effect, shape, mag, scales);
            if let Ok(y0) = predict(&b, clean.len()) {
                if base_fit_max_z(&y0, truth, scales, seed) >= MIN_SHIFT_SIGMA {
                    return Some((shape, mag));
                }
            }
            mag *= 1.5;
        }
    }
    None
}

/// The beam with `effect` at `mag` (relative units of [`super::classes`]).
fn with_effect(base: &BeamSpec, effect: Effect, shape: f64, mag: f64, s: &NominalScales) -> BeamSpec {
    let mut b = base.clone();
    match effect {
        Effect::Cause(ModelClass::ExtraRelaxation) => {
            b.internal_variables.push(InternalVariable { delta: mag, omega_rad_s: shape })
        }
        Effect::Cause(ModelClass::ViscousDamping) => {
            b.viscous_damping_n_s_m2 = 2.0 * s.rho_a_kg_m * s.omega_1_rad_s * mag
        }
        Effect::Cause(ModelClass::SupportRotationalStiffness) => {
            b.support_rotational_stiffness_n_m_rad = mag * s.ei_n_m2 / s.length_m
        }
        Effect::Cause(ModelClass::AttachedMass) => {
            b.point_mass = Some(PointMass { mass_kg: mag * s.rho_a_kg_m * s.length_m, x_nm: shape })
        }
        Effect::Cause(ModelClass::AxialForce) => b.axial_force_n = shape * mag * s.buckling_load_n,
        Effect::Cause(ModelClass::ShearDeformation) => {
            b.shear_deformation = Some(ShearDeformation {
                poisson_ratio: crate::calibration::parameters::DEFAULT_POISSON_RATIO,
                shear_coefficient: 1.0 / mag,
            })
        }
        Effect::Foreign(Foreign::ClampedEnd) => b.support = Support::ClampedPinned,
        Effect::Foreign(Foreign::Coating) => b.density_kg_m3 *= 1.0 + mag,
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

fn finish(seed: u64, truth: BeamSpec, y0: Vec<Mode>, hidden: Hidden, z: f64, rng: &mut ChaCha8Rng) -> SyntheticCase {
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
    SyntheticCase { file, hidden, truth_beam: truth, base_fit_max_z: z }
}
