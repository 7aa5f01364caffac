//! The campaign's plan: a manifest CSV (or a folder and one `--beam`) turned
//! into one [`Task`] per record, in manifest order.
//!
//! Only a manifest whose structure is wrong is refused (exit 2, naming the
//! row and the column): an unreadable or non-CSV file, an unknown or repeated
//! column, no `record` column, a row with another number of cells than the
//! header, an empty `record` cell. A cell whose value is wrong (an unknown
//! `action`, `first_mode = abc`, a `support` that is no support) is that
//! record's error: its row in the table says so and the campaign goes on.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::beam::Support;
use crate::cli::CliError;
use crate::diagnose::DiagnoseSettings;
use crate::error::InputError;
use crate::identify::DEFAULT_MAX_ORDER;

/// The manifest's columns: `record` is required, the others optional (an
/// empty cell or a missing column takes the default: the CLI's flag, or the
/// kind read from the file name).
pub const MANIFEST_COLUMNS: [&str; 11] = [
    "record",
    "beam",
    "support",
    "kind",
    "action",
    "first_mode",
    "modes",
    "max_order",
    "samples",
    "max_causes",
    "seed",
];

/// What a record is: a lab or MD record (CSV, `identify` first) or a
/// measured-data file (YAML).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Kind {
    Lab,
    Measured,
}

/// What is done with the record's modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Action {
    Diagnose,
    Calibrate,
}

/// The options of one record: the manifest's cells over the command's flags.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordOptions {
    pub kind: Kind,
    pub action: Action,
    /// Overrides the support of the beam (lab records) or of the file's beam (measured-data files).
    pub support: Option<Support>,
    pub first_mode: Option<usize>,
    pub modes: Option<usize>,
    pub max_order: usize,
    pub samples: Option<usize>,
    pub max_causes: Option<usize>,
    pub thorough: bool,
    /// The diagnosis's (or calibration's) seed; default: the measured-data file's `sampler.seed`.
    pub seed: Option<u64>,
}

/// The command-wide settings every record starts from (`--beam`,
/// `--samples`, `--max-causes`, `--thorough`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Defaults {
    pub beam: Option<PathBuf>,
    pub samples: Option<usize>,
    pub max_causes: Option<usize>,
    pub thorough: bool,
}

impl Defaults {
    /// The flags against diagnose's ranges, before anything is read (exit 2
    /// naming the flag, as `nanobeam diagnose` would).
    pub fn check(&self) -> Result<(), CliError> {
        let args = crate::cli::diagnose::DiagnoseArgs {
            measured: PathBuf::new(),
            out: None,
            json: false,
            samples: self.samples,
            thorough: self.thorough,
            quick: false,
            max_causes: self.max_causes,
        };
        crate::cli::diagnose::settings(&args).validate()?;
        Ok(())
    }
}

/// One record of the campaign.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Task {
    /// 1-based position in the manifest (or in the folder's sorted listing): the table's order.
    pub row: usize,
    /// The record's path as the manifest writes it (relative to the manifest's folder).
    pub record: String,
    /// Where it is read from.
    pub record_path: PathBuf,
    /// The beam file as the manifest (or `--beam`) writes it; empty for a measured-data file.
    pub beam: String,
    pub beam_path: Option<PathBuf>,
    /// `key=value` pairs joined by `;`, the effective options in a fixed order:
    /// with the record's and the beam's sha256 the key a rerun skips on.
    pub options: String,
    /// The parsed options, or the one-line error of the cell that did not parse.
    pub parsed: Result<RecordOptions, String>,
}

/// The kind a file name says: `.csv`/`.csv.gz` a lab record, `.yaml`/`.yml` a measured-data file.
pub fn kind_of(name: &str) -> Option<Kind> {
    let lower = name.to_ascii_lowercase();
    if lower.ends_with(".csv") || lower.ends_with(".csv.gz") {
        Some(Kind::Lab)
    } else if lower.ends_with(".yaml") || lower.ends_with(".yml") {
        Some(Kind::Measured)
    } else {
        None
    }
}

