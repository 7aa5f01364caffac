//! The paper pipeline, in stages: load and validate the specs
//! (`paper/specs/`, `paper/published.yaml`) → reconstruct the lost inputs →
//! Table 2 and Figures 1–3 → the calibration cases in parallel → Figure 14 →
//! Case-3 evidence and diagnosis → noise replicates → audit → report.
//!
//! Every stage returns a typed result ([`crate::reproduce::results`]);
//! `results.json` is their one serialisation. Everything is computed before
//! anything is written; the output directory is then built in a temporary
//! sibling and renamed, so a failure leaves it as it was.

use std::path::{Path, PathBuf};
use std::time::Instant;

use rayon::prelude::*;
use serde_json::json;

use crate::calibration::output::{write_calibration_files, InferenceContext};
use crate::report::render::{render_template, write_dir_atomically};
use crate::reproduce::audit::{audit, AuditInput};
use crate::reproduce::cases::{case_result, run_case, table_files, truth_beam, CaseOutcome, Figure, TableFiles};
use crate::reproduce::document::{audit_figures, fit_table, provenance, report_context, DocumentInput};
use crate::reproduce::evidence::{diagnosis_stage, evidence_stage};
use crate::reproduce::figure14::frf_stage;
use crate::reproduce::forward::{forward_stage, ForwardOutcome};
use crate::reproduce::reconstruction::{reconstruct, Reconstruction};
use crate::reproduce::reference::Published;
use crate::reproduce::replicates::{replicate_cases, CaseReplicates, ReplicateInput};
use crate::reproduce::results::{ReconstructionResult, ReplicateCount, Results, Timings};
use crate::reproduce::specs::{CaseTable, Specs};

pub use crate::reproduce::error::ReproduceError;
pub use crate::reproduce::figure14::FrfOutcome;
use crate::reproduce::verdict::Verdict;

/// Where to read and write.
#[derive(Debug, Clone)]
pub struct Options {
    /// Repository root (holds `paper/`).
    pub root: PathBuf,
    pub out: PathBuf,
    pub quick: bool,
    /// The command line that started the run (for the provenance block).
    pub command_line: String,
}

/// What `run` returns (also written as results.json).
pub struct RunSummary {
    /// `results.json` as a JSON value (the serialisation of [`Results`]).
    pub results: serde_json::Value,
    pub verdicts: Vec<Verdict>,
    pub timings: Vec<(String, f64)>,
    /// The typed results themselves.
    pub typed: Results,
}

/// Wall time per stage.
struct Clock {
    start: Instant,
    timings: Vec<(String, f64)>,
}

impl Clock {
    fn time<T>(&mut self, name: &str, f: impl FnOnce() -> T) -> T {
        let t = Instant::now();
        let out = f();
        self.timings.push((name.to_string(), t.elapsed().as_secs_f64()));
        out
    }
}

/// Everything computed, before anything is written.
struct Computed {
    specs: Specs,
    rec: Reconstruction,
    forward: ForwardOutcome,
    cases: Vec<CaseOutcome>,
    frf: FrfOutcome,
    results: Results,
    tables: Vec<(CaseTable, TableFiles)>,
    audit_files: Vec<(String, String)>,
    audit_figures: Vec<Figure>,
}

