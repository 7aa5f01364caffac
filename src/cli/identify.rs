//! `nanobeam identify DATA.csv --beam BEAM.yaml [--modes K] [--first-mode N]
//! [--out MEASURED.yaml] [--plot DIR] [--json]`: a lab record → a
//! measured-data file. Thin: reads the files, calls
//! [`crate::identify::identify`], numbers the modes and writes the file through
//! [`crate::calibration::identified`], draws through [`crate::report::svg`].
//! Without `--out` the measured-data YAML goes to stdout; with it, a summary
//! table (or `--json`) does. Everything is computed before anything is written.

use std::path::{Path, PathBuf};

use clap::Args;
use serde::Serialize;

use crate::bayes::Control;
use crate::beam::BeamSpec;
use crate::calibration::identified::{measured_file, number_modes_with_sd, to_yaml, SCALE_FIELD};
use crate::calibration::measured::MeasuredFile;
use crate::calibration::numbering::predicted_count;
use crate::calibration::ModeObservation;
use crate::cli::{read_beam, write_out, CliError};
use crate::error::InputError;
use crate::identify::{
    identify_controlled, Identification, IdentifyError, IdentifySettings, Measurement, Stop, DEFAULT_MAX_ORDER,
};
use crate::report::render::{check_out_dir, check_out_file, write_dir_atomically, StagedFile};
use crate::report::svg::{line_plot, scatter_plot, Axis, LinePlot, RefLine, ScatterPlot, Series};
use crate::report::table::{fmt_sig, Table};
use crate::report::ReportError;

#[derive(Debug, Args)]
pub struct IdentifyArgs {
    /// Measured record (CSV, or gzipped CSV such as data/md/*.csv.gz; the header names the kind, see README).
    pub data: PathBuf,
    /// The nominal beam (YAML): copied into the output, and used to number the modes.
    #[arg(long)]
    pub beam: PathBuf,
    /// Report the K lowest modes the record shows clearly, in order (default: every clear mode in the band).
    #[arg(long, value_parser = |s: &str| crate::cli::clap_error::whole_number(s, ">= 1"))]
    pub modes: Option<usize>,
    /// Physical number of the lowest identified mode (when the numbering is ambiguous); checked against the --beam model's prior.
    #[arg(long, value_parser = |s: &str| crate::cli::clap_error::whole_number(s, ">= 1, at most the --beam mesh's free DOFs"))]
    pub first_mode: Option<usize>,
    /// Highest model order of the stabilisation diagram.
    #[arg(long, default_value_t = DEFAULT_MAX_ORDER, value_parser = |s: &str| crate::cli::clap_error::whole_number(s, ">= 4"))]
    pub max_order: usize,
    /// Write the measured-data file here (atomically) instead of stdout.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Directory for fit.svg, residuals.svg, stabilisation.svg (written atomically).
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Print the identification as JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct JsonOut<'a> {
    modes: &'a [ModeObservation],
    identification: &'a Identification,
}

impl From<IdentifyError> for CliError {
    fn from(e: IdentifyError) -> Self {
        match e {
            IdentifyError::Input(i) => CliError::Input(i),
            IdentifyError::Numerical(m) => CliError::Failure(format!("numerical failure: {m}")),
            IdentifyError::Cancelled => CliError::Failure(IdentifyError::Cancelled.to_string()),
        }
    }
}

/// A bad `--out` FILE or `--plot` DIR (an existing directory for the file,
/// a foreign non-empty directory, a missing or read-only parent) is bad input
/// (exit 2, naming the flag and its value); any other write failure is exit 1.
fn out_error(flag: &str, path: &Path, e: ReportError) -> CliError {
    match e {
        ReportError::OutPath { reason, .. } => {
            let allowed = if flag == "--out" {
                "a file path in an existing writable directory"
            } else {
                "a new path, an empty directory or a directory written by nanobeam"
            };
            CliError::Input(InputError::new(flag, path.display(), format!("{allowed}; {reason}")))
        }
        other => CliError::Failure(format!("cannot write {flag} {}: {other}", path.display())),
    }
}

