//! Inputs shared by the hardening tests.

/// A measured file of the exact model's modes 1 and 2 (Δ = 0.4, Ω = 4.5e11)
/// with a small sampler.
pub const MEASURED: &str = "beam: { length_nm: 8.0, diameter_nm: 1.0, youngs_modulus_pa: 1.0e12, density_kg_m3: 2300.0, support: simply-supported, elements: 20 }
modes:
  - { mode: 1, omega_rad_s: 9.3e11, omega_sd_rad_s: 2.8e9, zeta: 0.0614, zeta_sd: 0.0018 }
  - { mode: 2, omega_rad_s: 3.8e12, omega_sd_rad_s: 1.1e10, zeta: 0.0168, zeta_sd: 0.0005 }
sampler: { draws_per_chain: 1000, burn_in: 200, nonadaptive_draws: 300, adaptation_start: 300, covariance_skip: 100, chains: 2, multistart_points: 16 }
";
