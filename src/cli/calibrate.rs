//! `nanobeam calibrate MEASURED.yaml [--out DIR] [--json]`.

use std::path::PathBuf;

use clap::Args;

use crate::calibration::output::{summary_cells, write_calibration_files, SUMMARY_HEADERS};
use crate::calibration::{calibrate, CalibrateOptions};
use crate::cli::{read_measured, write_out, CliError};
use crate::report::render::write_dir_atomically;
use crate::report::table::Table;

#[derive(Debug, Args)]
pub struct CalibrateArgs {
    /// Measured-data file (YAML): beam, modes, optional parameters and sampler.
    pub measured: PathBuf,
    /// Directory for chains.csv, summary.json and SVG plots (written atomically).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &CalibrateArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    let data = read_measured(&args.measured)?;
    let result = calibrate(&data, &CalibrateOptions { progress: true });
    if let Some(dir) = &args.out {
        let posterior = crate::calibration::BeamPosterior::new(&data, data.parameters.clone());
        let ctx = crate::calibration::output::InferenceContext { posterior: &posterior, seed: data.sampler.seed };
        write_dir_atomically(dir, |tmp| write_calibration_files(tmp, &result, None, Some(&ctx)))
            .map_err(|e| CliError::Failure(format!("cannot write {}: {e}", dir.display())))?;
    }
    if args.json {
        let json = serde_json::to_string(&result.json()).expect("summary serialises");
        return write_out(out, &(json + "\n"));
    }
    let mut t = Table::new(std::iter::once("parameter").chain(SUMMARY_HEADERS));
    for p in &result.summary.parameters {
        t.push_row(std::iter::once(p.name.clone()).chain(summary_cells(p)));
    }
    let acc: Vec<String> = result.acceptance.iter().map(|a| format!("{a:.3}")).collect();
    let text = format!(
        "{}\nacceptance per DR stage: [{}]; rejected invalid proposals: {}; log posterior at MAP: {:.4}\n",
        t.to_markdown(),
        acc.join(", "),
        result.rejected_invalid,
        result.log_posterior_map
    );
    write_out(out, &text)
}
