//! The problem side of the argmin-style split: a posterior is a log-density
//! over a named parameter vector. Samplers and optimisers consume it and know
//! nothing about what computes it (beams live elsewhere).

use rand::RngCore;

/// An unnormalised log posterior log π(θ | y) = log π(θ) + log L(θ), eq. (24),
/// split into prior and likelihood so tempered samplers (TMCMC) can weight the
/// likelihood alone.
pub trait Posterior: Sync {
    /// Parameter names, in the order of θ.
    fn names(&self) -> Vec<String>;

    /// Dimension of θ.
    fn dim(&self) -> usize {
        self.names().len()
    }

    /// log π(θ); `f64::NEG_INFINITY` outside the prior's support.
    fn log_prior(&self, theta: &[f64]) -> f64;

    /// log L(θ) = log π(y | θ). May return NaN or ±∞ when the model fails;
    /// samplers count that as a rejection, never a crash.
    fn log_likelihood(&self, theta: &[f64]) -> f64;

    /// One draw from the prior (used by TMCMC and multi-start optimisers).
    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64>;

    /// Maps θ to the canonical member of the set of points this posterior
    /// cannot tell apart because some of its components are exchangeable
    /// (identical priors, a likelihood symmetric in them): a permutation of
    /// those components only, so log π is unchanged. Reports apply it to every
    /// draw so that chains which found the same mode under different labels
    /// agree and R̂ measures real disagreement; samplers never call it. The
    /// default claims no symmetry (the identity).
    fn relabel(&self, _theta: &mut [f64]) {}

    /// log π(θ) + log L(θ); the likelihood is not evaluated outside the support.
    fn log_posterior(&self, theta: &[f64]) -> f64 {
        let lp = self.log_prior(theta);
        if !lp.is_finite() {
            return f64::NEG_INFINITY;
        }
        let ll = self.log_likelihood(theta);
        if ll.is_nan() {
            f64::NEG_INFINITY
        } else {
            lp + ll
        }
    }
}

/// A posterior that counts its likelihood evaluations: each is one solve of
/// the forward model, the unit the diagnosis reports its cost in. The count
/// is a function of the sampler's seed alone (the samplers' draws are), so it
/// is deterministic at any thread count.
pub struct Counted<'a, P: ?Sized> {
    inner: &'a P,
    count: std::sync::atomic::AtomicU64,
}

impl<'a, P: Posterior + ?Sized> Counted<'a, P> {
    pub fn new(inner: &'a P) -> Self {
        Self { inner, count: std::sync::atomic::AtomicU64::new(0) }
    }

    /// Likelihood evaluations so far.
    pub fn count(&self) -> u64 {
        self.count.load(std::sync::atomic::Ordering::Relaxed)
    }
}

impl<P: Posterior + ?Sized> Posterior for Counted<'_, P> {
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
        self.count.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.inner.log_likelihood(theta)
    }

    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
        self.inner.sample_prior(rng)
    }

    fn relabel(&self, theta: &mut [f64]) {
        self.inner.relabel(theta)
    }
}
