//! Candidate model classes: the base model, the paper's β-inflated baseline
//! (eq. 41) and one class per candidate cause, each with physically
//! motivated priors derived from the nominal beam (never from the data).
//!
//! Prior scales (ω₁⁰ = first undamped frequency of the nominal local elastic
//! beam, ω_n⁰ that of the highest mode in the file):
//! - `extra-relaxation` (N → N+1, eq. 8): Δ_{N+1} ~ U[0, 1] like Δ₁ (§4.2.1);
//!   Ω_{N+1} ~ log-U[ω₁⁰/3, 3ω_n⁰]: a relaxation is only identifiable as one
//!   when its ridge (Fig. 1–3: ζ peaks at Ω ≈ ω_r) lies near the measured band;
//!   far below it acts as viscous damping, far above as a stiffness change.
//! - `viscous-damping` (C of eq. 13): since D = (C/ρA)·M (A5 vs A4), mode r
//!   gets ζ_r = C/(2ρA ω_r); C ~ log-U over ζ₁ ∈ [1e-4, 0.3] at ω₁⁰, i.e.
//!   C ∈ 2ρAω₁⁰·[1e-4, 0.3] (from unmeasurable to heavily damped).
//! - `support-rotational-stiffness`: a rotational spring on each rotation
//!   the support leaves free, each end its own: k₀ = κ₀ EI/L at x = 0 and
//!   k_L = κ_L EI/L at x = L, κ ~ log-U[1e-2, 1e3] each, independently
//!   (simply supported: two parameters; clamped–pinned: κ_L alone). κ = 1e-2
//!   is "no spring" at the diagnosis's noise (ω₁ moves 0.08 % for one end,
//!   a quarter of the 0.3 % sd), κ = 1e3 a clamp (a clamped–pinned beam's
//!   ω₁–ω₅ within 0.25 %; both measured in `tests/beam_end_springs.rs`), so the class spans a
//!   spring at one end, at both alike or apart, and an end clamped that the
//!   file declares pinned. Why two parameters and not one class per end:
//!   left, right and both as separate classes would add two singles and 14
//!   pairs on a simply supported beam (55 → 77 models with the ten causes); one class keeps the
//!   count (55). On data that cannot tell the beam from its mirror image
//!   ([`data_mirror`]) the two ends are folded onto κ₀ ≥ κ_L
//!   (`BeamPosterior::with_ordered_pair`, evidence unchanged), unless the
//!   model also holds a point mass, whose position fold already uses the
//!   symmetry. To first order a spring shifts ω_n² by a sum over the ends,
//!   so from ω alone κ₀ + κ_L is what is measured and the split is the weak
//!   direction of the posterior; the second order and mode shapes tell the
//!   ends apart.
//! - `attached-mass`: m = μ ρAL, μ ~ log-U[1e-3, 1], x ~ U[0, L].
//! - `axial-force`: N/N_cr ~ asinh-U[−0.5, 100] (uniform in asinh(N/N_cr)),
//!   N_cr = the buckling load of the nominal local beam (π²EI/L² simply
//!   supported, 4π²EI/L² clamped–clamped). Reasoning: a suspended tube is
//!   pulled by its fabrication and its gate (tension) or pushed by thermal
//!   mismatch (compression); compression beyond half the buckling load lowers
//!   ω₁ by > 30 % and leaves a tube that buckles at the next disturbance, so
//!   compression stops at −N_cr/2 as before. Tension reaches the string
//!   regime: suspended nanotube resonators are tuned by more than 20× with
//!   0–2 % strain (issue 40), and since N/N_cr = ε·AL²/(π²I) = 1.6 ε (L/d)²
//!   for a solid section, 0.6 % strain is 100 N_cr on a tube of L/d = 100
//!   (ω₁ × √101 ≈ 10 simply supported). A uniform prior on [−0.5, 100] N_cr
//!   would put 98 % of its mass above 2 N_cr and cost a moderate tension
//!   ln(100.5/2.5) ≈ 3.7 nats of Occam factor, more than the selection
//!   threshold; uniform in asinh(N/N_cr) the prior is nearly flat for
//!   |N| ≲ N_cr (compression keeps a density within 11 % of flat) and
//!   log-uniform in the tension beyond, so a moderate tension costs
//!   ln(5.78/2.5) ≈ 0.8 nats against the old U[−0.5, 2] and each decade of
//!   the string regime is reached at the same prior mass. TMCMC samples
//!   u = asinh(N/N_cr), where the prior is uniform on [−0.48, 5.30]: a
//!   random walk there has one natural scale from compression to the
//!   string, as ln x has for the log-uniform priors. The model rejects draws
//!   at or past the nonlocal buckling load (zero likelihood).
//! - `shear-deformation`: a nonlocal Timoshenko beam with κ ~ U[0.3, 1] and
//!   ν = 0.2 fixed. Only κG/E = κ/(2(1 + ν)) enters, so ν is held at the
//!   calibration default (`calibration::parameters::DEFAULT_POISSON_RATIO`,
//!   within the 0.14–0.28 reported for nanotubes) and κ carries the
//!   uncertainty: from 1 (stiffer than the solid circle's 0.88) down to 0.3,
//!   below a thin-walled tube's 2(1+ν)/(4+3ν) ≈ 0.52 (Cowper 1966), for the
//!   softer effective shear of multi-walled tubes whose walls slide.
//! - `section-mismatch`: the file's nominal section or material is off. The
//!   diameter d, the modulus E, the density ρ and a uniform added mass per
//!   length ε (an adsorbate layer) reach the modal data only through
//!   ω_ref² = EI/(ρA L⁴) ∝ E d²/(ρ(1 + ε)) (for a section scaled alike in
//!   every dimension, I/A ∝ d²): every pole is ω_ref times a function of
//!   e0a/L, the Δᵢ and Ωᵢ/ω_ref (`beam::model`'s scaling), and e0a is a
//!   length of its own, so a wrong d does not move e0a/L. Exactly one factor
//!   is identifiable, f = (E d²/ρ(1 + ε)) / nominal: the class samples the
//!   modulus, E = f·E_nominal with the section and ρ as declared, and the
//!   report reads f back as "as if d were √f·d, or E/ρ f times the nominal".
//!   Prior f ~ log-U[2/3, 3/2]. Reasoning: a tube's diameter is known to
//!   about ±10 % from TEM or AFM (issue 40), so d² to [0.81, 1.21]; the
//!   modulus and effective density of a tube are conventions of its wall
//!   thickness, each taken as uncertain by about ±10 % around the common
//!   0.34 nm convention; together [0.81·0.9/1.1, 1.21·1.1/0.9] ≈ [0.66, 1.48],
//!   rounded to a range symmetric in ln f. An adsorbate of +15–30 % mass
//!   (f = 0.77–0.87) lies inside. What separates f from the base model's own
//!   parameters is the n-dependence: e0a bends ω_n below (nπ/L)², and the
//!   relaxation moves ζ_n and (Ω below the band) scales ω_n by √(1 + Δ); a
//!   uniform scale of every ω_n at fixed ζ_n is neither, but Δ comes close
//!   (the derivation and its measurement are in `tests/diagnose_catalogue.md`).
//!   The class is no candidate when the file's parameters already sample
//!   the diameter, the modulus or the density ([`ModelClass::free_in`]): the
//!   base model then carries it.
//! - `elastic-foundation`: a Winkler modulus k (N/m²) under the whole span,
//!   signed: a substrate or an embedding matrix pushes back (k > 0), a gate's
//!   electrostatic pull is a negative spring (k < 0). Eringen's law acts on
//!   its reaction as on the inertia (`beam::fe::scaling`), so without other
//!   coupling it adds k/ρA to every ω² (any support; `tests/beam_foundation.rs`):
//!   its signature is a constant added to ω_n², where a tension adds
//!   ∝ n² and a section mismatch multiplies. Prior k/k_ref ~
//!   asinh-U[−1, 100] with k_ref = ρA(ω₁⁰)², the nominal local beam's first
//!   modal stiffness per length, so k/k_ref is the fraction by which it moves
//!   ω₁². Reasoning: a pull at −k_ref takes ω₁ of the nominal beam to zero
//!   (the pull-in instability), the physical end of a gate's softening;
//!   draws past the model's own bound (lower with e0a) are rejected by the
//!   model (zero likelihood), as for compression. A matrix's Winkler modulus
//!   is of the order of its Young's modulus (the usual estimate for a fibre
//!   in an elastic medium), 1–3 GPa for a polymer; for a tube of EI ≈
//!   5e-26 N·m² (a (5,5) tube with the 0.34 nm wall) that is k/k_ref ≈ 1 at
//!   L = 7 nm and, since k_ref ∝ L⁻⁴, ≈ 100 at L = 22 nm (ω₁ × 10), where
//!   the range stops: stiffer embeddings leave the modes little of the beam
//!   to diagnose. Uniform in asinh(k/k_ref) for the reason the axial force is
//!   (nearly flat for |k| ≲ k_ref, log-uniform beyond). A Pasternak shear
//!   layer G_p adds −G_p w″, the form of a tension N = G_p (with Eringen's
//!   operator on both): `axial-force` carries it, so it is no class of its own.
//! - `loss-factor`: frequency-independent (hysteretic) damping, the complex
//!   modulus E(1 + iη) of the beam's own stiffness (`beam::spec`), so that
//!   every mode of an otherwise undamped beam gets ζ = sin(½ atan η) ≈ η/2:
//!   a damping flat in mode number, where viscous damping falls as 1/ω_n and
//!   a relaxation peaks near its Ω. η ~ log-U[2e-4, 0.6], the viscous
//!   class's ζ range [1e-4, 0.3] read as η = 2ζ: from unmeasurable beside the
//!   base model's own damping to a heavily damped tube (room-temperature
//!   suspended tubes show quality factors of order 100, η ≈ 1e-2: Sazonova et
//!   al., Nature 431 (2004) 284).
//! - `strain-gradient`: the material length l of nonlocal strain-gradient
//!   elasticity (Lim, Zhang & Reddy, J. Mech. Phys. Solids 78 (2015)
//!   298–313; `beam::fe::scaling`): at wavenumber q the bending stiffness
//!   grows by (1 + l²q²) against Eringen's (1 + (e0a)²q²), so mode n's ω²
//!   gains a relative stiffening that grows with n (∝ q_n² while l q_n ≲ 1).
//!   Prior l ~ log-U[0.01/q_max, min(10/q_max, L)], q_max = (ρA(ω_n⁰)²/EI)^¼
//!   the wavenumber of the highest measured mode on the nominal local beam
//!   (nπ/L simply supported): the beam's own length scale as the data
//!   resolve it. Reasoning: at l q_max = 0.01 the highest mode's ω moves by
//!   5e-5, far below the 0.3 % noise ("no gradient"); at l q_max = 10 it is
//!   ×10, the string-like end the axial force also reaches, and l ≤ L is the
//!   beam's own bound (`beam::spec::MAX_GRADIENT_TILDE`). The values used
//!   for nanotubes are lengths of the lattice's order: the nonlocal length
//!   e0a < 2 nm (Wang & Wang, Nanotechnology 18 (2007) 075702; the paper's
//!   prior U[0, 2] nm), and NSGT studies of tubes take l of the order of
//!   e0a, varying l/e0a about 1 in their parametric studies (Lim et al.;
//!   calibrated against molecular dynamics for tubes by Mehralian, Tadi Beni
//!   & Zeverdejani, Physica B 521 (2017) 102–111), i.e. l up to about 2 nm
//!   (a reading of that literature, not a value measured here). On the
//!   paper's 8 nm tube with five modes (q_max ≈ 1.96 nm⁻¹) the range is
//!   l ∈ [0.005, 5.1] nm, on a 20 nm tube [0.013, 12.7] nm, so such a tube's
//!   l lies inside with a factor 2.5 to spare. Log-uniform
//!   because the scale is unknown over decades; the beam is then C² (quintic
//!   elements, `beam::spec::MAX_GRADIENT_ELEMENTS`), and the class does not
//!   combine with `shear-deformation`, whose Timoshenko beam the strain
//!   gradient is not defined on ([`Model::candidates`]).
//!   Confounding: to first order in q² the undamped ω_n² ∝
//!   q⁴(1 + (l² − (e0a)²)q² + …), so on few low modes l and e0a trade off
//!   along l² − (e0a)² = const, the weak direction of the posterior; both are
//!   sampled (e0a with the base's prior), and the next order,
//!   (e0a)²((e0a)² − l²)q⁴, separates them on modes with e0a·q ≳ 1. The
//!   class's own reach is a net stiffening (l > e0a) that grows with n, which
//!   the base cannot give: e0a only softens. A gradient that cancels only
//!   part of e0a adds no fit the base lacks and pays the Occam factor of
//!   ln(1000) ≈ 6.9 nats of prior width against the posterior's, so an
//!   ordinary nonlocal beam is not named `strain-gradient`. The other
//!   stiffenings have other n-dependences: `section-mismatch` multiplies
//!   every ω_n² alike, a tension adds N q²/ρA (relative ∝ 1/q², falling with
//!   n), a foundation adds k/ρA (relative ∝ 1/q⁴); the one that can rise
//!   with n is a relaxation whose Ω lies inside the band (Re G steps from 1
//!   to 1 + Δ across Ω), which also puts a ζ peak at Ω: measured ζ tells it
//!   from the elastic gradient, which leaves ζ as the base model has it.
//! - Strain-rate (Kelvin–Voigt) damping, E(1 + τs), is no class of its own:
//!   it is the extra relaxation's fast limit. For |s| ≪ Ω,
//!   G(s) = 1 + Δs/(s + Ω) = 1 + (Δ/Ω)s − (Δ/Ω²)s² + …, i.e. Kelvin–Voigt
//!   with τ = Δ/Ω, plus a stiffening Δ(ω/Ω)²/(1 + (ω/Ω)²) of Re G. The class's
//!   prior reaches Ω = 3ω_n⁰ with Δ ≤ 1, so it holds τ ≤ 1/(3ω_n⁰), i.e.
//!   Kelvin–Voigt damping up to ζ_n = τω_n/2 ≈ 1/6 on the highest measured
//!   mode, with a stiffening of that mode ≤ Δ/10 that e0a and the relaxation
//!   absorb. The steering side's draw found both of its Kelvin–Voigt sets
//!   named `extra-relaxation` (issue 65); a strain rate beyond that range
//!   (ζ_n > 1/6) would need Ω above the prior and reads `unexplained`.
//! - `baseline`: the base model with β² ~ IG(9.5, 11.1) (§4.3); not a cause.
//!
//! Log-uniform priors are sampled in u = ln x, the axial force's in
//! u = asinh(N/N_cr), where each is uniform; the evidence is invariant under
//! this change of variables.

