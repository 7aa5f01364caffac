//! A long run's caller-side control: a cancellation flag the samplers poll
//! at their loop boundaries, and a progress sink they advance.
//!
//! Contract: neither changes a number. The flag is read with a relaxed
//! atomic load and nothing else (no random stream is drawn from, no
//! iteration is reordered), and progress only receives counts, so a run that
//! is not cancelled gives the same bytes with any [`Control`]. A cancelled
//! run stops at the next boundary and returns its layer's `Cancelled` error
//! ([`crate::bayes::BayesError::Cancelled`] and the variants that wrap it),
//! never a partial result.
//!
//! Where the work polls: every DRAM step ([`crate::bayes::dram::run_chain`]),
//! every TMCMC stage and every sample's Metropolis moves within a stage
//! ([`crate::bayes::tmcmc::tmcmc_controlled`]), and the callers' own loops
//! (`calibration::calibrate_posterior` between its phases, `diagnose` before
//! each model's evidence). The latency from [`Control::cancel`] to the return
//! is therefore a few forward solves per thread plus whatever phase between
//! two polls is running (a MAP search, the predictive checks).

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Receives a run's progress: a phase of known size, then increments.
/// Implementations must be cheap (they are called from worker threads) and
/// must not block: the CLI draws an indicatif bar, the Python front stores the
/// counts in atomics its waiting thread reads.
pub trait Progress: Send + Sync {
    /// A new phase of `total` units named `unit` ("draws", "models").
    fn start(&self, unit: &'static str, total: u64);
    /// `n` more units of the current phase are done.
    fn advance(&self, n: u64);
    /// The phase is over (finished or abandoned).
    fn finish(&self);
}

/// Cancellation and progress of one run; the default never cancels and
/// reports nothing. Clones share the flag and the sink.
#[derive(Clone, Default)]
pub struct Control {
    cancelled: Arc<AtomicBool>,
    progress: Option<Arc<dyn Progress>>,
}

impl Control {
    /// A control reporting to `progress`.
    pub fn with_progress(progress: Arc<dyn Progress>) -> Self {
        Self { progress: Some(progress), ..Self::default() }
    }

    /// Asks the run to stop at its next poll (from any thread).
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    /// Has [`Control::cancel`] been called?
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    /// `Err(Cancelled)` once cancelled: `control.check()?` at a loop boundary.
    pub fn check(&self) -> Result<(), Cancelled> {
        if self.is_cancelled() {
            Err(Cancelled)
        } else {
            Ok(())
        }
    }

    /// Starts a phase of the progress sink (if any).
    pub fn start(&self, unit: &'static str, total: u64) {
        if let Some(p) = &self.progress {
            p.start(unit, total);
        }
    }

    /// Advances the progress sink (if any).
    pub fn advance(&self, n: u64) {
        if let Some(p) = &self.progress {
            p.advance(n);
        }
    }

    /// Ends the current phase of the progress sink (if any).
    pub fn finish(&self) {
        if let Some(p) = &self.progress {
            p.finish();
        }
    }
}

impl fmt::Debug for Control {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Control")
            .field("cancelled", &self.is_cancelled())
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

/// Controls never distinguish settings: they change no number (module doc),
/// so two settings that differ only in their control give the same result.
impl PartialEq for Control {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// The run was cancelled through its [`Control`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("cancelled by the caller")]
pub struct Cancelled;
