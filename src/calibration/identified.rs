//! Identified modes → a measured-data file (`nanobeam identify`'s output,
//! read unchanged by `calibrate` and `diagnose`).
//!
//! # Physical mode numbers
//! The measured-data file refers to physical modes (1-based, by |s|, eq. 34),
//! but a record only shows resonances. The identified modes, sorted by
//! frequency, are matched to the modes of a *family* of beams, the `--beam`
//! file over the base model's whole prior (e0a, the N = 1 relaxation (δ, Ω),
//! shear deformation and the nominal section; `calibration::numbering` has
//! the family, its closed forms and the search), by the order-preserving
//! one-to-one numbering with the least squared ln-misfit. Order preservation
//! is physics: modes keep their order under the model's error; skipping a
//! predicted mode is allowed (a mode with a node at the force or the sensor
//! is absent from the record, and a thermal record's line can drown in its
//! neighbours' noise). One beam of the family has one e0a, one relaxation,
//! one shear and one section for all its modes: that is what lets a missing
//! line show as a gap, and a relaxation between two modes show as the
//! stiffening of the modes above it rather than as another numbering.
//!
//! A numbering is refused only when another one also fits a beam of the
//! prior within [`AMBIGUITY_MARGIN`] (after what the grid may hide); the
//! refusal names the lowest identified mode, both numberings and what would
//! decide. A stated `--first-mode` is checked against the same family
//! ([`number_modes_checked`]).
//!
//! Modes are numbered against every mode the record holds clearly, never
//! against a chosen subset (`--modes K`): a subset that leaves a mode out
//! would otherwise be renumbered into the gap.

use crate::beam::BeamSpec;
use crate::calibration::measured::{MeasuredData, MeasuredFile, ModeObservation};
use crate::calibration::numbering::{extra, fits, predicted_count, skips, Family, Fit};
pub use crate::calibration::numbering::{
    AMBIGUITY_MARGIN, E0A_RANGE_NM, EXTRA_PREDICTED, FIRST_MODE_TOLERANCE, MAX_SKIPS, SKIP_MARGIN,
};
use crate::error::InputError;

/// Physical mode numbers and what the numbering has to say about them.
#[derive(Debug, Clone, PartialEq)]
pub struct Numbered {
    /// The physical number of each identified mode (1-based), in order.
    pub numbers: Vec<usize>,
    /// A stated `--first-mode` that fits much worse than another numbering
    /// (taken, not refused: some beam of the prior fits it).
    pub warning: Option<String>,
}

/// Physical mode numbers for identified frequencies (sorted ascending); see
/// [`number_modes_checked`].
pub fn number_modes(
    beam: &BeamSpec,
    omegas_rad_s: &[f64],
    first_mode: Option<usize>,
) -> Result<Vec<usize>, InputError> {
    number_modes_checked(beam, omegas_rad_s, first_mode).map(|n| n.numbers)
}

/// 0-based mode indices as 1-based numbers, runs of three or more as
/// `a-b` (`1-6, 8`), so that two numberings fit a one-line message.
fn one_based(m: &[usize]) -> String {
    let mut parts: Vec<String> = vec![];
    let mut i = 0;
    while i < m.len() {
        let mut j = i;
        while j + 1 < m.len() && m[j + 1] == m[j] + 1 {
            j += 1;
        }
        if j >= i + 2 {
            parts.push(format!("{}-{}", m[i] + 1, m[j] + 1));
        } else {
            parts.extend((i..=j).map(|k| (m[k] + 1).to_string()));
        }
        i = j + 1;
    }
    parts.join(", ")
}

/// Physical mode numbers for identified frequencies (sorted ascending),
/// with `first_mode` the stated number of the lowest (checked, see the
/// module doc), and a warning when the stated number fits much worse than
/// another. Exit-2 errors name `--first-mode` with its value as written
/// (`''` when not given: nothing written, as the CLI shows an empty value;
/// issue 69: "absent" read as a value). The frequencies' σ are taken as negligible
/// beside the margins; [`number_modes_with_sd`] takes them.
pub fn number_modes_checked(
    beam: &BeamSpec,
    omegas_rad_s: &[f64],
    first_mode: Option<usize>,
) -> Result<Numbered, InputError> {
    number_modes_with_sd(beam, omegas_rad_s, None, first_mode)
}

