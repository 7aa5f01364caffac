//! The YAML beam description (a public contract: field names never change).
//!
//! Lengths are in nanometres, everything else in SI; every field name carries
//! its unit. Unknown fields are rejected by serde, out-of-range values by
//! [`BeamSpec::validate`].

use serde::{Deserialize, Serialize};

use crate::error::{fmt_num, non_negative, positive, InputError};

/// Boundary conditions at x = 0 and x = L.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Support {
    /// w = 0 at both ends (rotations free).
    SimplySupported,
    /// w = w' = 0 at both ends.
    ClampedClamped,
    /// w = w' = 0 at x = 0, free at x = L (cantilever).
    ClampedFree,
    /// w = w' = 0 at x = 0, w = 0 at x = L.
    ClampedPinned,
}

impl Support {
    pub const ALL: [Support; 4] =
        [Support::SimplySupported, Support::ClampedClamped, Support::ClampedFree, Support::ClampedPinned];

    pub fn name(self) -> &'static str {
        match self {
            Support::SimplySupported => "simply-supported",
            Support::ClampedClamped => "clamped-clamped",
            Support::ClampedFree => "clamped-free",
            Support::ClampedPinned => "clamped-pinned",
        }
    }

    /// Whether the support at x = L is that at x = 0 (simply supported,
    /// clamped–clamped): then a beam and its mirror image about midspan have
    /// the same modes.
    pub fn mirrors_itself(self) -> bool {
        matches!(self, Support::SimplySupported | Support::ClampedClamped)
    }
}

/// One internal variable of the relaxation kernel, eq. (8):
/// E_rel(t) = E [1 + Σ Δi exp(−Ωi t)].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InternalVariable {
    /// Relaxation amplitude Δi (dimensionless, ≥ 0).
    pub delta: f64,
    /// Inverse relaxation time Ωi in rad/s (> 0).
    pub omega_rad_s: f64,
}

/// A point mass rigidly attached to the beam axis (model extension, default off).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointMass {
    /// Mass in kg (> 0).
    pub mass_kg: f64,
    /// Position along the beam in nm, 0 ≤ x ≤ length_nm.
    pub x_nm: f64,
}

/// Shear deformation and rotary inertia (nonlocal Timoshenko beam, extension,
/// default off). The shear modulus is G = E/(2(1 + ν)); E and G relax
/// together (ν is constant), so the relaxation factor multiplies the whole
/// elastic stiffness (bending + shear).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShearDeformation {
    /// Poisson's ratio ν, −1 < ν ≤ 0.5 (isotropic elasticity).
    pub poisson_ratio: f64,
    /// Timoshenko shear coefficient κ, 0 < κ ≤ 1. Omitted in YAML: the
    /// section's ([`BeamSpec::default_shear_coefficient`]; solid circle
    /// 6(1+ν)/(7+6ν) ≈ 0.88, thin tube 2(1+ν)/(4+3ν) ≈ 0.52 at ν = 0.2).
    pub shear_coefficient: f64,
}

impl ShearDeformation {
    /// κG/E = κ/(2(1 + ν)).
    pub fn shear_to_youngs(&self) -> f64 {
        self.shear_coefficient / (2.0 * (1.0 + self.poisson_ratio))
    }
}

/// The cross-section when it is not the default solid circle of
/// `diameter_nm` (YAML: `section: { tube: { wall_nm: 0.34 } }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Section {
    /// A circular tube whose mean (mid-wall) diameter is the beam's `diameter_nm`.
    pub tube: Tube,
}

/// A circular tube of mean diameter d (the beam's `diameter_nm`) and wall t:
/// the annulus between radii (d − t)/2 and (d + t)/2, so A = π d t and
/// I = π d t (d² + t²)/8 exactly. A carbon nanotube is a tube with the
/// conventional wall t = 0.34 nm (graphite's interlayer spacing).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tube {
    /// Wall thickness t in nm, 0 < t < `diameter_nm`.
    pub wall_nm: f64,
}

/// Timoshenko shear coefficient of a solid circle, 6(1 + ν)/(7 + 6ν)
/// (G. R. Cowper, J. Appl. Mech. 33 (1966) 335–340, Table 1).
pub fn solid_circle_shear_coefficient(poisson_ratio: f64) -> f64 {
    6.0 * (1.0 + poisson_ratio) / (7.0 + 6.0 * poisson_ratio)
}