/// The plan of `source`: a manifest CSV, or a folder whose `.csv`,
/// `.csv.gz`, `.yaml` and `.yml` files (sorted by name, the `--beam` file
/// and `exclude` left out) are the records.
pub fn plan(source: &Path, defaults: &Defaults, exclude: Option<&Path>) -> Result<Vec<Task>, CliError> {
    defaults.check()?;
    if source.is_dir() {
        return plan_folder(source, defaults, exclude);
    }
    let text = std::fs::read_to_string(source).map_err(|e| {
        InputError::new("MANIFEST", source.display(), format!("a readable manifest CSV or a folder of records ({e})"))
    })?;
    let base = source.parent().map(Path::to_path_buf).unwrap_or_default();
    plan_manifest(&text, &base, defaults)
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

fn plan_folder(dir: &Path, defaults: &Defaults, exclude: Option<&Path>) -> Result<Vec<Task>, CliError> {
    let entries = std::fs::read_dir(dir)
        .map_err(|e| InputError::new("MANIFEST", dir.display(), format!("a readable folder ({e})")))?;
    let mut names: Vec<String> = entries
        .filter_map(|e| e.ok())
        .filter(|e| e.path().is_file())
        .filter_map(|e| e.file_name().to_str().map(str::to_string))
        .filter(|n| kind_of(n).is_some())
        .filter(|n| {
            let p = dir.join(n);
            !defaults.beam.as_deref().is_some_and(|b| same_file(&p, b)) && !exclude.is_some_and(|x| same_file(&p, x))
        })
        .collect();
    names.sort();
    Ok(names
        .into_iter()
        .enumerate()
        .map(|(i, name)| {
            let cells = Cells { record: name.clone(), ..Cells::default() };
            task(i + 1, &cells, dir, defaults)
        })
        .collect())
}

/// The cells of one manifest row (trimmed; empty = default).
#[derive(Debug, Default)]
struct Cells {
    record: String,
    beam: String,
    support: String,
    kind: String,
    action: String,
    first_mode: String,
    modes: String,
    max_order: String,
    samples: String,
    max_causes: String,
    seed: String,
}

impl Cells {
    fn set(&mut self, column: &str, value: String) {
        let slot = match column {
            "record" => &mut self.record,
            "beam" => &mut self.beam,
            "support" => &mut self.support,
            "kind" => &mut self.kind,
            "action" => &mut self.action,
            "first_mode" => &mut self.first_mode,
            "modes" => &mut self.modes,
            "max_order" => &mut self.max_order,
            "samples" => &mut self.samples,
            "max_causes" => &mut self.max_causes,
            _ => &mut self.seed,
        };
        *slot = value;
    }
}

/// A malformed manifest: one line naming the row (data rows from 1, the
/// header not counted, with its line in the file) and the column.
fn malformed(row: usize, line: u64, column: &str, value: impl std::fmt::Display, allowed: &str) -> CliError {
    InputError::new(format!("manifest row {row} (line {line}), column {column}"), value, allowed).into()
}

/// Line `line` (1-based; the first that is not a `#` comment for the header,
/// `line` 1) of `text` as written, cut and quoted by
/// [`crate::error::clip_quoted`]; `''` for an empty or absent line.
fn written_line(text: &str, line: u64) -> String {
    let mut lines = text.lines();
    let found = match line {
        0 => None,
        1 => lines.find(|l| !l.trim_start().starts_with('#')),
        _ => lines.nth(line as usize - 1),
    };
    match found.map(str::trim).filter(|l| !l.is_empty()) {
        Some(l) => crate::error::clip_quoted(l),
        None => "''".to_string(),
    }
}

/// Parses a manifest's text; relative paths are resolved against `base`.
/// Lines starting with `#` are comments.
pub fn plan_manifest(text: &str, base: &Path, defaults: &Defaults) -> Result<Vec<Task>, CliError> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| InputError::new("manifest header", written_line(text, 1), format!("a CSV header line ({e})")))?
        .iter()
        .map(str::to_string)
        .collect();
    let known = MANIFEST_COLUMNS.join(", ");
    for (i, name) in header.iter().enumerate() {
        if !MANIFEST_COLUMNS.contains(&name.as_str()) {
            return Err(malformed(0, 1, &format!("{} of the header", i + 1), name, &format!("one of {known}")));
        }
        if header[..i].contains(name) {
            return Err(malformed(0, 1, &format!("{} of the header", i + 1), name, "each column once"));
        }
    }
    if !header.iter().any(|h| h == "record") {
        // the header as written (issue 69: "(missing)" in the value slot)
        return Err(InputError::new(
            "manifest header",
            format!("`{}`", crate::error::clip(&header.join(","))),
            "a header with a `record` column (the others are optional: docs/campaign.md)",
        )
        .into());
    }
    let mut tasks = Vec::new();
    for (i, result) in reader.records().enumerate() {
        let row = i + 1;
        let record = result.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            // the row as written (issue 69: "(unreadable)" in the value slot)
            CliError::from(InputError::new(
                format!("manifest row {row} (line {line})"),
                written_line(text, line),
                format!("a CSV row ({e})"),
            ))
        })?;
        let line = record.position().map_or(0, |p| p.line());
        if record.len() != header.len() {
            let column = header.get(record.len()).map_or("(extra)", String::as_str);
            return Err(malformed(
                row,
                line,
                column,
                format!("{} cells", record.len()),
                &format!("{} cells, one per header column", header.len()),
            ));
        }
        let mut cells = Cells::default();
        for (name, value) in header.iter().zip(record.iter()) {
            cells.set(name, value.to_string());
        }
        if cells.record.is_empty() {
            return Err(malformed(row, line, "record", "''", "the path of a record file"));
        }
        tasks.push(task(row, &cells, base, defaults));
    }
    Ok(tasks)
}