/// Runs the whole reproduction into `opts.out`.
pub fn run(opts: &Options) -> Result<RunSummary, ReproduceError> {
    let c = compute(opts)?;
    let reconstructed_yaml = reconstructed_yaml(&c.rec, &c.specs);
    let forward_figures = forward_figures(&c.forward);
    let doc = DocumentInput {
        results: &c.results,
        rec: &c.rec,
        specs: &c.specs,
        cases: &c.cases,
        tables: &c.tables,
        forward_figures: &forward_figures,
        audit_figures: &c.audit_figures,
        table_2_md: &c.forward.table2_md,
        maps_delta: c.forward.delta,
    };
    let report = render_template(&opts.root.join("paper/templates"), "report.md.tera", &report_context(&doc))?;
    let results_json = serde_json::to_string_pretty(&c.results).expect("results serialise") + "\n";
    write_dir_atomically(&opts.out, |dir: &Path| -> Result<(), ReproduceError> {
        let w = |name: &str, text: &str| -> Result<(), ReproduceError> {
            std::fs::write(dir.join(name), text).map_err(|e| ReproduceError::Failure(format!("{name}: {e}")))
        };
        w("reconstructed.yaml", &reconstructed_yaml)?;
        for (name, fit) in [("table-5", &c.rec.fit_table_4), ("table-10", &c.rec.fit_table_9)] {
            let t = fit_table(fit);
            w(&format!("{name}.csv"), &t.to_csv())?;
            w(&format!("{name}.md"), &t.to_markdown())?;
        }
        let tables = c.tables.iter().flat_map(|(_, t)| t.files.iter());
        for (name, text) in c.forward.files.iter().chain(tables).chain(&c.frf.files).chain(&c.audit_files) {
            w(name, text)?;
        }
        for case in &c.cases {
            let sub = dir.join(format!("case-{}", case.spec.id.to_lowercase()));
            std::fs::create_dir_all(&sub).map_err(|e| ReproduceError::Failure(e.to_string()))?;
            let ctx = InferenceContext { posterior: &case.posterior, seed: case.spec.seed };
            write_calibration_files(&sub, &case.result, Some(&case.truth), Some(&ctx))?;
        }
        w("results.json", &results_json)?;
        w("report.md", &report)?;
        Ok(())
    })?;
    // The generated, snapshot-checked copy of the reconstruction lives in paper/.
    std::fs::write(opts.root.join("paper/reconstructed.yaml"), &reconstructed_yaml)
        .map_err(|e| ReproduceError::Failure(format!("paper/reconstructed.yaml: {e}")))?;
    let results = serde_json::from_str(&results_json).expect("results.json parses");
    Ok(RunSummary {
        results,
        verdicts: c.results.audit.clone(),
        timings: c.results.timings_s.0.clone(),
        typed: c.results,
    })
}

/// Every stage, timed; nothing written.
fn compute(opts: &Options) -> Result<Computed, ReproduceError> {
    let mut clock = Clock { start: Instant::now(), timings: Vec::new() };
    let published_path = opts.root.join("paper/published.yaml");
    let (published, specs) = clock.time("load", || -> Result<_, ReproduceError> {
        let published = Published::load(&published_path)
            .map_err(|e| ReproduceError::Input(format!("paper/published.yaml: {e}")))?;
        let specs = Specs::load(&opts.root.join("paper/specs")).map_err(|e| ReproduceError::Input(e.to_string()))?;
        Ok((published, specs))
    })?;
    let rec = clock.time("reconstruction", || reconstruct(&specs.reconstruction, &published));
    let forward = clock.time("table_2_figures_1_3", || forward_stage(&specs, &rec, opts.quick))?;
    let cases: Vec<CaseOutcome> = clock.time("cases", || {
        specs.cases.par_iter().map(|c| run_case(c, &rec, &published, opts.quick)).collect::<Result<Vec<_>, _>>()
    })?;
    let tables = clock.time("tables_figures_4_13", || {
        specs
            .tables
            .tables
            .iter()
            .map(|t| Ok((t.clone(), table_files(t, &cases)?)))
            .collect::<Result<Vec<_>, ReproduceError>>()
    })?;
    let frf = clock.time("figure_14", || frf_stage(&specs, &rec, &cases, opts.quick))?;
    let evidence = clock.time("case_3_evidence", || evidence_stage(&specs.evidence, &cases, opts.quick));
    let diagnosis = clock.time("case_3_diagnosis", || diagnosis_stage(&specs.evidence, &cases, &rec, opts.quick))?;
    let count = if opts.quick { specs.audit.quick_replicates } else { specs.audit.replicates };
    let replicates = clock.time("noise_replicates", || replicate_stage(&cases, &rec, &published, count));
    let verdicts = clock.time("audit", || {
        audit(&AuditInput {
            published: &published,
            rec: &rec,
            forward: &forward,
            cases: &cases,
            frf: &frf,
            replicates: &replicates,
        })
    });
    let (audit_files, audit_figures) = clock.time("audit_figures", || audit_figures(&verdicts))?;
    clock.timings.push(("total_before_writing".into(), clock.start.elapsed().as_secs_f64()));
    let mut inputs = vec![published_path];
    inputs.extend(specs.files.iter().cloned());
    let results = Results {
        quick: opts.quick,
        reconstruction: ReconstructionResult::new(&rec),
        table_2: forward.table2_rows.clone(),
        cases: cases.iter().map(case_result).collect(),
        figure_14: frf.result.clone(),
        case_3_evidence: evidence,
        case_3_diagnosis: diagnosis,
        replicates: replicates
            .iter()
            .map(|r| ReplicateCount {
                case: r.id.clone(),
                replicates: r.replicates.len(),
                failed: r.failed(),
                shape: r.shape.clone(),
            })
            .collect(),
        audit: verdicts,
        timings_s: Timings(clock.timings),
        provenance: provenance(&opts.root, &inputs, &opts.command_line)?,
    };
    Ok(Computed { specs, rec, forward, cases, frf, results, tables, audit_files, audit_figures })
}