/// Timoshenko shear coefficient of a thin-walled circular tube,
/// 2(1 + ν)/(4 + 3ν) (Cowper 1966, Table 1; his hollow-circle formula as the
/// radius ratio → 1). The thin-wall limit is used for every tube, not
/// Cowper's thick annulus: a nanotube's wall is one atomic layer whose shear
/// flow is that of a thin shell; t = 0.34 nm only sets its bending stiffness.
pub fn thin_tube_shear_coefficient(poisson_ratio: f64) -> f64 {
    2.0 * (1.0 + poisson_ratio) / (4.0 + 3.0 * poisson_ratio)
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// A beam as written in YAML. Read through [`BeamSpecYaml`], which lets
/// `shear_deformation.shear_coefficient` default to the section's
/// ([`BeamSpec::default_shear_coefficient`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(from = "BeamSpecYaml")]
pub struct BeamSpec {
    pub length_nm: f64,
    /// Solid circular section (default): the diameter, A = πd²/4, I = πd⁴/64.
    /// With a tube [`section`](Self::section): the tube's mean diameter.
    pub diameter_nm: f64,
    pub youngs_modulus_pa: f64,
    pub density_kg_m3: f64,
    pub support: Support,
    /// Number of Hermite beam elements.
    pub elements: usize,
    /// Eringen nonlocal parameter e0a in nm, eq. (5).
    #[serde(default)]
    pub nonlocal_e0a_nm: f64,
    /// External viscous damping C of eq. (13), N·s/m².
    #[serde(default)]
    pub viscous_damping_n_s_m2: f64,
    /// Internal variables (Δi, Ωi) of eq. (8); empty = elastic.
    #[serde(default)]
    pub internal_variables: Vec<InternalVariable>,
    /// Rotational spring at each supported end, N·m/rad (extension, default
    /// 0); it acts on the rotations the support leaves free (both ends
    /// simply supported, x = L clamped–pinned, none clamped–clamped or
    /// clamped–free).
    #[serde(default)]
    pub support_rotational_stiffness_n_m_rad: f64,
    /// A rotational spring at x = 0 only ("left"), N·m/rad, in parallel with
    /// [`support_rotational_stiffness_n_m_rad`](Self::support_rotational_stiffness_n_m_rad)
    /// (the two add; default 0). Only where the support leaves the rotation
    /// free: x = 0 of a simply supported beam.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub support_rotational_stiffness_left_n_m_rad: f64,
    /// A rotational spring at x = L only ("right"), N·m/rad, as the left one:
    /// x = L of a simply supported or clamped–pinned beam.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub support_rotational_stiffness_right_n_m_rad: f64,
    /// Attached point mass (extension, default none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_mass: Option<PointMass>,
    /// Axial force N in newtons, tension > 0, compression < 0 (extension,
    /// default 0). Elastic: not multiplied by the relaxation factor.
    /// Compression must stay above the (nonlocal) buckling load of the
    /// beam's mesh and support (checked by [`BeamSpec::validate`]).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub axial_force_n: f64,
    /// Winkler elastic foundation k under the whole span, N/m² (force per
    /// length per deflection; extension, default 0): > 0 for a substrate or
    /// an embedding matrix, < 0 for an electrostatic gate's pull (a negative
    /// spring), which must leave the beam stable (checked by
    /// [`BeamSpec::validate`]). Elastic (not relaxed), and Eringen's law acts
    /// on its reaction as on every distributed transverse load (the reaction
    /// enters through the nonlocal translational mass form: `fe::scaling`), so
    /// when the foundation is the only extension coupling the modes it adds
    /// k/ρA to every ω² of the undamped beam, any support.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub elastic_foundation_n_m2: f64,
    /// Frequency-independent (hysteretic) loss factor η of the beam's own
    /// stiffness (bending and shear, relaxed or not): the complex modulus
    /// E(1 + iη) at ω > 0, 0 ≤ η < 1 (extension, default 0). Every mode of an
    /// otherwise undamped beam gets ζ = sin(½·atan η) ≈ η/2. Defined in the
    /// frequency domain only (a hysteretic loss has no causal time-domain
    /// form), so a beam with η > 0 has no state-space model, no impulse
    /// response and no real relaxation poles: its modes are the oscillatory
    /// poles alone (`solve::family`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub loss_factor: f64,
    /// Material length scale l of nonlocal strain-gradient elasticity, nm
    /// (Lim, Zhang & Reddy 2015; extension, default 0 = the classical beam):
    /// at wavenumber q the stiffness grows by (1 + l²q²) against Eringen's
    /// (1 + (e0a)²q²). The beam equation becomes of sixth order, solved on C²
    /// (quintic Hermite) elements with the higher-order boundary conditions
    /// of `fe::scaling`'s module doc; relaxed with the modulus like the rest
    /// of the bending stiffness. 0 <= l <= length_nm; Euler–Bernoulli only
    /// (refused with shear deformation).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub strain_gradient_length_nm: f64,
    /// Shear deformation and rotary inertia (Timoshenko beam; default off).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_deformation: Option<ShearDeformation>,
    /// The section's shape when not a solid circle (default: solid circle).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section: Option<Section>,
}

/// [`BeamSpec`] as read from YAML: the same fields, with the shear
/// coefficient optional (its default depends on the section, a sibling
/// field, so it is resolved after the whole beam is read).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BeamSpecYaml {
    length_nm: f64,
    diameter_nm: f64,
    youngs_modulus_pa: f64,
    density_kg_m3: f64,
    support: Support,
    elements: usize,
    #[serde(default)]
    nonlocal_e0a_nm: f64,
    #[serde(default)]
    viscous_damping_n_s_m2: f64,
    #[serde(default)]
    internal_variables: Vec<InternalVariable>,
    #[serde(default)]
    support_rotational_stiffness_n_m_rad: f64,
    #[serde(default)]
    support_rotational_stiffness_left_n_m_rad: f64,
    #[serde(default)]
    support_rotational_stiffness_right_n_m_rad: f64,
    #[serde(default)]
    point_mass: Option<PointMass>,
    #[serde(default)]
    axial_force_n: f64,
    #[serde(default)]
    elastic_foundation_n_m2: f64,
    #[serde(default)]
    loss_factor: f64,
    #[serde(default)]
    strain_gradient_length_nm: f64,
    #[serde(default)]
    shear_deformation: Option<ShearDeformationYaml>,
    #[serde(default)]
    section: Option<Section>,
}