fn resolve(base: &Path, cell: &str) -> PathBuf {
    let p = Path::new(cell);
    if p.is_absolute() {
        p.to_path_buf()
    } else {
        base.join(p)
    }
}

fn parse_number<T: std::str::FromStr>(
    row: usize,
    column: &str,
    cell: &str,
    allowed: &str,
) -> Result<Option<T>, String> {
    if cell.is_empty() {
        return Ok(None);
    }
    cell.parse::<T>()
        .map(Some)
        .map_err(|_| InputError::new(format!("manifest row {row}, column {column}"), cell, allowed).to_string())
}

fn task(row: usize, cells: &Cells, base: &Path, defaults: &Defaults) -> Task {
    let record_path = resolve(base, &cells.record);
    let parsed = options(row, cells, defaults);
    let (beam, beam_path) = match &parsed {
        Ok(o) if o.kind == Kind::Measured => (String::new(), None),
        _ if !cells.beam.is_empty() => (cells.beam.clone(), Some(resolve(base, &cells.beam))),
        _ => match &defaults.beam {
            Some(b) => (b.display().to_string(), Some(b.clone())),
            None => (String::new(), None),
        },
    };
    let options = match &parsed {
        Ok(o) => options_text(o),
        Err(_) => raw_options_text(cells),
    };
    Task { row, record: cells.record.clone(), record_path, beam, beam_path, options, parsed }
}