/// `--first-mode` against the beam before anything is computed: at least 1,
/// and at most the number of physical modes the `--beam` mesh has (its free
/// DOFs), since the lowest identified mode is one of them.
pub fn check_first_mode(first: Option<usize>, beam: &BeamSpec) -> Result<(), CliError> {
    let dofs = beam.free_dofs();
    match first {
        Some(f) if f == 0 || f > dofs => Err(InputError::new(
            "--first-mode",
            f,
            format!("1..={dofs} (physical modes of the --beam mesh: its free DOFs)"),
        )
        .into()),
        _ => Ok(()),
    }
}

/// `--first-mode` against the identified modes: modes f ..= f + k − 1 and the
/// spare ones the numbering compares against (`predicted_count`) must all be
/// modes of the `--beam` mesh.
fn check_first_mode_fits(first: Option<usize>, k: usize, beam: &BeamSpec) -> Result<(), CliError> {
    let dofs = beam.free_dofs();
    let Some(f) = first else { return Ok(()) };
    let spare = predicted_count(k, Some(1)) - k;
    let last_first = (dofs + 1).saturating_sub(k + spare);
    if f > last_first {
        return Err(InputError::new(
            "--first-mode",
            f,
            format!(
                "1..={last_first} ({k} identified modes from it on plus {spare} spare must be among the {dofs} modes of the --beam mesh)"
            ),
        )
        .into());
    }
    Ok(())
}

/// A mode the record puts where the measured-data file cannot take it is a
/// property of the record: name the quantity the file refused (`zeta_sd`, not
/// the record's abscissa: issue 69, defect 7) and the mode by the frequency
/// the record shows it at.
/// The frequency is in the record's unit: Hz for a record written in Hz or
/// in seconds, whose user never wrote rad/s (issue 69).
fn record_error(e: InputError, observations: &[ModeObservation], text: &str) -> CliError {
    if let Some(rest) = e.field.strip_prefix("modes[") {
        let (index, quantity) = rest.split_once(']').unwrap_or((rest, ""));
        let quantity = quantity.trim_start_matches('.');
        let mode = index.parse::<usize>().ok().and_then(|i| observations.get(i));
        let field = match mode {
            Some(m) => {
                let at = format!("{:.4e} rad/s", m.omega_rad_s);
                format!(
                    "{} (the mode identified at {})",
                    if quantity.is_empty() { "mode" } else { quantity },
                    if in_rad_s(text) { at } else { rad_s_as_hz(&at) }
                )
            }
            None => e.field.clone(),
        };
        return CliError::Input(InputError::new(
            field,
            e.value,
            format!("a mode a measured-data file takes: {}", e.allowed),
        ));
    }
    CliError::Input(e)
}

/// The column names of a record's header line as written (a byte-order mark
/// dropped, each name trimmed and unquoted): what the refusals below name the
/// record's columns by.
fn header_names(text: &str) -> Vec<String> {
    let header = text.strip_prefix('\u{feff}').unwrap_or(text).lines().next().unwrap_or("");
    header.split(',').map(|n| n.trim().trim_matches('"').to_string()).collect()
}

/// The record's abscissa column is `frequency_hz`.
fn in_hz(text: &str) -> bool {
    header_names(text).first().is_some_and(|c| c == "frequency_hz")
}

/// The record's abscissa column is `omega_rad_s`: its user wrote rad/s.
fn in_rad_s(text: &str) -> bool {
    header_names(text).first().is_some_and(|c| c == "omega_rad_s")
}

/// The identification's refusals of a record written in seconds (a
/// ring-down, a thermal record, whose lines are fitted in rad/s) show each
/// frequency in Hz, as a thermal record's length refusals do: its user never
/// wrote rad/s (issue 69). The field is left as named ([`thermal_terms`]
/// names a thermal record's PSD).
fn time_terms(e: IdentifyError, text: &str) -> IdentifyError {
    let IdentifyError::Input(mut e) = e else { return e };
    if header_names(text).first().is_some_and(|c| c == "time_s") {
        for part in [&mut e.value, &mut e.allowed] {
            *part = rad_s_as_hz(part);
        }
    }
    e.into()
}