use crate::bayes::prior::Prior;
use crate::bayes::transform::{Coordinate, Reparameterized};
use crate::beam::{BeamError, BeamSpec, Support};
use crate::calibration::parameters::SHEAR_COEFFICIENT_PRIOR;
use crate::calibration::{BeamPosterior, ModeObservation, ModeScan, Parameter, ParameterSet, Target};

pub use super::mirror::{data_mirror, folds_end_springs, folds_mass_position, folds_mirror_image};
use super::mirror::{folded_end_springs, mass_position_upper_nm};
pub use super::model::{Model, ModelClass};
pub use super::section_reading::SectionReading;

/// Which ends of a cause parameter's prior range mean a stronger effect
/// ([lower, upper]): Δ, C, k_r and the mass at their upper end, κ at its
/// lower end (more shear), the axial force at both (the compression and the
/// tension limits), the modulus factor of a section mismatch at both (too
/// soft, too stiff). A relaxation time and a mass position have no stronger
/// end. A MAP pinned at such an end asks for more of the effect than the
/// class's physical range allows; pinned at the weak end it only says the
/// cause is barely needed, or that the truth sits at the limit (the hidden
/// suite's shear cases have κ = 1, the prior's upper end, and their MAPs sit
/// there: 4 of 4).
pub fn stronger_effect_ends(target: Target) -> [bool; 2] {
    match target {
        Target::Delta(_)
        | Target::ViscousDamping
        | Target::SupportRotationalStiffness
        | Target::SupportRotationalStiffnessLeft
        | Target::SupportRotationalStiffnessRight
        | Target::PointMassKg
        | Target::LossFactor
        | Target::StrainGradientLength => [false, true],
        Target::ShearCoefficient => [true, false],
        Target::AxialForce | Target::YoungsModulus | Target::ElasticFoundation => [true, true],
        _ => [false, false],
    }
}

