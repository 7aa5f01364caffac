//! Many modes of a fine mesh (issue 44, user-hostile 5): `modal` must reach
//! the modes it advertises (1..=free DOFs). Before, each eigenvalue past mode
//! ≈ 17 of a beam started its Newton–Maehly iteration from 0 (the
//! 1.25·λ_prev start overshoots once λ_{j+1}/λ_j < 1.25), so K modes took
//! O(K²) steps; on 300 elements `--modes 300` ran out of iterations, and the
//! 1 200-dimensional state space is past the dense fallback's limit: exit 1.
//!
//! Checks (no dense reference fits this size): the count; ω strictly rising;
//! the first ten equal, bit for bit, to a ten-mode request (the same
//! eigenvalues, found without the long deflation); modes 1–3 against the
//! closed form of a simply supported Euler–Bernoulli beam,
//! ω_j = (jπ/L)²·√(EI/ρA), within the cubic Hermite element's eigenvalue
//! error, O((jπh/L)⁴) relative ((3π/300)⁴ ≈ 1e-6 for mode 3): 1e-5 allowed.

use nanobeam::beam::{modal, BeamSpec};

#[test]
fn three_hundred_modes_of_three_hundred_elements() {
    let b: BeamSpec = serde_yaml::from_str(
        "{ length_nm: 8.0, diameter_nm: 1.0, youngs_modulus_pa: 1.0e12, density_kg_m3: 2300.0, \
         support: simply-supported, elements: 300 }",
    )
    .unwrap();
    let many = modal(&b, 300).unwrap();
    assert_eq!(many.modes.len(), 300);
    let w: Vec<f64> = many.modes.iter().map(|m| m.omega_rad_s).collect();
    assert!(w.windows(2).all(|p| p[1] > p[0]), "frequencies not rising");
    let few = modal(&b, 10).unwrap();
    for (a, e) in many.modes.iter().zip(&few.modes) {
        assert_eq!(a.omega_rad_s.to_bits(), e.omega_rad_s.to_bits(), "mode {}", e.mode);
    }
    let (l, d) = (8e-9, 1e-9);
    let (area, inertia) = (std::f64::consts::PI * d * d / 4.0, std::f64::consts::PI * d.powi(4) / 64.0);
    let c = (1.0e12 * inertia / (2300.0 * area)).sqrt();
    for j in 1..=3 {
        let exact = (j as f64 * std::f64::consts::PI / l).powi(2) * c;
        let rel = ((w[j - 1] - exact) / exact).abs();
        assert!(rel < 1e-5, "mode {j}: {} vs closed form {exact} (relative {rel:e})", w[j - 1]);
    }
}
