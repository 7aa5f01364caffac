//! `report.md`: the template context (every table, every figure with its
//! caption, the audit, timings, provenance) and the audit's replicate figures.

use std::path::Path;

use serde::Serialize;
use serde_json::Value;

use crate::report::svg::{self, HistogramPlot, NamedValues};
use crate::report::table::{fmt_interval, fmt_sig, Table};
use crate::reproduce::cases::{spec_file, CaseOutcome, Figure, TableFiles};
use crate::reproduce::error::ReproduceError;
use crate::reproduce::reconstruction::{Fit, Reconstruction};
use crate::reproduce::results::{Provenance, Results};
use crate::reproduce::specs::{CaseTable, Specs};
use crate::reproduce::verdict::{Status, Verdict};

/// Tables 5 and 10: reference values, their rounding intervals and the reconstruction's fit.
pub fn fit_table(f: &Fit) -> Table {
    let mut t =
        Table::new(["mode", "quantity", "reference", "rounding interval", "reproduced", "residual (σ)", "inside"]);
    for x in &f.values {
        t.push_row([
            x.mode.to_string(),
            x.quantity.to_string(),
            fmt_sig(x.reference, 5),
            fmt_interval(x.interval[0], x.interval[1], 5),
            fmt_sig(x.reproduced, 5),
            format!("{:+.3}", x.residual_sigma),
            if x.within_rounding { "✓".into() } else { "✗".into() },
        ]);
    }
    t
}

/// `(file name, text)` of generated files.
pub type Files = Vec<(String, String)>;

/// The figure of a noise-dependent verdict: the replicate distribution of its
/// statistic with our value, the paper's and the statement's boundary marked.
pub fn audit_figures(verdicts: &[Verdict]) -> Result<(Files, Vec<Figure>), ReproduceError> {
    let mut files = Vec::new();
    let mut figures = Vec::new();
    for v in verdicts {
        let Some(s) = &v.replicates else { continue };
        if s.values.is_empty() {
            continue;
        }
        let mut marks = vec![("ours (DRAM, our draw)".to_string(), s.ours)];
        marks.extend(s.paper.map(|p| ("paper".to_string(), p)));
        marks.extend(s.threshold.map(|t| ("boundary of the statement".to_string(), t)));
        marks.extend(s.noise_free.map(|x| ("noise-free data".to_string(), x)));
        let plot = HistogramPlot {
            title: format!("{}: {} over {} noise draws", v.id, s.label, s.values.len()),
            x_label: s.label.clone(),
            groups: vec![NamedValues { name: "replicates (MAP + Laplace)".into(), values: s.values.clone() }],
            bins: 30,
            marks,
            ..HistogramPlot::default()
        };
        let file = format!("audit-{}.svg", v.id.replace('_', "-"));
        files.push((file.clone(), svg::histogram(&plot)?));
        figures.push(Figure {
            file,
            caption: format!(
                "{} {}: distribution over {} noise replicates of {} (posterior summaries by MAP + Laplace with the DRAM shape of our draw); vertical lines: ours, {}the statement's boundary and the noise-free value",
                v.status.symbol(),
                v.id,
                s.values.len(),
                s.label,
                if s.paper.is_some() { "the paper's value, " } else { "" }
            ),
        });
    }
    Ok((files, figures))
}

/// The audit as a Markdown table.
fn audit_table(verdicts: &[Verdict]) -> String {
    let mut t = Table::new(["id", "claim", "reproduced", "tolerance", "verdict", "P", "measured cause"]);
    for v in verdicts {
        t.push_row([
            v.id.clone(),
            v.claim.clone(),
            v.reproduced.clone(),
            v.tolerance.clone(),
            v.status.symbol().to_string(),
            v.probability.map_or("-".into(), |p| format!("{p:.2}")),
            v.cause.clone(),
        ]);
    }
    t.to_markdown()
}

/// A case group of the report: its table, spec files, seeds and figures.
#[derive(Debug, Clone, Serialize)]
struct Section {
    caption: String,
    table: String,
    specs: Vec<String>,
    figures: Vec<Figure>,
}

/// The per-case directory figures (trace, marginal, pairs).
fn case_dir_figures(c: &CaseOutcome) -> Vec<Figure> {
    let dir = format!("case-{}", c.spec.id.to_lowercase());
    let mut f = Vec::new();
    for n in &c.names {
        f.push(Figure {
            file: format!("{dir}/trace_{n}.svg"),
            caption: format!("Case {}: trace of {n}, every chain, burn-in included; dashed: the true value", c.spec.id),
        });
        f.push(Figure {
            file: format!("{dir}/marginal_{n}.svg"),
            caption: format!(
                "Case {}: marginal posterior of {n} per chain (post-burn-in); dashed: the true value",
                c.spec.id
            ),
        });
    }
    f.push(Figure {
        file: format!("{dir}/pairs.svg"),
        caption: format!("Case {}: posterior pairs (post-burn-in draws of all chains)", c.spec.id),
    });
    f
}

/// Everything the report template reads.
pub struct DocumentInput<'a> {
    pub results: &'a Results,
    pub rec: &'a Reconstruction,
    pub specs: &'a Specs,
    pub cases: &'a [CaseOutcome],
    pub tables: &'a [(CaseTable, TableFiles)],
    pub forward_figures: &'a [Figure],
    pub audit_figures: &'a [Figure],
    pub table_2_md: &'a str,
    pub maps_delta: f64,
}