/// The identification's refusals of a thermal record in the record's terms
/// (issue 69, defect 8's subject): the record is fitted as the PSD of its
/// displacement columns, whose abscissa `omega_rad_s` the record lacks, and
/// whose "samples" are the PSD's bins, not the record's rows. The field names
/// the PSD of the record's columns (`PSD of thermal_a_m,thermal_b_m`; the
/// first and last of more than two) and the counts say bins.
fn thermal_terms(e: IdentifyError, text: &str) -> IdentifyError {
    let IdentifyError::Input(mut e) = e else { return e };
    let names = header_names(text);
    if e.field != "omega_rad_s" || !crate::identify::thermal::is_thermal(&names) {
        return e.into();
    }
    let columns = &names[1..];
    let clip = |n: &String| crate::error::clip(n);
    e.field = match columns {
        [a] => format!("PSD of {}", clip(a)),
        [a, b] => format!("PSD of {},{}", clip(a), clip(b)),
        [a, .., z] => format!("PSD of {},…,{} ({} columns)", clip(a), clip(z), columns.len()),
        [] => return e.into(),
    };
    for part in [&mut e.value, &mut e.allowed] {
        *part = part.replace(" samples", " bins");
    }
    e.into()
}

/// The identification's refusals of a record written in `frequency_hz` in the
/// record's terms (issue 69): the record is read as `omega_rad_s` (ω = 2πf),
/// so its refusals named that column and showed rad/s. The field names the
/// record's column and every frequency written `X rad/s` (or `[X, Y] rad/s`)
/// is shown in Hz.
fn hz_terms(e: IdentifyError, text: &str) -> IdentifyError {
    let IdentifyError::Input(mut e) = e else { return e };
    if e.field != "omega_rad_s" || !in_hz(text) {
        return e.into();
    }
    e.field = "frequency_hz".to_string();
    hz_values(e, text).into()
}

/// Every frequency written `X rad/s` in `e`'s value and allowed part shown
/// in Hz when the record's abscissa is `frequency_hz` or `time_s` (the
/// numbering's refusals: "lines from 1.480e11 Hz fit both …"; issue 69: the
/// user of a record in Hz or in seconds never wrote rad/s).
fn hz_values(mut e: InputError, text: &str) -> InputError {
    if in_hz(text) || header_names(text).first().is_some_and(|c| c == "time_s") {
        for part in [&mut e.value, &mut e.allowed] {
            *part = rad_s_as_hz(part);
        }
    }
    e
}

/// `text` with each frequency followed by ` rad/s` (`6.2832e11 rad/s`,
/// `[6.2648e11, 6.3016e11] rad/s`, `1.0e3 to 2.0e3 rad/s`) divided by 2π and
/// followed by ` Hz`, written with the same number of significant digits.
fn rad_s_as_hz(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find(" rad/s") {
        let head = &rest[..i];
        // the numbers just before: `X`, `[X, Y]` or `X to Y`
        let start = if head.ends_with(']') { head.rfind('[') } else { head.rfind([' ', '(']).map(|j| j + 1) };
        let mut start = start.unwrap_or(0);
        let mut separator = ", ";
        if let Some(before) = head[..start].strip_suffix(" to ") {
            let from = before.rfind([' ', '(']).map_or(0, |j| j + 1);
            if before[from..].parse::<f64>().is_ok() {
                (start, separator) = (from, " to ");
            }
        }
        let numbers = &head[start..];
        let converted: Option<Vec<String>> = numbers
            .trim_matches(['[', ']'])
            .split(separator)
            .map(|n| {
                let v: f64 = n.parse().ok()?;
                let digits = n.split(['e', 'E']).next().unwrap_or(n).split('.').nth(1).map_or(0, str::len);
                Some(format!("{:.*e}", digits, v / std::f64::consts::TAU))
            })
            .collect();
        match converted {
            Some(c) => {
                out.push_str(&head[..start]);
                out.push_str(&if numbers.starts_with('[') { format!("[{}]", c.join(", ")) } else { c.join(separator) });
                out.push_str(" Hz");
            }
            None => {
                out.push_str(head);
                out.push_str(" rad/s");
            }
        }
        rest = &rest[i + " rad/s".len()..];
    }
    out.push_str(rest);
    out
}

