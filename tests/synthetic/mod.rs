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
//! when a cap is reached) until true; a foreign effect grows further, until
//! no catalogue model of one or two causes fits it either. The case then
//! carries all its effects, and in a case of several causes each is grown
//! further until the model of the other causes cannot absorb it either
//! ([`generate_hidden`]).
//!
//! Test code, not part of the library: the integration tests that need
//! hidden-effect data include it with `mod synthetic;`. It uses the library's
//! public API only (the section-effect solver [`section_modes`] builds its
//! own pencil from the public element integrals).
#![allow(dead_code)] // each test binary uses part of it

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use nanobeam::bayes::map::map_estimate;
use nanobeam::bayes::rng::{stream, Purpose};
use nanobeam::bayes::transform::Coordinate;
use nanobeam::bayes::Posterior;
use nanobeam::beam::{self, BeamSpec, InternalVariable, Mode, PointMass, ShearDeformation, Support};
use nanobeam::calibration::measured::MeasuredFile;
use nanobeam::calibration::{DramSettings, MeasuredData, ModeObservation, ParameterSet};
use nanobeam::diagnose::classes::model_parameters;
use nanobeam::diagnose::{model_posterior, ClassPosterior, Model, ModelClass, NominalScales};
use num_complex::Complex64;

/// Minimum misfit, in measurement sds, the hidden effect must leave in the best base fit.
pub const MIN_SHIFT_SIGMA: f64 = 5.0;
/// Relative measurement sds (§4.2): 0.3 % on ω, 3 % on ζ.
pub const OMEGA_REL_SD: f64 = 0.003;
pub const ZETA_REL_SD: f64 = 0.03;

/// An effect no candidate class models (the open-world part of the tests).
/// The generator grows it until no catalogue model of at most two causes
/// fits the noise-free data: see [`generate_hidden`].
///
/// Three other candidates were tried and dropped because the catalogue fits
/// them (the generator could not make any unfittable within its cap):
/// a hysteretic loss factor (ζ raised alike on every mode: two relaxations
/// and viscous damping reproduce a flat ζ over the 1.5 decades of 6 modes
/// up to η = 0.2), a uniform coating (every frequency × 1/√(1 + ε):
/// e0a and an axial compression together make a near-uniform drop) and a
/// linear taper d(x) = d₀(1 + t(x/L − ½)) up to t = 1 (EI ∝ d⁴, ρA ∝ d²;
/// on a simply supported beam its effect is even in t and smooth in n,
/// four seeds of four gave up).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Foreign {
    /// An avoided crossing of one beam mode with a lossy resonance outside
    /// the beam (a clamp or substrate mode, ζ = [`CLAMP_MODE_ZETA`], detuned
    /// by 2–8 %): that mode alone shifts and borrows damping, which no
    /// smooth-in-n class reproduces.
    ModeCoupling,
    /// A local bending-stiffness defect (a vacancy cluster, a kink): EI
    /// lowered by a fraction ε over 1–3 adjacent elements (0.4–1.2 nm) at a
    /// random place. To first order it lowers ω_n like a point mass does
    /// (both ∝ sin²(nπx/L) on a simply supported beam), but averaged over
    /// its length, which a point mass is not once half a wavelength spans it.
    LocalDefect,
}

/// Damping ratio of the external resonance in [`Foreign::ModeCoupling`]
/// (a support mode radiating into the substrate: an order of magnitude
/// lossier than the beam's higher modes).
pub const CLAMP_MODE_ZETA: f64 = 0.05;

impl Foreign {
    pub const ALL: [Foreign; 2] = [Foreign::ModeCoupling, Foreign::LocalDefect];

    pub fn name(self) -> &'static str {
        match self {
            Foreign::ModeCoupling => "mode-coupling",
            Foreign::LocalDefect => "local-defect",
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
    /// The observations before the noise is drawn (the truth's ω and ζ, the
    /// same sds): the data's expectation. Its diagnosis says what the
    /// effects' sizes support without the luck of one noise draw.
    pub noise_free: Vec<ModeObservation>,
}

impl SyntheticCase {
    pub fn data(&self) -> MeasuredData {
        MeasuredData::from_file(self.file.clone()).expect("generated data are valid")
    }