/// [`ShearDeformation`] as read from YAML: κ may be omitted.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ShearDeformationYaml {
    poisson_ratio: f64,
    #[serde(default)]
    shear_coefficient: Option<f64>,
}

impl From<BeamSpecYaml> for BeamSpec {
    fn from(y: BeamSpecYaml) -> Self {
        let mut beam = BeamSpec {
            length_nm: y.length_nm,
            diameter_nm: y.diameter_nm,
            youngs_modulus_pa: y.youngs_modulus_pa,
            density_kg_m3: y.density_kg_m3,
            support: y.support,
            elements: y.elements,
            nonlocal_e0a_nm: y.nonlocal_e0a_nm,
            viscous_damping_n_s_m2: y.viscous_damping_n_s_m2,
            internal_variables: y.internal_variables,
            support_rotational_stiffness_n_m_rad: y.support_rotational_stiffness_n_m_rad,
            support_rotational_stiffness_left_n_m_rad: y.support_rotational_stiffness_left_n_m_rad,
            support_rotational_stiffness_right_n_m_rad: y.support_rotational_stiffness_right_n_m_rad,
            point_mass: y.point_mass,
            axial_force_n: y.axial_force_n,
            elastic_foundation_n_m2: y.elastic_foundation_n_m2,
            loss_factor: y.loss_factor,
            strain_gradient_length_nm: y.strain_gradient_length_nm,
            shear_deformation: None,
            section: y.section,
        };
        beam.shear_deformation = y.shear_deformation.map(|sd| ShearDeformation {
            poisson_ratio: sd.poisson_ratio,
            shear_coefficient: sd.shear_coefficient.unwrap_or_else(|| beam.default_shear_coefficient(sd.poisson_ratio)),
        });
        beam
    }
}

/// Largest element count accepted. The banded eigen path (Newton–Maehly on
/// det(K̃ − σM̃), certified by inertia counts) works to a noise floor of
/// ~eps·λ_max/λ₁ ∝ elements⁴ relative; measured over every support with and
/// without internal variables, e0a, spring and point mass, it certifies the
/// lowest eigenpairs up to 300 elements and starts failing (then the dense
/// state-space fallback, O(((2+N)·n)³), takes minutes) from ~350 elements on
/// a cantilever. 300 elements is also far beyond convergence: the Hermite
/// cubic eigenvalue error ≈ (jπ/elements)⁴/720 relative is < 1e-8 for the
/// first 20 modes.
pub const MAX_ELEMENTS: usize = 300;

/// Most internal variables: the family-polynomial root finder works on a
/// fixed buffer of this size (`family::family_roots`).
pub const MAX_INTERNAL_VARIABLES: usize = 16;

/// Window for every dimensional input, in its file unit (nm for lengths,
/// SI otherwise): `RAW_MIN <= v <= RAW_MAX`. Derivation (all products the
/// scaled model forms stay normal f64, |x| in [2.2e-308, 1.8e308]): with
/// d, L in m within [1e-39, 1e21], d⁴ ∈ [1e-156, 1e84], EI ∈ [1e-186, 1e114],
/// ρA ∈ [1e-108, 1e72], ω_ref = (d/4)√(E/ρ)/L² ∈ [1e-112, 1e129],
/// L³/EI ∈ [1e-231, 1e249]; every dimensionless group below is a ratio of
/// two such numbers. (A length of 1e308 nm or E = 1e-300 made ω_ref or
/// L³/EI overflow to inf/0 and the solver chase NaNs.)
pub const RAW_MIN: f64 = 1e-30;
pub const RAW_MAX: f64 = 1e30;

