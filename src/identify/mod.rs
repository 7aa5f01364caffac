//! Modal identification from measured records (signal processing only: no
//! beam model here). The numbering of the modes as physical modes needs the
//! beam model and happens in `calibration::identified`.
//!
//! Pipeline (what a modal-testing lab does, automated):
//! 1. **Initial poles at many orders**: LSCF ([`lscf`], rational-fraction
//!    polynomial in the z-domain) for complex receptances, |H|² of magnitude
//!    records and PSDs; the matrix pencil method ([`pencil`], ERA's
//!    single-output relative) for free decays.
//! 2. **Stabilisation diagram** ([`stabilisation`]): poles stable in
//!    frequency (1 %) and damping (5 %) over many orders are physical;
//!    underdamped only — real poles are never modes.
//! 3. **Joint refinement** ([`refine`]): all modes, real relaxation poles and
//!    residual terms fitted together by Levenberg–Marquardt; the number of
//!    real poles (0 … [`MAX_REAL_POLES`]) is chosen by BIC (sweeps,
//!    ring-downs) or a likelihood-ratio test (magnitude, PSD), so the relaxation
//!    background is modelled (not reported, not biasing the modes).
//! 4. **Noise model and uncertainties** ([`noise`]): uniform or additive +
//!    signal-proportional variance, chosen by the BIC on the residuals; the
//!    latter refits by weighted least squares; covariance σ̂²(J̃ᵀJ̃)⁺, or the
//!    sandwich where a Breusch–Pagan test leaves the noise model in doubt.
//! 5. **Free decays: poles the fit left out** ([`decay`]):
//!    the weighted residuals are searched for one more pole (a likelihood
//!    score on a frequency × decay-rate grid, Bonferroni bar at 1 % per
//!    record); one that passes joins the fit and the noise model is chosen
//!    again.
//!
//! Initial poles also come from [`peaks`]: every resonance standing
//! above its baseline by the threshold of [`peaks::threshold`] that the
//! diagram missed joins them.
//!
//! Which modes are reported: every mode in the band that the record holds
//! clearly under the fitted noise model (frequency records: its resonance
//! stands at least [`MIN_PEAK_SNR`] noise sd high, see `assemble::peak_snr`, with
//! [`MIN_POINTS_PER_RESONANCE`] samples in its fitted half-power band;
//! free decays: its residue at least [`MIN_AMPLITUDE_SNR`] sd from zero and
//! its initial amplitude at least [`MIN_RELATIVE_AMPLITUDE`] of the record's
//! largest sample), or
//! with `modes = Some(K)` the K lowest stable modes of the diagram that are
//! clear, in order (fewer clear than K: the clearest of the rest that the record holds, resolved with a bounded ζ and
//! standing ≥ 1 noise sd, fill up, and fewer of those than K is an input error naming `--modes`; the others, and the refinement's out-of-band pseudo-modes, stay
//! in the fit as background). No clear mode is an input error naming the
//! clearest one's height. Fewer stable modes than K, fewer
//! than [`MIN_POINTS_PER_RESONANCE`] samples in a mode's half-power band, or
//! no stable mode at all are input errors (exit 2).
//!
//! # Where each job lives
//! - records and units: [`data`] (CSV kinds, lab units), [`thermal`]
//!   (thermal-motion records → Welch PSD);
//! - detection: [`detect`] (the initial poles: the diagram's and the
//!   declared peaks', the under-sampling refusals) over [`lscf`], [`pencil`]
//!   and [`peaks`];
//! - stabilisation: [`stabilisation`] (the diagram, mode selection);
//! - the fit: [`refine`] (the rational model, joint Levenberg–Marquardt),
//!   [`projected`] (variable projection for the kinds linear in the
//!   residues), [`covariance`] (pseudo-inverse, leverages, the Welch
//!   sandwich), [`select`] (the number of real poles, the reweighting, the
//!   fallbacks), [`decay`] (a free decay's missed poles);
//! - the noise model: [`noise`];
//! - what is reported: [`assemble`]; the phases in order: [`pipeline`];
//!   the record's scaling: [`scaled`]; the sampling step of a time record,
//!   the same for every time origin: [`step`].
//!
//! Numbering the modes as physical modes needs the beam model and lives in
//! `calibration::identified`.

mod assemble;
pub mod covariance;
pub mod data;
mod decay;
mod detect;
pub mod lscf;
pub mod noise;
pub mod peaks;
pub mod pencil;
mod pipeline;
pub mod projected;
pub mod refine;
mod scaled;
mod select;
pub mod stabilisation;
pub mod step;
pub mod thermal;