    /// [`Self::data`] with the [`Self::noise_free`] observations.
    pub fn noise_free_data(&self) -> MeasuredData {
        let file = MeasuredFile { modes: self.noise_free.clone(), ..self.file.clone() };
        MeasuredData::from_file(file).expect("generated data are valid")
    }
}

/// The nominal beam the diagnosis sees (geometry and material only).
pub fn nominal_beam() -> BeamSpec {
    BeamSpec::elastic(8.0, 1.0, 1.0e12, 2300.0, Support::SimplySupported, 20)
}

/// How many of [`ModelClass::CAUSES`] (the first) [`draw_truth`] draws: the
/// seven the suites were drawn from before `elastic-foundation` joined the
/// catalogue, so every earlier seed keeps its truth.
const DRAWN_CAUSES: usize = 7;

/// Effect drawn by seed: clean with probability 1/8, else one of the first seven causes.
pub fn draw_truth(seed: u64) -> Option<ModelClass> {
    let mut rng = stream(seed, Purpose::SyntheticEffect, [0, 0]);
    let k = rng.gen_range(0..=DRAWN_CAUSES);
    ModelClass::CAUSES[..DRAWN_CAUSES].get(k).copied()
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
        // f − 1 of a stiffness-to-mass factor f, up to the class's prior 3/2
        Effect::Cause(ModelClass::SectionMismatch) => (0.01, 0.5),
        // |k|/(ρAω₁⁰²): a substrate up to 5, a gate's pull up to 0.5
        Effect::Cause(ModelClass::ElasticFoundation) => (0.02, 5.0),
        // η (ζ ≈ η/2 on every mode), up to the class's prior 0.6
        Effect::Cause(ModelClass::LossFactor) => (0.002, 0.6),
        // l·q_max (q_max the highest mode's wavenumber), up to 3 of the class's prior 10
        Effect::Cause(ModelClass::StrainGradient) => (0.02, 3.0),
        // coupling g (fraction of the geometric mean of the two squared frequencies);
        // beyond 0.1 the two resonances hybridize and "the beam mode" loses its meaning
        Effect::Foreign(Foreign::ModeCoupling) => (0.005, 0.1),
        // ε, the fraction of EI lost; 0.9 leaves a tenth of the section's stiffness
        Effect::Foreign(Foreign::LocalDefect) => (0.05, 0.9),
    }
}

/// The growth cap of `effect` with `shape`: [`magnitude_range`]'s, but a
/// compression is capped at half the buckling load (the class's prior), a gate's pull at half
/// the first mode's stiffness.
fn magnitude_cap(effect: Effect, shape: [f64; 2]) -> f64 {
    let (_, cap) = magnitude_range(effect);
    let pull = matches!(effect, Effect::Cause(ModelClass::AxialForce | ModelClass::ElasticFoundation));
    if pull && shape[0] < 0.0 {
        cap.min(0.5)
    } else {
        cap
    }
}

/// One effect to hide.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Effect {
    Cause(ModelClass),
    Foreign(Foreign),
}

/// Draws the shape of an effect: [position, relaxation time or sign; second
/// number], 0 where it has none.
fn draw_shape(effect: Effect, clean: &[Mode], length_nm: f64, rng: &mut ChaCha8Rng) -> [f64; 2] {
    match effect {
        Effect::Cause(ModelClass::ExtraRelaxation) => {
            [log_uniform(rng, clean[0].omega_rad_s, clean[clean.len() - 1].omega_rad_s), 0.0]
        }
        Effect::Cause(ModelClass::AttachedMass) => [rng.gen_range(0.1..0.9) * length_nm, 0.0],
        // tension twice as likely as compression
        Effect::Cause(ModelClass::AxialForce) => [if rng.gen_range(0..3) < 2 { 1.0 } else { -1.0 }, 0.0],
        // a substrate or a gate's pull, alike
        Effect::Cause(ModelClass::ElasticFoundation) => [if rng.gen_range(0..2) == 0 { 1.0 } else { -1.0 }, 0.0],
        // [the coupled mode (2..=n), the clamp mode's relative detuning ±(2–8 %)]
        Effect::Foreign(Foreign::ModeCoupling) => {
            let mode = rng.gen_range(2..=clean.len()) as f64;
            let sign = if rng.gen_range(0..2) == 0 { 1.0 } else { -1.0 };
            [mode, sign * rng.gen_range(0.02..0.08)]
        }
        // [first element, width in elements (1–3)]
        Effect::Foreign(Foreign::LocalDefect) => {
            let width = rng.gen_range(1..=3usize);
            let elements = nominal_beam().elements;
            [rng.gen_range(0..=elements - width) as f64, width as f64]
        }
        _ => [0.0, 0.0],
    }
}

