//! The paper pipeline as a library: what the paper publishes
//! (`reference`), the specs that drive the run (`specs`), the reconstruction
//! of its lost inputs, the stages (`forward`, `cases`, `figure14`,
//! `evidence`), the noise replicates and the audit, the typed `results`, the
//! report (`document`), and the golden comparison of `--check` (`check`).

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
