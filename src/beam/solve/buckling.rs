//! The buckling bound of a compressive axial force, and the complete
//! validation of a [`BeamSpec`] that needs it. The bound is an eigenvalue of
//! the assembled stiffness pencil, so it lives above the assembly
//! (`model`), and `spec` checks the fields alone ([`BeamSpec::validate`]
//! adds the bound to them): the spec never reaches into the assembly.

use crate::beam::error::BeamError;
use crate::beam::fe::model::UnitMesh;
use crate::beam::fe::scaling::ScaledModel;
use crate::beam::linalg::band::SymBand;
use crate::beam::spec::BeamSpec;
use crate::error::InputError;

impl BeamSpec {
    /// Checks every documented range; the error names the field, value and
    /// allowed range. The fields first ([`BeamSpec::validate_fields`]), then
    /// a compressive force against the buckling load ([`check_buckling`]).
    pub fn validate(&self) -> Result<(), InputError> {
        self.validate_fields()?;
        if self.elastic_foundation_n_m2 < 0.0 {
            check_foundation(self)?;
        }
        if self.axial_force_n < 0.0 {
            check_buckling(self)?;
        }
        Ok(())
    }
}

/// Rejects a negative (pulling) foundation at or beyond the loss of
/// stability: K̃ + K̃_spring + K̃_N⁺ + k̃_f M̃_beam must stay positive definite,
/// where K̃_N⁺ is the axial force's stiffness when it is a tension (which
/// stiffens) and 0 for a compression (checked next, against the beam with
/// its foundation, by [`check_buckling`], so a beam both pulled and
/// compressed names the force). The bound −k_cr is the lowest eigenvalue of
/// (K̃ + K̃_spring + K̃_N⁺, M̃_beam) times EI/L⁴; simply supported, continuum,
/// no force: k_cr = EIα₁⁴/(1 + μα₁²), α₁ = π/L, the ω₁² of the free beam
/// times ρA (tested in `tests/beam_foundation.rs`). Static, so relaxed (the
/// binding bound, as for the buckling load).
pub fn check_foundation(beam: &BeamSpec) -> Result<(), InputError> {
    if beam.elastic_foundation_n_m2 >= 0.0 {
        return Ok(());
    }
    let (k_el, mb, to_n_m2) = foundation_pencil(beam);
    let k_tilde = beam.elastic_foundation_n_m2 / to_n_m2;
    if matches!(k_el.ldl_inertia(&mb, -k_tilde, &mut Vec::new()), Some((0, _))) {
        return Ok(());
    }
    let allowed =
        match crate::beam::solve::eigen::lowest_eigenpairs(&k_el, &mb, 1, &mut Vec::new(), &|x| k_el.bilinear(x, x)) {
            Ok(pairs) => format!(
                "> {:.6e} N/m^2 (the loss of stability of this beam: {}, e0a = {} nm)",
                -pairs[0].lambda * to_n_m2,
                beam.support.name(),
                beam.nonlocal_e0a_nm
            ),
            Err(_) => "above the loss of stability of this beam (a substrate > 0)".to_string(),
        };
    Err(InputError::new("elastic_foundation_n_m2", crate::error::fmt_num(beam.elastic_foundation_n_m2), allowed))
}

/// (K̃ + K̃_spring + K̃_N⁺, M̃_beam, EI/L⁴): the foundation's stability pencil
/// and the factor from k̃_f to N/m² ([`check_foundation`]).
fn foundation_pencil(beam: &BeamSpec) -> (SymBand, SymBand, f64) {
    let mesh = UnitMesh::for_beam(beam);
    let mut free = beam.clone();
    free.axial_force_n = beam.axial_force_n.max(0.0);
    free.elastic_foundation_n_m2 = 0.0;
    let model = ScaledModel::new(&free, &mesh);
    let l = beam.length_nm * 1e-9;
    (model.k_total(), model.m_beam.clone(), beam.youngs_modulus_pa * beam.inertia_m4() / (l * l * l * l))
}

/// Rejects a compressive axial force at or beyond the buckling load of this
/// beam's mesh and support: the lowest eigenvalue ñ_cr of the geometric-
/// stiffness pencil (K̃ + K̃_spring) φ = ñ_cr (G̃₀ + ẽ²G̃₁) φ, i.e. the smallest
/// compression −N at which K̃ + K̃_spring + K̃_N loses positive definiteness
/// (the static limit ω → 0 of every mode; the relaxed and unrelaxed K̃ differ
/// by the factor 1 + ΣΔᵢ ≥ 1, so the relaxed, static one is the binding bound).
/// Simply supported, continuum: N_cr = −EIα₁²/(1 + μα₁²), α₁ = π/L
/// (tested in `tests/beam_axial_shear.rs`).
///
/// Cost: one mesh and one banded LDLᵀ inertia count; the bound itself (an
/// eigen-solve) is computed only for the error message.
pub fn check_buckling(beam: &BeamSpec) -> Result<(), InputError> {
    if beam.axial_force_n >= 0.0 {
        return Ok(());
    }
    let (k_el, kg, to_newton) = buckling_pencil(beam);
    // inertia of K_el − σG with σ = −ñ > 0: no negative pivot ⇔ stable
    let n_tilde = beam.axial_force_n / to_newton;
    if matches!(k_el.ldl_inertia(&kg, -n_tilde, &mut Vec::new()), Some((0, _))) {
        return Ok(());
    }
    let allowed = match buckling_load_n(beam) {
        Ok(n_cr) => format!(
            "> {n_cr:.6e} N (buckling load of this beam: {}, {} elements, e0a = {} nm)",
            beam.support.name(),
            beam.elements,
            beam.nonlocal_e0a_nm
        ),
        Err(_) => "above the buckling load of this beam (tension > 0)".to_string(),
    };
    Err(InputError::new("axial_force_n", crate::error::fmt_num(beam.axial_force_n), allowed))
}

/// The buckling load N_cr < 0 (newtons) of this beam's mesh and support (see
/// [`check_buckling`]), with its foundation; the axial force of `beam` itself is ignored.
pub fn buckling_load_n(beam: &BeamSpec) -> Result<f64, BeamError> {
    let (k_el, kg, to_newton) = buckling_pencil(beam);
    let pairs = crate::beam::solve::eigen::lowest_eigenpairs(&k_el, &kg, 1, &mut Vec::new(), &|x| k_el.bilinear(x, x))?;
    Ok(-pairs[0].lambda * to_newton)
}

/// (K̃ + K̃_spring + k̃_f M̃_beam, G̃₀ + ẽ²G̃₁, EI/L²): the buckling pencil
/// (with the beam's foundation, which stiffens or softens it) and the factor
/// from ñ to newtons.
fn buckling_pencil(beam: &BeamSpec) -> (SymBand, SymBand, f64) {
    let mesh = UnitMesh::for_beam(beam);
    let mut free = beam.clone();
    free.axial_force_n = 0.0;
    let model = ScaledModel::new(&free, &mesh);
    let kg = mesh.g0.plus_scaled(model.e_tilde * model.e_tilde, &mesh.g1);
    let l = beam.length_nm * 1e-9;
    let mut k_el = model.k_total();
    if model.foundation != 0.0 {
        k_el = k_el.plus_scaled(model.foundation, &model.m_beam);
    }
    (k_el, kg, beam.youngs_modulus_pa * beam.inertia_m4() / (l * l))
}
