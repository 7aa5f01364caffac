//! `nanobeam modal BEAM.yaml [--modes K] [--json]`.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use serde::Serialize;

use crate::beam::{modal, ModalResult};
use crate::cli::{read_beam, write_out, CliError};

#[derive(Debug, Args)]
pub struct ModalArgs {
    /// Beam description (YAML).
    pub beam: PathBuf,
    /// Number of modes to report.
    #[arg(long, default_value_t = 3, value_parser = |s: &str| crate::cli::clap_error::whole_number(s, "in 1..=the free DOFs of the beam's mesh"))]
    pub modes: usize,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct JsonMode {
    mode: usize,
    omega_rad_s: f64,
    zeta: f64,
    pole_re_rad_s: f64,
    pole_im_rad_s: f64,
}

#[derive(Serialize)]
struct JsonOverdamped {
    mode: usize,
    poles_rad_s: Vec<f64>,
}

#[derive(Serialize)]
struct JsonModal {
    modes: Vec<JsonMode>,
    /// Physical modes without an oscillatory pair (absent when there are none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    overdamped_modes: Vec<JsonOverdamped>,
}

pub fn run(args: &ModalArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    let beam = read_beam(&args.beam)?;
    let dofs = beam.free_dofs();
    if args.modes == 0 || args.modes > dofs {
        return Err(crate::error::InputError::new(
            "--modes",
            args.modes,
            format!("1..={dofs} (physical modes of this mesh: its free DOFs)"),
        )
        .into());
    }
    let result = modal(&beam, args.modes)?;
    let text = if args.json { json(&result) } else { table(&result) };
    write_out(out, &text)
}

/// Exactly `{"modes":[{"mode":…,"omega_rad_s":…,"zeta":…,"pole_re_rad_s":…,"pole_im_rad_s":…}]}`, plus
/// `"overdamped_modes":[{"mode":…,"poles_rad_s":[…]}]` when a physical mode is overdamped (mode
/// numbers are physical: an overdamped mode leaves a gap in `modes`).
pub fn json(result: &ModalResult) -> String {
    let doc = JsonModal {
        modes: result
            .modes
            .iter()
            .map(|m| JsonMode {
                mode: m.mode,
                omega_rad_s: m.omega_rad_s,
                zeta: m.zeta,
                pole_re_rad_s: m.pole.re,
                pole_im_rad_s: m.pole.im,
            })
            .collect(),
        overdamped_modes: result
            .overdamped
            .iter()
            .map(|o| JsonOverdamped { mode: o.mode, poles_rad_s: o.poles_rad_s.clone() })
            .collect(),
    };
    let mut s = serde_json::to_string(&doc).expect("plain numbers serialise");
    s.push('\n');
    s
}

pub fn table(result: &ModalResult) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{:>4}  {:>14}  {:>12}  {:>12}", "mode", "omega [rad/s]", "f [GHz]", "zeta");
    let last = result.modes.iter().map(|m| m.mode).chain(result.overdamped.iter().map(|o| o.mode)).max().unwrap_or(0);
    for number in 1..=last {
        if let Some(m) = result.mode(number) {
            let f_ghz = m.omega_rad_s / (2.0 * std::f64::consts::PI) / 1e9;
            let _ = writeln!(s, "{:>4}  {:>14.6e}  {:>12.6}  {:>12.6e}", m.mode, m.omega_rad_s, f_ghz, m.zeta);
        } else if let Some(o) = result.overdamped.iter().find(|o| o.mode == number) {
            let poles: Vec<String> = o.poles_rad_s.iter().map(|p| format!("{p:.6e}")).collect();
            let _ = writeln!(s, "{:>4}  overdamped: real poles [rad/s] {}", o.mode, poles.join(", "));
        }
    }
    if result.real_poles_rad_s.is_empty() {
        let _ = writeln!(s, "real poles: none");
    } else {
        let _ = writeln!(s, "real poles [rad/s] (relaxation / overdamped, of the modal families above):");
        for p in &result.real_poles_rad_s {
            let _ = writeln!(s, "  {p:.6e}");
        }
    }
    s
}