/// Lines decades from the beam's modes (issue 69, defect 6) are a unit left
/// in the record's abscissa: the error names its column as the header
/// writes it (a thermal record is read as a PSD, a `frequency_hz` column as
/// rad/s) and its unit.
fn scale_error(e: InputError, text: &str) -> CliError {
    if e.field != SCALE_FIELD || !e.value.starts_with("lines at ") {
        return e.into();
    }
    let names = header_names(text);
    let column = names.first().map_or("", String::as_str);
    let unit = match column {
        "time_s" => "seconds",
        "frequency_hz" => "Hz",
        _ => "rad/s",
    };
    InputError::new(column, e.value, format!("a column in {unit}: {}", e.allowed)).into()
}

/// A lab record identified, numbered against the nominal beam and turned into
/// a measured-data file: what `nanobeam identify` writes and the Python front
/// returns, computed by [`identify_record`] for both.
pub struct Identified {
    /// The poles, their σ and the fitted noise model.
    pub identification: Identification,
    /// The identified modes under their physical mode numbers.
    pub observations: Vec<ModeObservation>,
    /// The measured-data file of `beam` and `observations`.
    pub file: MeasuredFile,
    /// A stated `--first-mode` that fits much worse than another numbering.
    pub numbering_warning: Option<String>,
}

/// The record at `path` as text: a gzipped file (its first two bytes 1f 8b,
/// e.g. the committed `data/md/*.csv.gz`) is decompressed, anything else is
/// read as UTF-8. Errors name the path (exit 2).
pub fn read_record(path: &Path) -> Result<String, CliError> {
    use std::io::Read;
    let bad =
        |e: String| InputError::new("DATA.csv", path.display(), format!("a readable CSV file, plain or gzipped ({e})"));
    let bytes = std::fs::read(path).map_err(|e| bad(e.to_string()))?;
    let bytes = if bytes.starts_with(&[0x1f, 0x8b]) {
        let mut out = Vec::new();
        flate2::read::MultiGzDecoder::new(&bytes[..]).read_to_end(&mut out).map_err(|e| bad(format!("gzip: {e}")))?;
        out
    } else {
        bytes
    };
    String::from_utf8(bytes).map_err(|e| bad(format!("not UTF-8 text: {e}")).into())
}