/// The parameter vector of one class, with the sampling coordinate of each entry.
#[derive(Debug, Clone)]
pub struct ClassParameters {
    /// Physical parameters (priors in physical units), mapped onto the beam by name.
    pub set: ParameterSet,
    /// The sampling coordinate of each parameter: the one in which its prior
    /// is uniform (u = ln x for a log-uniform prior, asinh(x/s) for the
    /// axial force's asinh-uniform one; see `bayes::transform`).
    pub coordinates: Vec<Coordinate>,
}

/// Nominal scales of a beam used to place the extension priors.
#[derive(Debug, Clone, Copy)]
pub struct NominalScales {
    /// First undamped frequency of the nominal local elastic beam (rad/s).
    pub omega_1_rad_s: f64,
    /// Undamped frequency of the highest mode used, same beam (rad/s).
    pub omega_max_rad_s: f64,
    pub rho_a_kg_m: f64,
    pub ei_n_m2: f64,
    pub length_m: f64,
    /// |N_cr| of the nominal local elastic beam (newtons).
    pub buckling_load_n: f64,
}

impl NominalScales {
    /// Scales of `beam` with e0a = 0, no damping, no extensions, for modes 1..=`max_mode`.
    pub fn of(beam: &BeamSpec, max_mode: usize) -> Result<Self, BeamError> {
        // the same section as the beam's (a tube's A and I, not a solid circle's)
        let elastic = BeamSpec {
            section: beam.section,
            ..BeamSpec::elastic(
                beam.length_nm,
                beam.diameter_nm,
                beam.youngs_modulus_pa,
                beam.density_kg_m3,
                beam.support,
                beam.elements,
            )
        };
        let modes = crate::beam::modal(&elastic, max_mode)?.modes;
        let buckling_load_n = crate::beam::buckling_load_n(&elastic)?.abs();
        Ok(Self {
            omega_1_rad_s: modes[0].omega_rad_s,
            omega_max_rad_s: modes[max_mode - 1].omega_rad_s,
            rho_a_kg_m: beam.density_kg_m3 * beam.area_m2(),
            ei_n_m2: beam.youngs_modulus_pa * beam.inertia_m4(),
            length_m: beam.length_nm * 1e-9,
            buckling_load_n,
        })
    }
}

