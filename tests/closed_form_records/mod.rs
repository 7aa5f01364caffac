//! What the closed-form generators of `tests/diagnose_falsify.rs` and
//! `tests/diagnose_extensions.rs` share: the hidden suites' measurement noise
//! on (ω, ζ) of a simply supported beam's modes, and the measured-data file
//! the diagnosis reads (the nominal beam L = 8 nm, d = 1 nm, E = 1 TPa,
//! ρ = 2300 kg/m³, 20 elements). No code of `src/` makes the numbers: the
//! generators' closed forms do.
#![allow(dead_code)]

use nanobeam::beam::{BeamSpec, Support};
use nanobeam::calibration::measured::MeasuredFile;
use nanobeam::calibration::{DramSettings, MeasuredData, ModeObservation};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// The hidden suites' measurement sds, relative: ω 0.3 %, ζ 3 %.
pub const OMEGA_REL_SD: f64 = 0.003;
pub const ZETA_REL_SD: f64 = 0.03;

/// Measured modes `modes` of a truth whose mode n is `mode(n)` = (ω, ζ),
/// with the suites' sds, noise drawn from `seed`.
pub fn observations(mode: impl Fn(usize) -> (f64, f64), modes: &[usize], seed: u64) -> Vec<ModeObservation> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    modes
        .iter()
        .map(|&n| {
            let (omega, zeta) = mode(n);
            let (e1, e2): (f64, f64) = (StandardNormal.sample(&mut rng), StandardNormal.sample(&mut rng));
            ModeObservation {
                mode: n,
                omega_rad_s: omega * (1.0 + OMEGA_REL_SD * e1),
                omega_sd_rad_s: OMEGA_REL_SD * omega,
                zeta: zeta * (1.0 + ZETA_REL_SD * e2),
                zeta_sd: ZETA_REL_SD * zeta,
            }
        })
        .collect()
}

/// The measured-data file of `modes` on the nominal beam, the sampler seeded by `seed`.
pub fn file(modes: Vec<ModeObservation>, seed: u64) -> MeasuredFile {
    MeasuredFile {
        beam: BeamSpec::elastic(8.0, 1.0, 1.0e12, 2300.0, Support::SimplySupported, 20),
        modes,
        held_out_modes: vec![],
        mode_scans: vec![],
        parameters: None,
        sampler: Some(DramSettings { seed, ..DramSettings::default() }),
    }
}

/// [`file`], validated.
pub fn data(modes: Vec<ModeObservation>, seed: u64) -> MeasuredData {
    MeasuredData::from_file(file(modes, seed)).expect("generated data are valid")
}