/// A truth: the beam, and the effects that act on its modes rather than on a beam parameter.
#[derive(Debug, Clone)]
pub struct Truth {
    pub beam: BeamSpec,
    pub modal: Vec<(Foreign, [f64; 2], f64)>,
}

/// Generates the case of `seed` hiding `hidden`. Every effect alone is grown
/// until the best base fit misses some observable by ≥ [`MIN_SHIFT_SIGMA`];
/// a foreign effect further until the best fit of every catalogue model of
/// one or two causes does too ([`catalogue_fits`]): the issue's "no
/// class or pair of classes fits". Several causes are then grown until each
/// is visible against the model of the others ([`each_cause_visible`]).
/// The case carries all its effects.
///
/// Panics when 50 truths in a row admit no such effect (a generator that
/// cannot build the case it was asked for; never reached by the tests' seeds).
pub fn generate_hidden(seed: u64, hidden: &Hidden) -> SyntheticCase {
    let mut rng = stream(seed, Purpose::SyntheticCase, [0, 0]);
    let n_modes = rng.gen_range(4..=6);
    let effects: Vec<Effect> =
        hidden.causes.iter().map(|&c| Effect::Cause(c)).chain(hidden.foreign.map(Effect::Foreign)).collect();
    for _ in 0..50 {
        let mut beam = nominal_beam();
        beam.nonlocal_e0a_nm = rng.gen_range(0.8..1.2);
        beam.internal_variables =
            vec![InternalVariable { delta: rng.gen_range(0.3..0.6), omega_rad_s: log_uniform(&mut rng, 1e11, 1e12) }];
        let truth = Truth { beam, modal: vec![] };
        let Ok(clean) = predict(&truth, n_modes) else { continue };
        let scales = NominalScales::of(&truth.beam, n_modes).expect("nominal beam computes");
        let sized: Option<Vec<Sized>> = effects
            .iter()
            .map(|&effect| {
                visible_effect(seed, effect, &truth, &clean, &scales, &mut rng).map(|(shape, mag)| Sized {
                    effect,
                    shape,
                    mag,
                })
            })
            .collect();
        let Some(mut sized) = sized else { continue };
        if hidden.causes.len() >= 2 && hidden.foreign.is_none() {
            let Some(grown) = each_cause_visible(seed, sized, &truth, n_modes, &scales) else { continue };
            sized = grown;
        }
        let combined = with_all(&truth, &sized, &scales);
        let Ok(y0) = predict(&combined, n_modes) else { continue };
        let z = base_fit_max_z(&y0, &truth.beam, &scales, seed);
        return finish(seed, combined.beam, y0, hidden.clone(), z, &mut rng);
    }
    panic!("synthetic::generate_hidden: no truth of seed {seed} admits {}", hidden.label());
}

/// One effect of a case with its drawn shape and grown magnitude.
#[derive(Debug, Clone, Copy)]
struct Sized {
    effect: Effect,
    shape: [f64; 2],
    mag: f64,
}

/// `truth` carrying every effect of `sized`.
fn with_all(truth: &Truth, sized: &[Sized], s: &NominalScales) -> Truth {
    sized.iter().fold(truth.clone(), |t, e| with_effect(&t, e.effect, e.shape, e.mag, s))
}

/// Growth rounds [`each_cause_visible`] allows before it gives the truth up.
const MAX_SEPARATION_ROUNDS: usize = 12;

/// Grows the causes of a several-cause case until each is visible against
/// the others: for every cause, the best fit of the model of the *other*
/// causes ([`model_fit_max_z`]) to the combined noise-free data misses some
/// observable by ≥ [`MIN_SHIFT_SIGMA`]. It is the issue's "each effect
/// moves some observable ≥ 5 σ against the best base fit" with the base of
/// an effect in a pair being the model that has everything but it: a cause
/// the other cause's parameters absorb to within 5 σ moves nothing the data
/// can see. The first cause that fails grows ×1.5 and every cause is
/// checked again; `None` when a cause reaches its cap or
/// [`MAX_SEPARATION_ROUNDS`] pass (the truth is redrawn). A local search
/// that misses the other model's best fit leaves a cause looking visible
/// when it is not: the case is then harder than the rule asks, never easier.
///
/// Rival models that share no cause with the truth are not checked: a rival
/// pair that fits as well is a genuine ambiguity the diagnosis must report
/// (alternatives, next measurement), not one the generator removes.
fn each_cause_visible(
    seed: u64,
    mut sized: Vec<Sized>,
    truth: &Truth,
    n_modes: usize,
    s: &NominalScales,
) -> Option<Vec<Sized>> {
    let causes: Vec<ModelClass> = sized
        .iter()
        .filter_map(|e| match e.effect {
            Effect::Cause(c) => Some(c),
            Effect::Foreign(_) => None,
        })
        .collect();
    let truth_model = Model::with(&causes);
    for _ in 0..MAX_SEPARATION_ROUNDS {
        let y0 = predict(&with_all(truth, &sized, s), n_modes).ok()?;
        let absorbed = sized.iter().position(|e| {
            let Effect::Cause(c) = e.effect else { return false };
            model_fit_max_z(&truth_model.without(c), &y0, &truth.beam, s, seed) < MIN_SHIFT_SIGMA
        });
        let Some(i) = absorbed else { return Some(sized) };
        sized[i].mag *= 1.5;
        if sized[i].mag > magnitude_cap(sized[i].effect, sized[i].shape) * (1.0 + 1e-12) {
            return None;
        }
    }
    None
}