/// Bounds on the dimensionless groups the scaled solver sees (`model.rs`),
/// the range over which its root finders are tested (`tests/hardening_beam.rs`
/// runs every corner): ẽ = e0a/L; Δᵢ; Ω̃ᵢ = Ωᵢ/ω_ref; c̃ = C/(ρA ω_ref);
/// k̃_r = k_r L/EI; μ̃ = m/(ρA L). These are the limits at which every
/// corner (each group alone at its bound, on every support, at 2 and 300
/// elements, and at the corners of the raw window) was measured to give
/// finite modes in milliseconds; they keep the pole magnitudes within
/// ~1e13 of each other (relaxation poles near −Ω̃ᵢ/(1+Δᵢ) against
/// oscillatory ones near √λ̃ ≥ 3.5), which double-precision root finding
/// separates. All extremes *at once* on a 300-element mesh are not covered:
/// there the banded path can fail and the result is a clean numerical
/// failure (exit 1, see `state_space::MAX_DENSE_DIM`), never a hang.
/// Physically the limits are far outside a beam (e0a ≤ 10 L, relaxed/
/// unrelaxed modulus ≤ 1001, a spring 1e12 times stiffer than the beam is a
/// clamp, a mass 1e6 times the beam's).
pub const MAX_E_TILDE: f64 = 10.0;
pub const MAX_DELTA: f64 = 1e3;
pub const OMEGA_TILDE_RANGE: (f64, f64) = (1e-8, 1e10);
pub const MAX_C_TILDE: f64 = 1e4;
pub const MAX_SPRING_TILDE: f64 = 1e12;
pub const MAX_MASS_TILDE: f64 = 1e6;
/// Largest tension ñ = N L²/EI. The tension stiffness ñ·G adds to the bending
/// stiffness K̃, and mode r's bending share of its stiffness is ≈ (rπ)²/ñ
/// once ñ ≫ (rπ)²: the damping of the internal variables, e0a and the
/// spring act on that share alone (the axial force is elastic). At ñ = 1e8
/// the share is ≈ 1e-7, still 1e8 times the relative rounding of the
/// eigen solve; measured (simply supported and cantilever, 20 and 300
/// elements, one internal variable) every mode is finite with ζ > 0 there,
/// while at ñ = 1e10 the 300-element banded path fails and the 20-element
/// one returns ζ ≈ 3e-15, i.e. rounding; at ñ ≈ 1e39 (1e30 N on the 8 nm
/// beam) ζ came out −0.95. Physically ñ = 1e8 on the paper's beam is
/// 0.08 N, an axial stress ≈ 1e17 Pa, a million times a nanotube's strength.
pub const MAX_N_TILDE: f64 = 1e8;
/// Largest foundation modulus k̃ = k L⁴/EI. The foundation adds k̃ to every
/// mode's scaled ω² (module doc of `fe::scaling`), so mode r's bending share
/// of its stiffness is ≈ (rπ)⁴/k̃, and as for [`MAX_N_TILDE`] the damping of
/// the internal variables and e0a act on that share alone: at k̃ = 1e10 it is
/// ≈ 1e-8 for the first mode, still far above the eigen solve's relative
/// rounding (~1e-15) (derived by that argument, not measured as the force's
/// bound was). Physically k̃ = 1e10 on the paper's 8 nm beam (EI/L⁴ ≈
/// 1.2e7 N/m²) is k ≈ 1.2e17 N/m², some 4e7 times a polymer matrix's
/// (k ≈ E_matrix, a few GPa).
pub const MAX_FOUNDATION_TILDE: f64 = 1e10;
/// Largest strain-gradient length l̃ = l/L. Mode r's gradient share of its
/// stiffness is l̃²(rπ)²/(1 + l̃²(rπ)²): at l̃ = 1 it is 91 % for the first
/// mode, the beam a "gradient string" whose material length is its own
/// length, where a continuum length scale has lost its meaning (nanotube
/// values in the NSGT literature are l ≈ 0.1–2 nm on tubes of 5–100 nm,
/// l̃ ≲ 0.4). The element's K̃₃ entries grow as 1/h̃⁵ against K̃₂'s 1/h̃³,
/// so the pencil's spread λ_max/λ₁ grows as l̃²/h̃⁶: see
/// [`MAX_GRADIENT_ELEMENTS`] for the meshes on which l̃ ≤ 1 was measured to
/// solve.
pub const MAX_GRADIENT_TILDE: f64 = 1.0;
/// Largest mesh of a strain-gradient beam (l > 0). The from-scratch banded
/// eigen solve evaluates det(K̃ − σM̃) with a relative floor of
/// ~eps·λ_max/λ₁ in σ (`solve::eigen`), and on the C² mesh λ_max grows as
/// l̃²/h̃⁶ (against 1/h̃⁴ on the cubic mesh). Measured (10 modes, every
/// support, l̃ ∈ {1e-4, 0.01, 0.1, 0.3, 1}): up to 50 elements every case
/// solves on the banded decoupled path (0.3–0.6 ms in release) except the
/// cantilever at l̃ ≥ 0.3, which falls back to the state space (70 ms); at
/// 60–80 elements more cases fall back (to 0.3 s), at 100 the banded solve
/// fails from l̃ = 0.03 and at 200 from l̃ = 0.01, where the dense fallback
/// is beyond its dimension. Quintic elements converge at O(h⁶) in the
/// eigenvalue, so 50 elements resolve far more modes than a measurement
/// holds (the paper's mesh has 20).
pub const MAX_GRADIENT_ELEMENTS: usize = 50;
/// Range of the scaled shear stiffness g̃ = κGAL²/EI (≈ 100–450 for the
/// paper's L/d ≈ 8). Mode r's shear share of its compliance is ≈ (rπ)²/g̃:
/// at g̃ = 0.1 the first mode is ~99 % shear (a shear beam, no longer a
/// nanotube in bending), and below it the bending part falls under the
/// banded solver's resolution (measured: 100 elements fail at g̃ = 1e-2, a
/// 20-element cantilever gave ζ < 0 at 1e-6; κ = 1e-300 took 9 s to fail).
/// At g̃ = 1e10 the shear share is < 1e-8 for the first 10 modes (the
/// Euler–Bernoulli limit) and the modes were measured converged, finite
/// and unchanged from 1e8 to 7 digits on the same meshes.
pub const SHEAR_TILDE_RANGE: (f64, f64) = (0.1, 1e10);

