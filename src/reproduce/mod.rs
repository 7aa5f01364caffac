//! The paper pipeline as a library: what the paper publishes
//! (`reference`), the specs that drive the run (`specs`), the reconstruction
//! of its lost inputs, the stages (`forward`, `cases`, `figure14`,
//! `evidence`), the noise replicates and the audit, the typed `results`, the
//! report (`document`), and the golden comparison of `--check` (`check`).
//!
//! # Files
//! `reference` (published.yaml types; Σ → reference values with rounding intervals), `specs` (every
//! paper-specific choice), `reconstruction` (lost Tables 1, 4, 9; `table_4_beam_from_yaml` reads
//! the paper's beam back from `paper/reconstructed.yaml` for tests and benches), stages `forward`,
//! `cases`, `figure14`, `evidence`, `replicates`, `audit` (✓/≈/✗ with probabilities), `verdict`
//! (the verdict types the audit produces and results, document and check read), `error`
//! (`ReproduceError`), `results` (typed, serialised once), `document` (report context, figures,
//! provenance), `check` (golden comparison), `pipeline` (orchestration)

pub mod audit;
pub mod cases;
pub mod check;
pub mod document;
pub mod error;
pub mod evidence;
pub mod figure14;
pub mod forward;
pub mod pipeline;
pub mod reconstruction;
pub mod reference;
pub mod replicates;
pub mod results;
pub mod specs;
pub mod verdict;