fn options(row: usize, c: &Cells, d: &Defaults) -> Result<RecordOptions, String> {
    let at = |column: &str, value: &str, allowed: &str| {
        InputError::new(format!("manifest row {row}, column {column}"), value, allowed).to_string()
    };
    let kind = match c.kind.as_str() {
        "" => kind_of(&c.record).ok_or_else(|| {
            at("kind", "(empty)", "lab or measured (the record's name ends in neither .csv, .csv.gz, .yaml nor .yml)")
        })?,
        "lab" => Kind::Lab,
        "measured" => Kind::Measured,
        other => return Err(at("kind", other, "lab or measured")),
    };
    let action = match c.action.as_str() {
        "" | "diagnose" => Action::Diagnose,
        "calibrate" => Action::Calibrate,
        other => return Err(at("action", other, "diagnose or calibrate")),
    };
    let support = match c.support.as_str() {
        "" => None,
        s => Some(Support::ALL.into_iter().find(|x| x.name() == s).ok_or_else(|| {
            let names: Vec<&str> = Support::ALL.iter().map(|x| x.name()).collect();
            at("support", s, &format!("one of {}", names.join(", ")))
        })?),
    };
    let first_mode = parse_number(row, "first_mode", &c.first_mode, "an integer >= 1")?;
    let modes = parse_number(row, "modes", &c.modes, "an integer >= 1")?;
    let max_order = parse_number(row, "max_order", &c.max_order, "an integer >= 4")?.unwrap_or(DEFAULT_MAX_ORDER);
    let (lo, hi) = (DiagnoseSettings::MIN_SAMPLES, DiagnoseSettings::MAX_SAMPLES);
    let samples_range = format!("an integer {lo}..={hi}");
    let cell_samples: Option<usize> = parse_number(row, "samples", &c.samples, &samples_range)?;
    if cell_samples.is_some_and(|n| !(lo..=hi).contains(&n)) {
        return Err(at("samples", &c.samples, &samples_range));
    }
    let causes_range = format!("an integer 1..={}", DiagnoseSettings::MAX_CAUSES);
    let cell_causes: Option<usize> = parse_number(row, "max_causes", &c.max_causes, &causes_range)?;
    if cell_causes.is_some_and(|k| !(1..=DiagnoseSettings::MAX_CAUSES).contains(&k)) {
        return Err(at("max_causes", &c.max_causes, &causes_range));
    }
    let samples = cell_samples.or(d.samples);
    let max_causes = cell_causes.or(d.max_causes);
    let seed = parse_number(row, "seed", &c.seed, "an integer 0..=18446744073709551615")?;
    if kind == Kind::Measured {
        for (column, cell) in [("first_mode", &c.first_mode), ("modes", &c.modes), ("max_order", &c.max_order)] {
            if !cell.is_empty() {
                return Err(at(
                    column,
                    cell,
                    "empty for a measured-data file (an option of identify, for lab records)",
                ));
            }
        }
    }
    if kind == Kind::Lab && c.beam.is_empty() && d.beam.is_none() {
        return Err(at("beam", "(empty)", "a beam file to number the modes of a lab record (or --beam)"));
    }
    if first_mode == Some(0) {
        return Err(at("first_mode", "0", "an integer >= 1"));
    }
    if modes == Some(0) {
        return Err(at("modes", "0", "an integer >= 1"));
    }
    if max_order < 4 {
        return Err(at("max_order", &max_order.to_string(), "an integer >= 4"));
    }
    Ok(RecordOptions {
        kind,
        action,
        support,
        first_mode,
        modes,
        max_order,
        samples,
        max_causes,
        thorough: d.thorough,
        seed,
    })
}

/// The effective options as `key=value;…` in a fixed order: the ones that
/// apply to the record's kind and action, unset ones left out.
pub fn options_text(o: &RecordOptions) -> String {
    let mut parts = vec![
        format!("kind={}", if o.kind == Kind::Lab { "lab" } else { "measured" }),
        format!("action={}", if o.action == Action::Diagnose { "diagnose" } else { "calibrate" }),
    ];
    if let Some(s) = o.support {
        parts.push(format!("support={}", s.name()));
    }
    if o.kind == Kind::Lab {
        if let Some(f) = o.first_mode {
            parts.push(format!("first_mode={f}"));
        }
        if let Some(m) = o.modes {
            parts.push(format!("modes={m}"));
        }
        parts.push(format!("max_order={}", o.max_order));
    }
    if o.action == Action::Diagnose {
        if let Some(s) = o.samples {
            parts.push(format!("samples={s}"));
        }
        if let Some(k) = o.max_causes {
            parts.push(format!("max_causes={k}"));
        }
        parts.push(format!("thorough={}", o.thorough));
    }
    if let Some(s) = o.seed {
        parts.push(format!("seed={s}"));
    }
    parts.join(";")
}

