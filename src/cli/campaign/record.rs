//! One record of a campaign: read, identify (lab records), diagnose or
//! calibrate, and the table's row. The library calls are the ones
//! `nanobeam identify`, `diagnose` and `calibrate` make
//! ([`crate::cli::identify::identify_record`], [`crate::diagnose::diagnose_run`],
//! [`crate::calibration::calibrate`]), with the same settings from the same
//! flags, so a row says what those commands say of the same file.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;
use std::time::Instant;

use sha2::{Digest, Sha256};

use crate::bayes::Control;
use crate::calibration::measured::MeasuredFile;
use crate::calibration::{calibrate, CalibrateOptions, MeasuredData};
use crate::cli::campaign::manifest::{Action, Kind, RecordOptions, Task};
use crate::cli::campaign::table::Row;
use crate::cli::{name_serde_value, read_beam, CliError};
use crate::diagnose::{diagnose_run, report, Diagnosis, Summary};
use crate::error::InputError;

/// SHA-256 of `bytes`, lower-case hex.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect()
}

/// SHA-256 of the file at `path`, or empty when it cannot be read.
pub fn file_sha256(path: &Path) -> String {
    std::fs::read(path).map(|b| sha256_hex(&b)).unwrap_or_default()
}

/// The file's text, a `.gz` file decompressed.
fn text_of(path: &Path, bytes: &[u8], what: &str) -> Result<String, CliError> {
    let gz = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("gz"));
    let bad = |e: String| InputError::new(what, path.display(), format!("a readable UTF-8 text file{e}"));
    if gz {
        let mut text = String::new();
        flate2::read::GzDecoder::new(bytes)
            .read_to_string(&mut text)
            .map_err(|e| bad(format!(" compressed with gzip ({e})")))?;
        Ok(text)
    } else {
        String::from_utf8(bytes.to_vec()).map_err(|_| bad(String::new()).into())
    }
}

/// A float as the table writes it: the shortest text that reads back to the same f64.
pub fn num(x: f64) -> String {
    format!("{x:e}")
}

/// Runs `task` and returns its row (an error row when anything fails).
/// `control` cancels the work (the Python front's Ctrl-C).
pub fn run(task: &Task, control: &Control) -> Row {
    let started = Instant::now();
    let mut row = Row {
        row: task.row,
        record: task.record.clone(),
        beam: task.beam.clone(),
        options: task.options.clone(),
        ..Row::default()
    };
    // the hash of every record that can be read, even one whose options are wrong
    let bytes = std::fs::read(&task.record_path).map_err(|e| {
        InputError::new("record", task.record_path.display(), format!("a readable file ({e})")).to_string()
    });
    if let Ok(b) = &bytes {
        row.record_sha256 = sha256_hex(b);
    }
    let result = match (&task.parsed, bytes) {
        (Err(e), _) => Err(e.clone()),
        (Ok(_), Err(e)) => Err(e),
        (Ok(options), Ok(bytes)) => compute(task, &bytes, options, control, &mut row),
    };
    match result {
        Ok(()) => row.status = "ok".into(),
        Err(e) => {
            row.status = "error".into();
            row.error = e;
        }
    }
    row.wall_s = format!("{:.3}", started.elapsed().as_secs_f64());
    row
}

fn compute(task: &Task, bytes: &[u8], o: &RecordOptions, control: &Control, row: &mut Row) -> Result<(), String> {
    let line = |e: CliError| e.to_string();
    let data = match o.kind {
        Kind::Measured => measured(&task.record_path, bytes, o).map_err(line)?,
        Kind::Lab => {
            let beam_path = task.beam_path.as_deref().ok_or_else(|| {
                InputError::new("beam", "(none)", "a beam file to number the modes (manifest column or --beam)")
                    .to_string()
            })?;
            row.beam_sha256 = file_sha256(beam_path);
            lab(&task.record_path, bytes, beam_path, o, control, row).map_err(line)?
        }
    };
    row.modes = data.modes.iter().map(|m| m.mode.to_string()).collect::<Vec<_>>().join(" ");
    match o.action {
        Action::Diagnose => diagnose(&data, o, control, row).map_err(line),
        Action::Calibrate => calibrate_row(data, o, control, row).map_err(line),
    }
}

/// A measured-data file, its beam's support replaced when the manifest says so.
fn measured(path: &Path, bytes: &[u8], o: &RecordOptions) -> Result<MeasuredData, CliError> {
    let text = text_of(path, bytes, "MEASURED.yaml")?;
    let mut file: MeasuredFile = crate::error::parse_yaml(&text).map_err(|e| CliError::Input(name_serde_value(e)))?;
    if let Some(s) = o.support {
        file.beam.support = s;
    }
    MeasuredData::from_file(file).map_err(|e| CliError::Input(name_serde_value(e)))
}