/// (shape, magnitude) of `effect` on `truth` that the base model cannot
/// absorb (and, for a foreign effect, no catalogue model of ≤ 2 causes),
/// growing the magnitude ×1.5 up to its cap and redrawing the shape (at most
/// 6 times) when the cap is reached; `None` gives up on this truth.
fn visible_effect(
    seed: u64,
    effect: Effect,
    truth: &Truth,
    clean: &[Mode],
    scales: &NominalScales,
    rng: &mut ChaCha8Rng,
) -> Option<([f64; 2], f64)> {
    for _ in 0..6 {
        let (mut mag, _) = magnitude_range(effect);
        let shape = draw_shape(effect, clean, truth.beam.length_nm, rng);
        let cap = magnitude_cap(effect, shape);
        while mag <= cap * (1.0 + 1e-12) {
            let b = with_effect(truth, effect, shape, mag, scales);
            if let Ok(y0) = predict(&b, clean.len()) {
                if base_fit_max_z(&y0, &truth.beam, scales, seed) >= MIN_SHIFT_SIGMA
                    && (matches!(effect, Effect::Cause(_)) || !catalogue_fits(&y0, &truth.beam, scales, seed))
                {
                    return Some((shape, mag));
                }
            }
            mag *= 1.5;
        }
    }
    None
}

/// The truth with `effect` at `mag` (relative units of `nanobeam::diagnose::classes`).
fn with_effect(base: &Truth, effect: Effect, shape: [f64; 2], mag: f64, s: &NominalScales) -> Truth {
    let mut t = base.clone();
    let b = &mut t.beam;
    match effect {
        Effect::Cause(ModelClass::ExtraRelaxation) => {
            b.internal_variables.push(InternalVariable { delta: mag, omega_rad_s: shape[0] })
        }
        Effect::Cause(ModelClass::ViscousDamping) => {
            b.viscous_damping_n_s_m2 = 2.0 * s.rho_a_kg_m * s.omega_1_rad_s * mag
        }
        Effect::Cause(ModelClass::SupportRotationalStiffness) => {
            b.support_rotational_stiffness_n_m_rad = mag * s.ei_n_m2 / s.length_m
        }
        Effect::Cause(ModelClass::AttachedMass) => {
            b.point_mass = Some(PointMass { mass_kg: mag * s.rho_a_kg_m * s.length_m, x_nm: shape[0] })
        }
        Effect::Cause(ModelClass::AxialForce) => b.axial_force_n = shape[0] * mag * s.buckling_load_n,
        Effect::Cause(ModelClass::ShearDeformation) => {
            b.shear_deformation = Some(ShearDeformation {
                poisson_ratio: nanobeam::calibration::parameters::DEFAULT_POISSON_RATIO,
                shear_coefficient: 1.0 / mag,
            })
        }
        Effect::Cause(ModelClass::SectionMismatch) => b.youngs_modulus_pa *= 1.0 + mag,
        Effect::Cause(ModelClass::ElasticFoundation) => {
            b.elastic_foundation_n_m2 = shape[0] * mag * s.rho_a_kg_m * s.omega_1_rad_s * s.omega_1_rad_s
        }
        Effect::Cause(ModelClass::LossFactor) => b.loss_factor = mag,
        Effect::Cause(ModelClass::StrainGradient) => {
            let q_max_per_nm = (s.rho_a_kg_m * s.omega_max_rad_s * s.omega_max_rad_s / s.ei_n_m2).powf(0.25) * 1e-9;
            b.strain_gradient_length_nm = mag / q_max_per_nm
        }
        Effect::Foreign(f) => t.modal.push((f, shape, mag)),
    }
    t
}

