//! Stabilisation diagram: poles of the initial estimator at increasing model
//! orders, each classified against the poles of the previous order with the
//! usual criteria (Peeters & De Roeck 2001; Heylen, Lammens & Sas, *Modal
//! Analysis Theory and Testing*, 1997): a pole is *stable* when the previous
//! order has a pole within 1 % in natural frequency and 5 % in damping ratio.
//! Physical poles are stable over many orders; poles that fit noise or
//! approximate the non-modal background wander from order to order.
//!
//! Selection: stable poles are clustered across orders by natural frequency
//! (a pole joins the cluster whose latest member is within 1 %); a cluster
//! is a **mode** when it holds a stable pole in at least half of the orders
//! above the lowest order at which it appears — at least [`MIN_STABLE_ORDERS`] — and
//! lies inside the measured band. Only underdamped poles (complex, Re s < 0,
//! ζ < 1) can be modes; real poles are relaxation/background terms and are
//! kept separately for the refinement. Each mode's initial value is its
//! member at the highest order.

use num_complex::Complex64;
use serde::Serialize;

/// Relative natural-frequency tolerance of a stable pole.
pub const FREQ_TOL: f64 = 0.01;
/// Relative damping tolerance of a stable pole.
pub const DAMPING_TOL: f64 = 0.05;
/// Fewest orders a mode must be stable over.
pub const MIN_STABLE_ORDERS: usize = 4;
/// A pole with |Im s| ≤ this fraction of |s| counts as real.
pub const REAL_POLE_TOL: f64 = 1e-6;

/// How a pole compares with the previous order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Stability {
    /// Stable in frequency and damping.
    Stable,
    /// Stable in frequency only.
    Frequency,
    /// New or wandering.
    Unstable,
    /// A real (non-oscillatory) pole.
    Real,
}

/// One pole of the diagram.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DiagramPole {
    pub order: usize,
    pub omega_rad_s: f64,
    pub zeta: f64,
    pub stability: Stability,
    #[serde(skip)]
    pub pole: Complex64,
}

/// The diagram and what was selected from it.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Diagram {
    pub orders: Vec<usize>,
    pub poles: Vec<DiagramPole>,
}

/// ωₙ = |s| and ζ = −Re s/|s|.
pub fn omega_zeta(p: Complex64) -> (f64, f64) {
    let w = p.norm();
    (w, -p.re / w)
}

fn is_real(p: Complex64) -> bool {
    p.im.abs() <= REAL_POLE_TOL * p.norm()
}

impl Diagram {
    /// Builds the diagram from the stable-half-plane poles of each order
    /// (`poles_by_order[i]` belongs to `orders[i]`).
    pub fn build(orders: Vec<usize>, poles_by_order: &[Vec<Complex64>]) -> Self {
        let mut out = Vec::new();
        let mut prev: Vec<Complex64> = Vec::new();
        for (&order, poles) in orders.iter().zip(poles_by_order) {
            let mut current = Vec::new();
            for &p in poles.iter().filter(|p| p.re < 0.0 && (p.im > 0.0 || is_real(**p))) {
                let (w, z) = omega_zeta(p);
                let stability = if is_real(p) { Stability::Real } else { classify(w, z, &prev) };
                out.push(DiagramPole { order, omega_rad_s: w, zeta: z, stability, pole: p });
                if !is_real(p) {
                    current.push(p);
                }
            }
            prev = current;
        }
        Self { orders, poles: out }
    }

    /// The modes: clusters of stable poles (see the module doc) whose
    /// frequency lies in `[w_lo, w_hi]`, as initial poles sorted by frequency.
    /// With `frequency_only` a pole stable in frequency alone also counts
    /// (PSD records: the reasoning is where `identify::identify` reads the diagram).
    pub fn modes(&self, w_lo: f64, w_hi: f64, frequency_only: bool) -> Vec<Complex64> {
        // cluster: (latest ω, member count, first order, latest pole, latest order)
        let mut clusters: Vec<(f64, usize, usize, Complex64, usize)> = Vec::new();
        let counts = |s: Stability| s == Stability::Stable || (frequency_only && s == Stability::Frequency);
        for p in self.poles.iter().filter(|p| counts(p.stability)) {
            let hit = clusters
                .iter_mut()
                .filter(|c| c.4 < p.order && ((p.omega_rad_s - c.0).abs() <= FREQ_TOL * c.0))
                .min_by(|a, b| (p.omega_rad_s - a.0).abs().total_cmp(&(p.omega_rad_s - b.0).abs()));
            match hit {
                Some(c) => {
                    c.0 = p.omega_rad_s;
                    c.1 += 1;
                    c.3 = p.pole;
                    c.4 = p.order;
                }
                None => clusters.push((p.omega_rad_s, 1, p.order, p.pole, p.order)),
            }
        }
        let orders_above = |first: usize| self.orders.iter().filter(|&&o| o >= first).count();
        let mut modes: Vec<Complex64> = clusters
            .into_iter()
            .filter(|c| c.1 >= MIN_STABLE_ORDERS && 2 * c.1 >= orders_above(c.2))
            .filter(|c| c.0 >= w_lo && c.0 <= w_hi)
            .map(|c| c.3)
            .collect();
        modes.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
        // two clusters of one physical pole (a split at one order) keep the longer-lived member
        modes.dedup_by(|a, b| (a.norm() - b.norm()).abs() <= FREQ_TOL * b.norm());
        modes
    }

    /// Real poles (as positive decay rates, rad/s) of the highest order.
    pub fn real_poles_at_top(&self) -> Vec<f64> {
        let top = self.orders.last().copied().unwrap_or(0);
        self.poles.iter().filter(|p| p.order == top && p.stability == Stability::Real).map(|p| -p.pole.re).collect()
    }
}

fn classify(w: f64, z: f64, prev: &[Complex64]) -> Stability {
    let mut best = Stability::Unstable;
    for &q in prev {
        let (wq, zq) = omega_zeta(q);
        if (w - wq).abs() <= FREQ_TOL * w {
            if (z - zq).abs() <= DAMPING_TOL * z {
                return Stability::Stable;
            }
            best = Stability::Frequency;
        }
    }
    best
}