/// The tera context of `report.md.tera`.
pub fn report_context(d: &DocumentInput) -> Value {
    let r = d.results;
    let params =
        |f: &Fit| f.parameters.iter().map(|(n, v)| format!("{n} = {}", fmt_sig(*v, 5))).collect::<Vec<_>>().join(", ");
    let sections: Vec<Section> = d
        .tables
        .iter()
        .map(|(spec, files)| {
            let cases = crate::reproduce::cases::group(d.cases, &spec.cases);
            Section {
                caption: spec.caption.clone(),
                table: crate::reproduce::cases::case_table(&cases).to_markdown(),
                specs: cases.iter().map(|c| format!("`{}` (seed {})", spec_file(&c.spec), c.spec.seed)).collect(),
                figures: files.figures.clone(),
            }
        })
        .collect();
    let mut timing = Table::new(["stage", "wall time (s)"]);
    for (k, s) in &r.timings_s.0 {
        timing.push_row([k.clone(), format!("{s:.2}")]);
    }
    let mut case_times = Table::new(["case", "wall time (s)", "acceptance per DR stage", "rejected invalid"]);
    for c in d.cases {
        case_times.push_row([
            c.spec.id.clone(),
            format!("{:.2}", c.seconds),
            format!("{:?}", c.result.acceptance.iter().map(|a| (a * 1000.0).round() / 1000.0).collect::<Vec<_>>()),
            c.result.rejected_invalid.to_string(),
        ]);
    }
    let count = |s: Status| r.audit.iter().filter(|v| v.status == s).count();
    let rec = d.rec;
    serde_json::json!({
        "quick": r.quick,
        "results": r,
        "table_1_length_nm": fmt_sig(rec.table_1.length_nm, 5),
        "table_4_parameters": params(&rec.fit_table_4),
        "table_9_parameters": params(&rec.fit_table_9),
        "table_5_fit": fit_table(&rec.fit_table_4).to_markdown(),
        "table_10_fit": fit_table(&rec.fit_table_9).to_markdown(),
        "table_5_chi2": format!("{:.3}", rec.fit_table_4.chi2),
        "table_10_chi2": format!("{:.3}", rec.fit_table_9.chi2),
        "table_5_all_inside": rec.fit_table_4.all_within_rounding(),
        "table_10_all_inside": rec.fit_table_9.all_within_rounding(),
        "table_5_sigma_fit": fit_table(&rec.sigma_fit_table_4).to_markdown(),
        "table_10_sigma_fit": fit_table(&rec.sigma_fit_table_9).to_markdown(),
        "table_5_sigma_chi2": format!("{:.3}", rec.sigma_fit_table_4.chi2),
        "table_10_sigma_chi2": format!("{:.3}", rec.sigma_fit_table_9.chi2),
        "table_2": d.table_2_md,
        "maps_delta": format!("{:.4}", d.maps_delta),
        "forward_figures": d.forward_figures,
        "sections": sections,
        "case_figures": d.cases.iter().map(|c| serde_json::json!({
            "id": c.spec.id, "spec": spec_file(&c.spec), "seed": c.spec.seed, "figures": case_dir_figures(c),
        })).collect::<Vec<_>>(),
        "specs": d.specs.files.iter().map(|f| f.file_name().map(|n| n.to_string_lossy().into_owned())).collect::<Vec<_>>(),
        "figure_14_coverage": format!("{:.0}", 100.0 * r.figure_14.coverage_to_mode_4),
        "figure_14": r.figure_14,
        "case_3_evidence": r.case_3_evidence,
        "case_3_diagnosis": r.case_3_diagnosis,
        "audit": audit_table(&r.audit),
        "audit_figures": d.audit_figures,
        "audit_reproduced": count(Status::Reproduced),
        "audit_consistent": count(Status::Consistent),
        "audit_inconsistent": count(Status::Inconsistent),
        "audit_total": r.audit.len(),
        "replicates": r.replicates.first().map_or(0, |x| x.replicates),
        "timings": timing.to_markdown(),
        "case_times": case_times.to_markdown(),
        "provenance": provenance_table(&r.provenance),
    })
}

fn provenance_table(p: &Provenance) -> String {
    let mut t = Table::new(["item", "value"]);
    t.push_row(["nanobeam version".to_string(), p.nanobeam_version.clone()]);
    t.push_row(["git commit".to_string(), p.git_commit.clone().unwrap_or_else(|| "(git not available)".into())]);
    t.push_row(["work tree dirty".to_string(), p.git_dirty.map_or("(unknown)".into(), |d| d.to_string())]);
    t.push_row(["command line".to_string(), format!("`{}`", p.command_line)]);
    for (f, h) in &p.inputs_sha256 {
        t.push_row([format!("SHA-256 `{f}`"), format!("`{h}`")]);
    }
    t.to_markdown()
}

/// Version, git commit and dirty flag (when `git` runs), SHA-256 of every input, command line.
pub fn provenance(
    root: &Path,
    inputs: &[std::path::PathBuf],
    command_line: &str,
) -> Result<Provenance, ReproduceError> {
    use sha2::{Digest, Sha256};
    let git = |args: &[&str]| -> Option<String> {
        let out = std::process::Command::new("git").arg("-C").arg(root).args(args).output().ok()?;
        out.status.success().then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
    };
    let mut inputs_sha256 = Vec::new();
    for f in inputs {
        let bytes = std::fs::read(f).map_err(|e| ReproduceError::Failure(format!("{}: {e}", f.display())))?;
        let rel = f.strip_prefix(root).unwrap_or(f).to_string_lossy().into_owned();
        let hex: String = Sha256::digest(&bytes).iter().map(|b| format!("{b:02x}")).collect();
        inputs_sha256.push((rel, hex));
    }
    Ok(Provenance {
        nanobeam_version: env!("CARGO_PKG_VERSION").to_string(),
        git_commit: git(&["rev-parse", "HEAD"]),
        git_dirty: git(&["status", "--porcelain", "--untracked-files=no"]).map(|s| !s.is_empty()),
        inputs_sha256,
        command_line: command_line.to_string(),
    })
}
