//! Frequency response between a point force and a point displacement:
//! H(ω) = N(x_out)ᵀ T(iω)⁻¹ P(x_in) in m/N, with
//! T(s) = s²M + sD + K_spring + K_N + G(s)K (see `modal.rs`) and P the nodal load
//! of a unit force (A7). One banded complex LU per frequency: exact for every
//! model extension. In scaled units T = (EI/L³)·T̃(s/ω_ref), so
//! H = (L³/EI)·Nᵀ T̃⁻¹ P.

use num_complex::Complex64;

use crate::beam::band::BandLu;
use crate::beam::model::{check_position, ScaledModel, UnitMesh};
use crate::beam::spec::BeamSpec;
use crate::beam::BeamError;
use crate::error::InputError;

/// Receptance (m/N) at each ω (rad/s, finite, ≥ 0).
pub fn frf(
    beam: &BeamSpec,
    input_x_nm: f64,
    output_x_nm: f64,
    omega_rad_s: &[f64],
) -> Result<Vec<Complex64>, BeamError> {
    beam.validate()?;
    let xi = check_position("input_x_nm", input_x_nm, beam.length_nm)?;
    let xo = check_position("output_x_nm", output_x_nm, beam.length_nm)?;
    for (i, &w) in omega_rad_s.iter().enumerate() {
        if !(w.is_finite() && w >= 0.0) {
            return Err(InputError::new(format!("omega_rad_s[{i}]"), w, ">= 0 (finite)").into());
        }
    }
    let mesh = UnitMesh::for_beam(beam);
    let model = ScaledModel::new(beam, &mesh);
    let load = mesh.load_vector(xi, model.e_tilde);
    let out = mesh.shape_vector(xo);
    let n = model.n();
    let mut rhs = vec![Complex64::new(0.0, 0.0); n];
    omega_rad_s
        .iter()
        .map(|&w| {
            let s = Complex64::new(0.0, w / model.omega_ref);
            let (g, _) = model.relaxation(s);
            let lu = BandLu::factor_kd(n, model.k.kd, |i, j| {
                let ku = model.unrelaxed_entry(i, j);
                s * s * model.m.get(i, j) + s * (model.c * model.m_beam.get(i, j)) + ku + g * model.k.get(i, j)
            })
            .ok_or_else(|| BeamError::numerical(format!("T(iω) singular at ω = {w} rad/s (undamped resonance)")))?;
            for (r, &p) in rhs.iter_mut().zip(&load) {
                *r = Complex64::new(p, 0.0);
            }
            lu.solve(&mut rhs);
            let h: Complex64 = out.iter().zip(&rhs).map(|(&o, &x)| o * x).sum();
            if !h.is_finite() {
                return Err(BeamError::numerical(format!("non-finite receptance at ω = {w} rad/s")));
            }
            Ok(h * model.compliance)
        })
        .collect()
}
