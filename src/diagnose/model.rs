//! The identity of a candidate model: the causes ([`ModelClass`]) and the sets
//! of them a diagnosis compares ([`Model`]). Their priors and posteriors are
//! `classes`'.

use crate::beam::Support;
use crate::calibration::{ParameterSet, Target};

/// One candidate cause: an extension of the base model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ModelClass {
    ExtraRelaxation,
    ViscousDamping,
    SupportRotationalStiffness,
    AttachedMass,
    AxialForce,
    ShearDeformation,
    SectionMismatch,
    /// Last: a model's seed key is its causes' positions in [`Self::CAUSES`],
    /// so a new class is appended and the old models keep their seeds.
    ElasticFoundation,
    LossFactor,
    StrainGradient,
}

impl ModelClass {
    /// The candidate causes, in report order.
    pub const CAUSES: [ModelClass; 10] = [
        ModelClass::ExtraRelaxation,
        ModelClass::ViscousDamping,
        ModelClass::SupportRotationalStiffness,
        ModelClass::AttachedMass,
        ModelClass::AxialForce,
        ModelClass::ShearDeformation,
        ModelClass::SectionMismatch,
        ModelClass::ElasticFoundation,
        ModelClass::LossFactor,
        ModelClass::StrainGradient,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ModelClass::ExtraRelaxation => "extra-relaxation",
            ModelClass::ViscousDamping => "viscous-damping",
            ModelClass::SupportRotationalStiffness => "support-rotational-stiffness",
            ModelClass::AttachedMass => "attached-mass",
            ModelClass::AxialForce => "axial-force",
            ModelClass::ShearDeformation => "shear-deformation",
            ModelClass::SectionMismatch => "section-mismatch",
            ModelClass::ElasticFoundation => "elastic-foundation",
            ModelClass::LossFactor => "loss-factor",
            ModelClass::StrainGradient => "strain-gradient",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::CAUSES.into_iter().find(|c| c.name() == name)
    }

    /// Why measured ω and ζ alone never decide this cause, even when no
    /// model of the catalogue rivals it: an effect outside the catalogue
    /// that shares its signature to first order, and the measurement that
    /// separates the two. `None` for causes with no such known mimic.
    ///
    /// `section-mismatch` scales EI/ρA by one factor, which moves every
    /// undamped λ_n by that factor and leaves every mode shape nominal. A
    /// section or modulus that varies along the tube (a taper, a temperature
    /// gradient, a partial coating) moves λ_n by the mode-weighted mean of
    /// its variation, ∫(δEI·φ_n″² − λ_n δρA·φ_n²)dx / ∫EI φ_n″² dx: for a
    /// variation smooth on the scale of the measured modes' wavelengths that
    /// weight is nearly the same for every n, so a uniform factor fits
    /// (the oracle fits of `tests/diagnose_catalogue.rs`: a 10–20 % taper and
    /// an EI gradient fitted by section-mismatch alone within 0.01–0.21 sd of
    /// noise-free data). The variation skews the mode shapes, which the
    /// uniform factor cannot: a scan of a measured mode's shape separates them.
    pub fn first_order_mimic(self) -> Option<&'static str> {
        match self {
            ModelClass::SectionMismatch => Some(
                "a section or modulus that varies along the tube (a taper, a temperature gradient, a partial \
                 coating) with the same mean shifts every measured ω alike to first order, so ω and ζ cannot tell it \
                 from a uniform mismatch; the reading is that of the mean section. A scan of a measured mode's \
                 shape (mode_scans) would separate them: a uniform mismatch leaves every shape nominal",
            ),
            _ => None,
        }
    }

    /// Whether the cause changes a beam with `support` at all. The rotational
    /// spring acts on the rotations a support leaves free (`beam::model`):
    /// both ends of a simply supported beam, the pinned end of a
    /// clamped–pinned one, none on a clamped–clamped or clamped–free beam.
    /// There the class would add a parameter the likelihood ignores, its
    /// evidence that of the model without it up to estimator noise, and it
    /// would be listed as an alternative "within the margin" of every
    /// selection (measured on a clamped–clamped beam with a
    /// point mass: support-rotational-stiffness + attached-mass 0.0 nats
    /// from the selected attached-mass; on a cantilever the same).
    pub fn acts_on(self, support: Support) -> bool {
        match self {
            ModelClass::SupportRotationalStiffness => {
                matches!(support, Support::SimplySupported | Support::ClampedPinned)
            }
            _ => true,
        }
    }

    /// Whether the class is free to act given the file's parameters `base`:
    /// `section-mismatch` samples the modulus, so it is no candidate when
    /// the base model already samples the diameter, the modulus or the
    /// density (the paper's Cases 2A–2C and 3 carry the diameter as a
    /// nuisance parameter): the class would duplicate that parameter or add
    /// one the base's already spans.
    pub fn free_in(self, base: &ParameterSet) -> bool {
        match self {
            ModelClass::SectionMismatch => !base
                .params
                .iter()
                .any(|p| matches!(p.target, Target::Diameter | Target::YoungsModulus | Target::Density)),
            _ => true,
        }
    }

    /// How many parameters the class appends to the base model on a beam
    /// with `support` (what `add_extension` pushes; a test holds the two
    /// together): the support spring has one per free rotation.
    pub fn parameter_count(self, support: Support) -> usize {
        match self {
            ModelClass::ExtraRelaxation | ModelClass::AttachedMass => 2,
            ModelClass::SupportRotationalStiffness => match support {
                Support::SimplySupported => 2,
                Support::ClampedPinned => 1,
                Support::ClampedClamped | Support::ClampedFree => 0,
            },
            _ => 1,
        }
    }
}

