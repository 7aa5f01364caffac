//! Frequency response between a point force and a point displacement:
//! H(ω) = N(x_out)ᵀ T(iω)⁻¹ P(x_in) in m/N, with
//! T(s) = s²M + sD + K_spring + K_N + G(s)K (see `modal.rs`) and P the nodal load
//! of a unit force (A7). One banded complex LU per frequency: exact for every
//! model extension. In scaled units T = (EI/L³)·T̃(s/ω_ref), so
//! H = (L³/EI)·Nᵀ T̃⁻¹ P.

use num_complex::Complex64;

use crate::beam::error::BeamError;
use crate::beam::fe::model::{check_position, UnitMesh};
use crate::beam::fe::scaling::ScaledModel;
use crate::beam::linalg::band::BandLu;
use crate::beam::spec::BeamSpec;
use crate::error::{fmt_num, InputError};

/// Largest dimensionless frequency ω/ω_ref accepted: T̃(iω̃) has entries
/// ω̃²·M̃ᵢⱼ (|M̃ᵢⱼ| ≤ 1 + ẽ²·12·elements ≤ 4e5 for ẽ ≤ 10, 300 elements) next
/// to K̃ᵢⱼ ≤ 12·elements³ ≈ 3.2e8. The band LU forms products of two entries
/// (and their squares in its pivot test): with ω̃ ≤ 1e60 those stay below
/// (1e120·4e5)² ≈ 1e251 ≪ f64::MAX, so a singular or non-finite solve can
/// only be a true resonance, never overflow (1e100 overflowed: tested).
pub const MAX_OMEGA_TILDE: f64 = 1e60;

/// The largest ω (rad/s) [`frf`] accepts for this beam: `MAX_OMEGA_TILDE`·ω_ref.
pub fn max_frequency_rad_s(beam: &BeamSpec) -> Result<f64, BeamError> {
    beam.validate()?;
    let mesh = UnitMesh::new(1, beam.support);
    Ok(MAX_OMEGA_TILDE * ScaledModel::new(beam, &mesh).omega_ref)
}

/// Receptance (m/N) at each ω (rad/s, finite, ≥ 0).
pub fn frf(
    beam: &BeamSpec,
    input_x_nm: f64,
    output_x_nm: f64,
    omega_rad_s: &[f64],
) -> Result<Vec<Complex64>, BeamError> {
    let mut out = Vec::with_capacity(omega_rad_s.len());
    frf_each(beam, input_x_nm, output_x_nm, omega_rad_s.iter().copied(), |_, h| {
        out.push(h);
        Ok(())
    })?;
    Ok(out)
}

/// [`frf`] streamed: `sink(ω, H(ω))` for each ω in order, nothing kept, so
/// tables of any length run in constant memory. Stops at the first error
/// (of the model or of `sink`).
pub fn frf_each(
    beam: &BeamSpec,
    input_x_nm: f64,
    output_x_nm: f64,
    omega_rad_s: impl IntoIterator<Item = f64>,
    mut sink: impl FnMut(f64, Complex64) -> Result<(), BeamError>,
) -> Result<(), BeamError> {
    solve_each(beam, input_x_nm, &[("output_x_nm", output_x_nm)], omega_rad_s, |w, h| sink(w, h[0]))
}

/// Receptances (m/N) at several output points: `[ω][point]`, one LU per ω
/// for all points (an operating deflection shape at each ω).
pub fn frf_points(
    beam: &BeamSpec,
    input_x_nm: f64,
    output_x_nm: &[f64],
    omega_rad_s: &[f64],
) -> Result<Vec<Vec<Complex64>>, BeamError> {
    let names: Vec<String> = (0..output_x_nm.len()).map(|i| format!("output_x_nm[{i}]")).collect();
    let outputs: Vec<(&str, f64)> = names.iter().map(String::as_str).zip(output_x_nm.iter().copied()).collect();
    let mut out = Vec::with_capacity(omega_rad_s.len());
    solve_each(beam, input_x_nm, &outputs, omega_rad_s.iter().copied(), |_, h| {
        out.push(h.to_vec());
        Ok(())
    })?;
    Ok(out)
}

/// One banded LU of T(iω) per ω; `sink(ω, [H at each output])`.
fn solve_each(
    beam: &BeamSpec,
    input_x_nm: f64,
    outputs: &[(&str, f64)],
    omega_rad_s: impl IntoIterator<Item = f64>,
    mut sink: impl FnMut(f64, &[Complex64]) -> Result<(), BeamError>,
) -> Result<(), BeamError> {
    beam.validate()?;
    let xi = check_position("input_x_nm", input_x_nm, beam.length_nm)?;
    let xos =
        outputs.iter().map(|&(name, x)| check_position(name, x, beam.length_nm)).collect::<Result<Vec<f64>, _>>()?;
    let mesh = UnitMesh::for_beam(beam);
    let outs: Vec<Vec<f64>> = xos.into_iter().map(|xo| mesh.shape_vector(xo)).collect();
    let model = ScaledModel::new(beam, &mesh);
    let max_w = MAX_OMEGA_TILDE * model.omega_ref;
    let load = mesh.load_vector(xi, model.e_tilde);
    let n = model.n();
    let undamped = model.c == 0.0 && model.ivs.is_empty();
    let mut rhs = vec![Complex64::new(0.0, 0.0); n];
    let mut hs = vec![Complex64::new(0.0, 0.0); outs.len()];
    for (i, w) in omega_rad_s.into_iter().enumerate() {
        if !(w.is_finite() && w >= 0.0 && w <= max_w) {
            return Err(InputError::new(
                format!("omega_rad_s[{i}]"),
                fmt_num(w),
                format!("0 <= omega <= {max_w:e} ({MAX_OMEGA_TILDE:e} x omega_ref of this beam)"),
            )
            .into());
        }
        let s = Complex64::new(0.0, w / model.omega_ref);
        let (g, _) = model.relaxation(s);
        let lu = BandLu::factor_kd(n, model.k.kd, |i, j| {
            let ku = model.unrelaxed_entry(i, j);
            s * s * model.m.get(i, j) + s * (model.c * model.m_beam.get(i, j)) + ku + g * model.k.get(i, j)
        })
        .ok_or_else(|| {
            let why = if undamped { "a resonance of the undamped beam" } else { "a singular dynamic stiffness" };
            BeamError::numerical(format!("T(iω) singular at ω = {} rad/s ({why})", fmt_num(w)))
        })?;
        for (r, &p) in rhs.iter_mut().zip(&load) {
            *r = Complex64::new(p, 0.0);
        }
        lu.solve(&mut rhs);
        for (h, out) in hs.iter_mut().zip(&outs) {
            let v: Complex64 = out.iter().zip(&rhs).map(|(&o, &x)| o * x).sum();
            if !v.is_finite() {
                return Err(BeamError::numerical(format!("non-finite receptance at ω = {} rad/s", fmt_num(w))));
            }
            *h = v * model.compliance;
        }
        sink(w, &hs)?;
    }
    Ok(())
}