fn param(name: &str, prior: Prior) -> Parameter {
    let (lo, hi) = prior.support();
    let proposal_sd = if let Prior::LogUniform { .. } = prior { 0.01 * hi } else { 0.01 * (hi - lo) };
    Parameter {
        name: name.to_string(),
        target: Target::from_name(name).expect("known parameter name"),
        prior,
        proposal_sd,
    }
}

/// Builds the parameter vector of `model`. `base` is the file's parameter set;
/// a `beta_squared` entry in it is dropped from every model except the baseline
/// (where the file's β² prior replaces the paper's IG(9.5, 11.1)).
/// `scans` are the data's mode scans (they decide whether the mass position
/// is folded, [`folds_mass_position`]).
pub fn model_parameters(
    model: &Model,
    base: &ParameterSet,
    beam: &BeamSpec,
    scans: &[ModeScan],
    s: &NominalScales,
) -> ClassParameters {
    let file_beta = base.params.iter().find(|p| p.target == Target::BetaSquared).cloned();
    let mut params: Vec<Parameter> = base.params.iter().filter(|p| p.target != Target::BetaSquared).cloned().collect();
    if *model == Model::Baseline {
        params
            .push(file_beta.unwrap_or_else(|| param("beta_squared", Prior::InverseGamma { shape: 9.5, scale: 11.1 })));
    }
    for &class in model.causes() {
        add_extension(&mut params, class, beam, scans, s);
    }
    let coordinates = params.iter().map(|p| Coordinate::uniformising(&p.prior)).collect();
    ClassParameters { set: ParameterSet { params }, coordinates }
}

