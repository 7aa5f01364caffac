//! `nanobeam campaign`: one row per record, a failed record a row, a
//! malformed manifest exit 2, resume, and the same table at 1 and 2 threads.
//!
//! The records (small and fast: three modes, 8 elements, `--samples 50
//! --max-causes 1`, about 2 s each in the dev profile, 3x less than with 20
//! elements):
//! - `m3.yaml`: a hand-written measured-data file, the three modes of
//!   `tests/diagnose_cli.rs` (`M1`–`M3`) on an 8-element mesh, diagnosed as it stands;
//! - `sweep.csv`: a lab record made here by `nanobeam frf --csv` of the
//!   viscoelastic beam of `python/tests/test_cli_parity.py` (`VISCO`, 8 elements), with
//!   2 % of |H| of uniform noise on each part from a fixed 64-bit LCG (so
//!   `identify` finds sds a diagnosis can use), identified (`modes = 3`)
//!   against that beam, then diagnosed;
//! - `missing.yaml`: no such file (an error row);
//! - a row whose `samples` cell is not a number (an error row).

use std::path::Path;
use std::process::{Command, Output};

const BEAM: &str = "length_nm: 8.0\ndiameter_nm: 1.0\nyoungs_modulus_pa: 1.0e12\ndensity_kg_m3: 2300.0\n\
support: simply-supported\nelements: 8\nnonlocal_e0a_nm: 1.05\n\
internal_variables:\n  - { delta: 0.45, omega_rad_s: 3.0e11 }\n";

const M3: &str = "beam: { length_nm: 8.0, diameter_nm: 1.0, youngs_modulus_pa: 1.0e12, density_kg_m3: 2300.0, \
support: simply-supported, elements: 8 }\nmodes:\n\
  - { mode: 1, omega_rad_s: 8.3e11, omega_sd_rad_s: 2.5e9, zeta: 0.07, zeta_sd: 0.002 }\n\
  - { mode: 2, omega_rad_s: 2.9e12, omega_sd_rad_s: 9e9, zeta: 0.05, zeta_sd: 0.0015 }\n\
  - { mode: 3, omega_rad_s: 5.3e12, omega_sd_rad_s: 1.6e10, zeta: 0.03, zeta_sd: 0.001 }\n";

const MANIFEST: &str = "record,beam,modes,samples\n\
m3.yaml,,,\n\
sweep.csv,beam.yaml,3,\n\
missing.yaml,,,\n\
m3.yaml,,,abc\n";

fn nanobeam(args: &[&str], threads: Option<&str>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_nanobeam"));
    cmd.args(args);
    if let Some(t) = threads {
        cmd.env("RAYON_NUM_THREADS", t);
    }
    cmd.output().expect("binary runs")
}

/// The records and the manifest in a fresh folder.
fn campaign_folder() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("beam.yaml"), BEAM).unwrap();
    std::fs::write(d.join("m3.yaml"), M3).unwrap();
    let beam = d.join("beam.yaml");
    let sweep = nanobeam(
        &[
            "frf",
            beam.to_str().unwrap(),
            "--input-x-nm=2",
            "--output-x-nm=5.5",
            "--from-rad-s=2e11",
            "--to-rad-s=6e12",
            "--points=1200",
            "--log",
            "--csv",
        ],
        None,
    );
    assert!(sweep.status.success(), "{}", String::from_utf8_lossy(&sweep.stderr));
    std::fs::write(d.join("sweep.csv"), noisy(&String::from_utf8(sweep.stdout).unwrap())).unwrap();
    std::fs::write(d.join("manifest.csv"), MANIFEST).unwrap();
    dir
}

/// 2 % of |H| of uniform noise on each part of every sample (a 64-bit LCG, seed 12345).
fn noisy(csv: &str) -> String {
    let mut state: u64 = 12345;
    let mut u = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut lines = csv.lines();
    let mut out = format!("{}\n", lines.next().unwrap());
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let a = v[1].hypot(v[2]);
        out += &format!("{:e},{:e},{:e}\n", v[0], v[1] + 0.02 * a * u(), v[2] + 0.02 * a * u());
    }
    out
}

fn run_campaign(dir: &Path, out: &str, threads: Option<&str>) -> Output {
    let manifest = dir.join("manifest.csv");
    let out = dir.join(out);
    nanobeam(
        &[
            "campaign",
            manifest.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--samples",
            "50",
            "--max-causes",
            "1",
        ],
        threads,
    )
}

/// The table's rows as cells, `wall_s` (the one timing column) blanked.
fn cells_without_timing(path: &Path) -> Vec<Vec<String>> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let wall = r.headers().unwrap().iter().position(|h| h == "wall_s").unwrap();
    r.records()
        .map(|rec| {
            let mut v: Vec<String> = rec.unwrap().iter().map(str::to_string).collect();
            v[wall].clear();
            v
        })
        .collect()
}

fn column(path: &Path, name: &str) -> Vec<String> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let i = r.headers().unwrap().iter().position(|h| h == name).unwrap();
    r.records().map(|rec| rec.unwrap()[i].to_string()).collect()
}