/// The first `n_modes` modes of `truth`: the beam's (through
/// [`section_modes`] when a section effect is present), then its modal effects.
pub fn predict(truth: &Truth, n_modes: usize) -> Result<Vec<Mode>, beam::BeamError> {
    let defects: Vec<(&[f64; 2], f64)> =
        truth.modal.iter().filter(|(f, ..)| *f == Foreign::LocalDefect).map(|(_, shape, mag)| (shape, *mag)).collect();
    let mut modes = if defects.is_empty() {
        beam::modal(&truth.beam, n_modes)?.modes
    } else {
        let mut section = vec![1.0; truth.beam.elements];
        for (shape, mag) in defects {
            for (e, ei) in section.iter_mut().enumerate() {
                if (shape[0]..shape[0] + shape[1]).contains(&(e as f64)) {
                    *ei *= 1.0 - mag;
                }
            }
        }
        section_modes(&truth.beam, &section, n_modes)?
    };
    for &(effect, shape, mag) in &truth.modal {
        if effect == Foreign::ModeCoupling {
            let m = &mut modes[shape[0] as usize - 1];
            set_pole(m, coupled_pole(m.pole, shape[1], mag));
        }
    }
    Ok(modes)
}

/// The first `n_modes` modes of a beam whose element e has bending stiffness
/// EI·`section[e]`: Hermite elements (A4–A6, the library's public
/// `beam::element` integrals) with those factors (mass and Eringen's
/// operator on the inertia unchanged), every element relaxing alike (eq. 8).
/// The product has no non-uniform section, so this is the generator's own
/// truth, not a model the diagnosis could use. Only the base truth's
/// mechanisms are allowed (nonlocality and internal variables): the pencil
/// then decouples, each undamped eigenpair λ_j of (K̃, M̃) (dense Cholesky +
/// symmetric eigensolver; 40 DOFs) giving the family s̃² + λ_j G(s̃) = 0,
/// the relaxation factor G being the same in every element. The family's
/// roots come from the eigenvalues of its polynomial's companion matrix,
/// polished by Newton ([`family_poles`]), not from the library's root solver,
/// so the generator shares only the element integrals with what it tests.
pub fn section_modes(beam: &BeamSpec, section: &[f64], n_modes: usize) -> Result<Vec<Mode>, beam::BeamError> {
    use nanobeam::beam::element;
    let plain = beam.viscous_damping_n_s_m2 == 0.0
        && beam.support_rotational_stiffness_n_m_rad == 0.0
        && beam.axial_force_n == 0.0
        && beam.point_mass.is_none()
        && beam.shear_deformation.is_none();
    if !plain || section.len() != beam.elements {
        return Err(beam::BeamError::Numerical("a section effect combines with the base truth only".into()));
    }
    let dof_map = dof_map(beam.elements, beam.support);
    let n = dof_map.iter().flatten().count();
    // the dimensionless scaling of the paper's equations: ẽ = e0a/L,
    // ω_ref = √(EI/ρA)/L² (lengths in nm in the spec)
    let l = beam.length_nm * 1e-9;
    let ei = beam.youngs_modulus_pa * beam.inertia_m4();
    let rho_a = beam.density_kg_m3 * beam.area_m2();
    let omega_ref = (ei / rho_a).sqrt() / (l * l);
    let e_tilde = beam.nonlocal_e0a_nm / beam.length_nm;
    let e2 = e_tilde * e_tilde;
    let h = 1.0 / beam.elements as f64;
    let (ke, me, se) = (element::curvature_integral(h), element::mass_integral(h), element::slope_integral(h));
    let (mut k, mut m) = (nalgebra::DMatrix::<f64>::zeros(n, n), nalgebra::DMatrix::<f64>::zeros(n, n));
    for (e, &ei) in section.iter().enumerate() {
        for a in 0..4 {
            let Some(i) = dof_map[2 * e + a] else { continue };
            for b in 0..4 {
                let Some(j) = dof_map[2 * e + b] else { continue };
                k[(i, j)] += ei * ke[a][b];
                m[(i, j)] += me[a][b] + e2 * se[a][b];
            }
        }
    }
    let l = m.cholesky().ok_or_else(|| beam::BeamError::Numerical("section mass not positive definite".into()))?;
    let linv = l.l().try_inverse().ok_or_else(|| beam::BeamError::Numerical("singular Cholesky factor".into()))?;
    let a = &linv * k * linv.transpose();
    let sym = (&a + a.transpose()) * 0.5;
    let mut lambda: Vec<f64> = nalgebra::SymmetricEigen::new(sym).eigenvalues.iter().copied().collect();
    lambda.sort_by(f64::total_cmp);
    let ivs: Vec<(f64, f64)> = beam
        .internal_variables
        .iter()
        .filter(|iv| iv.delta > 0.0)
        .map(|iv| (iv.delta, iv.omega_rad_s / omega_ref))
        .collect();
    lambda
        .iter()
        .take(n_modes)
        .enumerate()
        .map(|(r, &lam)| {
            let s = family_poles(lam, &ivs)
                .into_iter()
                .filter(|s| s.im > 0.0)
                .max_by(|a, b| a.norm_sqr().total_cmp(&b.norm_sqr()))
                .ok_or_else(|| beam::BeamError::Numerical(format!("mode {} is overdamped", r + 1)))?;
            let pole = s * omega_ref;
            Ok(Mode { mode: r + 1, omega_rad_s: pole.norm(), zeta: -pole.re / pole.norm(), pole })
        })
        .collect()
}