/// Appends the parameters of one cause, with the priors of the module doc.
fn add_extension(
    params: &mut Vec<Parameter>,
    class: ModelClass,
    beam: &BeamSpec,
    scans: &[ModeScan],
    s: &NominalScales,
) {
    match class {
        ModelClass::ExtraRelaxation => {
            let used = params
                .iter()
                .filter_map(|p| match p.target {
                    Target::Delta(i) | Target::Omega(i) => Some(i + 1),
                    _ => None,
                })
                .max()
                .unwrap_or(0);
            let k = used.max(beam.internal_variables.len()) + 1; // 1-based number of the new variable
            let (dn, on) = if k == 1 {
                ("delta".to_string(), "omega_rad_s".to_string())
            } else {
                (format!("delta_{k}"), format!("omega_{k}_rad_s"))
            };
            params.push(param(&dn, Prior::Uniform { lower: 0.0, upper: 1.0 }));
            params.push(param(&on, Prior::LogUniform { lower: s.omega_1_rad_s / 3.0, upper: 3.0 * s.omega_max_rad_s }));
        }
        ModelClass::ViscousDamping => {
            let c_ref = 2.0 * s.rho_a_kg_m * s.omega_1_rad_s;
            params.push(param("viscous_damping_n_s_m2", Prior::LogUniform { lower: 1e-4 * c_ref, upper: 0.3 * c_ref }));
        }
        ModelClass::SupportRotationalStiffness => {
            let k_ref = s.ei_n_m2 / s.length_m;
            let (lo, hi) = END_SPRING_RANGE;
            let prior = Prior::LogUniform { lower: lo * k_ref, upper: hi * k_ref };
            let ends: &[&str] = match beam.support {
                Support::SimplySupported => {
                    &["support_rotational_stiffness_left_n_m_rad", "support_rotational_stiffness_right_n_m_rad"]
                }
                Support::ClampedPinned => &["support_rotational_stiffness_right_n_m_rad"],
                Support::ClampedClamped | Support::ClampedFree => &[],
            };
            params.extend(ends.iter().map(|name| param(name, prior)));
        }
        ModelClass::AttachedMass => {
            let m_ref = s.rho_a_kg_m * s.length_m;
            params.push(param("point_mass_kg", Prior::LogUniform { lower: 1e-3 * m_ref, upper: m_ref }));
            params.push(param(
                "point_mass_x_nm",
                Prior::Uniform { lower: 0.0, upper: mass_position_upper_nm(beam, scans) },
            ));
        }
        ModelClass::AxialForce => {
            let n = s.buckling_load_n;
            let (lo, hi) = AXIAL_FORCE_RANGE;
            params.push(param("axial_force_n", Prior::AsinhUniform { lower: lo * n, upper: hi * n, scale: n }));
        }
        ModelClass::ShearDeformation => {
            let (lower, upper) = SHEAR_COEFFICIENT_PRIOR;
            params.push(param("shear_coefficient", Prior::Uniform { lower, upper }));
        }
        ModelClass::SectionMismatch => {
            let (lo, hi) = SECTION_FACTOR_RANGE;
            let e = beam.youngs_modulus_pa;
            params.push(param("youngs_modulus_pa", Prior::LogUniform { lower: lo * e, upper: hi * e }));
        }
        ModelClass::ElasticFoundation => {
            let k_ref = s.rho_a_kg_m * s.omega_1_rad_s * s.omega_1_rad_s;
            let (lo, hi) = FOUNDATION_RANGE;
            params.push(param(
                "elastic_foundation_n_m2",
                Prior::AsinhUniform { lower: lo * k_ref, upper: hi * k_ref, scale: k_ref },
            ));
        }
        ModelClass::LossFactor => {
            let (lower, upper) = LOSS_FACTOR_RANGE;
            params.push(param("loss_factor", Prior::LogUniform { lower, upper }));
        }
        ModelClass::StrainGradient => {
            let (lower, upper) = strain_gradient_range_nm(s);
            params.push(param("strain_gradient_length_nm", Prior::LogUniform { lower, upper }));
        }
    }
}

