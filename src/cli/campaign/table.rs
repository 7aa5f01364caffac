//! The campaign's table: one [`Row`] per record, written as CSV (one header
//! line, then the rows in manifest order), atomically, and read back to
//! resume.
//!
//! Layout: one row per record and a fixed set of columns, so the header is
//! the same for every campaign (it is also how a table nanobeam wrote is
//! recognised) and a resumed table keeps its columns. The selected model's
//! whole posterior (its parameters differ from model to model) is one JSON
//! cell, `posterior`: `{"name": {"mean": …, "sd": …, "ci95": [lo, hi]}, …}`;
//! e0a, which every model has, also has its own three columns. The Python
//! front expands the JSON cell into `mean:NAME`, `ci95_lo:NAME`,
//! `ci95_hi:NAME` columns.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::cli::CliError;
use crate::error::InputError;
use crate::report::render::{check_out_file, StagedFile};
use crate::report::ReportError;

/// One record's result. Every cell is text (numbers formatted once, in
/// Rust, so the CLI's and Python's tables are the same bytes); empty where
/// it does not apply.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// 1-based position in the manifest.
    pub row: usize,
    /// The record's path as the manifest writes it.
    pub record: String,
    /// SHA-256 of the record file's bytes (as stored: a `.csv.gz` is hashed compressed).
    pub record_sha256: String,
    pub beam: String,
    pub beam_sha256: String,
    /// The effective options (`manifest::options_text`).
    pub options: String,
    /// `ok` or `error`.
    pub status: String,
    /// The identified (or measured) fitted mode numbers, space-separated.
    pub modes: String,
    /// The diagnosis's `cause`: `none`, a cause, `multiple` or `unexplained`.
    pub verdict: String,
    pub explained: String,
    /// The selected model's causes, `+`-joined.
    pub causes: String,
    pub decided_causes: String,
    /// `model (ln B gap g)`, `; `-joined; `, misfits` when it fails the misfit test.
    pub alternatives: String,
    /// The next (or falsifying) measurement, as the diagnosis summary words it.
    pub next_measurement: String,
    /// The model whose posterior is reported (the diagnosis's gain model; `calibrate` for a calibration).
    pub model: String,
    pub log_evidence: String,
    /// ln B of `model` against the base model.
    pub log_bayes_factor: String,
    pub e0a_mean_nm: String,
    pub e0a_ci95_lo_nm: String,
    pub e0a_ci95_hi_nm: String,
    /// JSON: the posterior summary of every parameter of `model`.
    pub posterior: String,
    pub forward_solves: String,
    /// Wall time of the record in seconds: the one column that differs between runs.
    pub wall_s: String,
    /// `identify`'s warnings (a thermal record's fit against its Welch segments).
    pub warnings: String,
    /// The one-line error of a failed record.
    pub error: String,
}

/// The header line of every campaign table, [`Row`]'s fields in order.
pub fn header() -> String {
    let mut w = csv::Writer::from_writer(vec![]);
    w.serialize(Row::default()).expect("plain data");
    let bytes = w.into_inner().expect("in memory");
    let text = String::from_utf8(bytes).expect("utf-8");
    text.lines().next().unwrap_or_default().to_string()
}

/// The table's CSV text: the header and `rows` sorted by manifest row.
pub fn to_csv(rows: &[Row]) -> String {
    let mut sorted: Vec<&Row> = rows.iter().collect();
    sorted.sort_by_key(|r| r.row);
    let mut w = csv::Writer::from_writer(vec![]);
    if sorted.is_empty() {
        return header() + "\n";
    }
    for r in sorted {
        w.serialize(r).expect("plain data");
    }
    String::from_utf8(w.into_inner().expect("in memory")).expect("utf-8")
}

fn out_error(path: &Path, reason: impl std::fmt::Display) -> CliError {
    InputError::new("--out", path.display(), format!("a new file or a campaign table nanobeam wrote; {reason}")).into()
}

/// The rows of the table at `path`: none when it does not exist or is
/// empty. A file that is not a campaign table (another header, a row that
/// does not parse) is refused (exit 2), so it is never overwritten.
pub fn read(path: &Path) -> Result<Vec<Row>, CliError> {
    check_out_file(path).map_err(|e| match e {
        ReportError::OutPath { reason, .. } => out_error(path, reason),
        other => CliError::Failure(format!("cannot use --out {}: {other}", path.display())),
    })?;
    let text = match std::fs::read(path) {
        Ok(bytes) => String::from_utf8(bytes).map_err(|_| out_error(path, "it is not UTF-8 text"))?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(vec![]),
        Err(e) => return Err(out_error(path, format!("it cannot be read ({e})"))),
    };
    if text.is_empty() {
        return Ok(vec![]);
    }
    if text.lines().next() != Some(header().as_str()) {
        return Err(out_error(path, "its first line is not a campaign table's header"));
    }
    let mut reader = csv::Reader::from_reader(text.as_bytes());
    reader
        .deserialize::<Row>()
        .enumerate()
        .map(|(i, r)| r.map_err(|e| out_error(path, format!("its row {} does not parse ({e})", i + 1))))
        .collect()
}

/// Writes the table at `path` in one atomic step (a temporary sibling
/// renamed over it).
pub fn write(path: &Path, rows: &[Row]) -> Result<(), CliError> {
    let text = to_csv(rows);
    let fail = |e: ReportError| CliError::Failure(format!("cannot write --out {}: {e}", path.display()));
    StagedFile::new(path, text.as_bytes()).map_err(fail)?.commit().map_err(fail)
}

/// Whether `row` is the result of `task`'s current inputs: same record
/// bytes, beam bytes and options, and not a failure (a failed record is
/// always run again: its cause may have been fixed).
pub fn is_current(row: &Row, record: &str, record_sha256: &str, beam_sha256: &str, options: &str) -> bool {
    row.status == "ok"
        && row.record == record
        && row.record_sha256 == record_sha256
        && row.beam_sha256 == beam_sha256
        && row.options == options
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_reads_back_and_a_foreign_file_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.csv");
        assert!(read(&path).unwrap().is_empty());
        let rows = vec![
            Row { row: 2, record: "b, with a comma.csv".into(), status: "ok".into(), ..Row::default() },
            Row { row: 1, record: "a.yaml".into(), status: "error".into(), error: "x \"y\"".into(), ..Row::default() },
        ];
        write(&path, &rows).unwrap();
        let back = read(&path).unwrap();
        assert_eq!(back, vec![rows[1].clone(), rows[0].clone()]);
        std::fs::write(&path, "a,b\n1,2\n").unwrap();
        let e = read(&path).unwrap_err().to_string();
        assert!(e.starts_with("invalid --out = ") && e.contains("header"), "{e}");
        assert_eq!(e.lines().count(), 1);
    }
}