/// The record `text` (CSV) identified with at most `max_order` poles (`modes`
/// of them if given), numbered against `beam` (from `first_mode` if given)
/// and made a measured-data file. The caller has checked `max_order` and
/// [`check_first_mode`] against the beam before reading the record; the
/// identified count is checked against `first_mode` here. `control` is
/// polled after reading the record and between the identification's phases
/// ([`identify_controlled`]); once cancelled the call returns a failure
/// (the Python front's Ctrl-C; the CLI's control never cancels).
pub fn identify_record(
    beam: BeamSpec,
    text: &str,
    modes: Option<usize>,
    max_order: usize,
    first_mode: Option<usize>,
    control: &Control,
) -> Result<Identified, CliError> {
    let record = Measurement::from_csv(text)?;
    control.check().map_err(|c| CliError::Failure(c.to_string()))?;
    let settings = IdentifySettings { modes, max_order };
    let polled = control.clone();
    let id = identify_controlled(&record, &settings, &Stop::new(move || polled.is_cancelled()))
        .map_err(|e| time_terms(hz_terms(thermal_terms(e, text), text), text))?;
    // numbered against every mode the record holds clearly (a subset chosen
    // by --modes is numbered within them, never renumbered into a gap)
    let found = &id.found_omegas_rad_s;
    check_first_mode_fits(first_mode, found.len(), &beam)?;
    // each found mode's σ, from the reported or the background list it went to
    let sds: Vec<f64> = found
        .iter()
        .map(|&w| {
            id.modes.iter().chain(&id.background_modes).find(|m| m.omega_rad_s == w).map_or(0.0, |m| m.omega_sd_rad_s)
        })
        .collect();
    let numbered = number_modes_with_sd(&beam, found, Some(&sds), first_mode)
        .map_err(|e| scale_error(hz_values(e, text), text))?;
    let all_numbers = numbered.numbers;
    let numbers: Vec<usize> = id
        .modes
        .iter()
        .map(|m| found.iter().position(|&w| w == m.omega_rad_s).map(|i| all_numbers[i]))
        .collect::<Option<_>>()
        .ok_or_else(|| CliError::Failure("a reported mode is missing from the numbered set".into()))?;
    let observations: Vec<ModeObservation> = id
        .modes
        .iter()
        .zip(&numbers)
        .map(|(m, &mode)| ModeObservation {
            mode,
            omega_rad_s: m.omega_rad_s,
            omega_sd_rad_s: m.omega_sd_rad_s,
            zeta: m.zeta,
            zeta_sd: m.zeta_sd,
        })
        .collect();
    let file = measured_file(beam, observations.clone()).map_err(|e| record_error(e, &observations, text))?;
    Ok(Identified { identification: id, observations, file, numbering_warning: numbered.warning })
}

/// The first line of every measured-data file `identify` writes.
const OUT_MARKER: &str = "# nanobeam identify ";

/// `--out` replaces a file only when `identify` wrote it (its first line is
/// [`OUT_MARKER`]) or it is empty: any other existing file, the input record
/// among them, is the user's data (issue 69, defect 4: `--out rec.csv`
/// replaced the record).
fn refuse_foreign_file(path: &Path) -> Result<(), CliError> {
    let Ok(mut f) = std::fs::File::open(path) else { return Ok(()) };
    if f.metadata().is_ok_and(|m| m.len() == 0) {
        return Ok(());
    }
    let mut head = vec![0u8; OUT_MARKER.len()];
    let ours = std::io::Read::read_exact(&mut f, &mut head).is_ok() && head == OUT_MARKER.as_bytes();
    if ours {
        return Ok(());
    }
    Err(InputError::new(
        "--out",
        path.display(),
        "a new path or a file nanobeam identify wrote (this file exists and nanobeam did not write it)",
    )
    .into())
}

/// Whether two output paths name the same place (their parents resolved,
/// the last components compared); paths whose parent does not exist differ.
fn same_target(a: &Path, b: &Path) -> bool {
    let resolve = |p: &Path| -> Option<(std::path::PathBuf, std::ffi::OsString)> {
        let parent = p.parent().filter(|q| !q.as_os_str().is_empty()).unwrap_or(Path::new("."));
        Some((std::fs::canonicalize(parent).ok()?, p.file_name()?.to_os_string()))
    };
    matches!((resolve(a), resolve(b)), (Some(x), Some(y)) if x == y)
}