/// The margin between two numberings: [`AMBIGUITY_MARGIN`], or
/// [`SKIP_MARGIN`] for an alternative with more skipped modes, or 3 noise sd
/// where that is more, the noise being the root sum of squares of σ/ω over
/// the modes the two number differently (the modes they number alike move
/// both misfits alike): an alternative within 3 noise sd cannot be told
/// from the chosen numbering by the data.
struct Margins {
    /// σ/ω of each identified mode (0 when not given).
    relative_sd: Vec<f64>,
}

impl Margins {
    fn between(&self, chosen: &Fit, other: &Fit) -> f64 {
        let noise = chosen
            .modes
            .iter()
            .zip(&other.modes)
            .zip(&self.relative_sd)
            .filter(|((a, b), _)| a != b)
            .map(|(_, r)| r * r)
            .sum::<f64>()
            .sqrt();
        let model = if skips(&other.modes) <= skips(&chosen.modes) { AMBIGUITY_MARGIN } else { SKIP_MARGIN };
        model.max(3.0 * noise)
    }
}

/// [`number_modes_checked`] with the frequencies' sds (rad/s, one per
/// frequency), which widen the margins to 3 noise sd where that is more.
pub fn number_modes_with_sd(
    beam: &BeamSpec,
    omegas_rad_s: &[f64],
    omega_sds_rad_s: Option<&[f64]>,
    first_mode: Option<usize>,
) -> Result<Numbered, InputError> {
    let k = omegas_rad_s.len();
    let margin = Margins {
        relative_sd: (0..k)
            .map(|i| {
                let r = omega_sds_rad_s.and_then(|sd| sd.get(i)).map_or(0.0, |s| s / omegas_rad_s[i]);
                if r.is_finite() {
                    r.abs()
                } else {
                    0.0
                }
            })
            .collect(),
    };
    if first_mode == Some(0) {
        return Err(InputError::new("--first-mode", 0, ">= 1 (mode numbers are 1-based)"));
    }
    if k == 0 {
        return Err(InputError::new("modes", "none identified", "at least one identified mode to number"));
    }
    let n = predicted_count(k, first_mode);
    let family = Family::new(beam, n)?;
    check_scale(&family, omegas_rad_s)?;
    let ids: Vec<f64> = omegas_rad_s.iter().map(|w| w.ln()).collect();
    let all = fits(&family, &ids, 0..n);
    let best = all
        .first()
        .filter(|b| b.cost.is_finite())
        .ok_or_else(|| InputError::new("--beam", format!("{n} predicted modes"), "a beam model with enough modes"))?;
    let Some(f) = first_mode else {
        check_unique(&all, best, None, omegas_rad_s, &margin)?;
        return Ok(Numbered { numbers: best.modes.iter().map(|j| j + 1).collect(), warning: None });
    };
    let from_n: Vec<Fit> = all.iter().filter(|x| x.first() == f - 1).cloned().collect();
    let best_n = from_n.first().filter(|b| b.cost.is_finite()).ok_or_else(|| {
        InputError::new(
            "--first-mode",
            f,
            format!("<= {} (the beam model's modes from it on must hold the {k} identified)", n + 1 - k),
        )
    })?;
    let x = extra(best, best_n);
    if x >= FIRST_MODE_TOLERANCE {
        return Err(InputError::new(
            "--first-mode",
            f,
            // one line of at most 200 characters (issue 69): the prior is docs/identify.md's
            format!(
                "a lowest-mode number some beam of the prior fits, e.g. {} (modes {} fit; modes {} misfit every --beam prior beam by {x:.3} in rms ln omega)",
                best.first() + 1,
                one_based(&best.modes),
                one_based(&best_n.modes),
            ),
        ));
    }
    let warning = (x >= margin.between(best, best_n)).then(|| {
        format!(
            "--first-mode {f}: modes {} fit the identified frequencies {x:.3} worse (root summed squared ln omega) than modes {} over the --beam model's prior; kept as stated",
            one_based(&best_n.modes),
            one_based(&best.modes)
        )
    });
    // consecutive from N when that fits within the margin of the best from N
    if let Some(c) = from_n.iter().find(|c| skips(&c.modes) == 0) {
        if extra(best_n, c) < margin.between(best_n, c) {
            return Ok(Numbered { numbers: c.modes.iter().map(|j| j + 1).collect(), warning });
        }
    }
    check_unique(&from_n, best_n, Some(f), omegas_rad_s, &margin)?;
    Ok(Numbered { numbers: best_n.modes.iter().map(|j| j + 1).collect(), warning })
}

