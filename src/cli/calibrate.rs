//! `nanobeam calibrate MEASURED.yaml [--out DIR] [--json]`.

use std::path::Path;

use crate::calibration::output::write_calibration_files;
use crate::calibration::{calibrate, CalibrateOptions, MeasuredData};
use crate::cli::CliError;
use crate::report::render::write_dir_atomically;
use crate::report::table::{fmt_interval, fmt_sig, Table};

pub fn run(path: &Path, out: Option<&Path>, json: bool) -> Result<(), CliError> {
    let text = std::fs::read_to_string(path).map_err(|e| CliError::read(path, e))?;
    let data = MeasuredData::from_yaml(&text)?;
    let result = calibrate(&data, &CalibrateOptions { progress: true });
    if let Some(dir) = out {
        write_dir_atomically(dir, |tmp| write_calibration_files(tmp, &result, None))
            .map_err(|e| CliError::Output(e.to_string()))?;
    }
    if json {
        println!("{}", serde_json::to_string(&result.json()).expect("serialisable"));
    } else {
        let mut t = Table::new(["parameter", "mean", "sd", "sd/mean", "CI95", "MAP", "R-hat", "ESS bulk", "ESS tail"]);
        for p in &result.summary.parameters {
            t.push_row([
                p.name.clone(),
                fmt_sig(p.mean, 4),
                fmt_sig(p.sd, 3),
                fmt_sig(p.cv, 3),
                fmt_interval(p.ci95[0], p.ci95[1], 4),
                p.map.map_or("-".into(), |m| fmt_sig(m, 4)),
                format!("{:.4}", p.rhat),
                format!("{:.0}", p.ess_bulk),
                format!("{:.0}", p.ess_tail),
            ]);
        }
        print!("{}", t.to_markdown());
        let acc: Vec<String> = result.acceptance.iter().map(|a| format!("{:.3}", a)).collect();
        println!(
            "\nacceptance per DR stage: [{}]; rejected invalid proposals: {}; log posterior at MAP: {:.4}",
            acc.join(", "),
            result.rejected_invalid,
            result.log_posterior_map
        );
    }
    Ok(())
}
