//! Time-domain response derived from the model: the displacement impulse
//! response h(t) between a point force and a point displacement, in m/(N·s).
//!
//! h is the inverse Laplace transform of the receptance H(s) = Nᵀ T(s)⁻¹ P of
//! `frf.rs`. It is computed from the augmented state space (A15) of
//! `state_space.rs`, ẋa = Aa xa + Ba f, y = Ca xa, with xa = [q; q̄₁ … q̄_N; q̇],
//! Ba = [0; 0; M⁻¹P] and Ca = [Nᵀ, 0, 0]. A unit impulse f = δ(t) sets
//! q̇(0⁺) = M⁻¹P with everything else zero, and the free motion after it is
//! xa(t) = exp(Aa t) xa(0⁺): sampled exactly (no time-stepping error) by
//! repeated multiplication with the one matrix exp(Aa Δt) (nalgebra's
//! scaling-and-squaring Padé exponential). Every pole of the model contributes —
//! the modes, the real relaxation poles of the internal variables and the
//! out-of-band modes of the mesh — so this is the response a ring-down
//! measurement of this model would record, not a sum of chosen modes.
//!
//! Scaling: in the units of `model.rs`, T = (EI/L³)·T̃(s/ω_ref), so with
//! t̃ = ω_ref·t the physical response is h(t) = (L³/EI)·ω_ref·h̃(ω_ref·t).

use crate::beam::error::BeamError;
use crate::beam::fe::model::{check_position, UnitMesh};
use crate::beam::fe::scaling::ScaledModel;
use crate::beam::solve::state_space;
use crate::beam::spec::BeamSpec;
use crate::error::{positive, InputError};

/// Displacement at `output_x_nm` (m) per unit force impulse (N·s) at
/// `input_x_nm`, sampled at t = k·dt_s for k = 0 … samples − 1 (h(0) = 0: a
/// force impulse changes the velocity, not the displacement).
pub fn impulse_response(
    beam: &BeamSpec,
    input_x_nm: f64,
    output_x_nm: f64,
    dt_s: f64,
    samples: usize,
) -> Result<Vec<f64>, BeamError> {
    beam.validate()?;
    let xi = check_position("input_x_nm", input_x_nm, beam.length_nm)?;
    let xo = check_position("output_x_nm", output_x_nm, beam.length_nm)?;
    positive("dt_s", dt_s)?;
    if samples == 0 {
        return Err(InputError::new("samples", samples, ">= 1").into());
    }
    // the beam's own mesh: Timoshenko with shear deformation, C² with a
    // strain gradient (the cubic one would drop both)
    let mesh = UnitMesh::for_beam(beam);
    let model = ScaledModel::new(beam, &mesh);
    let n = model.n();
    let a = state_space::state_matrix(&model)?;
    let dim = a.nrows();
    let chol = nalgebra::Cholesky::new(model.m.to_dense())
        .ok_or_else(|| BeamError::numerical("mass matrix is not positive definite"))?;
    let load = nalgebra::DVector::from_vec(mesh.load_vector(xi, model.e_tilde));
    let v0 = chol.solve(&load);
    let out = mesh.shape_vector(xo);
    let step = (a * (dt_s * model.omega_ref)).exp();
    if step.iter().any(|x| !x.is_finite()) {
        return Err(BeamError::numerical("non-finite matrix exponential of the state matrix"));
    }
    let mut x = nalgebra::DVector::<f64>::zeros(dim);
    let vel = dim - n;
    for i in 0..n {
        x[vel + i] = v0[i];
    }
    let scale = model.compliance * model.omega_ref;
    let mut h = Vec::with_capacity(samples);
    for _ in 0..samples {
        let y: f64 = out.iter().enumerate().map(|(i, &o)| o * x[i]).sum();
        if !y.is_finite() {
            return Err(BeamError::numerical("non-finite impulse response"));
        }
        h.push(scale * y);
        x = &step * &x;
    }
    Ok(h)
}