/// `nanobeam identify RECORD --beam BEAM --out m.yaml` and the file read
/// back as `diagnose m.yaml` reads it.
fn lab(
    path: &Path,
    bytes: &[u8],
    beam_path: &Path,
    o: &RecordOptions,
    control: &Control,
    row: &mut Row,
) -> Result<MeasuredData, CliError> {
    let mut beam = read_beam(beam_path)?;
    if let Some(s) = o.support {
        beam.support = s;
        beam.validate().map_err(|e| e.within("beam"))?;
    }
    crate::cli::identify::check_first_mode(o.first_mode, &beam)?;
    let text = text_of(path, bytes, "DATA.csv")?;
    let id = crate::cli::identify::identify_record(beam, &text, o.modes, o.max_order, o.first_mode, control)?;
    row.warnings = crate::identify::thermal::fit_warning(&text, &id.identification.x, id.identification.noise_sd)
        .unwrap_or_default();
    let yaml = crate::calibration::identified::to_yaml(&id.file, "");
    MeasuredData::from_yaml(&yaml).map_err(|e| CliError::Input(name_serde_value(e)))
}

/// The settings `nanobeam diagnose --samples N --max-causes K [--thorough]` selects.
fn diagnose(data: &MeasuredData, o: &RecordOptions, control: &Control, row: &mut Row) -> Result<(), CliError> {
    let args = crate::cli::diagnose::DiagnoseArgs {
        measured: Default::default(),
        out: None,
        json: false,
        samples: o.samples,
        thorough: o.thorough,
        quick: false,
        max_causes: o.max_causes,
    };
    let mut settings = crate::cli::diagnose::settings(&args);
    settings.seed = o.seed;
    settings.validate()?;
    settings.control = control.clone();
    let run = diagnose_run(data, &settings)?;
    fill_diagnosis(&run.diagnosis, row);
    Ok(())
}

fn fill_diagnosis(d: &Diagnosis, row: &mut Row) {
    row.verdict = d.cause.clone();
    row.explained = d.explained.to_string();
    row.causes = d.causes.join("+");
    row.decided_causes = d.decided_causes.join("+");
    row.alternatives = d
        .alternatives
        .iter()
        .map(|a| {
            let misfits = if a.misfits { ", misfits" } else { "" };
            format!("{} (ln B gap {:.2}{misfits})", a.extension, a.log_bayes_factor_gap)
        })
        .collect::<Vec<_>>()
        .join("; ");
    // the summary's own wording of the next measurement (and of a mode-shape
    // scan), or of the measurement that would falsify a decided verdict
    let kinds = ["next measurement: ", "mode-shape measurement: ", "would falsify: "];
    row.next_measurement =
        report::summary(d).lines().filter(|l| kinds.iter().any(|k| l.starts_with(k))).collect::<Vec<_>>().join(" ");
    let model = std::iter::once(&d.base)
        .chain(&d.candidates)
        .chain(std::iter::once(&d.baseline))
        .find(|c| c.extension == d.gain.extension)
        .unwrap_or(&d.base);
    row.model = model.extension.clone();
    row.log_evidence = num(model.log_evidence);
    row.log_bayes_factor = num(d.gain.log_bayes_factor);
    fill_posterior(&model.posterior, row);
    row.forward_solves = d.forward_evaluations.to_string();
}

fn fill_posterior(posterior: &BTreeMap<String, Summary>, row: &mut Row) {
    if let Some(s) = posterior.get("nonlocal_e0a_nm") {
        row.e0a_mean_nm = num(s.mean);
        row.e0a_ci95_lo_nm = num(s.ci95[0]);
        row.e0a_ci95_hi_nm = num(s.ci95[1]);
    }
    row.posterior = serde_json::to_string(posterior).expect("plain data");
}

/// `nanobeam calibrate` of the file (its own sampler settings; the manifest's seed if given).
fn calibrate_row(mut data: MeasuredData, o: &RecordOptions, control: &Control, row: &mut Row) -> Result<(), CliError> {
    if let Some(seed) = o.seed {
        data.sampler.seed = seed;
    }
    let result = calibrate(&data, &CalibrateOptions { control: control.clone() })?;
    row.model = "calibrate".into();
    let posterior: BTreeMap<String, Summary> = result
        .summary
        .parameters
        .iter()
        .map(|p| (p.name.clone(), Summary { mean: p.mean, sd: p.sd, ci95: p.ci95 }))
        .collect();
    fill_posterior(&posterior, row);
    row.warnings = result.warnings.join("; ");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `.gz` record is read decompressed; its hash is of the stored (compressed) bytes.
    #[test]
    fn a_gzip_record_is_read_decompressed() {
        use std::io::Write;
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        gz.write_all(b"time_s,displacement_m\n0,1\n").unwrap();
        let bytes = gz.finish().unwrap();
        assert_eq!(text_of(Path::new("r.csv.gz"), &bytes, "DATA.csv").unwrap(), "time_s,displacement_m\n0,1\n");
        let e = text_of(Path::new("r.csv.gz"), b"plain", "DATA.csv").unwrap_err().to_string();
        assert!(
            e.starts_with("invalid DATA.csv = r.csv.gz: allowed a readable UTF-8 text file compressed with gzip"),
            "{e}"
        );
        assert_eq!(sha256_hex(b"abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    }
}
