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
//! each model's evidence). Work with no loop of its own to poll in (a
//! Nelder–Mead search inside argmin, a parallel batch of importance draws, a
//! Laplace Hessian) sees the posterior through [`Controlled`], whose every
//! likelihood evaluation reads the flag: once cancelled, each evaluation is
//! −∞ without a solve, so the search or batch runs out at once and its caller
//! checks the flag after it. The latency from [`Control::cancel`] to the
//! return is therefore a few forward solves per thread plus whatever phase
//! between two polls is running that evaluates no posterior (the predictive
//! checks' solves at the posterior draws).

use std::fmt;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use rand::RngCore;

use crate::bayes::Posterior;

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
    ///
    /// Sequentially consistent, with [`Control::is_cancelled`]'s load: then
    /// every poll that follows the cancel in the single total order sees it,
    /// so each other thread finishes at most the one evaluation it had
    /// polled for. With relaxed orderings the flag could wait in the
    /// cancelling core's store buffer while the other threads went on with
    /// evaluations of a few nanoseconds (tests/bayes_control.rs counted 3
    /// after a cancel on 2 threads). The load is a plain load on x86-64 and
    /// costs nothing per evaluation.
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::SeqCst);
    }

    /// Has [`Control::cancel`] been called?
    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::SeqCst)
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

/// A posterior seen through a [`Control`]: the same density while the control
/// is not cancelled, and a likelihood of −∞ (no forward solve) once it is.
///
/// Contract: every method but `log_likelihood` is the inner posterior's, and
/// `log_likelihood` is too until [`Control::cancel`]; a run that is not
/// cancelled therefore gives the same bits through it. Once cancelled, its
/// numbers are meaningless: whoever runs work on it must check the control
/// after that work and return `Cancelled` instead of the result.
///
/// Why: a Nelder–Mead search (argmin's loop) or a parallel batch of draws
/// (rayon's) has no loop boundary of ours to poll at, and takes seconds on a
/// coupled beam model; a cancelled search whose every point is infeasible
/// stops at its first simplex (equal costs), a batch's remaining draws cost
/// nothing.
pub struct Controlled<'a, P: ?Sized> {
    inner: &'a P,
    control: &'a Control,
}

impl<'a, P: Posterior + ?Sized> Controlled<'a, P> {
    pub fn new(inner: &'a P, control: &'a Control) -> Self {
        Self { inner, control }
    }
}

impl<P: Posterior + ?Sized> Posterior for Controlled<'_, P> {
    fn names(&self) -> Vec<String> {
        self.inner.names()
    }

    fn dim(&self) -> usize {
        self.inner.dim()
    }

    fn log_prior(&self, theta: &[f64]) -> f64 {
        self.inner.log_prior(theta)
    }

    fn log_likelihood(&self, theta: &[f64]) -> f64 {
        if self.control.is_cancelled() {
            f64::NEG_INFINITY
        } else {
            self.inner.log_likelihood(theta)
        }
    }

    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
        self.inner.sample_prior(rng)
    }

    fn relabel(&self, theta: &mut [f64]) {
        self.inner.relabel(theta)
    }
}
