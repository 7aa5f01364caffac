//! Reparameterisation of a posterior: sample u with x = g(u) componentwise,
//! where g is the identity or the exponential.
//!
//! The density of u is π_u(u) = π_x(g(u))·|g′(u)|, so the log prior gains
//! ln|dx/du| = u_i for every log-scaled coordinate (x_i = e^{u_i}); the
//! likelihood is evaluated at x = g(u) unchanged. The evidence
//! ∫ L(g(u)) π_u(u) du = ∫ L(x) π_x(x) dx is invariant, which is why a sampler
//! may work in whichever coordinates suit it: a log-uniform prior over decades
//! is uniform in u, where random-walk proposals have one natural scale.

use rand::RngCore;

use super::Posterior;

/// `inner` seen in coordinates u, with `log_scale[i]`: x_i = e^{u_i}, else x_i = u_i.
#[derive(Debug, Clone)]
pub struct Reparameterized<P> {
    inner: P,
    log_scale: Vec<bool>,
}

impl<P: Posterior> Reparameterized<P> {
    /// `log_scale` has one entry per coordinate of `inner`; a log-scaled
    /// coordinate's prior must have support in x > 0.
    pub fn new(inner: P, log_scale: Vec<bool>) -> Self {
        debug_assert_eq!(log_scale.len(), inner.dim());
        Self { inner, log_scale }
    }

    pub fn inner(&self) -> &P {
        &self.inner
    }

    pub fn log_scale(&self) -> &[bool] {
        &self.log_scale
    }

    /// x = g(u).
    pub fn to_inner(&self, u: &[f64]) -> Vec<f64> {
        u.iter().zip(&self.log_scale).map(|(&v, &l)| if l { v.exp() } else { v }).collect()
    }

    /// u = g⁻¹(x) (−∞ for a log-scaled x ≤ 0: outside the support).
    pub fn from_inner(&self, x: &[f64]) -> Vec<f64> {
        x.iter()
            .zip(&self.log_scale)
            .map(|(&v, &l)| {
                if !l {
                    v
                } else if v > 0.0 {
                    v.ln()
                } else {
                    f64::NEG_INFINITY
                }
            })
            .collect()
    }
}

impl<P: Posterior> Posterior for Reparameterized<P> {
    fn names(&self) -> Vec<String> {
        self.inner.names()
    }

    fn dim(&self) -> usize {
        self.inner.dim()
    }

    fn log_prior(&self, u: &[f64]) -> f64 {
        if u.iter().any(|v| !v.is_finite()) {
            return f64::NEG_INFINITY;
        }
        let jacobian: f64 = u.iter().zip(&self.log_scale).filter(|(_, &l)| l).map(|(&v, _)| v).sum();
        self.inner.log_prior(&self.to_inner(u)) + jacobian
    }

    fn log_likelihood(&self, u: &[f64]) -> f64 {
        self.inner.log_likelihood(&self.to_inner(u))
    }

    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
        self.from_inner(&self.inner.sample_prior(rng))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bayes::prior::Prior;

    /// A log-uniform prior on [a, b] alone (flat likelihood).
    struct LogUniformOnly(Prior);

    impl Posterior for LogUniformOnly {
        fn names(&self) -> Vec<String> {
            vec!["x".into()]
        }
        fn log_prior(&self, x: &[f64]) -> f64 {
            self.0.ln_pdf(x[0])
        }
        fn log_likelihood(&self, _: &[f64]) -> f64 {
            0.0
        }
        fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
            vec![self.0.sample(rng)]
        }
    }

    /// log-U[a, b] in u = ln x is U[ln a, ln b]: density 1/ln(b/a) everywhere
    /// inside, −∞ outside, and the round trip x → u → x is exact to round-off.
    #[test]
    fn log_uniform_becomes_uniform_in_log_coordinates() {
        let (a, b) = (1e-3, 1e2);
        let p = Reparameterized::new(LogUniformOnly(Prior::LogUniform { lower: a, upper: b }), vec![true]);
        let flat = -(b / a).ln().ln();
        for x in [2e-3_f64, 0.5, 80.0] {
            let u = x.ln();
            assert!((p.log_prior(&[u]) - flat).abs() < 1e-12, "x = {x}");
            assert!((p.to_inner(&[u])[0] / x - 1.0).abs() < 1e-15);
        }
        assert_eq!(p.log_prior(&[(b * 1.01).ln()]), f64::NEG_INFINITY);
        assert_eq!(p.from_inner(&[0.0])[0], f64::NEG_INFINITY);
    }
}
