//! `reproduce` in quick mode: every table and figure is produced, the
//! reconstruction is stable (golden), the quick tables match their golden
//! values at the precision the Monte Carlo error supports, and a bad spec
//! leaves the output directory untouched.

use std::path::{Path, PathBuf};

use nanobeam::reproduce::pipeline::{run, Options};

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), target).unwrap();
        }
    }
}

/// A scratch copy of the repository's `paper/` so the run cannot touch the real one.
fn scratch_root() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    copy_dir(&Path::new(env!("CARGO_MANIFEST_DIR")).join("paper"), &dir.path().join("paper"));
    let root = dir.path().to_path_buf();
    (dir, root)
}

/// Rounds `x` to the decade of 4 Monte Carlo standard errors: two runs that
/// differ only by Monte Carlo noise agree at this precision except near a
/// rounding boundary (the snapshot records the rounding step as well).
fn round_to_mc(x: f64, mcse: f64) -> String {
    let q = 10f64.powf((4.0 * mcse).log10().ceil());
    format!("{} (step {q:e})", (x / q).round() * q)
}

#[test]
fn quick_reproduction_produces_everything_and_matches_golden() {
    let (_guard, root) = scratch_root();
    let out = root.join("out");
    let summary = run(&Options { root: root.clone(), out: out.clone(), quick: true }).expect("quick reproduction runs");
    for f in [
        "report.md", "results.json", "reconstructed.yaml", "table-2.csv", "table-2.md", "table-5.csv", "table-5.md", "table-10.csv", "table-10.md", "table-7.csv", "table-7.md", "table-8.csv",
        "table-8.md", "table-12.csv", "table-12.md", "figure-1a.svg", "figure-1b.svg", "figure-2a.svg", "figure-3b.svg",
        "figure-4a.svg", "figure-4b.svg", "figure-5a.svg", "figure-6b.svg", "figure-7-1a.svg", "figure-8a.svg", "figure-11b.svg",
        "figure-12-2b.svg", "figure-13-3.svg", "figure-13-3-n2.svg", "figure-14.svg", "figure-14.csv",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## 4. Audit"), "report lacks the audit section");
    assert!(!summary.verdicts.is_empty());
    for v in &summary.verdicts {
        assert!(v.pass || !v.note.is_empty(), "unexplained ✗ for {}", v.id);
    }

    // The reconstruction is deterministic (seeded multi-start; fitted values rounded to 5
    // significant digits, exact ones to 6: see `r5` in src/reproduce/pipeline.rs).
    let rec = std::fs::read_to_string(out.join("reconstructed.yaml")).unwrap();
    insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false }, {
        insta::assert_snapshot!("reconstructed_yaml", rec);
    });
    assert_eq!(rec, std::fs::read_to_string(root.join("paper/reconstructed.yaml")).unwrap());

    // Quick-mode case tables, rounded to what their Monte Carlo error supports.
    let mut lines = Vec::new();
    for c in summary.results["cases"].as_array().unwrap() {
        for p in c["parameters"].as_array().unwrap() {
            let mean = p["mean"].as_f64().unwrap();
            let mcse = p["mcse_mean"].as_f64().unwrap();
            lines.push(format!("{} {}: mean {}", c["id"].as_str().unwrap(), p["name"].as_str().unwrap(), round_to_mc(mean, mcse)));
        }
    }
    insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false }, {
        insta::assert_snapshot!("quick_case_means", lines.join("\n"));
    });
}

#[test]
fn a_bad_spec_names_file_and_field_and_leaves_out_untouched() {
    let (_guard, root) = scratch_root();
    let out = root.join("out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("previous.txt"), "keep").unwrap();
    let case = root.join("paper/specs/case-1a.yaml");
    let text = std::fs::read_to_string(&case).unwrap();
    for (bad, field) in [
        (text.clone() + "colour: blue\n", "colour"),
        (text.replacen("seed: 101\n", "", 1), "seed"),
        (text.replace("lower: 0.0, upper: 1.0 }, proposal_sd: 0.01", "lower: -1.0, upper: 1.0 }, proposal_sd: 0.01"), "parameters.delta.prior.lower"),
    ] {
        std::fs::write(&case, bad).unwrap();
        let err = run(&Options { root: root.clone(), out: out.clone(), quick: true }).err().expect("bad spec rejected").to_string();
        assert!(err.contains("case-1a.yaml") && err.contains(field), "{err}");
        assert_eq!(std::fs::read_dir(&out).unwrap().count(), 1, "DIR changed");
    }
}