use num_complex::Complex64;
use serde::Serialize;

use crate::error::InputError;
pub use data::Measurement;
pub use noise::NoiseModel;
pub use pipeline::{identify, identify_controlled};
pub use refine::Stop;
pub use stabilisation::Diagram;

/// Highest number of real (relaxation/background) poles tried in the
/// refinement (candidates 0 … MAX_REAL_POLES, chosen by BIC or, for the
/// joint-LM kinds, by likelihood-ratio tests). The relaxation
/// poles of a meshed viscoelastic beam (one per mesh mode and internal
/// variable) lie in a narrow interval of the negative real axis; a sum of
/// poles on an interval is approximated by a few poles with an error that falls
/// geometrically with their number. Measured on the paper's beam (20 elements,
/// noise-free 4 000-point sweep over modes 1–5), ζ's worst relative error:
/// 2 real poles + 1 out-of-band mode 3·10⁻⁵, 3 + 2: 3·10⁻⁷.
pub const MAX_REAL_POLES: usize = 3;
/// Oscillatory poles kept above the band of a frequency record (not
/// reported): the nearest out-of-band modes, whose tails the residual
/// polynomial (a Taylor series converging only below them) represents poorly.
pub const OUT_OF_BAND_MODES: usize = 2;
/// Samples a resonance needs within its half-power band ω_d ± σ (the peak,
/// its width and its height: three points determine a Lorentzian).
pub const MIN_POINTS_PER_RESONANCE: usize = 3;
/// How far above the band (× ω_max) the initial estimator represents poles.
pub const REACH: f64 = 1.5;
/// Residue signal-to-noise ratio a reported mode needs by default: a
/// residue within 5 sd of zero is a pole the data barely hold (noise fitted
/// consistently across orders), not a resonance.
pub const MIN_AMPLITUDE_SNR: f64 = 5.0;
/// Height of a resonance over the noise sd at it (under the fitted noise
/// model) a frequency record's mode needs by default. A mode fitted to the
/// noise stands about one sd high; 5 sd is the declaration threshold of
/// [`peaks`] (false alarm ≤ N·Q(5) per record of N samples), and a
/// resonance the issue calls visible stands 20 sd high.
pub const MIN_PEAK_SNR: f64 = 5.0;
/// Smallest initial amplitude 2|A_r| of a reported free-decay mode, as a
/// fraction of the record's largest |sample|: the dynamic range a record
/// holds a mode in. A noise-free (or nearly so) record's residue sd is that
/// of its non-modal content (an anti-alias filter's start-up, a truncated
/// response), not of a noise, and the poles that fit it pass any residue
/// SNR: the paper's beam behind `tests/identify_loop.rs`'s FIR filter,
/// noise-free, reported 5 such poles beside its 3 modes, at 7.6·10⁻⁸ –
/// 2.9·10⁻⁵ of the peak (the modes at 0.47–2.7). 10⁻⁴ (80 dB) is a choice:
/// about 10 quantisation sd of a 16-bit converter (2⁻¹⁵/√12 = 8.8·10⁻⁶ of full
/// scale), 20 × under the weakest visible mode of the coverage study
/// (20 sd of a floor of 10⁻⁴ of the peak, tests/identify_coverage.md).
pub const MIN_RELATIVE_AMPLITUDE: f64 = 1e-4;
/// Largest damping ratio of a reported mode (without `modes = K`): a pole
/// with ζ ≥ 1/√2 gives no resonance (its receptance magnitude falls
/// monotonically with frequency) and decays without a visible oscillation;
/// it is background (a real pole of the noise fitted as an oscillatory one
/// with ζ → 1 passed the residue test: tests/identify_coverage.md).
pub const MAX_MODE_ZETA: f64 = std::f64::consts::FRAC_1_SQRT_2;
/// Largest sd of ζ of a reported mode (without `modes = K`): ±2 sd of
/// more than this spans every ζ a resonance can have (0 … [`MAX_MODE_ZETA`]),
/// so the record does not hold the mode's damping, and a measured-data file
/// takes no ζ sd above 1. A mode the bath of an MD record nearly overdamps
/// is such a case (`tests/identify_md.md`, round 6). This is the sd at which
/// ζ ± 2 sd spans the range for every ζ in it; a mode whose ζ ± 2 sd spans
/// it with a smaller sd (a ζ inside the range) is background too
/// (`assemble::spans_every_zeta`).
pub const MAX_MODE_ZETA_SD: f64 = 0.5 * MAX_MODE_ZETA;
/// Largest pencil parameter L of the matrix pencil (Hankel columns − 1):
/// with L = 50 the 10-ms ring-down of a 10 kHz mode sampled at 200 kHz
/// (N = 2000) spans only 2.5 periods per row and the pole wanders across
/// orders; 200 keeps the SVD (O(N·L²)) near 0.1 s for N = 2000.
pub const PENCIL_CAP: usize = 200;
/// Default highest model order of the stabilisation diagram.
pub const DEFAULT_MAX_ORDER: usize = 40;