pub fn run(args: &IdentifyArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    if args.max_order < 4 {
        return Err(InputError::new("--max-order", args.max_order, ">= 4").into());
    }
    // every output is checked before anything is computed
    if let Some(path) = &args.out {
        check_out_file(path).map_err(|e| out_error("--out", path, e))?;
        refuse_foreign_file(path)?;
    }
    if let Some(dir) = &args.plot {
        if args.out.as_deref().is_some_and(|out| same_target(out, dir)) {
            return Err(InputError::new("--plot", dir.display(), "a directory other than --out's file").into());
        }
        check_out_dir(dir).map_err(|e| out_error("--plot", dir, e))?;
    }
    let beam = read_beam(&args.beam)?;
    check_first_mode(args.first_mode, &beam)?;
    let text = read_record(&args.data)?;
    let Identified { identification: id, observations, file, numbering_warning } =
        identify_record(beam, &text, args.modes, args.max_order, args.first_mode, &Control::default())?;
    if let Some(w) = numbering_warning {
        eprintln!("warning: {w}");
    }
    // thermal-motion records (issue 43): the fit's ν̂ against the Welch segments
    if let Some(w) = crate::identify::thermal::fit_warning(&text, &id.x, id.noise_sd) {
        eprintln!("warning: {w}");
    }
    // its first line, written `# ` + comment, is what `refuse_foreign_file` recognises
    let comment = format!(
        "{}{}: {} record, {} modes; sds from the fit (residual noise sd {:.4e}, {} residuals, {} parameters)",
        OUT_MARKER.trim_start_matches("# "),
        args.data.display(),
        id.kind,
        observations.len(),
        id.noise_sd,
        id.residual_count,
        id.parameter_count
    );
    let yaml = to_yaml(&file, &comment);
    let figures = match &args.plot {
        Some(_) => Some(figures(&id).map_err(|e| CliError::Failure(format!("cannot draw: {e}")))?),
        None => None,
    };
    // all or nothing: the file is staged (and removed on any failure or
    // signal) until the plot directory is in place
    let staged = match &args.out {
        Some(path) => Some(StagedFile::new(path, yaml.as_bytes()).map_err(|e| out_error("--out", path, e))?),
        None => None,
    };
    if let (Some(dir), Some(figs)) = (&args.plot, figures) {
        write_dir_atomically(dir, |tmp| {
            for (name, svg) in &figs {
                // the temporary directory is itself registered for cleanup
                std::fs::write(tmp.join(name), svg.as_bytes()).map_err(|e| ReportError::io(tmp.join(name), e))?;
            }
            Ok::<(), ReportError>(())
        })
        .map_err(|e| out_error("--plot", dir, e))?;
    }
    if let (Some(path), Some(staged)) = (&args.out, staged) {
        staged.commit().map_err(|e| out_error("--out", path, e))?;
    }
    if args.json {
        let json = serde_json::to_string(&JsonOut { modes: &observations, identification: &id }).expect("serialises");
        return write_out(out, &(json + "\n"));
    }
    if args.out.is_none() {
        return write_out(out, &yaml);
    }
    let mut t = Table::new(["mode", "omega_rad_s", "omega_sd_rad_s", "zeta", "zeta_sd"]);
    for o in &observations {
        t.push_row([
            o.mode.to_string(),
            fmt_sig(o.omega_rad_s, 7),
            fmt_sig(o.omega_sd_rad_s, 3),
            fmt_sig(o.zeta, 6),
            fmt_sig(o.zeta_sd, 3),
        ]);
    }
    write_out(out, &format!("{}\n{comment}\n", t.to_markdown()))
}

