//! `nanobeam campaign MANIFEST.csv|FOLDER [--beam BEAM.yaml] [--out TABLE.csv]
//! [--samples N] [--max-causes K] [--thorough]`: many records to one table
//! (docs/campaign.md).
//!
//! Each record goes through what `nanobeam identify` (lab and MD records)
//! and `nanobeam diagnose` (or `calibrate`) do ([`record::run`]); its result
//! is one row of the table ([`table::Row`]), a failure a row with its error.
//! The records run in parallel on rayon's pool (each diagnosis is itself
//! parallel over its models); the table is rewritten atomically, in
//! manifest order, after every record, so an interrupted campaign leaves a
//! table of the records it finished, and a rerun with the same `--out`
//! skips every record whose bytes, beam and options match an `ok` row.
//! Nothing in a row depends on the order records finish in or the number of
//! threads, except `wall_s`.

pub mod manifest;
pub mod record;
pub mod table;

use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::Mutex;

use clap::Args;
use rayon::prelude::*;

use crate::bayes::Control;
use crate::cli::{write_out, CliError};

pub use manifest::{Defaults, Task};
pub use table::Row;

#[derive(Debug, Args)]
pub struct CampaignArgs {
    /// A manifest CSV (header: record, and any of beam, support, kind, action, first_mode, modes,
    /// max_order, samples, max_causes, seed; paths relative to its folder), or a folder whose
    /// .csv, .csv.gz, .yaml and .yml files are the records.
    pub manifest: PathBuf,
    /// The beam file of every lab record whose row names none (and of a folder's records).
    #[arg(long)]
    pub beam: Option<PathBuf>,
    /// The table (CSV), rewritten atomically after every record; an existing table is resumed.
    /// Without it the table goes to stdout at the end.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// TMCMC samples per stage per model of every diagnosis (diagnose's --samples).
    #[arg(long, value_parser = |s: &str| crate::cli::clap_error::whole_number(s, &format!("in {}..={}", crate::diagnose::DiagnoseSettings::MIN_SAMPLES, crate::diagnose::DiagnoseSettings::MAX_SAMPLES)))]
    pub samples: Option<usize>,
    /// The most causes of a model (diagnose's --max-causes).
    #[arg(long, value_parser = |s: &str| crate::cli::clap_error::whole_number(s, &format!("in 1..={}", crate::diagnose::DiagnoseSettings::MAX_CAUSES)))]
    pub max_causes: Option<usize>,
    /// diagnose's --thorough for every record.
    #[arg(long)]
    pub thorough: bool,
}

/// The tasks to run and the rows kept from an earlier table: the rows of
/// `existing` that are current for a task of `tasks` (same record bytes,
/// beam bytes and options, status `ok`) are kept, every other task is run.
/// Rows of `existing` for no task of the manifest are dropped.
pub fn resume(tasks: Vec<Task>, existing: &[Row]) -> (Vec<Task>, Vec<Row>) {
    let mut todo = Vec::new();
    let mut kept = Vec::new();
    for t in tasks {
        let record_sha = record::file_sha256(&t.record_path);
        let beam_sha = t.beam_path.as_deref().map(record::file_sha256).unwrap_or_default();
        match existing.iter().find(|r| table::is_current(r, &t.record, &record_sha, &beam_sha, &t.options)) {
            Some(r) => kept.push(Row { row: t.row, ..r.clone() }),
            None => todo.push(t),
        }
    }
    (todo, kept)
}

/// The records-done bar (`pos/len records, the record last started`), drawn only when stderr is a terminal.
fn bar(total: u64) -> Option<indicatif::ProgressBar> {
    if !std::io::stderr().is_terminal() {
        return None;
    }
    let pb = indicatif::ProgressBar::new(total);
    pb.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} records ({eta}) {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    Some(pb)
}

pub fn run(args: &CampaignArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    let existing = match &args.out {
        Some(path) => table::read(path)?,
        None => vec![],
    };
    let defaults = Defaults {
        beam: args.beam.clone(),
        samples: args.samples,
        max_causes: args.max_causes,
        thorough: args.thorough,
    };
    let tasks = manifest::plan(&args.manifest, &defaults, args.out.as_deref())?;
    let total = tasks.len();
    let (todo, kept) = resume(tasks, &existing);
    let dropped = existing.iter().filter(|r| r.status == "ok").count().saturating_sub(kept.len());
    if !kept.is_empty() || dropped > 0 {
        eprintln!(
            "campaign: {} of {total} records already in the table, {} to run{}",
            kept.len(),
            todo.len(),
            if dropped > 0 {
                format!(" ({dropped} ok row(s) of the old table replaced or dropped)")
            } else {
                String::new()
            }
        );
    }
    let started = std::time::Instant::now();
    let rows: Mutex<BTreeMap<usize, Row>> = Mutex::new(kept.into_iter().map(|r| (r.row, r)).collect());
    let write_error: Mutex<Option<CliError>> = Mutex::new(None);
    let pb = bar(total as u64);
    if let Some(pb) = &pb {
        pb.set_position((total - todo.len()) as u64);
    }
    if let Some(path) = &args.out {
        table::write(path, &rows.lock().expect("no panic holds the lock").values().cloned().collect::<Vec<_>>())?;
    }
    todo.par_iter().for_each(|task| {
        if let Some(pb) = &pb {
            pb.set_message(task.record.clone());
        }
        let row = record::run(task, &Control::default());
        let mut all = rows.lock().expect("no panic holds the lock");
        all.insert(row.row, row);
        if let Some(path) = &args.out {
            if let Err(e) = table::write(path, &all.values().cloned().collect::<Vec<_>>()) {
                write_error.lock().expect("no panic holds the lock").get_or_insert(e);
            }
        }
        drop(all);
        if let Some(pb) = &pb {
            pb.inc(1);
        }
    });
    if let Some(pb) = pb {
        pb.finish_and_clear();
    }
    if let Some(e) = write_error.into_inner().expect("no panic holds the lock") {
        return Err(e);
    }
    let rows: Vec<Row> = rows.into_inner().expect("no panic holds the lock").into_values().collect();
    let failed = rows.iter().filter(|r| r.status != "ok").count();
    eprintln!(
        "campaign: {total} records, {} ok, {failed} failed, {} run in {:.1} s",
        total - failed,
        todo.len(),
        started.elapsed().as_secs_f64()
    );
    for r in rows.iter().filter(|r| r.status != "ok") {
        eprintln!("  row {} {}: {}", r.row, r.record, r.error);
    }
    match &args.out {
        Some(path) => write_out(out, &format!("{}: {} rows\n", path.display(), rows.len())),
        None => write_out(out, &table::to_csv(&rows)),
    }
}