/// A model compared by its evidence: the base model plus a set of causes, or
/// the β-inflated baseline of eq. (41) (which absorbs misfit as noise and is
/// never a cause).
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Model {
    /// The base model with these extensions (sorted, none = the base model itself).
    Extended(Vec<ModelClass>),
    /// Base + β² ~ IG(9.5, 11.1), eq. (41).
    Baseline,
}

impl Model {
    pub const BASE: Model = Model::Extended(Vec::new());

    /// The base model with `causes` (order does not matter).
    pub fn with(causes: &[ModelClass]) -> Self {
        let mut c = causes.to_vec();
        c.sort_unstable();
        c.dedup();
        Model::Extended(c)
    }

    /// Every model of at most `k` causes, by number of causes, then in the
    /// order of [`ModelClass::CAUSES`] (the base first; 56 models at k = 2).
    pub fn up_to(k: usize) -> Vec<Model> {
        let mut models = vec![Model::BASE];
        let mut level = vec![Model::BASE];
        for _ in 0..k.min(ModelClass::CAUSES.len()) {
            // extend each model only by causes after its last (causes are kept
            // sorted, in the order of CAUSES), so each set appears once
            level = level
                .iter()
                .flat_map(|m| {
                    let last = m.causes().last().copied();
                    ModelClass::CAUSES
                        .into_iter()
                        .filter(move |&c| last.is_none_or(|l| c > l))
                        .map(move |c| Model::with(&[m.causes(), &[c]].concat()))
                })
                .collect();
            models.extend(level.iter().cloned());
        }
        models
    }

    /// [`Model::up_to`] without the models of a cause that does not act on
    /// `support` ([`ModelClass::acts_on`]) or is not free given the file's
    /// parameters `base` ([`ModelClass::free_in`]), and without the models
    /// that combine `shear-deformation` with `strain-gradient` (the strain
    /// gradient is defined on the Euler–Bernoulli beam only: `beam::spec`
    /// refuses the pair): the candidates of a diagnosis.
    pub fn candidates(k: usize, support: Support, base: &ParameterSet) -> Vec<Model> {
        Model::up_to(k)
            .into_iter()
            .filter(|m| m.causes().iter().all(|c| c.acts_on(support) && c.free_in(base)))
            .filter(|m| {
                let c = m.causes();
                !(c.contains(&ModelClass::ShearDeformation) && c.contains(&ModelClass::StrainGradient))
            })
            .collect()
    }

    /// This model without `cause` (the model itself when it lacks it).
    pub fn without(&self, cause: ModelClass) -> Model {
        Model::with(&self.causes().iter().copied().filter(|&c| c != cause).collect::<Vec<_>>())
    }

    /// The causes this model adds to the base (empty for the base and the baseline).
    pub fn causes(&self) -> &[ModelClass] {
        match self {
            Model::Extended(c) => c,
            Model::Baseline => &[],
        }
    }

    /// The inverse of [`Model::name`].
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "base" => Some(Model::BASE),
            "baseline-beta" => Some(Model::Baseline),
            _ => name.split('+').map(ModelClass::from_name).collect::<Option<Vec<_>>>().map(|c| Model::with(&c)),
        }
    }

    /// `base`, `baseline-beta`, a cause's name, or causes joined by `+`.
    pub fn name(&self) -> String {
        match self {
            Model::Baseline => "baseline-beta".into(),
            Model::Extended(c) if c.is_empty() => "base".into(),
            Model::Extended(c) => c.iter().map(|c| c.name()).collect::<Vec<_>>().join("+"),
        }
    }
}