/// Four rows in manifest order, two ok and two errors (exit 0), and the
/// same table, every column but `wall_s`, at 1 and 2 threads.
#[test]
fn one_row_per_record_failed_records_are_rows_and_threads_do_not_change_the_table() {
    let dir = campaign_folder();
    let one = run_campaign(dir.path(), "one.csv", Some("1"));
    assert!(one.status.success(), "{}", String::from_utf8_lossy(&one.stderr));
    let t1 = dir.path().join("one.csv");
    assert_eq!(column(&t1, "row"), ["1", "2", "3", "4"]);
    assert_eq!(column(&t1, "status"), ["ok", "ok", "error", "error"]);
    let errors = column(&t1, "error");
    assert!(errors[2].contains("missing.yaml") && errors[2].contains("a readable file"), "{}", errors[2]);
    assert!(errors[3].contains("manifest row 4, column samples = abc"), "{}", errors[3]);
    assert_eq!(column(&t1, "modes")[1], "1 2 3");
    for (i, v) in column(&t1, "verdict").iter().take(2).enumerate() {
        assert!(!v.is_empty(), "row {} has no verdict", i + 1);
    }
    let e0a = column(&t1, "e0a_mean_nm");
    assert!(e0a[1].parse::<f64>().is_ok(), "{e0a:?}");
    let two = run_campaign(dir.path(), "two.csv", Some("2"));
    assert!(two.status.success(), "{}", String::from_utf8_lossy(&two.stderr));
    assert_eq!(cells_without_timing(&t1), cells_without_timing(&dir.path().join("two.csv")));
}

/// A rerun with the same `--out` skips the `ok` rows whose record, beam and
/// options are unchanged and runs the failed ones again.
#[test]
fn a_rerun_skips_the_records_already_in_the_table() {
    let dir = campaign_folder();
    let first = run_campaign(dir.path(), "t.csv", None);
    assert!(first.status.success(), "{}", String::from_utf8_lossy(&first.stderr));
    let t = dir.path().join("t.csv");
    let before = std::fs::read_to_string(&t).unwrap();
    let started = std::time::Instant::now();
    let again = run_campaign(dir.path(), "t.csv", None);
    let elapsed = started.elapsed().as_secs_f64();
    let stderr = String::from_utf8_lossy(&again.stderr);
    assert!(again.status.success(), "{stderr}");
    assert!(stderr.contains("2 of 4 records already in the table, 2 to run"), "{stderr}");
    assert!(elapsed < 2.0, "the rerun took {elapsed:.1} s");
    // the kept `ok` rows are byte for byte those of the first run (their
    // wall_s included); the failed rows ran again, so only their timing may
    // differ (a missing file's row measured 0.000 s once and 0.001 s the
    // next time)
    let after = std::fs::read_to_string(&t).unwrap();
    let ok_rows =
        |text: &str| -> Vec<String> { text.lines().filter(|l| l.contains(",ok,")).map(str::to_string).collect() };
    assert_eq!(ok_rows(&after), ok_rows(&before));
    assert_eq!(ok_rows(&before).len(), 2);
    let before_path = dir.path().join("before.csv");
    std::fs::write(&before_path, &before).unwrap();
    assert_eq!(cells_without_timing(&t), cells_without_timing(&before_path));
    // a changed record is run again
    std::fs::write(dir.path().join("m3.yaml"), M3.replace("zeta: 0.03,", "zeta: 0.031,")).unwrap();
    let third = run_campaign(dir.path(), "t.csv", None);
    let stderr = String::from_utf8_lossy(&third.stderr);
    assert!(stderr.contains("1 of 4 records already in the table, 3 to run"), "{stderr}");
}

/// A malformed manifest (or a bad campaign-wide flag) exits 2 with one line
/// naming its row and column (the flag), and writes no table; a foreign
/// `--out` file is refused and left as it was.
#[test]
fn a_malformed_manifest_or_a_foreign_table_exits_2_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let manifest = d.join("manifest.csv");
    let out = d.join("t.csv");
    let cases = [
        ("record,modes\na.yaml,\nb.yaml\n", "manifest row 2 (line 3), column modes"),
        ("record,colour\na.yaml,red\n", "column 2 of the header = colour"),
        ("record,modes\n,3\n", "manifest row 1 (line 2), column record"),
    ];
    for (text, named) in cases {
        std::fs::write(&manifest, text).unwrap();
        let o = nanobeam(&["campaign", manifest.to_str().unwrap(), "--out", out.to_str().unwrap()], None);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        assert!(stderr.contains(named), "{named}: {stderr}");
        assert!(!out.exists(), "no table for a malformed manifest");
    }
    std::fs::write(&manifest, "record\na.yaml\n").unwrap();
    // a campaign-wide flag out of diagnose's range: refused before anything runs
    let o = nanobeam(&["campaign", manifest.to_str().unwrap(), "--out", out.to_str().unwrap(), "--samples", "3"], None);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert_eq!(stderr.trim(), "invalid --samples = 3: allowed 50..=100000");
    assert!(!out.exists(), "no table for a bad flag");
    std::fs::write(&out, "mine,not,nanobeam's\n").unwrap();
    let o = nanobeam(&["campaign", manifest.to_str().unwrap(), "--out", out.to_str().unwrap()], None);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(stderr.starts_with("invalid --out = ") && stderr.lines().count() == 1, "{stderr}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "mine,not,nanobeam's\n");
}