/// `RAW_MIN <= value <= RAW_MAX` (or exactly 0 when `zero_ok`).
#[inline]
fn in_window(field: &str, value: f64, zero_ok: bool) -> Result<(), InputError> {
    let ok = value.is_finite() && ((RAW_MIN..=RAW_MAX).contains(&value) || (zero_ok && value == 0.0));
    if ok {
        Ok(())
    } else {
        Err(outside_window(field, value, zero_ok))
    }
}

/// The error of [`in_window`], out of line (it runs on every forward evaluation).
#[cold]
#[inline(never)]
fn outside_window(field: &str, value: f64, zero_ok: bool) -> InputError {
    let zero = if zero_ok { "0 or " } else { "" };
    InputError::new(field, fmt_num(value), format!("{zero}{RAW_MIN:e} <= x <= {RAW_MAX:e}"))
}

impl BeamSpec {
    /// A local elastic beam of this geometry and material: e0a = 0, no
    /// damping, no internal variables, ideal supports, no point mass, no axial
    /// force, Euler–Bernoulli (every extension at its default "off").
    pub fn elastic(
        length_nm: f64,
        diameter_nm: f64,
        youngs_modulus_pa: f64,
        density_kg_m3: f64,
        support: Support,
        elements: usize,
    ) -> Self {
        BeamSpec {
            length_nm,
            diameter_nm,
            youngs_modulus_pa,
            density_kg_m3,
            support,
            elements,
            nonlocal_e0a_nm: 0.0,
            viscous_damping_n_s_m2: 0.0,
            internal_variables: vec![],
            support_rotational_stiffness_n_m_rad: 0.0,
            support_rotational_stiffness_left_n_m_rad: 0.0,
            support_rotational_stiffness_right_n_m_rad: 0.0,
            point_mass: None,
            axial_force_n: 0.0,
            elastic_foundation_n_m2: 0.0,
            loss_factor: 0.0,
            strain_gradient_length_nm: 0.0,
            shear_deformation: None,
            section: None,
        }
    }

    /// The rotational spring stiffness at x = 0 and at x = L, N·m/rad: the
    /// both-ends field plus each end's own (springs in parallel add). Where
    /// the support fixes the rotation it acts on nothing (`beam::model`).
    pub fn support_rotational_stiffness_at_ends_n_m_rad(&self) -> [f64; 2] {
        let both = self.support_rotational_stiffness_n_m_rad;
        [both + self.support_rotational_stiffness_left_n_m_rad, both + self.support_rotational_stiffness_right_n_m_rad]
    }

    /// Whether this beam is its own mirror image about midspan: supports that
    /// [`Support::mirrors_itself`] and the same spring at both ends.
    pub fn mirrors_itself(&self) -> bool {
        self.support.mirrors_itself()
            && self.support_rotational_stiffness_left_n_m_rad == self.support_rotational_stiffness_right_n_m_rad
    }

