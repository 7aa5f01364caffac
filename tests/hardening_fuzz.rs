//! Issue 11: property test of the YAML front end through the real binary:
//! mutated and garbage beam / measured files never panic or die by a signal;
//! every run exits 0, 1 or 2, and a failing run prints exactly one stderr line.

use std::process::Command;

use proptest::prelude::*;

mod common_hardening;
use common_hardening as cli_cases;

const BEAM: &str = "length_nm: 8.0\ndiameter_nm: 1.0\nyoungs_modulus_pa: 1.0e12\ndensity_kg_m3: 2300.0\nsupport: clamped-free\nelements: 12\nnonlocal_e0a_nm: 0.5\nviscous_damping_n_s_m2: 1.0e-5\ninternal_variables:\n  - { delta: 0.4, omega_rad_s: 4.5e11 }\npoint_mass: { mass_kg: 1.0e-26, x_nm: 3.0 }\n";

/// Pieces a hostile user types: numbers at the edges, YAML syntax, aliases.
const TOKENS: &[&str] = &[
    "0",
    "-1",
    "1e400",
    "-1e400",
    "1e-400",
    "1e308",
    "1e-308",
    ".nan",
    ".inf",
    "-.inf",
    "~",
    "null",
    "[]",
    "{}",
    "[",
    "{",
    ":",
    ": ",
    "- ",
    "&a ",
    "*a",
    "!!str ",
    "'",
    "\"",
    "#",
    "\n",
    "  ",
    "\t",
    "999999999999999999999",
    "2.5",
    "true",
    "x",
    "modes",
    "elements",
    "mode",
    "<<: *a",
    "---\n",
    "...",
    "\u{0}",
    "é",
];

#[derive(Debug, Clone)]
enum Edit {
    Insert(usize, &'static str),
    Delete(usize, usize),
    Replace(usize, usize, &'static str),
    DuplicateLine(usize),
}

fn edit() -> impl Strategy<Value = Edit> {
    let tok = prop::sample::select(TOKENS);
    prop_oneof![
        (any::<usize>(), tok.clone()).prop_map(|(i, t)| Edit::Insert(i, t)),
        (any::<usize>(), 1usize..12).prop_map(|(i, n)| Edit::Delete(i, n)),
        (any::<usize>(), 1usize..8, tok).prop_map(|(i, n, t)| Edit::Replace(i, n, t)),
        any::<usize>().prop_map(Edit::DuplicateLine),
    ]
}

fn apply(base: &str, edits: &[Edit]) -> String {
    let mut s: Vec<char> = base.chars().collect();
    for e in edits {
        let len = s.len().max(1);
        match *e {
            Edit::Insert(i, t) => {
                let i = i % (s.len() + 1);
                s.splice(i..i, t.chars());
            }
            Edit::Delete(i, n) => {
                let i = i % len;
                let j = (i + n).min(s.len());
                s.drain(i.min(s.len())..j);
            }
            Edit::Replace(i, n, t) => {
                let i = (i % len).min(s.len());
                let j = (i + n).min(s.len());
                s.splice(i..j, t.chars());
            }
            Edit::DuplicateLine(i) => {
                let text: String = s.iter().collect();
                let lines: Vec<&str> = text.lines().collect();
                if !lines.is_empty() {
                    let k = i % lines.len();
                    let mut out: Vec<&str> = lines.clone();
                    out.insert(k, lines[k]);
                    s = (out.join("\n") + "\n").chars().collect();
                }
            }
        }
    }
    s.into_iter().collect()
}

fn check(cmd: &str, text: &str, extra: &[&str]) -> Result<(), TestCaseError> {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("in.yaml");
    std::fs::write(&p, text).unwrap();
    let mut args = vec![cmd, p.to_str().unwrap()];
    args.extend_from_slice(extra);
    let out = Command::new(env!("CARGO_BIN_EXE_nanobeam")).args(&args).env("RAYON_NUM_THREADS", "1").output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let code = out.status.code();
    prop_assert!(matches!(code, Some(0..=2)), "exit {:?} (signal?) for {:?}: {}", out.status, text, err);
    prop_assert!(!err.contains("panicked"), "panic for {:?}: {}", text, err);
    if code != Some(0) {
        prop_assert_eq!(err.lines().count(), 1, "not one line for {:?}: {}", text, err);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn mutated_beam_files(edits in prop::collection::vec(edit(), 1..6)) {
        check("modal", &apply(BEAM, &edits), &["--modes", "4"])?;
    }

    #[test]
    fn mutated_measured_files(edits in prop::collection::vec(edit(), 1..6)) {
        check("calibrate", &apply(cli_cases::MEASURED, &edits), &[])?;
    }

    #[test]
    fn garbage(bytes in prop::collection::vec(prop::sample::select(TOKENS), 0..40)) {
        check("modal", &bytes.concat(), &[])?;
    }
}
