//! `nanobeam frf BEAM.yaml --input-x-nm X --output-x-nm Y --from-rad-s A --to-rad-s B --points N [--log] [--json]`.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use serde::Serialize;

use crate::beam::frf;
use crate::cli::{read_beam, write_out, CliError};
use crate::error::{positive, InputError};

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
    #[arg(long)]
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

#[derive(Serialize)]
struct JsonFrf {
    points: Vec<JsonPoint>,
}

/// The frequency grid: linear or logarithmic from A to B inclusive.
pub fn grid(args: &FrfArgs) -> Result<Vec<f64>, InputError> {
    positive("from_rad_s", args.from_rad_s)?;
    positive("to_rad_s", args.to_rad_s)?;
    if args.to_rad_s <= args.from_rad_s {
        return Err(InputError::new("to_rad_s", args.to_rad_s, format!("> from_rad_s = {}", args.from_rad_s)));
    }
    if args.points < 2 {
        return Err(InputError::new("points", args.points, ">= 2"));
    }
    let n = args.points;
    Ok((0..n)
        .map(|i| {
            let t = i as f64 / (n - 1) as f64;
            if args.log {
                (args.from_rad_s.ln() + t * (args.to_rad_s.ln() - args.from_rad_s.ln())).exp()
            } else {
                args.from_rad_s + t * (args.to_rad_s - args.from_rad_s)
            }
        })
        .collect())
}

pub fn run(args: &FrfArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    let beam = read_beam(&args.beam)?;
    let omegas = grid(args)?;
    let h = frf(&beam, args.input_x_nm, args.output_x_nm, &omegas)?;
    let text = if args.csv {
        let mut s = String::from("omega_rad_s,h_re_m_per_n,h_im_m_per_n\n");
        for (&w, z) in omegas.iter().zip(&h) {
            let _ = writeln!(s, "{w:e},{:e},{:e}", z.re, z.im);
        }
        s
    } else if args.json {
        let doc = JsonFrf {
            points: omegas
                .iter()
                .zip(&h)
                .map(|(&w, z)| JsonPoint {
                    omega_rad_s: w,
                    re_m_per_n: z.re,
                    im_m_per_n: z.im,
                    magnitude_m_per_n: z.norm(),
                    phase_rad: z.arg(),
                })
                .collect(),
        };
        let mut s = serde_json::to_string(&doc).expect("plain numbers serialise");
        s.push('\n');
        s
    } else {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{:>14}  {:>14}  {:>14}  {:>14}  {:>10}",
            "omega [rad/s]", "Re [m/N]", "Im [m/N]", "|H| [m/N]", "phase [rad]"
        );
        for (&w, z) in omegas.iter().zip(&h) {
            let _ =
                writeln!(s, "{:>14.6e}  {:>14.6e}  {:>14.6e}  {:>14.6e}  {:>10.6}", w, z.re, z.im, z.norm(), z.arg());
        }
        s
    };
    write_out(out, &text)
}