    /// Checks every field's documented range (the error names the field,
    /// value and allowed range); [`BeamSpec::validate`] adds the buckling
    /// bound, which needs the assembled stiffness.
    pub fn validate_fields(&self) -> Result<(), InputError> {
        in_window("length_nm", self.length_nm, false)?;
        in_window("diameter_nm", self.diameter_nm, false)?;
        if let Some(Section { tube }) = &self.section {
            in_window("section.tube.wall_nm", tube.wall_nm, false)?;
            if tube.wall_nm >= self.diameter_nm {
                return Err(InputError::new(
                    "section.tube.wall_nm",
                    fmt_num(tube.wall_nm),
                    format!("0 < wall_nm < diameter_nm = {} (the tube's mean diameter)", fmt_num(self.diameter_nm)),
                ));
            }
        }
        in_window("youngs_modulus_pa", self.youngs_modulus_pa, false)?;
        in_window("density_kg_m3", self.density_kg_m3, false)?;
        // a clamped-clamped single element has no free DOF (every node fixed)
        let min_elements = if self.support == Support::ClampedClamped { 2 } else { 1 };
        if self.elements < min_elements || self.elements > MAX_ELEMENTS {
            return Err(InputError::new(
                "elements",
                self.elements,
                format!("{min_elements}..={MAX_ELEMENTS} (for support {})", self.support.name()),
            ));
        }
        non_negative("nonlocal_e0a_nm", self.nonlocal_e0a_nm)?;
        non_negative("viscous_damping_n_s_m2", self.viscous_damping_n_s_m2)?;
        if self.internal_variables.len() > MAX_INTERNAL_VARIABLES {
            return Err(InputError::new(
                "internal_variables",
                format!("({} entries)", self.internal_variables.len()),
                format!("at most {MAX_INTERNAL_VARIABLES} entries"),
            ));
        }
        for (i, iv) in self.internal_variables.iter().enumerate() {
            // field names formatted only on failure (this runs once per forward evaluation)
            if !(iv.delta.is_finite() && iv.delta >= 0.0) {
                non_negative(&format!("internal_variables[{i}].delta"), iv.delta)?;
            }
            if !(iv.omega_rad_s.is_finite() && iv.omega_rad_s > 0.0) {
                positive(&format!("internal_variables[{i}].omega_rad_s"), iv.omega_rad_s)?;
            }
        }
        non_negative("support_rotational_stiffness_n_m_rad", self.support_rotational_stiffness_n_m_rad)?;
        self.check_end_springs()?;
        if let Some(pm) = &self.point_mass {
            positive("point_mass.mass_kg", pm.mass_kg)?;
            if !(pm.x_nm.is_finite() && pm.x_nm >= 0.0 && pm.x_nm <= self.length_nm) {
                return Err(InputError::new(
                    "point_mass.x_nm",
                    pm.x_nm,
                    format!("0 <= x_nm <= length_nm = {}", self.length_nm),
                ));
            }
        }
        self.validate_scaled_groups()?;
        self.validate_extensions()
    }

    /// The axial force and shear-deformation fields (the buckling bound of a
    /// compressive force is checked by [`BeamSpec::validate`]).
    fn validate_extensions(&self) -> Result<(), InputError> {
        if !self.axial_force_n.is_finite() {
            return Err(InputError::new("axial_force_n", self.axial_force_n, "finite (tension > 0, compression < 0)"));
        }
        if let Some(sd) = &self.shear_deformation {
            let nu = sd.poisson_ratio;
            if !(nu.is_finite() && nu > -1.0 && nu <= 0.5) {
                return Err(InputError::new("shear_deformation.poisson_ratio", nu, "-1 < poisson_ratio <= 0.5"));
            }
            let k = sd.shear_coefficient;
            if !(k.is_finite() && k > 0.0 && k <= 1.0) {
                return Err(InputError::new(
                    "shear_deformation.shear_coefficient",
                    fmt_num(k),
                    "0 < shear_coefficient <= 1",
                ));
            }
            self.check_shear_group(sd)?;
        }
        let l = self.length_nm * 1e-9;
        let k_unit = self.youngs_modulus_pa * self.inertia_m4() / (l * l * l * l);
        let k = self.elastic_foundation_n_m2;
        if !(k.is_finite() && k <= MAX_FOUNDATION_TILDE * k_unit) {
            return Err(InputError::new(
                "elastic_foundation_n_m2",
                fmt_num(k),
                format!(
                    "<= {:e} N/m^2 (k L^4/EI <= {MAX_FOUNDATION_TILDE:e}; negative down to the loss of stability)",
                    MAX_FOUNDATION_TILDE * k_unit
                ),
            ));
        }
        let lg = self.strain_gradient_length_nm;
        if !(lg.is_finite() && lg >= 0.0 && lg <= MAX_GRADIENT_TILDE * self.length_nm) {
            return Err(InputError::new(
                "strain_gradient_length_nm",
                fmt_num(lg),
                format!(
                    "0 <= strain_gradient_length_nm <= {} (l/L <= {MAX_GRADIENT_TILDE})",
                    fmt_num(MAX_GRADIENT_TILDE * self.length_nm)
                ),
            ));
        }
        if lg > 0.0 && self.elements > MAX_GRADIENT_ELEMENTS {
            return Err(InputError::new(
                "elements",
                self.elements,
                format!(
                    "<= {MAX_GRADIENT_ELEMENTS} with strain_gradient_length_nm > 0 (the C2 mesh's spectrum spreads as (l/L)^2/h^6)"
                ),
            ));
        }
        if lg > 0.0 && self.shear_deformation.is_some() {
            return Err(InputError::new(
                "strain_gradient_length_nm",
                fmt_num(lg),
                "0 with shear_deformation (the strain-gradient beam is Euler-Bernoulli: a Timoshenko one needs a second, shear-strain gradient)",
            ));
        }
        let eta = self.loss_factor;
        if !(eta.is_finite() && (0.0..1.0).contains(&eta)) {
            return Err(InputError::new(
                "loss_factor",
                fmt_num(eta),
                "0 <= loss_factor < 1 (zeta ~ loss_factor/2 on every mode)",
            ));
        }
        let n_unit = self.youngs_modulus_pa * self.inertia_m4() / (l * l);
        if self.axial_force_n > MAX_N_TILDE * n_unit {
            return Err(InputError::new(
                "axial_force_n",
                fmt_num(self.axial_force_n),
                format!(
                    "<= {:e} N in tension (N L^2/EI <= {MAX_N_TILDE:e}, EI/L^2 = {n_unit:e} N; compression < 0 down to the buckling load)",
                    MAX_N_TILDE * n_unit
                ),
            ));
        }
        Ok(())
    }

