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

/// One unit in the last printed digit of `x` when printed with 5 significant
/// digits (`r5` in src/reproduce/pipeline.rs; exact values carry 6, so the
/// bound covers them too).
fn last_digit_unit(x: f64) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    10f64.powi(x.abs().log10().floor() as i32 - 4)
}

/// Structural equality of two YAML trees, numbers allowed to differ by one
/// unit in their last printed digit (times 1.01 for the float round-off of
/// the rounding itself). Why not bytes: fitted values are resolved by the
/// Nelder–Mead stop only to ~2.4e-6 relative (see `r5`), so a last-bit change
/// in the forward model can move a value across a rounding boundary of its
/// 5th digit — one unit, never more. Label switching or a different optimum
/// moves far more and still fails.
fn compare_printed(a: &serde_yaml::Value, b: &serde_yaml::Value, path: &str, diffs: &mut Vec<String>) {
    use serde_yaml::Value;
    match (a, b) {
        (Value::Mapping(ma), Value::Mapping(mb)) => {
            let keys = |m: &serde_yaml::Mapping| m.keys().map(|k| format!("{k:?}")).collect::<Vec<_>>();
            if keys(ma) != keys(mb) {
                diffs.push(format!("{path}: keys {:?} vs {:?}", keys(ma), keys(mb)));
                return;
            }
            for ((k, va), vb) in ma.iter().zip(mb.values()) {
                compare_printed(va, vb, &format!("{path}.{}", k.as_str().unwrap_or("?")), diffs);
            }
        }
        (Value::Sequence(sa), Value::Sequence(sb)) if sa.len() == sb.len() => {
            for (i, (va, vb)) in sa.iter().zip(sb).enumerate() {
                compare_printed(va, vb, &format!("{path}[{i}]"), diffs);
            }
        }
        (Value::Number(na), Value::Number(nb)) => {
            let (x, y) = (na.as_f64().unwrap(), nb.as_f64().unwrap());
            if (x - y).abs() > 1.01 * last_digit_unit(x.abs().max(y.abs())) {
                diffs.push(format!("{path}: {x} vs {y}"));
            }
        }
        _ if a == b => {}
        _ => diffs.push(format!("{path}: {a:?} vs {b:?}")),
    }
}