/// fit.svg (data vs model; magnitude and, for complex records, phase.svg),
/// residuals.svg, stabilisation.svg.
fn figures(id: &Identification) -> crate::report::error::Result<Vec<(String, String)>> {
    let time = id.kind == "free decay";
    let x_label = if time { "time (s)" } else { "frequency (rad/s)" };
    let (y_label, pick): (&str, fn(&num_complex::Complex64) -> f64) = match id.kind {
        "free decay" => ("displacement (m)", |z| z.re),
        "displacement PSD" => ("PSD (m²·s/rad)", |z| z.re),
        _ => ("|H| (m/N)", |z| z.norm()),
    };
    let y_axis = if time { Axis::linear(y_label) } else { Axis::log(y_label) };
    let x_axis = if time { Axis::linear(x_label) } else { Axis::log(x_label) };
    let modes: Vec<RefLine> =
        if time { vec![] } else { id.modes.iter().map(|m| RefLine::Vertical(m.omega_rad_s)).collect() };
    let mut out = vec![(
        "fit.svg".to_string(),
        line_plot(&LinePlot {
            title: format!("{}: data and fitted model", id.kind),
            x_axis: x_axis.clone(),
            y_axis,
            series: vec![
                Series::new("measured", id.x.clone(), id.measured.iter().map(pick).collect()),
                Series::new("fitted model", id.x.clone(), id.fitted.iter().map(pick).collect()),
            ],
            ref_lines: modes.clone(),
            ..LinePlot::default()
        })?,
    )];
    if id.kind == "complex receptance" {
        out.push((
            "phase.svg".into(),
            line_plot(&LinePlot {
                title: "phase: data and fitted model".into(),
                x_axis: x_axis.clone(),
                y_axis: Axis::linear("phase (rad)"),
                series: vec![
                    Series::new("measured", id.x.clone(), id.measured.iter().map(|z| z.arg()).collect()),
                    Series::new("fitted model", id.x.clone(), id.fitted.iter().map(|z| z.arg()).collect()),
                ],
                ref_lines: modes.clone(),
                ..LinePlot::default()
            })?,
        ));
    }
    let r_label = match id.kind {
        "displacement PSD" => "Whittle deviance residual (-)",
        "free decay" => "residual (m)",
        "complex receptance" => "|residual| (m/N)",
        _ => "residual (m/N)",
    };
    out.push((
        "residuals.svg".into(),
        line_plot(&LinePlot {
            title: format!("residuals (noise sd {:.3e})", id.noise_sd),
            x_axis: if time { Axis::linear(x_label) } else { Axis::log(x_label) },
            y_axis: Axis::linear(r_label),
            series: vec![Series::new("model − data", id.x.clone(), id.residuals.clone())],
            ref_lines: vec![RefLine::Horizontal(0.0)],
            ..LinePlot::default()
        })?,
    ));
    out.push(("stabilisation.svg".into(), scatter_plot(&stabilisation(id))?));
    Ok(out)
}

fn stabilisation(id: &Identification) -> ScatterPlot {
    use crate::identify::stabilisation::Stability;
    let group = |name: &str, st: Stability| {
        let pts: Vec<_> = id.diagram.poles.iter().filter(|p| p.stability == st).collect();
        Series::new(name, pts.iter().map(|p| p.omega_rad_s).collect(), pts.iter().map(|p| p.order as f64).collect())
    };
    ScatterPlot {
        title: "stabilisation diagram (dashed: reported modes)".into(),
        x_axis: Axis::log("natural frequency |s| (rad/s)"),
        y_axis: Axis::linear("model order"),
        groups: vec![
            group("stable (ω 1 %, ζ 5 %)", Stability::Stable),
            group("stable in ω only", Stability::Frequency),
            group("new / unstable", Stability::Unstable),
            group("real pole", Stability::Real),
        ],
        ref_lines: id.modes.iter().map(|m| RefLine::Vertical(m.omega_rad_s)).collect(),
        size: (800, 500),
    }
}

#[cfg(test)]
mod tests {
    use super::rad_s_as_hz;

    #[test]
    fn frequencies_in_rad_s_are_shown_in_hz_with_their_digits() {
        let tau = std::f64::consts::TAU;
        let text = format!(
            "[{:.4e}, {:.4e}] rad/s of a line at {:.3e} rad/s (at 5 rad/s); 3 samples",
            tau,
            2.0 * tau,
            3e9 * tau
        );
        // the digits shown, not more: 1.2566e1 rad/s is 1.9999e0 Hz, 5 rad/s 8e-1 Hz
        assert_eq!(rad_s_as_hz(&text), "[1.0000e0, 1.9999e0] Hz of a line at 3.000e9 Hz (at 8e-1 Hz); 3 samples");
        assert_eq!(rad_s_as_hz("no number rad/s"), "no number rad/s");
        assert_eq!(rad_s_as_hz("lines at 6.283e0 to 1.885e1 rad/s"), "lines at 1.000e0 to 3.000e0 Hz");
    }
}
