//! Reparameterisation of a posterior: sample u with x = g(u) componentwise,
//! where g is the identity, the exponential or s·sinh ([`Coordinate`]).
//!
//! The density of u is π_u(u) = π_x(g(u))·|g′(u)|, so the log prior gains
//! ln|dx/du|: u_i for a log-scaled coordinate (x_i = e^{u_i}), ln(s cosh u_i)
//! for an asinh-scaled one (x_i = s sinh u_i); the likelihood is evaluated at
//! x = g(u) unchanged. The evidence ∫ L(g(u)) π_u(u) du = ∫ L(x) π_x(x) dx is
//! invariant, which is why a sampler may work in whichever coordinates suit
//! it: a log-uniform prior over decades is uniform in u = ln x, an
//! asinh-uniform one (`Prior::AsinhUniform`, a signed quantity over decades)
//! uniform in u = asinh(x/s), where random-walk proposals have one natural scale.

use rand::RngCore;

use super::prior::Prior;
use super::Posterior;

/// The sampling coordinate u of one parameter x.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Coordinate {
    /// x = u.
    Identity,
    /// x = e^u (x > 0).
    Log,
    /// x = scale·sinh u (scale > 0).
    Asinh { scale: f64 },
}

impl Coordinate {
    /// The coordinate in which `prior` is uniform, where there is one
    /// (log-uniform: ln x; asinh-uniform: asinh(x/scale)); else x itself.
    pub fn uniformising(prior: &Prior) -> Self {
        match *prior {
            Prior::LogUniform { .. } => Coordinate::Log,
            Prior::AsinhUniform { scale, .. } => Coordinate::Asinh { scale },
            _ => Coordinate::Identity,
        }
    }

    /// x = g(u).
    pub fn to_x(self, u: f64) -> f64 {
        match self {
            Coordinate::Identity => u,
            Coordinate::Log => u.exp(),
            Coordinate::Asinh { scale } => scale * u.sinh(),
        }
    }

    /// u = g⁻¹(x) (−∞ for a log-scaled x ≤ 0: outside the support).
    pub fn to_u(self, x: f64) -> f64 {
        match self {
            Coordinate::Identity => x,
            Coordinate::Log if x > 0.0 => x.ln(),
            Coordinate::Log => f64::NEG_INFINITY,
            Coordinate::Asinh { scale } => (x / scale).asinh(),
        }
    }

    /// ln |dx/du| at u.
    pub fn ln_jacobian(self, u: f64) -> f64 {
        match self {
            Coordinate::Identity => 0.0,
            Coordinate::Log => u,
            // ln cosh u = |u| + ln(1 + e^{−2|u|}) − ln 2, without overflow for large |u|
            Coordinate::Asinh { scale } => {
                scale.ln() + u.abs() + (-2.0 * u.abs()).exp().ln_1p() - std::f64::consts::LN_2
            }
        }
    }
}

/// `inner` seen in coordinates u, x_i = g_i(u_i) with g_i = `coordinates[i]`.
#[derive(Debug, Clone)]
pub struct Reparameterized<P> {
    inner: P,
    coordinates: Vec<Coordinate>,
}

impl<P: Posterior> Reparameterized<P> {
    /// `log_scale` has one entry per coordinate of `inner`: x_i = e^{u_i}
    /// where true (the prior's support must be x > 0), else x_i = u_i.
    pub fn new(inner: P, log_scale: Vec<bool>) -> Self {
        let coordinates =
            log_scale.into_iter().map(|l| if l { Coordinate::Log } else { Coordinate::Identity }).collect();
        Self::with_coordinates(inner, coordinates)
    }

    /// One [`Coordinate`] per coordinate of `inner`.
    pub fn with_coordinates(inner: P, coordinates: Vec<Coordinate>) -> Self {
        debug_assert_eq!(coordinates.len(), inner.dim());
        Self { inner, coordinates }
    }

    pub fn inner(&self) -> &P {
        &self.inner
    }

    pub fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }

    /// x = g(u).
    pub fn to_inner(&self, u: &[f64]) -> Vec<f64> {
        u.iter().zip(&self.coordinates).map(|(&v, c)| c.to_x(v)).collect()
    }

    /// u = g⁻¹(x) (−∞ for a log-scaled x ≤ 0: outside the support).
    pub fn from_inner(&self, x: &[f64]) -> Vec<f64> {
        x.iter().zip(&self.coordinates).map(|(&v, c)| c.to_u(v)).collect()
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
        let jacobian: f64 = u.iter().zip(&self.coordinates).map(|(&v, c)| c.ln_jacobian(v)).sum();
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
    struct PriorOnly(Prior);

    impl Posterior for PriorOnly {
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
        let p = Reparameterized::new(PriorOnly(Prior::LogUniform { lower: a, upper: b }), vec![true]);
        let flat = -(b / a).ln().ln();
        for x in [2e-3_f64, 0.5, 80.0] {
            let u = x.ln();
            assert!((p.log_prior(&[u]) - flat).abs() < 1e-12, "x = {x}");
            assert!((p.to_inner(&[u])[0] / x - 1.0).abs() < 1e-15);
        }
        assert_eq!(p.log_prior(&[(b * 1.01).ln()]), f64::NEG_INFINITY);
        assert_eq!(p.from_inner(&[0.0])[0], f64::NEG_INFINITY);
    }

    /// asinh-U[a, b] with scale s in u = asinh(x/s) is U[asinh(a/s), asinh(b/s)]:
    /// flat inside (from compression to decades of tension), −∞ outside, and
    /// the round trip is exact to round-off, at |u| where cosh u would overflow too.
    #[test]
    fn asinh_uniform_becomes_uniform_in_asinh_coordinates() {
        let (a, b, s) = (-0.5e-9, 100e-9, 1e-9);
        let prior = Prior::AsinhUniform { lower: a, upper: b, scale: s };
        let p = Reparameterized::with_coordinates(PriorOnly(prior), vec![Coordinate::uniformising(&prior)]);
        let flat = -((b / s).asinh() - (a / s).asinh()).ln();
        for x in [-0.4e-9, 0.0, 1e-11, 3e-9, 99e-9] {
            let u = (x / s).asinh();
            assert!((p.log_prior(&[u]) - flat).abs() < 1e-12, "x = {x}");
            assert!((p.to_inner(&[u])[0] - x).abs() <= 1e-15 * x.abs().max(s));
        }
        assert_eq!(p.log_prior(&[(a / s).asinh() - 1e-3]), f64::NEG_INFINITY);
        let c = Coordinate::Asinh { scale: 2.0 };
        assert!((c.ln_jacobian(800.0) - (2.0f64.ln() + 800.0 - std::f64::consts::LN_2)).abs() < 1e-12);
        assert!((c.ln_jacobian(0.3) - (2.0 * 0.3f64.cosh()).ln()).abs() < 1e-15);
    }
}
