//! A `section-mismatch` posterior read in the user's terms (`classes`' module
//! doc derives why one factor f on EI/ρA is all the data identify).

use crate::beam::BeamSpec;

/// A `section-mismatch` posterior read in the user's terms: the factor f on
/// EI/ρA (= E/E_nominal as sampled), and what it means for each nominal value
/// alone. Since ω ∝ √f, a factor f is a section √f times larger in every
/// dimension (I/A ∝ d²), or E/ρ f times the nominal, or a mass per length
/// 1/f times the nominal (an adsorbate of 1/f − 1).
#[derive(Debug, Clone, Copy, serde::Serialize, PartialEq)]
pub struct SectionReading {
    /// f: posterior mean and central 95 % interval.
    pub stiffness_to_mass_factor: f64,
    pub stiffness_to_mass_factor_ci95: [f64; 2],
    /// The declared diameter and the one that alone would explain f (d·√f at the mean of f).
    pub declared_diameter_nm: f64,
    pub equivalent_diameter_nm: f64,
    pub equivalent_diameter_ci95_nm: [f64; 2],
    /// (f − 1)·100: E/ρ that much above the nominal (negative: below).
    pub e_over_rho_change_percent: f64,
    /// (1/f − 1)·100: the mass per length that much above the nominal.
    pub mass_per_length_change_percent: f64,
}

impl SectionReading {
    /// From the posterior mean and central 95 % interval of `youngs_modulus_pa` on a beam declaring `nominal`.
    pub fn new(nominal: &BeamSpec, modulus_mean_pa: f64, modulus_ci95_pa: [f64; 2]) -> Self {
        let e0 = nominal.youngs_modulus_pa;
        let f = modulus_mean_pa / e0;
        let ci = [modulus_ci95_pa[0] / e0, modulus_ci95_pa[1] / e0];
        let d = nominal.diameter_nm;
        SectionReading {
            stiffness_to_mass_factor: f,
            stiffness_to_mass_factor_ci95: ci,
            declared_diameter_nm: d,
            equivalent_diameter_nm: d * f.sqrt(),
            equivalent_diameter_ci95_nm: [d * ci[0].sqrt(), d * ci[1].sqrt()],
            e_over_rho_change_percent: 100.0 * (f - 1.0),
            mass_per_length_change_percent: 100.0 * (1.0 / f - 1.0),
        }
    }

    /// One sentence: "behaves as if d = 1.070 nm instead of 1 nm …, or as if E/ρ were 14.5 % higher, …".
    pub fn sentence(&self) -> String {
        let pct = self.e_over_rho_change_percent;
        let (word, mass_word) = if pct >= 0.0 { ("higher", "lower") } else { ("lower", "higher") };
        format!(
            "behaves as if d = {:.3} nm instead of {} nm (95 %: {:.3}–{:.3} nm), or as if E/ρ were {:.1} % {word}, or the \
             mass per length {:.1} % {mass_word}",
            self.equivalent_diameter_nm,
            self.declared_diameter_nm,
            self.equivalent_diameter_ci95_nm[0],
            self.equivalent_diameter_ci95_nm[1],
            pct.abs(),
            self.mass_per_length_change_percent.abs(),
        )
    }
}