/// Free DOF index of each global Hermite DOF (w, w′ per node) of `elements`
/// elements on [0, 1], `None` where `support` fixes it: a pinned end fixes w,
/// a clamped end w and w′, a free end nothing (the library numbers its free
/// DOFs the same way, in global order, which the uniform-section test checks).
fn dof_map(elements: usize, support: Support) -> Vec<Option<usize>> {
    let last = elements;
    let fixed: Vec<usize> = match support {
        Support::SimplySupported => vec![0, 2 * last],
        Support::ClampedClamped => vec![0, 1, 2 * last, 2 * last + 1],
        Support::ClampedFree => vec![0, 1],
        Support::ClampedPinned => vec![0, 1, 2 * last],
    };
    let mut next = 0;
    (0..2 * (elements + 1))
        .map(|g| {
            (!fixed.contains(&g)).then(|| {
                next += 1;
                next - 1
            })
        })
        .collect()
}

/// The roots of one family (scaled units), s̃²Πᵢ(s̃ + Ω̃ᵢ) + λ[Πᵢ(s̃ + Ω̃ᵢ) +
/// Σᵢ Δᵢ s̃ Π_{k≠i}(s̃ + Ω̃ₖ)] = 0, i.e. s̃² + λG(s̃) = 0 with
/// G(s̃) = 1 + Σᵢ Δᵢ s̃/(s̃ + Ω̃ᵢ): the eigenvalues of the companion matrix of
/// the monic polynomial, each polished by Newton steps on the polynomial
/// (Horner) until a step is at round-off level.
pub fn family_poles(lambda: f64, ivs: &[(f64, f64)]) -> Vec<Complex64> {
    // polynomials as coefficient vectors, lowest degree first
    let mul = |p: &[f64], q: &[f64]| {
        let mut out = vec![0.0; p.len() + q.len() - 1];
        for (i, a) in p.iter().enumerate() {
            for (j, b) in q.iter().enumerate() {
                out[i + j] += a * b;
            }
        }
        out
    };
    let prod = |skip: Option<usize>| {
        ivs.iter().enumerate().filter(|(i, _)| Some(*i) != skip).fold(vec![1.0], |p, (_, &(_, om))| mul(&p, &[om, 1.0]))
    };
    let all = prod(None);
    let mut poly = mul(&all, &[0.0, 0.0, 1.0]);
    for (i, c) in all.iter().enumerate() {
        poly[i] += lambda * c;
    }
    for (i, &(delta, _)) in ivs.iter().enumerate() {
        for (j, c) in mul(&prod(Some(i)), &[0.0, 1.0]).iter().enumerate() {
            poly[j] += lambda * delta * c;
        }
    }
    let deg = poly.len() - 1;
    let lead = poly[deg];
    let mut companion = nalgebra::DMatrix::<f64>::zeros(deg, deg);
    for i in 1..deg {
        companion[(i, i - 1)] = 1.0;
    }
    for i in 0..deg {
        companion[(i, deg - 1)] = -poly[i] / lead;
    }
    let horner = |s: Complex64| {
        let (mut p, mut dp) = (Complex64::new(0.0, 0.0), Complex64::new(0.0, 0.0));
        for &c in poly.iter().rev() {
            dp = dp * s + p;
            p = p * s + c;
        }
        (p, dp)
    };
    companion
        .complex_eigenvalues()
        .iter()
        .map(|&s0| {
            let mut s = s0;
            for _ in 0..20 {
                let (p, dp) = horner(s);
                let step = p / dp;
                if !step.is_finite() {
                    break;
                }
                s -= step;
                if step.norm() <= 4.0 * f64::EPSILON * s.norm() {
                    break;
                }
            }
            s
        })
        .collect()
}

