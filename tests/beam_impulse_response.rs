//! `beam::impulse_response` is the inverse Fourier transform of `beam::frf`:
//! checked by integrating h(t)e^{−iωt} numerically and comparing with the
//! banded-solve receptance (independent code paths: matrix exponential of the
//! state space vs. complex LU of T(iω)).

use nanobeam::beam::{frf, impulse_response, modal, BeamSpec, InternalVariable, ShearDeformation, Support};
use num_complex::Complex64;

#[test]
fn fourier_transform_of_the_impulse_response_is_the_receptance() {
    // 4 elements (8 DOFs: the highest mesh mode is resolved by the time step),
    // viscous damping making every mode decay at c/(2ρA), one internal variable.
    let beam = euler_bernoulli();
    check(&beam);
}

/// The same on a Timoshenko beam: the impulse response builds the beam's
/// own mesh (it had built the Euler–Bernoulli one whatever the beam, so a
/// Timoshenko beam's response was the Euler–Bernoulli beam's, while the
/// receptance was the Timoshenko one's).
#[test]
fn a_timoshenko_beams_impulse_response_is_its_receptance() {
    let beam = BeamSpec {
        shear_deformation: Some(ShearDeformation { poisson_ratio: 0.2, shear_coefficient: 0.6 }),
        ..euler_bernoulli()
    };
    check(&beam);
}

fn euler_bernoulli() -> BeamSpec {
    BeamSpec {
        length_nm: 8.0,
        diameter_nm: 1.0,
        youngs_modulus_pa: 1.0e12,
        density_kg_m3: 2300.0,
        support: Support::SimplySupported,
        elements: 4,
        nonlocal_e0a_nm: 0.5,
        viscous_damping_n_s_m2: 5e-4,
        internal_variables: vec![InternalVariable { delta: 0.3, omega_rad_s: 5e11 }],
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

fn check(beam: &BeamSpec) {
    let beam = beam.clone();
    let modes = modal(&beam, 8).unwrap();
    let w_top = modes.modes.last().unwrap().omega_rad_s;
    let decay = modes.modes.iter().map(|m| m.zeta * m.omega_rad_s).fold(f64::INFINITY, f64::min);
    let decay = decay.min(modes.real_poles_rad_s.iter().map(|p| p.abs()).fold(f64::INFINITY, f64::min));
    // dt·ω_top = 0.05; integrate until e^{−decay·T} < 1e-13.
    let dt = 0.05 / w_top;
    let n = ((30.0 / decay) / dt).ceil() as usize;
    let h = impulse_response(&beam, 3.0, 5.5, dt, n).unwrap();
    let omegas = [0.5 * modes.modes[0].omega_rad_s, modes.modes[0].omega_rad_s, modes.modes[1].omega_rad_s];
    let reference = frf(&beam, 3.0, 5.5, &omegas).unwrap();
    let slope0 = (h[1] - h[0]) / dt;
    for (&w, &href) in omegas.iter().zip(&reference) {
        // Trapezoid rule with the Euler–Maclaurin end correction:
        // ∫₀^∞ f = dt·Σ' f_k + dt²/12·f'(0) + O(dt⁴ f'''), f = h e^{−iωt},
        // f(0) = h(0) = 0, f'(0) = h'(0). The remainder is
        // ~ (dt·ω_top)⁴/720 ≈ 9e-9 of the integrand's scale, and the
        // one-sided difference for h'(0) errs by O(dt·h''), i.e. the end
        // correction by O(dt³ h'') ≈ (dt·ω_top)³/12 ≈ 1e-5 of the correction
        // itself; 1e-6 of max|H| bounds both with margin (measured: ~1e-11).
        let mut sum = Complex64::new(0.0, 0.0);
        let rot = Complex64::from_polar(1.0, -w * dt);
        let mut e = Complex64::new(1.0, 0.0);
        for (k, &hk) in h.iter().enumerate() {
            let weight = if k == 0 { 0.5 } else { 1.0 };
            sum += weight * hk * e;
            e *= rot;
        }
        let integral = dt * sum + dt * dt / 12.0 * slope0;
        let scale = reference.iter().map(|z| z.norm()).fold(0.0, f64::max);
        let err = (integral - href).norm() / scale;
        println!("omega {w:e}: |FT(h) − H| / max|H| = {err:.2e}");
        assert!(err < 1e-6, "omega {w:e}: {err:e}");
    }
}