#[test]
fn quick_reproduction_produces_everything_and_matches_golden() {
    let (_guard, root) = scratch_root();
    let out = root.join("out");
    let summary = run(&Options { root: root.clone(), out: out.clone(), quick: true, command_line: "test".into() })
        .expect("quick reproduction runs");
    for f in [
        "report.md",
        "results.json",
        "reconstructed.yaml",
        "table-2.csv",
        "table-2.md",
        "table-5.csv",
        "table-5.md",
        "table-10.csv",
        "table-10.md",
        "table-7.csv",
        "table-7.md",
        "table-8.csv",
        "table-8.md",
        "table-12.csv",
        "table-12.md",
        "figure-1a.svg",
        "figure-1b.svg",
        "figure-2a.svg",
        "figure-3b.svg",
        "figure-4a.svg",
        "figure-4b.svg",
        "figure-5a.svg",
        "figure-6b.svg",
        "figure-7-1a.svg",
        "figure-8a.svg",
        "figure-11b.svg",
        "figure-12-2b.svg",
        "figure-13-3.svg",
        "figure-13-3-n2.svg",
        "figure-14.svg",
        "figure-14.csv",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("## 4. Audit"), "report lacks the audit section");
    assert!(!summary.verdicts.is_empty());
    // The report shows everything: every generated figure is referenced in report.md.
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let mut svgs = Vec::new();
    for entry in walk(&out) {
        if entry.extension().is_some_and(|e| e == "svg") {
            svgs.push(entry.strip_prefix(&out).unwrap().to_string_lossy().into_owned());
        }
    }
    assert!(svgs.len() > 60, "only {} figures", svgs.len());
    for f in &svgs {
        assert!(report.contains(&format!("]({f})")), "{f} is not shown in report.md");
    }
    assert!(svgs.iter().any(|f| f.starts_with("audit-")), "no replicate figure");
    assert!(out.join("case-1a/inference_data.nc").exists());
    assert!(report.contains("## 7. Provenance") && report.contains("SHA-256 `paper/published.yaml`"));
    for v in &summary.verdicts {
        assert!(
            v.status == nanobeam::reproduce::audit::Status::Reproduced || !v.cause.is_empty(),
            "unexplained ≈/✗ for {}",
            v.id
        );
    }

    // The paper's Case-3 data (N̄ = 2 truth, fitted with N = 1) is diagnosed as
    // a missing internal variable, by a margin well beyond the threshold.
    let dx = &summary.results["case_3_diagnosis"];
    assert_eq!(dx["cause"], "extra-relaxation", "{dx}");
    assert!(dx["misfit_detected"].as_bool().unwrap());

    // The reconstruction (seeded multi-start) must reproduce the committed
    // paper/reconstructed.yaml, which the rest of the project reads.
    let rec = std::fs::read_to_string(out.join("reconstructed.yaml")).unwrap();
    let committed =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("paper/reconstructed.yaml")).unwrap();
    let (actual, golden): (serde_yaml::Value, serde_yaml::Value) =
        (serde_yaml::from_str(&rec).unwrap(), serde_yaml::from_str(&committed).unwrap());
    let mut diffs = Vec::new();
    compare_printed(&actual, &golden, "", &mut diffs);
    assert!(
        diffs.is_empty(),
        "reconstruction differs from paper/reconstructed.yaml (regenerate it with `cargo xtask reproduce`):\n{}",
        diffs.join("\n")
    );

    // Quick-mode case tables, rounded to what their Monte Carlo error supports.
    let mut lines = Vec::new();
    for c in summary.results["cases"].as_array().unwrap() {
        for p in c["parameters"].as_array().unwrap() {
            let mean = p["mean"].as_f64().unwrap();
            let mcse = p["mcse_mean"].as_f64().unwrap();
            lines.push(format!(
                "{} {}: mean {}",
                c["id"].as_str().unwrap(),
                p["name"].as_str().unwrap(),
                round_to_mc(mean, mcse)
            ));
        }
    }
    insta::with_settings!({ snapshot_path => "../golden", prepend_module_to_snapshot => false }, {
        insta::assert_snapshot!("quick_case_means", lines.join("\n"));
    });
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else {
            out.push(p);
        }
    }
    out
}

#[test]
fn a_bad_replicate_count_names_audit_yaml_and_the_field() {
    let (_guard, root) = scratch_root();
    let out = root.join("out");
    let audit = root.join("paper/specs/audit.yaml");
    let text = std::fs::read_to_string(&audit).unwrap();
    for (bad, field) in [
        (text.replace("replicates: 100", "replicates: 5"), "replicates = 5"),
        (text.replace("quick_replicates: 20", "quick_replicates: 2"), "quick_replicates = 2"),
        (text.replace("replicates: 100", "replicates: -3"), "replicates"),
    ] {
        std::fs::write(&audit, bad).unwrap();
        let err = run(&Options { root: root.clone(), out: out.clone(), quick: true, command_line: "test".into() })
            .err()
            .expect("bad replicate count rejected");
        let msg = err.to_string();
        assert!(matches!(err, nanobeam::reproduce::pipeline::ReproduceError::Input(_)), "{msg}");
        assert!(msg.contains("audit.yaml") && msg.contains(field), "{msg}");
        assert!(!out.exists(), "partial output directory");
    }
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
        (
            text.replace("lower: 0.0, upper: 1.0 }, proposal_sd: 0.01", "lower: -1.0, upper: 1.0 }, proposal_sd: 0.01"),
            "parameters.delta.prior.lower",
        ),
    ] {
        std::fs::write(&case, bad).unwrap();
        let err = run(&Options { root: root.clone(), out: out.clone(), quick: true, command_line: "test".into() })
            .err()
            .expect("bad spec rejected")
            .to_string();
        assert!(err.contains("case-1a.yaml") && err.contains(field), "{err}");
        assert_eq!(std::fs::read_dir(&out).unwrap().count(), 1, "DIR changed");
    }
}