    /// The scaled shear stiffness g̃ = κGAL²/EI = κ/(2(1 + ν))·AL²/I within
    /// [`SHEAR_TILDE_RANGE`], reported on the shear coefficient (the
    /// field a user tunes) with the κ range that puts g̃ there.
    fn check_shear_group(&self, sd: &ShearDeformation) -> Result<(), InputError> {
        let l = self.length_nm * 1e-9;
        let per_kappa = self.area_m2() * l * l / self.inertia_m4() / (2.0 * (1.0 + sd.poisson_ratio));
        let g = sd.shear_coefficient * per_kappa;
        let (lo, hi) = SHEAR_TILDE_RANGE;
        if (lo..=hi).contains(&g) {
            return Ok(());
        }
        Err(InputError::new(
            "shear_deformation.shear_coefficient",
            fmt_num(sd.shear_coefficient),
            format!(
                "{:e} <= shear_coefficient <= {:e} for this beam ({lo:e} <= kappa A L^2/(2(1+nu) I) <= {hi:e}, A L^2/(2(1+nu) I) = {per_kappa:e}; also <= 1)",
                lo / per_kappa,
                (hi / per_kappa).min(1.0)
            ),
        ))
    }

    /// The dimensionless groups of the scaled model within the solver's
    /// tested range (see [`MAX_E_TILDE`] and the constants after it).
    fn validate_scaled_groups(&self) -> Result<(), InputError> {
        let l = self.length_nm * 1e-9;
        let ei = self.youngs_modulus_pa * self.inertia_m4();
        let rho_a = self.density_kg_m3 * self.area_m2();
        let omega_ref = (ei / rho_a).sqrt() / (l * l);
        let at_most = |field: &str, value: f64, group: &str, max_group: f64, unit: f64| {
            if value <= max_group * unit {
                Ok(())
            } else {
                Err(InputError::new(
                    field,
                    fmt_num(value),
                    format!("<= {:e} ({group} <= {max_group:e})", max_group * unit),
                ))
            }
        };
        at_most("nonlocal_e0a_nm", self.nonlocal_e0a_nm, "e0a/L", MAX_E_TILDE, self.length_nm)?;
        let (lo, hi) = OMEGA_TILDE_RANGE;
        for (i, iv) in self.internal_variables.iter().enumerate() {
            if iv.delta > MAX_DELTA {
                at_most(&format!("internal_variables[{i}].delta"), iv.delta, "delta", MAX_DELTA, 1.0)?;
            }
            let w = iv.omega_rad_s / omega_ref;
            if !(lo..=hi).contains(&w) {
                return Err(InputError::new(
                    format!("internal_variables[{i}].omega_rad_s"),
                    fmt_num(iv.omega_rad_s),
                    format!(
                        "{:e} ..= {:e} ({lo:e} <= omega/omega_ref <= {hi:e}, omega_ref = sqrt(EI/rhoA)/L^2 = {omega_ref:e} rad/s)",
                        lo * omega_ref,
                        hi * omega_ref
                    ),
                ));
            }
        }
        at_most(
            "viscous_damping_n_s_m2",
            self.viscous_damping_n_s_m2,
            "C/(rhoA omega_ref)",
            MAX_C_TILDE,
            rho_a * omega_ref,
        )?;
        // each end's total (both-ends field + its own), named by the field that makes it
        let ends = self.support_rotational_stiffness_at_ends_n_m_rad();
        for (end, own) in [
            (ends[0], ("support_rotational_stiffness_left_n_m_rad", self.support_rotational_stiffness_left_n_m_rad)),
            (ends[1], ("support_rotational_stiffness_right_n_m_rad", self.support_rotational_stiffness_right_n_m_rad)),
        ] {
            let field = if own.1 > 0.0 { own.0 } else { "support_rotational_stiffness_n_m_rad" };
            at_most(field, end, "k_r L/EI at each end, both-ends and own field together", MAX_SPRING_TILDE, ei / l)?;
        }
        if let Some(pm) = &self.point_mass {
            at_most("point_mass.mass_kg", pm.mass_kg, "m/(rhoA L)", MAX_MASS_TILDE, rho_a * l)?;
        }
        Ok(())
    }