fn set_pole(m: &mut Mode, s: Complex64) {
    m.pole = s;
    m.omega_rad_s = s.norm();
    m.zeta = -s.re / s.norm();
}

/// The beam-mode pole of two oscillators, the beam mode (pole `s`) and a
/// clamp resonance at ω_c = ω(1 + δ) with ζ = [`CLAMP_MODE_ZETA`], coupled by
/// the stiffness g·ω·ω_c (mass-normalised): the eigenvalue of the 4×4 state
/// matrix [[0, I], [−K, −C]] with Im > 0 nearest the uncoupled `s` (g → 0
/// returns `s`). Frequencies are scaled by ω so the matrix is O(1).
fn coupled_pole(s: Complex64, detuning: f64, g: f64) -> Complex64 {
    let (w, z) = (s.norm(), -s.re / s.norm());
    let wc = 1.0 + detuning;
    let k = [[1.0, g * wc], [g * wc, wc * wc]];
    let c = [2.0 * z, 2.0 * CLAMP_MODE_ZETA * wc];
    #[rustfmt::skip]
    let a = nalgebra::Matrix4::new(
        0.0, 0.0, 1.0, 0.0,
        0.0, 0.0, 0.0, 1.0,
        -k[0][0], -k[0][1], -c[0], 0.0,
        -k[1][0], -k[1][1], 0.0, -c[1],
    );
    let s1 = s / w;
    let best = a
        .complex_eigenvalues()
        .iter()
        .copied()
        .filter(|q| q.im > 0.0)
        .min_by(|p, q| (p - s1).norm().total_cmp(&(q - s1).norm()))
        .expect("a lightly damped 2-DOF system has two poles with Im > 0");
    w * best
}

pub fn observations(y: &[Mode]) -> Vec<ModeObservation> {
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
    let post = model_posterior(&Model::BASE, &ParameterSet::paper_n1(), &nominal_beam(), &observations(y0), &[], s);
    let mut rng = stream(seed, Purpose::SyntheticBaseFit, [0, 0]);
    let iv = truth.internal_variables[0];
    let mut starts = vec![vec![truth.nonlocal_e0a_nm, iv.delta, iv.omega_rad_s]];
    starts.extend((0..128).map(|_| post.sample_prior(&mut rng)));
    fit_max_z(&post, starts, &[0.05, 0.05, 0.05e12], 3)
}

/// Screens `starts` by log posterior, runs Nelder–Mead (600 iterations,
/// simplex `sd`) from the best `restarts` and returns [`max_z`] at the best result.
fn fit_max_z(post: &ClassPosterior, starts: Vec<Vec<f64>>, sd: &[f64], restarts: usize) -> f64 {
    let mut scored: Vec<(f64, Vec<f64>)> = starts.into_iter().map(|u| (post.log_posterior(&u), u)).collect();
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    let best = scored
        .iter()
        .take(restarts)
        .map(|(_, u)| map_estimate(post, u, sd, 600))
        .max_by(|a, b| a.log_posterior.total_cmp(&b.log_posterior))
        .expect("starts");
    max_z(post, &best.theta)
}

/// Largest standardized residual of `post`'s data at `theta` (sampling coordinates).
fn max_z(post: &ClassPosterior, theta: &[f64]) -> f64 {
    let Some(fit) = post.inner().predict(&post.to_inner(theta)) else { return f64::INFINITY };
    let obs = post.inner();
    obs.observed().iter().zip(obs.sd()).zip(&fit).map(|((y, sd), f)| ((y - f) / sd).abs()).fold(0.0, f64::max)
}

/// Points screened per catalogue model in [`catalogue_fits`], and the
/// Nelder–Mead runs from the best of them. A local search can miss a
/// narrow basin: local-defect seed 404 passes as unfittable, yet the
/// diagnosis fits it with attached mass + shear deformation (a mass of
/// 0.69 ρAL 0.50 nm from a support, κ on its prior bound 0.3, e0a = 0.37 nm;
/// largest residual 2.3 σ on the noisy data). 256 points and 8 runs
/// did not find that fit either and doubled the generation
/// time, so the suite's seeds are checked by the diagnosis itself: a case
/// the catalogue fits fails the open-world test instead of passing it.
const CATALOGUE_STARTS: usize = 64;
const CATALOGUE_RESTARTS: usize = 3;