/// Why an identification failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IdentifyError {
    /// The record or a flag cannot support the fit (exit 2).
    #[error("{0}")]
    Input(#[from] InputError),
    /// The fit failed numerically (exit 1).
    #[error("numerical failure: {0}")]
    Numerical(String),
    /// The caller's stop flag was raised ([`identify_controlled`]).
    #[error("cancelled by the caller")]
    Cancelled,
}

/// Knobs of [`identify`].
#[derive(Debug, Clone, PartialEq)]
pub struct IdentifySettings {
    /// Number of modes to report: the K lowest clear ones (default: all clear modes in the band).
    pub modes: Option<usize>,
    /// Highest model order of the stabilisation diagram (default 40).
    pub max_order: usize,
}

impl Default for IdentifySettings {
    fn default() -> Self {
        Self { modes: None, max_order: DEFAULT_MAX_ORDER }
    }
}

/// One identified mode, sorted by frequency; `peak` is |A_r|/σ_r in the
/// record's units (the height of its resonance in |H|, or in √PSD).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct IdentifiedMode {
    pub omega_rad_s: f64,
    pub omega_sd_rad_s: f64,
    pub zeta: f64,
    pub zeta_sd: f64,
    pub peak: f64,
    /// |A_r|/sd(A_r), the residue's distance from zero in its sd.
    pub amplitude_snr: f64,
    /// How clearly the record holds the mode, under the fitted noise model
    /// (see `assemble::peak_snr`): frequency records, the height of its resonance over
    /// the noise sd at it; free decays, `amplitude_snr`. Modes are ranked by
    /// it; below [`MIN_PEAK_SNR`] a stable pole is background unless
    /// `modes = K` asks for it.
    pub peak_snr: f64,
}

/// The result: reported modes, background terms, fit statistics, and the
/// data for the figures.
#[derive(Debug, Clone, Serialize)]
pub struct Identification {
    pub kind: &'static str,
    pub modes: Vec<IdentifiedMode>,
    /// Oscillatory poles kept in the fit but not reported (with `modes = K`).
    pub background_modes: Vec<IdentifiedMode>,
    /// Real poles of the refinement, as decay rates γ (pole −γ), rad/s.
    pub real_poles_rad_s: Vec<f64>,
    /// Residual-based noise sd, in the units of the fitted quantity
    /// (m/N per component, m/N, or m; PSD: the relative sd 1/√ν̂ of a bin,
    /// ν̂ the estimated number of averages).
    pub noise_sd: f64,
    /// The noise model chosen with the modes (see [`noise`]).
    pub noise_model: NoiseModel,
    pub residual_count: usize,
    pub parameter_count: usize,
    pub diagram: Diagram,
    /// Frequencies (rad/s, ascending) of every mode a run without `modes = K`
    /// reports, together with the reported ones: what the modes are numbered
    /// against (numbering a chosen subset alone can renumber it).
    #[serde(skip)]
    pub found_omegas_rad_s: Vec<f64>,
    /// Abscissa of the record (rad/s or s).
    #[serde(skip)]
    pub x: Vec<f64>,
    /// Fitted model at the abscissae, in the record's units (complex: H;
    /// magnitude: |H|; PSD: PSD; time: displacement).
    #[serde(skip)]
    pub fitted: Vec<Complex64>,
    /// The record, in the same form.
    #[serde(skip)]
    pub measured: Vec<Complex64>,
    /// Residuals of the fitted quantity (model − data), record units.
    #[serde(skip)]
    pub residuals: Vec<f64>,
}

/// Level of the likelihood-ratio test that adds real poles to a joint-LM
/// (magnitude, PSD) refinement.
pub const REAL_POLE_TEST_LEVEL: f64 = 0.05;