/// Decades beyond the family's modes (mode 1 of its softest beam, the last
/// predicted mode of its stiffest) that a record's lines may all lie before
/// they are refused as a record in another unit.
pub const SCALE_TOLERANCE_DECADES: f64 = 1.0;

/// The field of [`check_scale`]'s error; the CLI names the record's column.
pub const SCALE_FIELD: &str = "omega_rad_s";

/// Issue 69, defect 6: a record whose every line lies more than
/// [`SCALE_TOLERANCE_DECADES`] below mode 1 of every beam of the prior, or
/// above its last predicted mode, is in another unit (LAMMPS step numbers or
/// picoseconds left in `time_s` put the cc7 tube's lines 12–15 decades below
/// its modes), and any numbering of it is arbitrary: refused, with the decades.
fn check_scale(family: &Family, omegas_rad_s: &[f64]) -> Result<(), InputError> {
    let (lo, hi) = family.ln_span();
    let low = omegas_rad_s.iter().copied().fold(f64::INFINITY, f64::min);
    let high = omegas_rad_s.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let ln10 = 10f64.ln();
    let (decades, side) = if high.ln() < lo - SCALE_TOLERANCE_DECADES * ln10 {
        ((lo - high.ln()) / ln10, "below")
    } else if low.ln() > hi + SCALE_TOLERANCE_DECADES * ln10 {
        ((low.ln() - hi) / ln10, "above")
    } else {
        return Ok(());
    };
    Err(InputError::new(
        SCALE_FIELD,
        format!("lines at {low:.3e} to {high:.3e} rad/s"),
        format!(
            "lines near the --beam model's modes ({:.3e} to {:.3e} rad/s over its prior); these are {decades:.1} decades {side} them",
            lo.exp(),
            hi.exp()
        ),
    ))
}

/// Refuses `chosen` when another numbering of `all` fits a beam of the
/// prior within the margin of it ([`AMBIGUITY_MARGIN`], [`SKIP_MARGIN`], or
/// 3 noise sd).
fn check_unique(
    all: &[Fit],
    chosen: &Fit,
    first: Option<usize>,
    omegas_rad_s: &[f64],
    margins: &Margins,
) -> Result<(), InputError> {
    // an alternative with more skipped modes than the chosen numbering counts
    // within the tighter SKIP_MARGIN: a skip needs a reason (a node at the
    // sensor, a lost line), and over the whole prior a numbering with one more
    // skip near the top often fits nearly as well (cc7's modes 1-6 against
    // 1-5, 7: 0.042 more)
    let Some(other) = all.iter().find(|o| o.modes != chosen.modes && extra(chosen, o) < margins.between(chosen, o))
    else {
        return Ok(());
    };
    let decide = if other.first() != chosen.first() {
        "state --first-mode N, or a lower line would decide"
    } else {
        let i = (0..chosen.modes.len()).find(|&i| chosen.modes[i] != other.modes[i]).unwrap_or(0);
        return Err(InputError::new(
            "--first-mode",
            first.map_or("''".to_string(), |f| f.to_string()),
            format!(
                "a numbering the prior decides: lines from {:.3e} rad/s fit both modes {} and {} of its beams; a shape scan of line {} or e0a would decide",
                omegas_rad_s[0],
                one_based(&chosen.modes),
                one_based(&other.modes),
                i + 1,
            ),
        ));
    };
    Err(InputError::new(
        "--first-mode",
        first.map_or("''".to_string(), |f| f.to_string()),
        format!(
            "a numbering the prior decides: lines from {:.3e} rad/s fit both modes {} and {} of its beams; {decide}",
            omegas_rad_s[0],
            one_based(&chosen.modes),
            one_based(&other.modes),
        ),
    ))
}

/// The measured-data file of identified modes on `beam`, validated as
/// `calibrate` and `diagnose` will read it.
pub fn measured_file(beam: BeamSpec, modes: Vec<ModeObservation>) -> Result<MeasuredFile, InputError> {
    let file =
        MeasuredFile { beam, modes, held_out_modes: vec![], mode_scans: vec![], parameters: None, sampler: None };
    MeasuredData::from_file(file.clone())?;
    Ok(file)
}

/// YAML text of a measured-data file, with a header comment.
pub fn to_yaml(file: &MeasuredFile, comment: &str) -> String {
    let body = serde_yaml::to_string(file).expect("plain data serialises");
    let mut out: String = comment.lines().map(|l| format!("# {l}\n")).collect();
    out.push_str(&body);
    out
}