/// The catalogue models a foreign effect must defeat: every single cause and
/// every pair of the causes the suite was built with (without
/// `section-mismatch` and `strain-gradient`, so that the keyed streams of
/// [`model_fit_max_z`], and with them the suite's data, are those of before
/// each class: a model's stream is keyed by its place in this list, and
/// `strain-gradient`, last in the causes, would move every pair's).
fn catalogue_models() -> Vec<Model> {
    Model::up_to(2)
        .into_iter()
        .filter(|m| {
            *m != Model::BASE
                && !m.causes().contains(&ModelClass::SectionMismatch)
                && !m.causes().contains(&ModelClass::StrainGradient)
        })
        .collect()
}

/// Does some model of [`catalogue_models`] fit noise-free `y0`, i.e. leave
/// its largest standardized residual below [`MIN_SHIFT_SIGMA`] at its best
/// fit? Models are tried cheapest first (decoupled damping classes, then
/// the coupled ones; measured cost per evaluation at prior draws 3 µs to
/// 1 ms) and the answer is the first that fits ([`model_fit_max_z`]). A
/// local optimizer can miss a better fit, which would make a foreign case
/// look unfittable when it is not; the diagnosis's own TMCMC then finds the
/// fit, and the open-world test fails on that case rather than passing by it.
fn catalogue_fits(y0: &[Mode], truth: &BeamSpec, s: &NominalScales, seed: u64) -> bool {
    let mut models = catalogue_models();
    let cost = |m: &Model| {
        m.causes()
            .iter()
            .map(|c| match c {
                ModelClass::ExtraRelaxation | ModelClass::ViscousDamping => 0,
                ModelClass::ShearDeformation => 2,
                _ => 1,
            })
            .sum::<usize>()
    };
    // stable: equal costs keep the catalogue's order
    models.sort_by_key(cost);
    models.iter().any(|model| model_fit_max_z(model, y0, truth, s, seed) < MIN_SHIFT_SIGMA)
}

/// Largest standardized residual of `model`'s best fit to noise-free `y0`:
/// [`CATALOGUE_STARTS`] points screened (a quarter with the base
/// coordinates at the truth's, the rest prior draws), Nelder–Mead (600
/// iterations) from the best [`CATALOGUE_RESTARTS`], simplex 5 % of each
/// prior's width in its sampling coordinate (0.05 in ln x for log-uniform
/// priors, 5 % of the asinh width for the axial force). The random stream
/// is keyed by the model's place in [`catalogue_models`], so a model's fit
/// to the same data is the same wherever it is asked for.
pub fn model_fit_max_z(model: &Model, y0: &[Mode], truth: &BeamSpec, s: &NominalScales, seed: u64) -> f64 {
    let iv = truth.internal_variables[0];
    let base_truth = [truth.nonlocal_e0a_nm, iv.delta, iv.omega_rad_s];
    let k = catalogue_models().iter().position(|m| m == model).expect("a catalogue model");
    let params = model_parameters(model, &ParameterSet::paper_n1(), &nominal_beam(), &[], s);
    let post = model_posterior(model, &ParameterSet::paper_n1(), &nominal_beam(), &observations(y0), &[], s);
    let sd: Vec<f64> = params
        .set
        .params
        .iter()
        .zip(&params.coordinates)
        .map(|(p, &c)| {
            let (lo, hi) = p.prior.support();
            match c {
                Coordinate::Log => 0.05,
                c => 0.05 * (c.to_u(hi) - c.to_u(lo)),
            }
        })
        .collect();
    let mut rng = stream(seed, Purpose::SyntheticBaseFit, [1 + k as u64, 0]);
    let starts = (0..CATALOGUE_STARTS)
        .map(|i| {
            let mut u = post.sample_prior(&mut rng);
            if i < CATALOGUE_STARTS / 4 {
                u[..3].copy_from_slice(&base_truth);
            }
            u
        })
        .collect();
    fit_max_z(&post, starts, &sd, CATALOGUE_RESTARTS)
}

fn finish(seed: u64, truth: BeamSpec, y0: Vec<Mode>, hidden: Hidden, z: f64, rng: &mut ChaCha8Rng) -> SyntheticCase {
    let noise_free = observations(&y0);
    let mut modes = noise_free.clone();
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
        mode_scans: vec![],
        parameters: None,
        sampler: Some(DramSettings { seed, ..DramSettings::default() }),
    };
    SyntheticCase { file, hidden, truth_beam: truth, base_fit_max_z: z, noise_free }
}
