//! Table 2 (local elastic frequencies) and Figures 1–3 (ω_r/ω'_r and ζ_r over
//! e0a × Ω), §4.1.

use rayon::prelude::*;

use crate::beam::{self, InternalVariable};
use crate::report::svg::{self, Axis, Heatmap};
use crate::report::table::{fmt_sig, Table};
use crate::reproduce::error::ReproduceError;
use crate::reproduce::reconstruction::{ghz_to_rad_s, Reconstruction};
use crate::reproduce::results::{r6, Table2Row};
use crate::reproduce::specs::Specs;

/// A map over the grid, indexed `[e0a][Ω]`.
pub type Grid = Vec<Vec<f64>>;

/// Table 2, the map grids and their files.
pub struct ForwardOutcome {
    pub table2_rows: Vec<Table2Row>,
    pub table2_md: String,
    /// `maps[r]` = (ratio grid `[e0a][Ω]`, zeta grid) for mode r+1.
    pub maps: Vec<(Grid, Grid)>,
    pub e0a: Vec<f64>,
    pub omega: Vec<f64>,
    pub local_omega: Vec<f64>,
    pub delta: f64,
    pub files: Vec<(String, String)>,
}

/// Computes Table 2 and the maps of Figures 1–3 (quick: the coarse grid).
pub fn forward_stage(specs: &Specs, rec: &Reconstruction, quick: bool) -> Result<ForwardOutcome, ReproduceError> {
    let fs = &specs.forward;
    let local = rec.table_1.clone();
    let m = beam::modal(&local, fs.modes).map_err(|e| ReproduceError::Failure(format!("Table 2: {e}")))?;
    let local_omega: Vec<f64> = m.modes.iter().map(|x| x.omega_rad_s).collect();
    let mut t2 = Table::new(["mode", "omega_rad_s", "f_ghz"]);
    let mut rows = Vec::new();
    for (i, w) in local_omega.iter().enumerate() {
        t2.push_row([format!("{}", i + 1), fmt_sig(*w, 6), fmt_sig(w / ghz_to_rad_s(1.0), 6)]);
        rows.push(Table2Row { mode: i + 1, omega_rad_s: r6(*w), f_ghz: r6(w / ghz_to_rad_s(1.0)) });
    }
    let delta = fs.delta.unwrap_or_else(|| rec.truth_table_4.internal_variables[0].delta);
    let e0a = fs.e0a_nm.values(quick);
    let omega = fs.omega_rad_s.values(quick);
    let grid: Vec<Vec<Vec<(f64, f64)>>> = e0a
        .par_iter()
        .map(|&e| {
            omega
                .iter()
                .map(|&w| {
                    let mut b = local.clone();
                    b.nonlocal_e0a_nm = e;
                    b.internal_variables = vec![InternalVariable { delta, omega_rad_s: w }];
                    match beam::modal(&b, fs.modes) {
                        Ok(r) => r.modes.iter().map(|x| (x.omega_rad_s, x.zeta)).collect(),
                        Err(_) => vec![(f64::NAN, f64::NAN); fs.modes],
                    }
                })
                .collect()
        })
        .collect();
    let mut maps = Vec::new();
    let mut files = vec![("table-2.csv".to_string(), t2.to_csv()), ("table-2.md".to_string(), t2.to_markdown())];
    for r in 0..fs.modes {
        let ratio: Vec<Vec<f64>> =
            grid.iter().map(|row| row.iter().map(|v| v[r].0 / local_omega[r]).collect()).collect();
        let zeta: Vec<Vec<f64>> = grid.iter().map(|row| row.iter().map(|v| v[r].1).collect()).collect();
        let mut csv = String::from("e0a_nm,omega_rad_s,omega_ratio,zeta\n");
        for (i, e) in e0a.iter().enumerate() {
            for (j, w) in omega.iter().enumerate() {
                csv += &format!("{e},{w:e},{:.9},{:.9}\n", ratio[i][j], zeta[i][j]);
            }
        }
        files.push((format!("figure-{}.csv", r + 1), csv));
        // Heatmap z is indexed [y][x]: y = e0a, x = Ω.
        for (suffix, z, label) in
            [("a", &ratio, format!("ω{}/ω'{}", r + 1, r + 1)), ("b", &zeta, format!("ζ{}", r + 1))]
        {
            let hm = Heatmap {
                title: format!("Figure {}{}: mode {} (Δ = {:.3})", r + 1, suffix, r + 1, delta),
                x_axis: Axis::log("Ω (rad/s)"),
                y_axis: Axis::linear("e0a (nm)"),
                x: omega.clone(),
                y: e0a.clone(),
                z: z.clone(),
                z_label: label,
                ..Heatmap::default()
            };
            files.push((format!("figure-{}{}.svg", r + 1, suffix), svg::heatmap(&hm)?));
        }
        maps.push((ratio, zeta));
    }
    Ok(ForwardOutcome { table2_rows: rows, table2_md: t2.to_markdown(), maps, e0a, omega, local_omega, delta, files })
}
