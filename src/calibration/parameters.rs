//! Named calibration parameters and how each one maps onto a beam.
//!
//! A parameter set is an ordered list of (name, prior, proposal sd). The name
//! decides what the value changes in the beam (or, for `beta_squared`, in the
//! likelihood's noise scaling, eq. 41).

use serde::{Deserialize, Serialize};

use crate::bayes::prior::Prior;
use crate::beam::{BeamSpec, InternalVariable, PointMass, ShearDeformation};
use crate::error::InputError;

/// What a named parameter acts on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    /// Eringen parameter e0a (nm).
    NonlocalE0a,
    /// Δ of internal variable `i` (0-based), eq. (8).
    Delta(usize),
    /// Ω of internal variable `i` (0-based) in rad/s, eq. (8).
    Omega(usize),
    /// Diameter d (nm): a nuisance parameter in Cases 2A–2C and 3.
    Diameter,
    /// β² of eq. (41): Σ̃ = β² Σεε. Acts on the likelihood, not on the beam.
    BetaSquared,
    ViscousDamping,
    /// The rotational spring at every free rotation of a supported end.
    SupportRotationalStiffness,
    /// The rotational spring at x = 0 only, and at x = L only.
    SupportRotationalStiffnessLeft,
    SupportRotationalStiffnessRight,
    PointMassKg,
    PointMassXnm,
    YoungsModulus,
    Density,
    Length,
    /// Axial force N in newtons (tension > 0, compression < 0).
    AxialForce,
    /// Timoshenko shear coefficient κ (turns shear deformation on).
    ShearCoefficient,
    /// Poisson's ratio ν of the shear modulus G = E/(2(1 + ν)) (turns shear deformation on).
    PoissonRatio,
    /// Winkler foundation modulus k in N/m² (substrate > 0, a gate's pull < 0).
    ElasticFoundation,
    /// Hysteretic loss factor η, 0 ≤ η < 1 (the complex modulus E(1 + iη)).
    LossFactor,
    /// Strain-gradient length l in nm (nonlocal strain-gradient elasticity).
    StrainGradientLength,
}

/// Names accepted in `parameters`, with the allowed form. `delta`/`omega_rad_s`
/// are the first internal variable; `delta_2`, `omega_2_rad_s`, ... further ones.
pub const KNOWN_NAMES: &str = "nonlocal_e0a_nm, delta, omega_rad_s, delta_K, omega_K_rad_s (K >= 2), \
diameter_nm, beta_squared, viscous_damping_n_s_m2, support_rotational_stiffness_n_m_rad, \
support_rotational_stiffness_left_n_m_rad, support_rotational_stiffness_right_n_m_rad, \
point_mass_kg, point_mass_x_nm, youngs_modulus_pa, density_kg_m3, length_nm, axial_force_n, \
shear_coefficient, poisson_ratio, elastic_foundation_n_m2, loss_factor, strain_gradient_length_nm";

impl Target {
    pub fn from_name(name: &str) -> Option<Target> {
        Some(match name {
            "nonlocal_e0a_nm" => Target::NonlocalE0a,
            "delta" => Target::Delta(0),
            "omega_rad_s" => Target::Omega(0),
            "diameter_nm" => Target::Diameter,
            "beta_squared" => Target::BetaSquared,
            "viscous_damping_n_s_m2" => Target::ViscousDamping,
            "support_rotational_stiffness_n_m_rad" => Target::SupportRotationalStiffness,
            "support_rotational_stiffness_left_n_m_rad" => Target::SupportRotationalStiffnessLeft,
            "support_rotational_stiffness_right_n_m_rad" => Target::SupportRotationalStiffnessRight,
            "point_mass_kg" => Target::PointMassKg,
            "point_mass_x_nm" => Target::PointMassXnm,
            "youngs_modulus_pa" => Target::YoungsModulus,
            "density_kg_m3" => Target::Density,
            "length_nm" => Target::Length,
            "axial_force_n" => Target::AxialForce,
            "shear_coefficient" => Target::ShearCoefficient,
            "poisson_ratio" => Target::PoissonRatio,
            "elastic_foundation_n_m2" => Target::ElasticFoundation,
            "loss_factor" => Target::LossFactor,
            "strain_gradient_length_nm" => Target::StrainGradientLength,
            _ => {
                if let Some(k) = name.strip_prefix("delta_") {
                    let k: usize = k.parse().ok().filter(|&k| k >= 2)?;
                    Target::Delta(k - 1)
                } else if let Some(rest) = name.strip_prefix("omega_") {
                    let k: usize = rest.strip_suffix("_rad_s")?.parse().ok().filter(|&k| k >= 2)?;
                    Target::Omega(k - 1)
                } else {
                    return None;
                }
            }
        })
    }
}