/// The noise replicates of every case with a truth to compare against.
fn replicate_stage(
    cases: &[CaseOutcome],
    rec: &Reconstruction,
    published: &Published,
    count: usize,
) -> Vec<CaseReplicates> {
    let inputs: Vec<ReplicateInput> = cases
        .iter()
        .map(|c| ReplicateInput {
            id: &c.spec.id,
            seed: c.spec.seed,
            truth: truth_beam(&c.spec, rec),
            covariance_set: published.covariance_set(&c.spec.covariance_set).expect("validated covariance set id"),
            posterior: &c.posterior,
            dram: &c.result,
        })
        .collect();
    replicate_cases(&inputs, count).into_iter().flatten().collect()
}

/// Figures 1–3 with their captions.
fn forward_figures(f: &ForwardOutcome) -> Vec<Figure> {
    (1..=f.maps.len())
        .flat_map(|r| {
            [
                Figure {
                    file: format!("figure-{r}a.svg"),
                    caption: format!(
                        "Figure {r}a: ω{r}/ω'{r} of the noise-free model over e0a × Ω (Δ = {:.4})",
                        f.delta
                    ),
                },
                Figure {
                    file: format!("figure-{r}b.svg"),
                    caption: format!("Figure {r}b: ζ{r} of the noise-free model over e0a × Ω (Δ = {:.4})", f.delta),
                },
            ]
        })
        .collect()
}

fn reconstructed_yaml(rec: &Reconstruction, specs: &Specs) -> String {
    let header = "# GENERATED by `cargo xtask reproduce` (reproduce::reconstruction); do not edit.\n\
# Reference values (Tables 5, 10) are derived from the printed covariances; the lost\n\
# inputs (Tables 1, 4, 9) are their least-squares fit in units of the paper's sigma.\n";
    let body = json!({
        "fixed_assumptions": {
            "diameter_nm": specs.reconstruction.diameter_nm,
            "youngs_modulus_pa": specs.reconstruction.youngs_modulus_pa,
            "density_kg_m3": specs.reconstruction.density_kg_m3,
            "support": specs.reconstruction.support.name(),
            "elements": specs.reconstruction.elements,
            "frequency_unit": "the paper's GHz is cyclic frequency: omega_rad_s = 2*pi*1e9*GHz",
            "identifiable": "only EI/(rho A L^4) and e0a/L; L is fitted with d, E, rho held",
        },
        "reconstruction": ReconstructionResult::new(rec),
    });
    header.to_string() + &serde_yaml::to_string(&body).expect("yaml")
}