/// The prior range of the `strain-gradient` class's l·q_max (log-uniform;
/// the module doc's reasoning), q_max the highest measured mode's wavenumber.
pub const STRAIN_GRADIENT_RANGE: (f64, f64) = (0.01, 10.0);

/// The `strain-gradient` class's prior range of l in nm: [`STRAIN_GRADIENT_RANGE`]
/// over q_max = (ρA(ω_n⁰)²/EI)^¼ (nπ/L simply supported), the upper end at
/// most the beam's own bound l ≤ L (`beam::spec::MAX_GRADIENT_TILDE`).
pub fn strain_gradient_range_nm(s: &NominalScales) -> (f64, f64) {
    let q_max_per_nm = (s.rho_a_kg_m * s.omega_max_rad_s * s.omega_max_rad_s / s.ei_n_m2).powf(0.25) * 1e-9;
    let (lo, hi) = STRAIN_GRADIENT_RANGE;
    let l_nm = s.length_m * 1e9;
    let upper = (hi / q_max_per_nm).min(crate::beam::spec::MAX_GRADIENT_TILDE * l_nm);
    ((lo / q_max_per_nm).min(0.5 * upper), upper)
}

/// The prior range of the `loss-factor` class's η (log-uniform; the module doc's reasoning).
pub const LOSS_FACTOR_RANGE: (f64, f64) = (2e-4, 0.6);

/// The prior range of the `elastic-foundation` class in units of
/// k_ref = ρA(ω₁⁰)² (a pull < 0; the module doc's reasoning).
pub const FOUNDATION_RANGE: (f64, f64) = (-1.0, 100.0);

/// The prior range of each end's κ = k L/EI of `support-rotational-stiffness`
/// (the module doc's reasoning).
pub const END_SPRING_RANGE: (f64, f64) = (1e-2, 1e3);

/// The prior range of the `axial-force` class in units of the nominal
/// buckling load |N_cr| (compression < 0; the module doc's reasoning).
pub const AXIAL_FORCE_RANGE: (f64, f64) = (-0.5, 100.0);

/// The prior range of the stiffness-to-mass factor f of `section-mismatch`
/// (the module doc's reasoning); defined beside the other priors in
/// `calibration::parameters`, where `identify`'s numbering reads it too.
pub use crate::calibration::parameters::SECTION_FACTOR_RANGE;

/// The posterior of one model in its sampling coordinates (log-uniform priors sampled in ln x).
pub type ClassPosterior = Reparameterized<BeamPosterior>;

/// Two relaxations closer than this in |ln(Ωᵢ/Ωⱼ)| are one (see
/// `BeamPosterior::with_distinct_relaxations`): 5 %, which removes ≈ 2·0.05/5.8
/// ≈ 2 % of the extra relaxation's prior (its Ω spans ln(9ω_n/ω₁) ≈ 5.8 nats
/// for 5 modes), i.e. ≤ 0.02 nats of log evidence, far below the ln B ≥ 3 threshold.
pub const DISTINCT_RELAXATIONS: f64 = 0.05;