/// One entry of `parameters:` as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParameterEntry {
    pub prior: Prior,
    /// Standard deviation of the initial (non-adaptive) proposal C0, eq. (30),
    /// in the parameter's unit. Default: 1 % of the prior's scale.
    #[serde(default)]
    pub proposal_sd: Option<f64>,
}

/// A resolved parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    pub name: String,
    pub target: Target,
    pub prior: Prior,
    pub proposal_sd: f64,
}

/// The ordered parameter vector θ.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterSet {
    pub params: Vec<Parameter>,
}

impl ParameterSet {
    pub fn len(&self) -> usize {
        self.params.len()
    }

    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }

    pub fn names(&self) -> Vec<String> {
        self.params.iter().map(|p| p.name.clone()).collect()
    }

    /// The paper's N = 1 set (§4.2.1): e0a ~ U[0, 2] nm, Δ ~ U[0, 1],
    /// Ω ~ U[0, 1e13] rad/s, C0 = diag(0.01 nm, 0.01, 0.01e12 rad/s)².
    pub fn paper_n1() -> Self {
        let p = |name: &str, lower: f64, upper: f64, sd: f64| Parameter {
            name: name.to_string(),
            target: Target::from_name(name).expect("known name"),
            prior: Prior::Uniform { lower, upper },
            proposal_sd: sd,
        };
        ParameterSet {
            params: vec![
                p("nonlocal_e0a_nm", 0.0, 2.0, 0.01),
                p("delta", 0.0, 1.0, 0.01),
                p("omega_rad_s", 0.0, 1e13, 0.01e12),
            ],
        }
    }

    /// Builds the set from the YAML mapping, preserving the written order.
    pub fn from_mapping(map: &serde_yaml::Mapping) -> Result<Self, InputError> {
        if map.is_empty() {
            return Err(InputError::new("parameters", "{}", "at least one parameter"));
        }
        let mut params = Vec::with_capacity(map.len());
        for (key, value) in map {
            let name = key
                .as_str()
                .ok_or_else(|| InputError::new("parameters", yaml_key_text(key), "string keys naming parameters"))?
                .to_string();
            let field = format!("parameters.{name}");
            let target = Target::from_name(&name)
                .ok_or_else(|| InputError::new("parameters", &name, format!("one of: {KNOWN_NAMES}")))?;
            if params.len() >= MAX_PARAMETERS {
                return Err(InputError::new(
                    "parameters",
                    format!("({} entries)", map.len()),
                    format!("at most {MAX_PARAMETERS} parameters"),
                ));
            }
            if params.iter().any(|p: &Parameter| p.target == target) {
                return Err(InputError::new(&field, &name, "each parameter once"));
            }
            let entry: ParameterEntry = crate::error::from_yaml_value(&field, value.clone()).map_err(|e| {
                // serde reports errors inside the internally tagged `Prior`
                // without its path: parse the prior alone to name it
                match value.get("prior") {
                    Some(p) => {
                        crate::error::from_yaml_value::<Prior>(&format!("{field}.prior"), p.clone()).err().unwrap_or(e)
                    }
                    None => e,
                }
            })?;
            entry.prior.validate(&format!("{field}.prior"))?;
            check_prior_range(&entry.prior, &format!("{field}.prior"))?;
            let proposal_sd = match entry.proposal_sd {
                Some(sd) => {
                    check_proposal_sd(&entry.prior, &format!("{field}.proposal_sd"), sd)?;
                    sd
                }
                None => default_proposal_sd(&entry.prior),
            };
            params.push(Parameter { name, target, prior: entry.prior, proposal_sd });
        }
        Ok(ParameterSet { params })
    }

    /// Rejects parameters the beam cannot carry (e.g. `delta_2` on a beam
    /// with one internal variable) and physically impossible prior supports.
    pub fn check_against_beam(&self, beam: &BeamSpec) -> Result<(), InputError> {
        let n_iv = beam.internal_variables.len();
        for p in &self.params {
            let field = format!("parameters.{}", p.name);
            let needs_iv = match p.target {
                Target::Delta(i) | Target::Omega(i) => Some(i),
                _ => None,
            };
            if let Some(i) = needs_iv {
                if i > n_iv {
                    return Err(InputError::new(
                        &field,
                        &p.name,
                        format!("internal variable {} needs variables 1..{} calibrated or listed in beam.internal_variables", i + 1, i),
                    ));
                }
            }
            check_range(p, &field)?;
            if p.target == Target::PointMassXnm {
                let (_, hi) = p.prior.support();
                if hi > beam.length_nm {
                    return Err(InputError::new(
                        format!("{field}.prior"),
                        hi,
                        format!("a support within the beam [0, length_nm = {}]", beam.length_nm),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Index of β² in θ, if calibrated.
    pub fn beta_squared_index(&self) -> Option<usize> {
        self.params.iter().position(|p| p.target == Target::BetaSquared)
    }

    /// The beam with θ applied. Internal variables beyond the beam's list are
    /// appended (Δ = 0, Ω = 1e12 rad/s placeholders are overwritten by θ).
    pub fn apply(&self, base: &BeamSpec, theta: &[f64]) -> BeamSpec {
        let mut beam = base.clone();
        self.apply_in_place(&mut beam, theta);
        beam
    }

    /// [`Self::apply`] into an existing beam (no allocation when the number of
    /// internal variables does not change).
    pub fn apply_in_place(&self, beam: &mut BeamSpec, theta: &[f64]) {
        for (p, &v) in self.params.iter().zip(theta) {
            match p.target {
                Target::NonlocalE0a => beam.nonlocal_e0a_nm = v,
                Target::Delta(i) => iv_mut(beam, i).delta = v,
                Target::Omega(i) => iv_mut(beam, i).omega_rad_s = v,
                Target::Diameter => beam.diameter_nm = v,
                Target::BetaSquared => {}
                Target::ViscousDamping => beam.viscous_damping_n_s_m2 = v,
                Target::SupportRotationalStiffness => beam.support_rotational_stiffness_n_m_rad = v,
                Target::SupportRotationalStiffnessLeft => beam.support_rotational_stiffness_left_n_m_rad = v,
                Target::SupportRotationalStiffnessRight => beam.support_rotational_stiffness_right_n_m_rad = v,
                Target::PointMassKg => point_mass_mut(beam).mass_kg = v,
                Target::PointMassXnm => point_mass_mut(beam).x_nm = v,
                Target::YoungsModulus => beam.youngs_modulus_pa = v,
                Target::Density => beam.density_kg_m3 = v,
                Target::Length => beam.length_nm = v,
                Target::AxialForce => beam.axial_force_n = v,
                Target::ShearCoefficient => shear_mut(beam).shear_coefficient = v,
                Target::PoissonRatio => shear_mut(beam).poisson_ratio = v,
                Target::ElasticFoundation => beam.elastic_foundation_n_m2 = v,
                Target::LossFactor => beam.loss_factor = v,
                Target::StrainGradientLength => beam.strain_gradient_length_nm = v,
            }
        }
    }
}

fn iv_mut(beam: &mut BeamSpec, i: usize) -> &mut InternalVariable {
    while beam.internal_variables.len() <= i {
        beam.internal_variables.push(InternalVariable { delta: 0.0, omega_rad_s: 1e12 });
    }
    &mut beam.internal_variables[i]
}

fn point_mass_mut(beam: &mut BeamSpec) -> &mut PointMass {
    let half = beam.length_nm / 2.0;
    beam.point_mass.get_or_insert(PointMass { mass_kg: 0.0, x_nm: half })
}

/// Default Poisson's ratio when a calibration turns shear deformation on
/// for a beam that has none: ν = 0.2, within the 0.14–0.28 reported for
/// carbon nanotubes (Lu, Phys. Rev. Lett. 79 (1997) 1297: 0.28; graphene's
/// in-plane 0.16–0.19). Only G = E/(2(1 + ν)) depends on it, through κG.
pub const DEFAULT_POISSON_RATIO: f64 = 0.2;

/// The range of the shear coefficient κ a diagnosis's `shear-deformation`
/// cause samples (uniform; at ν = [`DEFAULT_POISSON_RATIO`]), and the
/// softest shear `identify` numbers modes against: from 1 down to 0.3,
/// below a thin tube's ≈ 0.52 (the reasoning is in `diagnose::classes`).
pub const SHEAR_COEFFICIENT_PRIOR: (f64, f64) = (0.3, 1.0);

/// The prior range of the stiffness-to-mass factor f (on EI/ρA, sampled as
/// E/E_nominal) of a diagnosis's `section-mismatch` cause (the reasoning is in
/// `diagnose::classes`), and the nominal section's uncertainty `identify`
/// numbers modes against: every ω scales by √f.
pub const SECTION_FACTOR_RANGE: (f64, f64) = (2.0 / 3.0, 1.5);

/// Shear deformation as a calibration turns it on: ν = [`DEFAULT_POISSON_RATIO`]
/// and the section's shear coefficient at that ν (`BeamSpec::default_shear_coefficient`:
/// solid circle or thin tube, Cowper 1966).
fn shear_mut(beam: &mut BeamSpec) -> &mut ShearDeformation {
    let shear_coefficient = beam.default_shear_coefficient(DEFAULT_POISSON_RATIO);
    beam.shear_deformation.get_or_insert(ShearDeformation { poisson_ratio: DEFAULT_POISSON_RATIO, shear_coefficient })
}

/// The prior's support must lie in the parameter's physical range: [0, ∞)
/// for most ([`check_physical`]); any real for the axial force and the
/// foundation (the buckling and stability bounds depend on the other
/// parameters, so draws beyond them are rejected by the model, like any
/// invalid beam); (0, 1] for κ; (−1, 0.5] for ν.
fn check_range(p: &Parameter, field: &str) -> Result<(), InputError> {
    // a normal prior: its ±4 sd range (as `check_physical` does for ≥ 0)
    let (lo, hi) = match p.prior {
        Prior::Normal { mean, sd } => (mean - 4.0 * sd, mean + 4.0 * sd),
        _ => p.prior.support(),
    };
    let within = |lo_ok: bool, hi_ok: bool, allowed: &str| {
        if !lo_ok {
            Err(InputError::new(format!("{field}.prior.lower"), lo, allowed.to_string()))
        } else if !hi_ok {
            Err(InputError::new(format!("{field}.prior.upper"), hi, allowed.to_string()))
        } else {
            Ok(())
        }
    };
    match p.target {
        Target::AxialForce | Target::ElasticFoundation => Ok(()),
        Target::ShearCoefficient => {
            within(lo >= 0.0, hi <= 1.0, "a support within the physical range 0 < shear_coefficient <= 1")
        }
        Target::PoissonRatio => {
            within(lo >= -1.0, hi <= 0.5, "a support within the physical range -1 < poisson_ratio <= 0.5")
        }
        Target::LossFactor => within(lo >= 0.0, hi < 1.0, "a support within the physical range 0 <= loss_factor < 1"),
        _ => check_physical(&p.prior, field),
    }
}

/// Most calibrated parameters: every named target once (13 names plus up to
/// 16 internal variables, 2 each) stays below this.
pub const MAX_PARAMETERS: usize = 64;

/// A YAML key as the user wrote it (for the error line).
fn yaml_key_text(key: &serde_yaml::Value) -> String {
    serde_yaml::to_string(key).map(|t| t.trim().replace('\n', " ")).unwrap_or_else(|_| "(key)".into())
}

/// Largest |bound| or location of a prior, and smallest scale: with
/// |x| ≤ 1e150 and scale ≥ 1e-140, every square the sampler and the
/// summaries form — (x − mean)², sd² of a proposal (≥ 1e-9·scale, see
/// [`check_proposal_sd`]) times 2.4²/d and a DR factor ≥ 1e-6 — is a normal
/// f64 (|·| in [1e-306, 1e300]), and sums of up to 1e7 such squares stay
/// below f64::MAX (a uniform bound of 1.7e308 made the posterior mean inf).
pub const PRIOR_MAX_ABS: f64 = 1e150;
pub const PRIOR_MIN_SCALE: f64 = 1e-140;
/// A prior's scale relative to its location: below this, the random-walk
/// steps (≥ 1e-9 of the scale) fall under the rounding of the values
/// themselves (2.2e-16 relative) and the chain cannot move.
pub const PRIOR_MIN_RELATIVE_SCALE: f64 = 1e-6;

/// The prior's scale: support width when bounded, else its sd, else (inverse
/// gamma without a finite variance) its scale parameter.
fn prior_scale(prior: &Prior) -> f64 {
    let (lo, hi) = prior.support();
    if lo.is_finite() && hi.is_finite() {
        hi - lo
    } else {
        match *prior {
            Prior::InverseGamma { scale, .. } => prior.sd().unwrap_or(scale),
            _ => prior.sd().unwrap_or(1.0),
        }
    }
}

/// Numeric range of a prior (see [`PRIOR_MAX_ABS`]).
pub fn check_prior_range(prior: &Prior, field: &str) -> Result<(), InputError> {
    use crate::error::fmt_num;
    let values: Vec<(&str, f64)> = match *prior {
        Prior::Uniform { lower, upper } | Prior::LogUniform { lower, upper } => {
            vec![("lower", lower), ("upper", upper)]
        }
        Prior::AsinhUniform { lower, upper, scale } => vec![("lower", lower), ("upper", upper), ("scale", scale)],
        Prior::Normal { mean, sd } => vec![("mean", mean), ("sd", sd)],
        Prior::InverseGamma { shape, scale } => vec![("shape", shape), ("scale", scale)],
    };
    for &(name, v) in &values {
        if v.abs() > PRIOR_MAX_ABS {
            return Err(InputError::new(format!("{field}.{name}"), fmt_num(v), format!("|x| <= {PRIOR_MAX_ABS:e}")));
        }
    }
    if let Prior::InverseGamma { shape, scale } = *prior {
        if !(1e-2..=1e6).contains(&shape) {
            return Err(InputError::new(format!("{field}.shape"), fmt_num(shape), "1e-2 <= shape <= 1e6"));
        }
        if scale < PRIOR_MIN_SCALE {
            return Err(InputError::new(format!("{field}.scale"), fmt_num(scale), format!(">= {PRIOR_MIN_SCALE:e}")));
        }
        return Ok(());
    }
    let scale = prior_scale(prior);
    let location = values
        .iter()
        .take(if matches!(prior, Prior::Normal { .. }) { 1 } else { 2 })
        .fold(0.0f64, |a, v| a.max(v.1.abs()));
    let min_scale = PRIOR_MIN_SCALE.max(PRIOR_MIN_RELATIVE_SCALE * location);
    if scale.is_nan() || scale < min_scale {
        let (name, v) =
            if matches!(prior, Prior::Normal { .. }) { ("sd", values[1].1) } else { ("upper", values[1].1) };
        let what = if name == "sd" { "sd" } else { "upper - lower" };
        return Err(InputError::new(
            format!("{field}.{name}"),
            fmt_num(v),
            format!("{what} >= {min_scale:e} (max({PRIOR_MIN_SCALE:e}, {PRIOR_MIN_RELATIVE_SCALE:e} x |location|))"),
        ));
    }
    Ok(())
}

/// The C0 step of a parameter: between 1e-9 and 1 times the prior's scale.
/// Above the scale nearly every proposal leaves the support (a step of 1e200
/// on a [0, 1] prior: acceptance 0, frozen chains); below 1e-9 of it a chain
/// of 1e4–1e7 states moves ≤ ~3e-6 of the scale before adaptation and its
/// covariance is rounding noise.
pub fn check_proposal_sd(prior: &Prior, field: &str, sd: f64) -> Result<(), InputError> {
    let scale = prior_scale(prior);
    let (lo, hi) = (1e-9 * scale, scale);
    if sd.is_finite() && sd >= lo && sd <= hi {
        Ok(())
    } else {
        Err(InputError::new(
            field,
            crate::error::fmt_num(sd),
            format!("{lo:e} <= sd <= {hi:e} (1e-9 to 1 times the prior's scale {scale:e})"),
        ))
    }
}

/// 1 % of the prior's scale (support width for bounded priors, sd otherwise):
/// the same relative size as the paper's C0 for e0a and Δ.
fn default_proposal_sd(prior: &Prior) -> f64 {
    let (lo, hi) = prior.support();
    if lo.is_finite() && hi.is_finite() {
        0.01 * (hi - lo)
    } else {
        0.01 * prior.sd().unwrap_or(1.0).abs().max(f64::MIN_POSITIVE)
    }
}

/// Every beam quantity and β² is non-negative by nature: bounded priors must
/// lie in [0, ∞); a normal prior must put its mean at least 4 sd above 0
/// (P(x < 0) < 3e-5; such draws are rejected by the sampler as invalid).
pub fn check_physical(prior: &Prior, field: &str) -> Result<(), InputError> {
    match *prior {
        Prior::Normal { mean, sd } => {
            if mean - 4.0 * sd <= 0.0 {
                return Err(InputError::new(
                    format!("{field}.prior.mean"),
                    mean,
                    format!("> 4 sd = {} (physical range >= 0)", 4.0 * sd),
                ));
            }
        }
        _ => {
            let (lo, _) = prior.support();
            if lo < 0.0 {
                return Err(InputError::new(
                    format!("{field}.prior.lower"),
                    lo,
                    "a support within the physical range >= 0",
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::Support;

    fn beam() -> BeamSpec {
        BeamSpec::from_yaml(
            "length_nm: 8\ndiameter_nm: 1\nyoungs_modulus_pa: 1e12\ndensity_kg_m3: 2300\nsupport: clamped-free\nelements: 20\n",
        )
        .unwrap()
    }

    fn set(yaml: &str) -> Result<ParameterSet, InputError> {
        let map: serde_yaml::Mapping = serde_yaml::from_str(yaml).unwrap();
        let set = ParameterSet::from_mapping(&map)?;
        set.check_against_beam(&beam())?;
        Ok(set)
    }

    #[test]
    fn axial_force_and_shear_names_act_on_the_beam() {
        let s = set("axial_force_n: { prior: { dist: uniform, lower: -1.0e-9, upper: 5.0e-9 } }\n\
                     shear_coefficient: { prior: { dist: uniform, lower: 0.5, upper: 1.0 } }\n\
                     poisson_ratio: { prior: { dist: uniform, lower: 0.1, upper: 0.3 } }")
        .unwrap();
        let b = s.apply(&beam(), &[-2e-10, 0.8, 0.25]);
        assert_eq!(b.support, Support::ClampedFree);
        assert_eq!(b.axial_force_n, -2e-10);
        let sd = b.shear_deformation.unwrap();
        assert_eq!((sd.shear_coefficient, sd.poisson_ratio), (0.8, 0.25));
        // κ alone turns shear on with the documented default ν
        let s = set("shear_coefficient: { prior: { dist: uniform, lower: 0.5, upper: 1.0 } }").unwrap();
        assert_eq!(s.apply(&beam(), &[0.7]).shear_deformation.unwrap().poisson_ratio, DEFAULT_POISSON_RATIO);
    }

    #[test]
    fn priors_outside_the_physical_range_are_named() {
        let e = set("shear_coefficient: { prior: { dist: uniform, lower: 0.5, upper: 1.5 } }").unwrap_err();
        assert_eq!(e.field, "parameters.shear_coefficient.prior.upper");
        let e = set("poisson_ratio: { prior: { dist: uniform, lower: -1.5, upper: 0.3 } }").unwrap_err();
        assert_eq!(e.field, "parameters.poisson_ratio.prior.lower");
        let e = set("poisson_ratio: { prior: { dist: normal, mean: 0.4, sd: 0.1 } }").unwrap_err();
        assert_eq!(e.field, "parameters.poisson_ratio.prior.upper");
    }
}