    /// The per-end spring fields: finite, ≥ 0, and 0 on an end whose rotation
    /// the support fixes (clamped) or that has no support (free): a spring
    /// there would act on nothing, and a file that declares one is
    /// contradicting its support (the both-ends field keeps its old meaning,
    /// every free rotation at a supported end, and is accepted on any support).
    fn check_end_springs(&self) -> Result<(), InputError> {
        let fields = [
            ("support_rotational_stiffness_left_n_m_rad", self.support_rotational_stiffness_left_n_m_rad, "x = 0"),
            ("support_rotational_stiffness_right_n_m_rad", self.support_rotational_stiffness_right_n_m_rad, "x = L"),
        ];
        let free = match self.support {
            Support::SimplySupported => [true, true],
            Support::ClampedPinned => [false, true],
            Support::ClampedClamped | Support::ClampedFree => [false, false],
        };
        for ((field, value, end), free) in fields.into_iter().zip(free) {
            non_negative(field, value)?;
            if value > 0.0 && !free {
                return Err(InputError::new(
                    field,
                    fmt_num(value),
                    format!(
                        "0 on a {} beam ({end} is clamped or free: no rotation for a spring; {})",
                        self.support.name(),
                        match self.support {
                            Support::ClampedPinned => "only support_rotational_stiffness_right_n_m_rad acts",
                            _ => "no per-end spring acts",
                        }
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Free DOFs of the FE mesh (2 per node minus those fixed by the
    /// supports, as in `model::UnitMesh`): the number of physical modes the
    /// model has.
    pub fn free_dofs(&self) -> usize {
        let fixed = match self.support {
            Support::SimplySupported => 2,
            Support::ClampedClamped => 4,
            Support::ClampedFree => 2,
            Support::ClampedPinned => 3,
        };
        (2 * (self.elements + 1)).saturating_sub(fixed)
    }

    /// The beam reflected about midspan, x → L − x: its point mass moved to
    /// the mirror position and its per-end springs swapped, the only
    /// features of a beam that are not the same all along it or at both ends
    /// (a new such feature must be reflected here too). With supports that
    /// [`Support::mirrors_itself`] it has the same modes.
    pub fn mirror_image(&self) -> BeamSpec {
        let mut m = self.clone();
        if let Some(p) = m.point_mass.as_mut() {
            p.x_nm = self.length_nm - p.x_nm;
        }
        m.support_rotational_stiffness_left_n_m_rad = self.support_rotational_stiffness_right_n_m_rad;
        m.support_rotational_stiffness_right_n_m_rad = self.support_rotational_stiffness_left_n_m_rad;
        m
    }

    /// Cross-section area in m²: πd²/4 (solid circle) or π d t (tube).
    pub fn area_m2(&self) -> f64 {
        let d = self.diameter_nm * 1e-9;
        match &self.section {
            None => std::f64::consts::PI * d * d / 4.0,
            Some(Section { tube }) => std::f64::consts::PI * d * tube.wall_nm * 1e-9,
        }
    }

    /// Second moment of area in m⁴: πd⁴/64 (solid circle) or π d t (d² + t²)/8 (tube).
    pub fn inertia_m4(&self) -> f64 {
        let d = self.diameter_nm * 1e-9;
        match &self.section {
            None => std::f64::consts::PI * d.powi(4) / 64.0,
            Some(Section { tube }) => {
                let t = tube.wall_nm * 1e-9;
                std::f64::consts::PI * d * t * (d * d + t * t) / 8.0
            }
        }
    }

    /// The Timoshenko shear coefficient of this beam's section for Poisson's
    /// ratio ν (Cowper 1966): the default κ when shear deformation is turned
    /// on without one.
    pub fn default_shear_coefficient(&self, poisson_ratio: f64) -> f64 {
        match self.section {
            None => solid_circle_shear_coefficient(poisson_ratio),
            Some(_) => thin_tube_shear_coefficient(poisson_ratio),
        }
    }

    /// Parses YAML (unknown fields rejected) and validates. Parse errors are
    /// reported as an [`InputError`] on the field serde names.
    pub fn from_yaml(text: &str) -> Result<Self, InputError> {
        let spec: BeamSpec = crate::error::parse_yaml(text)?;
        spec.validate()?;
        Ok(spec)
    }
}
