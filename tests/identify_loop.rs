//! Closing the loop: model → simulated record → identify → the model's modes.

use nanobeam::beam::{frf, impulse_response, modal, BeamSpec, InternalVariable, Support};
use nanobeam::identify::{identify, IdentifySettings, Measurement};

/// The paper's beam (Table 4 truth as reconstructed in paper/reconstructed.yaml).
fn paper_beam() -> BeamSpec {
    BeamSpec {
        length_nm: 8.1321,
        diameter_nm: 1.0,
        youngs_modulus_pa: 1.0e12,
        density_kg_m3: 2300.0,
        support: Support::SimplySupported,
        elements: 20,
        nonlocal_e0a_nm: 1.217,
        viscous_damping_n_s_m2: 0.0,
        internal_variables: vec![InternalVariable { delta: 0.4999, omega_rad_s: 3.9925e11 }],
        support_rotational_stiffness_n_m_rad: 0.0,
        point_mass: None,
    }
}

#[test]
fn noise_free_sweep_gives_the_model_modes() {
    let beam = paper_beam();
    let truth = modal(&beam, 6).unwrap();
    for m in &truth.modes {
        println!("truth mode {} omega {:e} zeta {:.6}", m.mode, m.omega_rad_s, m.zeta);
    }
    println!("real poles {:?}", truth.real_poles_rad_s);
    let w_hi = 0.5 * (truth.modes[4].omega_rad_s + truth.modes[5].omega_rad_s);
    let n = 4000;
    let w: Vec<f64> = (0..n).map(|i| 0.2 * truth.modes[0].omega_rad_s + (w_hi - 0.2 * truth.modes[0].omega_rad_s) * i as f64 / (n - 1) as f64).collect();
    let h = frf(&beam, 3.6, 6.8, &w).unwrap();
    let data = Measurement::Complex { omega_rad_s: w, h_m_per_n: h };
    let t0 = std::time::Instant::now();
    let id = identify(&data, &IdentifySettings::default()).unwrap();
    println!("{:.3} s, noise sd {:e}, real poles {:?}", t0.elapsed().as_secs_f64(), id.noise_sd, id.real_poles_rad_s);
    for m in &id.modes {
        println!("id omega {:e} ± {:e} zeta {:.6} ± {:e} peak {:e}", m.omega_rad_s, m.omega_sd_rad_s, m.zeta, m.zeta_sd, m.peak);
    }
    for m in &id.background_modes {
        println!("bg omega {:e} zeta {:.6}", m.omega_rad_s, m.zeta);
    }
}

#[test]
fn debug_diagram() {
    let beam = paper_beam();
    let truth = modal(&beam, 6).unwrap();
    let w_hi = 0.5 * (truth.modes[4].omega_rad_s + truth.modes[5].omega_rad_s);
    let n = 4000;
    let w: Vec<f64> = (0..n).map(|i| 0.2 * truth.modes[0].omega_rad_s + (w_hi - 0.2 * truth.modes[0].omega_rad_s) * i as f64 / (n - 1) as f64).collect();
    let h = frf(&beam, 3.6, 6.8, &w).unwrap();
    let data = Measurement::Complex { omega_rad_s: w, h_m_per_n: h };
    let id = identify(&data, &IdentifySettings::default()).unwrap();
    for p in &id.diagram.poles {
        if p.order % 8 == 0 || p.order > 34 {
            println!("order {} w {:.4e} z {:.4} {:?}", p.order, p.omega_rad_s, p.zeta, p.stability);
        }
    }
}