/// The posterior of `model` given the fitted `modes` and `scans` of a beam whose known part is `beam`.
pub fn model_posterior(
    model: &Model,
    parameters: &ParameterSet,
    beam: &BeamSpec,
    modes: &[ModeObservation],
    scans: &[ModeScan],
    scales: &NominalScales,
) -> ClassPosterior {
    let p = model_parameters(model, parameters, beam, scans, scales);
    let fold = folded_end_springs(model, &p.set, beam, scans);
    let mut posterior =
        BeamPosterior::from_parts(beam, modes, p.set).with_scans(scans).with_distinct_relaxations(DISTINCT_RELAXATIONS);
    if let Some(pair) = fold {
        posterior = posterior.with_ordered_pair(pair);
    }
    Reparameterized::with_coordinates(posterior, p.coordinates)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `up_to(k)` lists every set of at most k causes once: C(10, 0) + … + C(10, k).
    #[test]
    fn up_to_lists_every_set_of_causes_once() {
        // `up_to` and `Model::with` rely on CAUSES being in the enum's order
        assert!(ModelClass::CAUSES.windows(2).all(|w| w[0] < w[1]));
        for (k, n) in [(0, 1), (1, 11), (2, 56), (3, 176), (10, 1024)] {
            let models = Model::up_to(k);
            assert_eq!(models.len(), n, "k = {k}");
            assert_eq!(models[0], Model::BASE);
            let mut distinct = models.clone();
            distinct.sort();
            distinct.dedup();
            assert_eq!(distinct.len(), n, "k = {k}: a model listed twice");
            assert!(models.windows(2).all(|w| w[0].causes().len() <= w[1].causes().len()));
        }
        let pair = Model::with(&[ModelClass::AxialForce, ModelClass::AttachedMass]);
        assert_eq!(pair.without(ModelClass::AxialForce), Model::with(&[ModelClass::AttachedMass]));
        assert_eq!(pair.without(ModelClass::ShearDeformation), pair);
    }

    /// The strain-gradient prior on the paper's tube (8 nm, simply supported,
    /// modes 1–5): q_max = 5π/L, so l ∈ [0.01, 10]/q_max = [0.0051, 5.09] nm,
    /// inside l ≤ L; on one mode the upper end is held at L (10/q₁ = 25 nm).
    /// q_max comes from the FE ω₅ of 20 cubic elements, whose ω² errs by
    /// ≤ 2(5π/20)⁴/720 ≈ 1.1e-3 (Rayleigh–Ritz bound with a factor 2 for the
    /// higher orders), so q_max = (ρAω²/EI)^¼ by ≤ 2.7e-4. The class never
    /// pairs with shear-deformation.
    #[test]
    fn the_strain_gradient_prior_spans_the_measured_band() {
        let beam = BeamSpec::elastic(8.0, 1.0, 1.0e12, 2300.0, Support::SimplySupported, 20);
        let s5 = NominalScales::of(&beam, 5).unwrap();
        let (lo, hi) = strain_gradient_range_nm(&s5);
        let q = 5.0 * std::f64::consts::PI / 8.0;
        assert!((lo * q / 0.01 - 1.0).abs() < 2.7e-4 && (hi * q / 10.0 - 1.0).abs() < 2.7e-4, "{lo} {hi}");
        let s1 = NominalScales::of(&beam, 1).unwrap();
        assert_eq!(strain_gradient_range_nm(&s1).1, 8.0);
        let base = ParameterSet::paper_n1();
        let p = model_parameters(&Model::with(&[ModelClass::StrainGradient]), &base, &beam, &[], &s5);
        let l = p.set.params.last().unwrap();
        assert_eq!((l.name.as_str(), l.prior.support()), ("strain_gradient_length_nm", (lo, hi)));
        let pairs = |m: &Model| {
            m.causes().contains(&ModelClass::ShearDeformation) && m.causes().contains(&ModelClass::StrainGradient)
        };
        assert!(!Model::candidates(3, Support::SimplySupported, &base).iter().any(pairs));
    }

    /// The candidates leave out exactly the models of a cause that cannot act
    /// on the support, and each cause that can act does: the spring moves
    /// ω₁ of a simply supported and a clamped–pinned beam and leaves the
    /// clamped–clamped and clamped–free beams' ω₁ as they are (to rounding:
    /// the spring's rows are eliminated with the rotations it would act on).
    #[test]
    fn candidates_leave_out_causes_the_support_hides() {
        use crate::beam::modal;
        for support in Support::ALL {
            let mut beam = BeamSpec::elastic(8.0, 1.0, 1.0e12, 2300.0, support, 12);
            let w0 = modal(&beam, 1).unwrap().modes[0].omega_rad_s;
            beam.support_rotational_stiffness_n_m_rad = 10.0 * 6.1e-18 / 8e-9;
            let moved = modal(&beam, 1).unwrap().modes[0].omega_rad_s / w0 - 1.0;
            let acts = ModelClass::SupportRotationalStiffness.acts_on(support);
            let ok = if acts { moved > 1e-3 } else { moved.abs() < 1e-12 };
            assert!(ok, "{}: ω₁ moved by {moved:e}", support.name());
            let models = Model::candidates(2, support, &ParameterSet::paper_n1());
            // the up_to(2) sets less shear-deformation + strain-gradient
            let expected = if acts { 55 } else { 45 };
            assert_eq!(models.len(), expected, "{}", support.name());
            assert!(models.iter().all(|m| m.causes().iter().all(|c| c.acts_on(support))));
        }
    }

    /// `section-mismatch` is no candidate when the file already samples the
    /// diameter (the paper's Case 3 nuisance), and reads in the user's terms:
    /// f = 1.1449 on a declared 1 nm is d = 1.07 nm, E/ρ 14.49 % higher, the
    /// mass per length 12.66 % lower (1/1.1449 = 0.8734).
    #[test]
    fn section_mismatch_leaves_a_sampled_section_alone_and_reads_in_user_terms() {
        let mut base = ParameterSet::paper_n1();
        assert!(ModelClass::SectionMismatch.free_in(&base));
        let all = Model::candidates(2, Support::SimplySupported, &base);
        base.params.push(param("diameter_nm", Prior::Normal { mean: 1.0, sd: 0.05 }));
        assert!(!ModelClass::SectionMismatch.free_in(&base));
        let without = Model::candidates(2, Support::SimplySupported, &base);
        assert_eq!((all.len(), without.len()), (55, 45));
        assert!(without.iter().all(|m| !m.causes().contains(&ModelClass::SectionMismatch)));
        let beam = BeamSpec::elastic(8.0, 1.0, 1.0e12, 2300.0, Support::SimplySupported, 20);
        let r = SectionReading::new(&beam, 1.1449e12, [1.0e12, 1.21e12]);
        assert!((r.equivalent_diameter_nm - 1.07).abs() < 1e-12);
        assert!((r.equivalent_diameter_ci95_nm[1] - 1.1).abs() < 1e-12);
        assert!((r.e_over_rho_change_percent - 14.49).abs() < 1e-9);
        assert!((r.mass_per_length_change_percent + 12.656).abs() < 1e-3);
        let s = r.sentence();
        assert!(
            s.starts_with("behaves as if d = 1.070 nm instead of 1 nm") && s.contains("E/ρ were 14.5 % higher"),
            "{s}"
        );
        let p =
            model_parameters(&Model::with(&[ModelClass::SectionMismatch]), &ParameterSet::paper_n1(), &beam, &[], &{
                NominalScales::of(&beam, 5).unwrap()
            });
        let e = p.set.params.last().unwrap();
        assert_eq!((e.name.as_str(), e.prior.support()), ("youngs_modulus_pa", (1.0e12 * 2.0 / 3.0, 1.5e12)));
    }

    /// The support spring samples each free end: two stiffnesses on a simply
    /// supported beam, folded onto κ₀ ≥ κ_L on mirror data (the prior is
    /// −∞ on the other half and ln 2 above the unfolded one inside, prior
    /// draws are ordered), not folded beside a point mass (its position
    /// fold takes the symmetry); one (x = L) on a clamped–pinned beam.
    #[test]
    fn the_support_spring_samples_each_free_end_folded_on_mirror_data() {
        use crate::bayes::Posterior;
        use rand::SeedableRng;
        let spring = Model::with(&[ModelClass::SupportRotationalStiffness]);
        let with_mass = Model::with(&[ModelClass::SupportRotationalStiffness, ModelClass::AttachedMass]);
        let ss = BeamSpec::elastic(8.0, 1.0, 1.0e12, 2300.0, Support::SimplySupported, 20);
        let cp = BeamSpec { support: Support::ClampedPinned, ..ss.clone() };
        assert!(folds_end_springs(&spring, &ss, &[]) && folds_mirror_image(&spring, &ss, &[]));
        assert!(!folds_end_springs(&with_mass, &ss, &[]) && folds_mirror_image(&with_mass, &ss, &[]));
        assert!(!folds_end_springs(&spring, &cp, &[]));
        let base = ParameterSet::paper_n1();
        let names = |b: &BeamSpec| -> Vec<String> {
            let p = model_parameters(&spring, &base, b, &[], &NominalScales::of(b, 5).unwrap());
            p.set.params[base.params.len()..].iter().map(|p| p.name.clone()).collect()
        };
        assert_eq!(
            names(&ss),
            ["support_rotational_stiffness_left_n_m_rad", "support_rotational_stiffness_right_n_m_rad"]
        );
        assert_eq!(names(&cp), ["support_rotational_stiffness_right_n_m_rad"]);
        let modes: Vec<ModeObservation> = (1..=3)
            .map(|r| ModeObservation {
                mode: r,
                omega_rad_s: 1e11 * (r * r) as f64,
                omega_sd_rad_s: 1e8,
                zeta: 0.01,
                zeta_sd: 1e-3,
            })
            .collect();
        let scales = NominalScales::of(&ss, 3).unwrap();
        let post = model_posterior(&spring, &base, &ss, &modes, &[], &scales).inner().clone();
        let unfolded = BeamPosterior::from_parts(&ss, &modes, model_parameters(&spring, &base, &ss, &[], &scales).set);
        let k = ss.youngs_modulus_pa * ss.inertia_m4() / 8e-9;
        let theta = |k0: f64, kl: f64| [1.0, 0.5, 3e11, k0 * k, kl * k];
        let (inside, outside) = (theta(5.0, 0.1), theta(0.1, 5.0));
        assert!((post.log_prior(&inside) - unfolded.log_prior(&inside) - std::f64::consts::LN_2).abs() < 1e-12);
        assert_eq!(post.log_prior(&outside), f64::NEG_INFINITY);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        assert!((0..200).all(|_| {
            let t = post.sample_prior(&mut rng);
            t[3] >= t[4]
        }));
    }

    /// `parameter_count` is what `add_extension` appends, for every class.
    #[test]
    fn parameter_count_matches_the_extension() {
        let beam = crate::beam::BeamSpec::elastic(8.0, 1.0, 1.0e12, 2300.0, crate::beam::Support::SimplySupported, 20);
        let scales = NominalScales::of(&beam, 5).unwrap();
        let base = ParameterSet::paper_n1();
        for c in ModelClass::CAUSES {
            let n = model_parameters(&Model::with(&[c]), &base, &beam, &[], &scales).set.params.len();
            assert_eq!(n - base.params.len(), c.parameter_count(beam.support), "{}", c.name());
        }
    }
}