/// The options of a row whose cells did not parse: its non-empty cells as written.
fn raw_options_text(c: &Cells) -> String {
    let pairs = [
        ("kind", &c.kind),
        ("action", &c.action),
        ("support", &c.support),
        ("first_mode", &c.first_mode),
        ("modes", &c.modes),
        ("max_order", &c.max_order),
        ("samples", &c.samples),
        ("max_causes", &c.max_causes),
        ("seed", &c.seed),
    ];
    pairs.iter().filter(|(_, v)| !v.is_empty()).map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(";")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn defaults() -> Defaults {
        Defaults { beam: Some("beam.yaml".into()), samples: Some(60), max_causes: None, thorough: false }
    }

    #[test]
    fn cells_become_options_and_bad_cells_become_the_row_error() {
        let text = "record,first_mode,action\n# a comment\na.csv,2,\nb.yaml,,calibrate\nc.csv,x,\nd.txt,,\n";
        let tasks = plan_manifest(text, Path::new("m"), &defaults()).unwrap();
        assert_eq!(tasks.len(), 4);
        assert_eq!(tasks[0].options, "kind=lab;action=diagnose;first_mode=2;max_order=40;samples=60;thorough=false");
        assert_eq!(tasks[0].record_path, Path::new("m/a.csv"));
        assert_eq!(tasks[0].beam, "beam.yaml");
        assert_eq!(tasks[1].options, "kind=measured;action=calibrate");
        assert_eq!(tasks[1].beam, "");
        let e = tasks[2].parsed.clone().unwrap_err();
        assert!(e.contains("manifest row 3, column first_mode") && e.contains("= x"), "{e}");
        assert_eq!(tasks[2].options, "first_mode=x");
        assert!(tasks[3].parsed.clone().unwrap_err().contains("column kind"));
        let tasks =
            plan_manifest("record,samples,max_causes\na.yaml,3,\nb.yaml,,4\n", Path::new(""), &defaults()).unwrap();
        let e = tasks[0].parsed.clone().unwrap_err();
        assert_eq!(e, "invalid manifest row 1, column samples = 3: allowed an integer 50..=100000");
        assert!(tasks[1].parsed.clone().unwrap_err().contains("column max_causes = 4: allowed an integer 1..=3"));
    }

    /// A folder's records are its .csv, .csv.gz, .yaml and .yml files sorted by name, the
    /// `--beam` file and the table left out.
    #[test]
    fn a_folder_is_its_record_files_in_name_order() {
        let dir = tempfile::tempdir().unwrap();
        for name in ["b.yaml", "a.csv.gz", "beam.yaml", "notes.txt", "t.csv", "c.CSV"] {
            std::fs::write(dir.path().join(name), "").unwrap();
        }
        let d = Defaults { beam: Some(dir.path().join("beam.yaml")), ..Defaults::default() };
        let tasks = plan(dir.path(), &d, Some(&dir.path().join("t.csv"))).unwrap();
        let names: Vec<&str> = tasks.iter().map(|t| t.record.as_str()).collect();
        assert_eq!(names, ["a.csv.gz", "b.yaml", "c.CSV"]);
        assert_eq!(tasks.iter().map(|t| t.row).collect::<Vec<_>>(), [1, 2, 3]);
        assert_eq!(tasks[0].parsed.as_ref().unwrap().kind, Kind::Lab);
        assert_eq!(tasks[1].parsed.as_ref().unwrap().kind, Kind::Measured);
    }

    #[test]
    fn a_malformed_manifest_names_row_and_column() {
        let e = plan_manifest("record,colour\na.csv,red\n", Path::new(""), &defaults()).unwrap_err().to_string();
        assert!(e.contains("column 2 of the header") && e.contains("colour"), "{e}");
        let e = plan_manifest("record,seed\na.csv,1\nb.csv\n", Path::new(""), &defaults()).unwrap_err().to_string();
        assert!(e.contains("manifest row 2 (line 3), column seed"), "{e}");
        let e = plan_manifest("record,seed\n,1\n", Path::new(""), &defaults()).unwrap_err().to_string();
        assert!(e.contains("manifest row 1 (line 2), column record"), "{e}");
        let e = plan_manifest("beam\nb.yaml\n", Path::new(""), &defaults()).unwrap_err().to_string();
        // the header as written in the value slot (issue 69: "(missing)")
        assert!(e.starts_with("invalid manifest header = `beam`: allowed a header with a `record` column"), "{e}");
    }
}
