//! `nanobeam frf BEAM.yaml --input-x-nm X --output-x-nm Y --from-rad-s A --to-rad-s B --points N [--log] [--json]`.

use std::io::Write as _;
use std::path::PathBuf;

use clap::Args;
use serde::Serialize;

use crate::beam::{frf_each, max_frequency_rad_s, BeamError, BeamSpec, MAX_OMEGA_TILDE};
use crate::cli::{read_beam, CliError};
use crate::error::{fmt_num, InputError};

#[derive(Debug, Args)]
pub struct FrfArgs {
    /// Beam description (YAML).
    pub beam: PathBuf,
    /// Position of the point force along the beam, nm.
    #[arg(long)]
    pub input_x_nm: f64,
    /// Position of the measured displacement, nm.
    #[arg(long)]
    pub output_x_nm: f64,
    /// First frequency, rad/s (> 0).
    #[arg(long)]
    pub from_rad_s: f64,
    /// Last frequency, rad/s (> from).
    #[arg(long)]
    pub to_rad_s: f64,
    /// Number of frequencies (>= 2).
    #[arg(long, value_parser = |s: &str| crate::cli::clap_error::whole_number(s, &format!("in 2..={MAX_POINTS}")))]
    pub points: usize,
    /// Logarithmic spacing (default linear).
    #[arg(long)]
    pub log: bool,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Print CSV `omega_rad_s,h_re_m_per_n,h_im_m_per_n` (the record `nanobeam identify` reads).
    #[arg(long, conflicts_with = "json")]
    pub csv: bool,
}

#[derive(Serialize)]
struct JsonPoint {
    omega_rad_s: f64,
    re_m_per_n: f64,
    im_m_per_n: f64,
    magnitude_m_per_n: f64,
    phase_rad: f64,
}

/// Most points of one table. Each point is one banded complex LU (measured
/// 4.3 µs at 20 elements, 1e6 points in 4.3 s and 5 MB resident: the table
/// is streamed) and one ~80-byte line; the LU is linear in the elements, so
/// at the largest mesh (300) 1e6 points take about a minute and 80 MB of text.
pub const MAX_POINTS: usize = 1_000_000;

/// Checks the grid arguments (before anything is computed).
pub fn check_grid(args: &FrfArgs) -> Result<(), InputError> {
    if !(args.from_rad_s.is_finite() && args.from_rad_s > 0.0) {
        return Err(InputError::new("--from-rad-s", fmt_num(args.from_rad_s), "> 0 (finite)"));
    }
    if !(args.to_rad_s.is_finite() && args.to_rad_s > args.from_rad_s) {
        return Err(InputError::new(
            "--to-rad-s",
            fmt_num(args.to_rad_s),
            format!("> --from-rad-s = {} (finite)", fmt_num(args.from_rad_s)),
        ));
    }
    if !(2..=MAX_POINTS).contains(&args.points) {
        return Err(InputError::new("--points", args.points, format!("2..={MAX_POINTS}")));
    }
    Ok(())
}

/// Frequency `i` of the grid: linear or logarithmic from A to B inclusive.
fn grid_point(args: &FrfArgs, i: usize) -> f64 {
    let t = i as f64 / (args.points - 1) as f64;
    if args.log {
        (args.from_rad_s.ln() + t * (args.to_rad_s.ln() - args.from_rad_s.ln())).exp()
    } else {
        args.from_rad_s + t * (args.to_rad_s - args.from_rad_s)
    }
}

/// The frequency grid: linear or logarithmic from A to B inclusive.
pub fn grid(args: &FrfArgs) -> Result<Vec<f64>, InputError> {
    check_grid(args)?;
    Ok((0..args.points).map(|i| grid_point(args, i)).collect())
}

/// `--to-rad-s` within the band the FRF solver is tested on for this beam
/// ([`MAX_OMEGA_TILDE`] × its reference frequency); shared with the Python front.
pub fn check_top_frequency(beam: &BeamSpec, to_rad_s: f64) -> Result<(), CliError> {
    let max_w = max_frequency_rad_s(beam)?;
    if to_rad_s > max_w {
        return Err(InputError::new(
            "--to-rad-s",
            fmt_num(to_rad_s),
            format!("<= {max_w:e} ({MAX_OMEGA_TILDE:e} x omega_ref of this beam)"),
        )
        .into());
    }
    Ok(())
}

pub fn run(args: &FrfArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    let beam = read_beam(&args.beam)?;
    check_grid(args)?;
    check_top_frequency(&beam, args.to_rad_s)?;
    let mut w = std::io::BufWriter::with_capacity(1 << 16, out);
    let io = |e: std::io::Error| BeamError::Numerical(format!("cannot write output: {e}"));
    if args.csv {
        writeln!(w, "omega_rad_s,h_re_m_per_n,h_im_m_per_n").map_err(io)?;
    } else if args.json {
        w.write_all(b"{\"points\":[").map_err(io)?;
    } else {
        writeln!(
            w,
            "{:>14}  {:>14}  {:>14}  {:>14}  {:>10}",
            "omega [rad/s]", "Re [m/N]", "Im [m/N]", "|H| [m/N]", "phase [rad]"
        )
        .map_err(io)?;
    }
    let mut first = true;
    frf_each(&beam, args.input_x_nm, args.output_x_nm, (0..args.points).map(|i| grid_point(args, i)), |om, z| {
        if args.csv {
            writeln!(w, "{om:e},{:e},{:e}", z.re, z.im).map_err(io)?;
        } else if args.json {
            let p = JsonPoint {
                omega_rad_s: om,
                re_m_per_n: z.re,
                im_m_per_n: z.im,
                magnitude_m_per_n: z.norm(),
                phase_rad: z.arg(),
            };
            if !first {
                w.write_all(b",").map_err(io)?;
            }
            serde_json::to_writer(&mut w, &p).map_err(|e| io(e.into()))?;
        } else {
            writeln!(w, "{:>14.6e}  {:>14.6e}  {:>14.6e}  {:>14.6e}  {:>10.6}", om, z.re, z.im, z.norm(), z.arg())
                .map_err(io)?;
        }
        first = false;
        Ok(())
    })
    .map_err(|e| match e {
        BeamError::Numerical(m) if m.starts_with("cannot write output") => CliError::Failure(m),
        other => other.into(),
    })?;
    if args.json {
        w.write_all(b"]}\n").map_err(|e| CliError::Failure(format!("cannot write output: {e}")))?;
    }
    w.flush().map_err(|e| CliError::Failure(format!("cannot write output: {e}")))
}
