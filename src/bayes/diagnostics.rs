//! Convergence diagnostics for MCMC output of one scalar parameter:
//! rank-normalised split-R̂, bulk and tail effective sample size, and the
//! integrated autocorrelation time.
//!
//! Definitions follow Vehtari, Gelman, Simpson, Carpenter & Bürkner (2021),
//! "Rank-normalization, folding, and localization: an improved R̂", Bayesian
//! Analysis 16(2), exactly as implemented in ArviZ (`arviz.rhat(method="rank")`,
//! `arviz.ess(method="bulk" | "tail")`):
//!
//! * input: `chains[m][n]`, M chains of N draws each (post burn-in, equal lengths);
//! * split: every chain is cut into its first ⌊N/2⌋ and its last ⌊N/2⌋ draws
//!   (the middle draw is dropped when N is odd), giving 2M chains;
//! * rank normalisation: with r the fractional rank (ties averaged) of a draw
//!   among all S pooled draws, z = Φ⁻¹((r − 3/8)/(S + 1/4)) (Blom);
//! * classic R̂ of M' chains of length n: W = mean of the chain variances
//!   (ddof 1), B = n·var(chain means, ddof 1),
//!   R̂ = sqrt(((n − 1)/n · W + B/n) / W);
//! * rank R̂ = max(R̂ of the rank-normalised split draws,
//!   R̂ of the rank-normalised split folded draws |x − median(x)|);
//! * ESS (Geyer's initial monotone sequence on the multi-chain autocorrelation,
//!   Stan reference manual §"Effective sample size"): with ĉ_m(t) the biased
//!   autocovariance of chain m (divided by n), W = mean_m ĉ_m(0)·n/(n−1),
//!   var⁺ = (n−1)/n·W + var(chain means, ddof 1) (second term only if M > 1),
//!   ρ̂_t = 1 − (W − mean_m ĉ_m(t))/var⁺; pairs Γ_k = ρ̂_{2k} + ρ̂_{2k+1} are summed
//!   while positive and forced monotone non-increasing;
//!   τ̂ = −1 + 2 Σ_{t ≤ t_max} ρ̂_t + ρ̂_{t_max+1}, τ̂ ≥ 1/log10(MN), ESS = MN/τ̂;
//! * bulk ESS = ESS of the split chains of the rank-normalised draws (ranks
//!   over all draws before splitting, as ArviZ does);
//! * tail ESS = min over q ∈ {5 %, 95 %} of the ESS of the split chains of the
//!   indicator I(x ≤ Q(q)), Q the type-7 (linear) quantile of the pooled draws.
//!
//! Deviation from ArviZ: ArviZ returns NaN for R̂ of a single chain; here a
//! single chain is split into two halves and R̂ is computed from those, which
//! is the same formula and still detects a drifting chain. Inputs with fewer
//! than 4 draws per chain, non-finite values or ragged chains give NaN.
//!
//! Autocovariances: the first 64 lags are direct sums (enough for well-mixed
//! chains, where Geyer's sequence stops after a few lags); beyond that all lags
//! come from a small hand-written radix-2 FFT: the `rustfft` crate is not a
//! dependency of this workspace, and the direct O(N·lag) sum becomes O(N²) for
//! poorly mixing chains (4 × 20 000 draws would cost ~10⁹ multiplications per
//! call, three calls per parameter).

use num_complex::Complex64;
use statrs::distribution::{ContinuousCDF, Normal};

/// Rank-normalised split-R̂ (maximum of bulk and folded-tail R̂), see module docs.
/// NaN for invalid input (ragged chains, < 4 draws per chain, non-finite draws).
pub fn rhat(chains: &[Vec<f64>]) -> f64 {
    let Some(n) = valid_draws_per_chain(chains) else {
        return f64::NAN;
    };
    if n < 4 {
        return f64::NAN;
    }
    let split = split_chains(chains);
    let bulk = classic_rhat(&rank_normalize(&split));
    let med = median(&pooled(chains));
    let folded: Vec<Vec<f64>> = chains.iter().map(|c| c.iter().map(|x| (x - med).abs()).collect()).collect();
    let tail = classic_rhat(&rank_normalize(&split_chains(&folded)));
    bulk.max(tail)
}

/// (rank R̂, bulk ESS, tail ESS) together, bit-identical to [`rhat`],
/// [`ess_bulk`], [`ess_tail`] called one by one, with one sort of the pooled
/// draws instead of two sorts and four selections (a large part of a
/// `calibrate`: `benches/README.md`, "Measurements cited by src/"):
/// * with an even number of draws per chain, splitting keeps every draw, so
///   the rank normalisation of the split chains is the split of the rank
///   normalisation (ranks depend on the pooled values only);
/// * the median and the 5 %/95 % quantiles are the same order statistics of
///   the sorted draws as of the selections;
/// * the folded draws |x − med| come sorted from the sorted x without a second
///   sort: x ↦ x − med is monotone in floating point (rounding is monotone),
///   so along ascending x the folded values descend below the median and
///   ascend from it; merging the two runs sorts them (ties are averaged by
///   value, so their order among themselves is irrelevant).
pub fn convergence(chains: &[Vec<f64>]) -> (f64, f64, f64) {
    convergence_and_quantiles(chains, []).0
}

/// [`convergence`] and the type-7 quantiles `ps` of the pooled draws, read
/// from the same sort (`summarize` selected its 95 % interval with two more
/// passes over the draws). The quantiles are the bits of
/// [`quantile_select`] (the same order statistics and formula; see the test
/// `quantile_select_equals_quantile_sorted`); `None` where `convergence` takes
/// its unsorted fallback (an odd or < 4 draw count, or chains of unequal length).
pub fn convergence_and_quantiles<const K: usize>(
    chains: &[Vec<f64>],
    ps: [f64; K],
) -> ((f64, f64, f64), Option<[f64; K]>) {
    let n = match valid_draws_per_chain(chains) {
        Some(n) if n >= 4 && n % 2 == 0 => n,
        _ => return ((rhat(chains), ess_bulk(chains), ess_tail(chains)), None),
    };
    debug_assert!(n % 2 == 0);
    let order = sorted_with_positions(chains);
    let quantiles = ps.map(|p| quantile_of_sorted(order.len(), |k| order[k].0, p));
    let sorted = |k: usize| order[k].0;
    let ranked_split = split_chains(&reshape(&normal_scores(&order), chains));
    let bulk = classic_rhat(&ranked_split);
    let med = quantile_of_sorted(order.len(), sorted, 0.5);
    // first position with x ≥ med (x < med before it, in ascending x)
    let mid = order.partition_point(|&(x, _)| x < med);
    let (below, above) = order.split_at(mid);
    let mut folded = Vec::with_capacity(order.len());
    let (mut i, mut j) = (below.len(), 0);
    while i > 0 || j < above.len() {
        let lo = (i > 0).then(|| ((below[i - 1].0 - med).abs(), below[i - 1].1));
        let hi = (j < above.len()).then(|| ((above[j].0 - med).abs(), above[j].1));
        match (lo, hi) {
            (Some(l), Some(h)) if l.0 <= h.0 => {
                folded.push(l);
                i -= 1;
            }
            (Some(l), None) => {
                folded.push(l);
                i -= 1;
            }
            (_, Some(h)) => {
                folded.push(h);
                j += 1;
            }
            (None, None) => unreachable!("loop condition"),
        }
    }
    let tail = classic_rhat(&split_chains(&reshape(&normal_scores(&folded), chains)));
    let q = [0.05, 0.95].map(|p| quantile_of_sorted(order.len(), sorted, p));
    ((bulk.max(tail), ess(&ranked_split), tail_ess_at(chains, q)), Some(quantiles))
}

/// Bulk effective sample size: ESS of the rank-normalised split chains.
pub fn ess_bulk(chains: &[Vec<f64>]) -> f64 {
    let Some(n) = valid_draws_per_chain(chains) else {
        return f64::NAN;
    };
    if n < 4 {
        return f64::NAN;
    }
    ess(&split_chains(&rank_normalize(chains)))
}

/// Tail effective sample size: min of the ESS of I(x ≤ Q(5 %)) and I(x ≤ Q(95 %)),
/// each on split chains.
pub fn ess_tail(chains: &[Vec<f64>]) -> f64 {
    let Some(n) = valid_draws_per_chain(chains) else {
        return f64::NAN;
    };
    if n < 4 {
        return f64::NAN;
    }
    let mut all = pooled(chains);
    tail_ess_at(chains, [0.05, 0.95].map(|p| quantile_select(&mut all, p)))
}

/// min over the quantiles q of the ESS of the split indicator chains I(x ≤ q).
fn tail_ess_at(chains: &[Vec<f64>], quantiles: [f64; 2]) -> f64 {
    quantiles.iter().map(|&q| indicator_ess(&split_indicator_bits(chains, q))).fold(f64::INFINITY, f64::min)
}

/// A 0/1 series as bits: bit i % 64 of word i / 64 is draw i (zero beyond `n`).
struct Bits {
    words: Vec<u64>,
    n: usize,
}

impl Bits {
    fn ones(&self) -> u64 {
        self.words.iter().map(|w| u64::from(w.count_ones())).sum()
    }

    /// Number of ones among draws a..b (a ≤ b ≤ n).
    fn ones_in(&self, a: usize, b: usize) -> u64 {
        let prefix = |k: usize| -> u64 {
            let full: u64 = self.words[..k / 64].iter().map(|w| u64::from(w.count_ones())).sum();
            let partial =
                if k.is_multiple_of(64) { 0 } else { (self.words[k / 64] & ((1u64 << (k % 64)) - 1)).count_ones() };
            full + u64::from(partial)
        };
        prefix(b) - prefix(a)
    }

    /// The biased lag-t autocovariance (1/n)Σ_{i<n−t} (aᵢ − μ)(a_{i+t} − μ)
    /// of the series with mean μ, from counts (see [`indicator_ess`]).
    fn autocovariance(&self, t: usize, mu: f64) -> f64 {
        let n = self.n;
        let (s, h, tl) = (self.lagged_products(t), self.ones_in(0, n - t), self.ones_in(t, n));
        (s as f64 - mu * (h + tl) as f64 + (n - t) as f64 * mu * mu) / n as f64
    }

    /// Σ_{i < n − t} aᵢ·a_{i+t}: the ones of the series ANDed with itself
    /// shifted down by t (the shifted series is zero from n − t on).
    fn lagged_products(&self, t: usize) -> u64 {
        let (skip, shift) = (t / 64, t % 64);
        let w = &self.words;
        (0..w.len().saturating_sub(skip))
            .map(|k| {
                let lo = w[k + skip] >> shift;
                let hi = if shift == 0 { 0 } else { w.get(k + skip + 1).map_or(0, |x| x << (64 - shift)) };
                u64::from((w[k] & (lo | hi)).count_ones())
            })
            .sum()
    }
}

/// The split chains of I(x ≤ q) as [`split_chains`] orders them (all first
/// halves, then all second halves).
fn split_indicator_bits(chains: &[Vec<f64>], q: f64) -> Vec<Bits> {
    let pack = |draws: &[f64]| Bits {
        words: draws
            .chunks(64)
            .map(|c| c.iter().enumerate().fold(0u64, |w, (i, &x)| w | (u64::from(x <= q) << i)))
            .collect(),
        n: draws.len(),
    };
    let halves = |c: &Vec<f64>| (c.len() / 2, c.len());
    let first = chains.iter().map(|c| pack(&c[..halves(c).0]));
    let second = chains.iter().map(|c| pack(&c[halves(c).1 - halves(c).0..]));
    first.chain(second).collect()
}

/// [`ess`] of indicator chains from exact counts (cheaper than the float
/// autocovariance of the two tail indicators). With k ones in a chain of n, μ = k/n, the centred lag-t sum
/// is Σ_{i<n−t} (aᵢ − μ)(a_{i+t} − μ) = S_t − μ(H_t + T_t) + (n − t)μ², with
/// S_t the lagged products and H_t, T_t the ones among draws 0..n−t and t..n,
/// all integers; the chain means k/n are the bits of [`mean`]'s (a sum of
/// 0/1 is exact). It equals [`ess`] of the 0/1 series up to the rounding of
/// either's sums (see the test `indicator_ess_matches_float_ess`).
fn indicator_ess(chains: &[Bits]) -> f64 {
    let (m, n) = (chains.len(), chains.first().map_or(0, |c| c.n));
    if m == 0 || n < 2 || chains.iter().any(|c| c.n != n) {
        return f64::NAN;
    }
    let ones: Vec<u64> = chains.iter().map(Bits::ones).collect();
    if ones.iter().all(|&k| k == 0) || ones.iter().all(|&k| k == n as u64) {
        return (m * n) as f64; // constant: as `ess`
    }
    let nf = n as f64;
    let means: Vec<f64> = ones.iter().map(|&k| k as f64 / nf).collect();
    let mean_acov =
        |t: usize| chains.iter().zip(&means).map(|(c, &mu)| c.autocovariance(t, mu)).sum::<f64>() / m as f64;
    geyer_ess(n, &means, mean_acov)
}

/// Effective sample size of the given chains as they are (no splitting, no rank
/// normalisation): Geyer's initial monotone sequence on the multi-chain
/// autocorrelation (module docs). Constant input returns the number of draws
/// (as ArviZ); invalid input returns NaN.
pub fn ess(chains: &[Vec<f64>]) -> f64 {
    let Some(n) = valid_draws_per_chain(chains) else {
        return f64::NAN;
    };
    let m = chains.len();
    let total = (m * n) as f64;
    if n < 2 {
        return f64::NAN;
    }
    let (lo, hi) = chains.iter().flatten().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    // ArviZ: `np.max - np.min < np.finfo(float).resolution` (1e-15) → constant.
    if hi - lo < 1e-15 {
        return total;
    }
    let acov = LazyAutocovariance::new(chains);
    let means: Vec<f64> = chains.iter().map(|c| mean(c)).collect();
    geyer_ess(n, &means, |t| acov.mean_at(t))
}

/// Geyer's initial monotone sequence (module docs) for M chains of n ≥ 2
/// draws with chain means `means` and chain-averaged biased autocovariance
/// `mean_acov(t)` (asked for t = 0, 1, 2, … in increasing order).
fn geyer_ess(n: usize, means: &[f64], mean_acov: impl Fn(usize) -> f64) -> f64 {
    let m = means.len();
    let total = (m * n) as f64;
    let nf = n as f64;
    let mean_var = mean_acov(0) * nf / (nf - 1.0);
    let mut var_plus = mean_var * (nf - 1.0) / nf;
    if m > 1 {
        var_plus += variance_ddof1(means);
    }
    let rho = |t: usize| 1.0 - (mean_var - mean_acov(t)) / var_plus;

    // Geyer's initial positive sequence (transcribed from ArviZ `_ess`).
    let mut rho_t = vec![0.0; n];
    let mut rho_even = 1.0;
    rho_t[0] = rho_even;
    let mut rho_odd = if n > 1 { rho(1) } else { 0.0 };
    if n > 1 {
        rho_t[1] = rho_odd;
    }
    let mut t = 1usize;
    while t + 3 < n && rho_even + rho_odd > 0.0 {
        rho_even = rho(t + 1);
        rho_odd = rho(t + 2);
        if rho_even + rho_odd >= 0.0 {
            rho_t[t + 1] = rho_even;
            rho_t[t + 2] = rho_odd;
        }
        t += 2;
    }
    // ArviZ: max_t = t - 2 (may be -1 when the loop never ran: n ≤ 4).
    let max_t = t as i64 - 2;
    if rho_even > 0.0 && max_t + 1 >= 0 && ((max_t + 1) as usize) < n {
        rho_t[(max_t + 1) as usize] = rho_even;
    }
    // Geyer's initial monotone sequence.
    let mut t = 1i64;
    while t <= max_t - 2 {
        let tu = t as usize;
        if rho_t[tu + 1] + rho_t[tu + 2] > rho_t[tu - 1] + rho_t[tu] {
            rho_t[tu + 1] = (rho_t[tu - 1] + rho_t[tu]) / 2.0;
            rho_t[tu + 2] = rho_t[tu + 1];
        }
        t += 2;
    }
    let upto = (max_t + 1).max(0) as usize; // exclusive end of rho_t[: max_t + 1]
    let mut tau = -1.0 + 2.0 * rho_t[..upto.min(n)].iter().sum::<f64>();
    if upto < n {
        tau += rho_t[upto];
    }
    tau = tau.max(1.0 / total.log10());
    let ess = total / tau;
    if rho_t.iter().any(|r| r.is_nan()) {
        f64::NAN
    } else {
        ess
    }
}

/// Normalised autocorrelation ρ_k = ĉ(k)/ĉ(0), k = 0..=max_lag (clipped to N − 1),
/// with the biased autocovariance ĉ(k) = (1/N) Σ_{i<N−k} (x_i − x̄)(x_{i+k} − x̄).
/// A constant series gives ρ_0 = 1 and ρ_k = 0 for k ≥ 1.
pub fn autocorrelation(x: &[f64], max_lag: usize) -> Vec<f64> {
    if x.is_empty() {
        return Vec::new();
    }
    let c = autocovariance(x);
    let last = max_lag.min(x.len() - 1);
    if c[0] <= 0.0 {
        let mut r = vec![0.0; last + 1];
        r[0] = 1.0;
        return r;
    }
    c[..=last].iter().map(|v| v / c[0]).collect()
}

/// Integrated autocorrelation time τ = 1 + 2 Σ_{k=1}^{M} ρ_k of one chain, with
/// Sokal's automatic window: M is the smallest lag with M ≥ c·τ(M), c = 5
/// (Sokal 1997, "Monte Carlo methods in statistical mechanics", §3; also emcee).
/// The chain's ESS is then ≈ N/τ. Returns NaN for fewer than 2 or non-finite draws.
pub fn integrated_autocorrelation_time(x: &[f64]) -> f64 {
    const C: f64 = 5.0;
    if x.len() < 2 || x.iter().any(|v| !v.is_finite()) {
        return f64::NAN;
    }
    let rho = autocorrelation(x, x.len() - 1);
    let mut tau = 1.0;
    for (k, r) in rho.iter().enumerate().skip(1) {
        tau += 2.0 * r;
        if (k as f64) >= C * tau {
            break;
        }
    }
    tau
}

/// Lags below this are summed directly; the first request beyond switches to FFT.
const DIRECT_LAGS: usize = 64;

/// Chain-averaged biased autocovariance mean_m ĉ_m(t), computed on demand: direct
/// sums for t < [`DIRECT_LAGS`] (well-mixed chains stop the Geyer sequence within a
/// few lags, costing O(M·N·t)), otherwise all lags at once by FFT (O(M·N log N)).
struct LazyAutocovariance<'a> {
    chains: &'a [Vec<f64>],
    centred: Vec<Vec<f64>>,
    fft: std::cell::OnceCell<Vec<f64>>,
}

impl<'a> LazyAutocovariance<'a> {
    fn new(chains: &'a [Vec<f64>]) -> Self {
        let centred = chains
            .iter()
            .map(|c| {
                let mu = mean(c);
                c.iter().map(|x| x - mu).collect()
            })
            .collect();
        Self { chains, centred, fft: std::cell::OnceCell::new() }
    }

    fn mean_at(&self, t: usize) -> f64 {
        let m = self.chains.len() as f64;
        if t < DIRECT_LAGS && self.fft.get().is_none() {
            return self.centred.iter().map(|y| dot(&y[..y.len() - t], &y[t..]) / y.len() as f64).sum::<f64>() / m;
        }
        let all = self.fft.get_or_init(|| {
            let per_chain: Vec<Vec<f64>> = self.chains.iter().map(|c| autocovariance(c)).collect();
            (0..per_chain[0].len()).map(|k| per_chain.iter().map(|a| a[k]).sum::<f64>() / m).collect()
        });
        all[t]
    }
}

/// Σ aᵢbᵢ over the common length with four interleaved partial sums, added as
/// (s₀ + s₁) + (s₂ + s₃) + tail: independent additions the CPU pipelines (and
/// vectorises) where one running sum is a chain of dependent additions (issue
/// 15: the direct autocovariance lags were ~5 % of a whole `calibrate`). Its
/// rounding differs from the one-accumulator sum's by O(eps·Σ|aᵢbᵢ|), the
/// order of either's own error (a blocked sum's error bound is, if anything,
/// smaller: Higham, *Accuracy and Stability of Numerical Algorithms*, §4.2).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut s = [0.0f64; 4];
    for (x, y) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        for ((acc, xi), yi) in s.iter_mut().zip(x).zip(y) {
            *acc += xi * yi;
        }
    }
    let tail: f64 = a[n - n % 4..].iter().zip(&b[n - n % 4..]).map(|(x, y)| x * y).sum();
    (s[0] + s[1]) + (s[2] + s[3]) + tail
}

/// Biased autocovariance ĉ(k), k = 0..N−1, of one series, via zero-padded FFT:
/// ĉ = IFFT(|FFT(x − x̄)|²)/N with padding to a power of two ≥ 2N (no wrap-around).
pub fn autocovariance(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    if n == 0 {
        return Vec::new();
    }
    let mu = mean(x);
    let size = (2 * n).next_power_of_two();
    let mut buf: Vec<Complex64> = x.iter().map(|&v| Complex64::new(v - mu, 0.0)).collect();
    buf.resize(size, Complex64::new(0.0, 0.0));
    fft_in_place(&mut buf, false);
    for z in buf.iter_mut() {
        *z = Complex64::new(z.norm_sqr(), 0.0);
    }
    fft_in_place(&mut buf, true);
    let scale = 1.0 / (size as f64 * n as f64);
    buf[..n].iter().map(|z| z.re * scale).collect()
}

/// Iterative radix-2 Cooley–Tukey FFT (length must be a power of two); the
/// inverse is unnormalised (caller divides by the length).
fn fft_in_place(a: &mut [Complex64], inverse: bool) {
    let n = a.len();
    debug_assert!(n.is_power_of_two());
    let mut j = 0usize;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            a.swap(i, j);
        }
    }
    let sign = if inverse { 1.0 } else { -1.0 };
    let mut len = 2;
    while len <= n {
        let ang = sign * 2.0 * std::f64::consts::PI / len as f64;
        // Twiddles computed directly (not by repeated multiplication) to keep
        // round-off at O(ε log N).
        let half = len / 2;
        let tw: Vec<Complex64> = (0..half).map(|k| Complex64::from_polar(1.0, ang * k as f64)).collect();
        for start in (0..n).step_by(len) {
            for k in 0..half {
                let u = a[start + k];
                let v = a[start + k + half] * tw[k];
                a[start + k] = u + v;
                a[start + k + half] = u - v;
            }
        }
        len <<= 1;
    }
}

/// Type-7 (linear interpolation, numpy's default) quantile of sorted data:
/// h = (N − 1)p, Q = x_⌊h⌋ + (h − ⌊h⌋)(x_⌊h⌋+1 − x_⌊h⌋).
pub fn quantile_sorted(sorted: &[f64], p: f64) -> f64 {
    let n = sorted.len();
    if n == 0 {
        return f64::NAN;
    }
    let h = (n - 1) as f64 * p.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(n - 1);
    sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
}

/// Rank-normalises all draws jointly: z = Φ⁻¹((r − 3/8)/(S + 1/4)) with r the
/// average (fractional) rank among all S pooled draws, returned in the same shape.
pub fn rank_normalize(chains: &[Vec<f64>]) -> Vec<Vec<f64>> {
    reshape(&normal_scores(&sorted_with_positions(chains)), chains)
}

/// (value, pooled position) of every draw, sorted by value (ties get their
/// average rank in [`normal_scores`], so their order among themselves is
/// irrelevant). An LSD radix sort on the keys' bits (`radsort`, which skips
/// the bytes all keys share), fewer instructions than a comparison sort on
/// a calibration's draws (`benches/README.md`, "Measurements cited by src/"). The
/// draws are finite ([`valid_draws_per_chain`]), where its order is `<`'s
/// (−0 just before +0, as `total_cmp`; `==` groups them either way).
fn sorted_with_positions(chains: &[Vec<f64>]) -> Vec<(f64, usize)> {
    let mut order: Vec<(f64, usize)> = chains.iter().flatten().copied().zip(0..).collect();
    radsort::sort_by_key(&mut order, |a| a.0);
    order
}

/// Blom scores z = Φ⁻¹((r − 3/8)/(S + 1/4)) by pooled position, from values
/// sorted ascending with their positions; Φ⁻¹ once per tie group (a chain
/// repeats its state at every rejection, so there are several times fewer
/// groups than draws).
fn normal_scores(order: &[(f64, usize)]) -> Vec<f64> {
    let s = order.len();
    let normal = Normal::new(0.0, 1.0).expect("standard normal");
    let denom = s as f64 + 0.25;
    let mut z = vec![0.0; s];
    let mut i = 0;
    while i < s {
        let mut j = i;
        while j + 1 < s && order[j + 1].0 == order[i].0 {
            j += 1;
        }
        // Positions i..=j (0-based) share the average 1-based rank.
        let r = (i + j) as f64 / 2.0 + 1.0;
        let zr = normal.inverse_cdf((r - 0.375) / denom);
        for &(_, k) in &order[i..=j] {
            z[k] = zr;
        }
        i = j + 1;
    }
    z
}

/// Pooled values back in the shape of `chains`.
fn reshape(z: &[f64], chains: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let mut out = Vec::with_capacity(chains.len());
    let mut k = 0;
    for c in chains {
        out.push(z[k..k + c.len()].to_vec());
        k += c.len();
    }
    out
}

/// The type-7 quantile of n sorted values `sorted(0..n)`: the same order
/// statistics and formula as [`quantile_select`] and [`quantile_sorted`].
fn quantile_of_sorted(n: usize, sorted: impl Fn(usize) -> f64, p: f64) -> f64 {
    if n == 0 {
        return f64::NAN;
    }
    let h = (n - 1) as f64 * p.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(n - 1);
    sorted(lo) + (h - lo as f64) * (sorted(hi) - sorted(lo))
}

/// [`quantile_sorted`] of `x` without sorting it (two selections, same value:
/// the type-7 quantile needs only the order statistics ⌊h⌋ and ⌊h⌋ + 1); `x` is reordered.
pub fn quantile_select(x: &mut [f64], p: f64) -> f64 {
    let n = x.len();
    if n == 0 {
        return f64::NAN;
    }
    let h = (n - 1) as f64 * p.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let (_, &mut at_lo, right) = x.select_nth_unstable_by(lo, f64::total_cmp);
    let at_hi = right.iter().copied().min_by(f64::total_cmp).unwrap_or(at_lo);
    at_lo + (h - lo as f64) * (at_hi - at_lo)
}

/// Splits every chain into its first ⌊N/2⌋ and last ⌊N/2⌋ draws.
pub fn split_chains(chains: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let mut out = Vec::with_capacity(2 * chains.len());
    let mut second = Vec::with_capacity(chains.len());
    for c in chains {
        let half = c.len() / 2;
        out.push(c[..half].to_vec());
        second.push(c[c.len() - half..].to_vec());
    }
    // ArviZ stacks all first halves, then all second halves.
    out.extend(second);
    out
}

/// Classic (non-split) potential scale reduction factor of equal-length chains.
pub fn classic_rhat(chains: &[Vec<f64>]) -> f64 {
    let n = chains[0].len() as f64;
    let means: Vec<f64> = chains.iter().map(|c| mean(c)).collect();
    let w = chains.iter().map(|c| variance_ddof1(c)).sum::<f64>() / chains.len() as f64;
    let b = n * variance_ddof1(&means);
    ((b / w + n - 1.0) / n).sqrt()
}

fn valid_draws_per_chain(chains: &[Vec<f64>]) -> Option<usize> {
    let n = chains.first()?.len();
    let ok = chains.iter().all(|c| c.len() == n && c.iter().all(|x| x.is_finite()));
    ok.then_some(n)
}

fn pooled(chains: &[Vec<f64>]) -> Vec<f64> {
    chains.iter().flatten().copied().collect()
}

fn median(x: &[f64]) -> f64 {
    quantile_select(&mut x.to_vec(), 0.5)
}

pub(crate) fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

pub(crate) fn variance_ddof1(x: &[f64]) -> f64 {
    let mu = mean(x);
    x.iter().map(|v| (v - mu) * (v - mu)).sum::<f64>() / (x.len() as f64 - 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shared computation gives the bits of the three separate ones (even
    /// and odd chain lengths, ties from repeated states included).
    #[test]
    fn convergence_equals_the_separate_diagnostics() {
        for n in [4usize, 9, 50, 51] {
            let chains: Vec<Vec<f64>> = (0..4)
                .map(|c| (0..n).map(|i| (((i / 3) * 7919 + c * 104_729) % 97) as f64 * 0.01 + c as f64 * 0.1).collect())
                .collect();
            let (r, b, t) = convergence(&chains);
            assert_eq!(r.to_bits(), rhat(&chains).to_bits(), "n = {n}");
            assert_eq!(b.to_bits(), ess_bulk(&chains).to_bits(), "n = {n}");
            assert_eq!(t.to_bits(), ess_tail(&chains).to_bits(), "n = {n}");
        }
        // MCMC-like: random walks that repeat their state on ~half the steps,
        // values on both sides of the median at equal distances (folded ties)
        let mut state = 12345u64;
        let mut u = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let chains: Vec<Vec<f64>> = (0..4)
            .map(|_| {
                let mut x = 0.0f64;
                (0..2000)
                    .map(|_| {
                        if u() < 0.5 {
                            x = ((x + (u() - 0.5)) * 64.0).round() / 64.0;
                        }
                        x
                    })
                    .collect()
            })
            .collect();
        let (r, b, t) = convergence(&chains);
        assert_eq!(r.to_bits(), rhat(&chains).to_bits());
        assert_eq!(b.to_bits(), ess_bulk(&chains).to_bits());
        assert_eq!(t.to_bits(), ess_tail(&chains).to_bits());
        // the quantiles read from the shared sort are the selections' bits
        let ps = [0.0, 0.025, 0.5, 0.975, 1.0];
        let ((r2, b2, t2), q) = convergence_and_quantiles(&chains, ps);
        assert_eq!((r2.to_bits(), b2.to_bits(), t2.to_bits()), (r.to_bits(), b.to_bits(), t.to_bits()));
        let q = q.expect("even chain length: the sorted route");
        let mut all = pooled(&chains);
        for (p, qk) in ps.into_iter().zip(q) {
            assert_eq!(qk.to_bits(), quantile_select(&mut all, p).to_bits(), "p = {p}");
        }
    }

    /// The integer-count tail ESS agrees with the float ESS of the same 0/1
    /// split chains. Per lag, the float chain-average of (1/n)Σ(aᵢ − μ)(a_{i+t} − μ)
    /// sums n terms of magnitude ≤ 1, so its rounding is ≤ γ_n ≈ n·ε absolute
    /// (Higham §3.1); the count route rounds a few times at magnitude ≤ 1 after
    /// dividing by n. So |Δ| ≤ 2nε per lag; ESS itself is compared at 1e-9
    /// relative: τ̂ sums L ≤ 50 lags (these walks stop within ~20) of
    /// ρ̂ = 1 − (W − ĉ_t)/var⁺, var⁺ ≥ p(1 − p) ≥ 0.0475, so its error is
    /// ≤ 2L·2nε/0.0475 ≈ 4.5e-10 at n = 500 (the bound is loose, the test is not).
    #[test]
    fn indicator_ess_matches_float_ess() {
        let mut state = 987_654_321u64;
        let mut u = move || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [9usize, 130, 1001] {
            let chains: Vec<Vec<f64>> = (0..4)
                .map(|_| {
                    let mut x = 0.0f64;
                    (0..n)
                        .map(|_| {
                            if u() < 0.6 {
                                x += u() - 0.5;
                            }
                            x
                        })
                        .collect()
                })
                .collect();
            let mut all = pooled(&chains);
            for p in [0.0, 0.05, 0.5, 0.95, 1.0] {
                let q = quantile_select(&mut all, p) - if p == 0.0 { 1.0 } else { 0.0 };
                let bits = split_indicator_bits(&chains, q);
                let float: Vec<Vec<f64>> =
                    chains.iter().map(|c| c.iter().map(|&x| if x <= q { 1.0 } else { 0.0 }).collect()).collect();
                let split = split_chains(&float);
                for (b, f) in bits.iter().zip(&split) {
                    assert_eq!(b.n, f.len());
                    let ones = f.iter().filter(|&&v| v == 1.0).count() as u64;
                    assert_eq!(b.ones(), ones, "n = {n}, p = {p}");
                    for t in 0..b.n {
                        let direct = (0..b.n - t).filter(|&i| f[i] == 1.0 && f[i + t] == 1.0).count() as u64;
                        assert_eq!(b.lagged_products(t), direct, "n = {n}, p = {p}, t = {t}");
                        let head = f[..b.n - t].iter().filter(|&&v| v == 1.0).count() as u64;
                        assert_eq!(b.ones_in(0, b.n - t), head);
                    }
                }
                let (fast, slow) = (indicator_ess(&bits), ess(&split));
                let half = split[0].len();
                if half >= 2 {
                    assert!((fast - slow).abs() <= 1e-9 * slow.abs(), "n = {n}, p = {p}: {fast} vs {slow}");
                    let acov = LazyAutocovariance::new(&split);
                    for t in 0..half.min(64) {
                        let means: Vec<f64> = split.iter().map(|c| mean(c)).collect();
                        let exact = bits.iter().zip(&means).map(|(c, &mu)| c.autocovariance(t, mu)).sum::<f64>()
                            / bits.len() as f64;
                        let bound = 2.0 * half as f64 * f64::EPSILON;
                        assert!((acov.mean_at(t) - exact).abs() <= bound, "n = {n}, p = {p}, t = {t}");
                    }
                }
            }
        }
    }

    /// The radix sort orders as `total_cmp` does (−0 before +0, ties
    /// adjacent) and keeps every (value, position) pair.
    #[test]
    fn sorted_with_positions_orders_as_total_cmp() {
        let chains = vec![vec![0.5, -0.0, 3.0, -2.5, 0.0, 1e-300], vec![-1e300, 0.5, -0.0, 7.0, -2.5, 0.0]];
        let order = sorted_with_positions(&chains);
        let mut expected: Vec<(f64, usize)> = chains.iter().flatten().copied().zip(0..).collect();
        expected.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut got = order.clone();
        // ties among themselves in any order: compare as sorted pairs
        got.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        assert_eq!(got, expected);
        assert!(order.windows(2).all(|w| w[0].0.total_cmp(&w[1].0).is_le()), "{order:?}");
    }

    /// Selection gives the bits of the sorted type-7 quantile, ties and ends included.
    #[test]
    fn quantile_select_equals_quantile_sorted() {
        for n in [1usize, 2, 3, 10, 101] {
            let x: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 * 0.37 - 1.0).collect();
            let mut sorted = x.clone();
            sorted.sort_by(f64::total_cmp);
            for p in [0.0, 0.025, 0.05, 0.5, 0.95, 0.975, 1.0] {
                assert_eq!(quantile_select(&mut x.clone(), p).to_bits(), quantile_sorted(&sorted, p).to_bits());
            }
        }
    }

    #[test]
    fn fft_autocovariance_matches_direct_sum() {
        let x: Vec<f64> = (0..37).map(|i| ((i * 7919) % 31) as f64 * 0.3 - (i as f64).sin()).collect();
        let c = autocovariance(&x);
        let mu = mean(&x);
        for k in 0..x.len() {
            let direct: f64 = (0..x.len() - k).map(|i| (x[i] - mu) * (x[i + k] - mu)).sum::<f64>() / x.len() as f64;
            // FFT round-off: O(ε log2(size) Σx²/N) ≈ 1e-16·7·(c0 scale ≈ 10) → 1e-12 is ≥ 100× margin.
            assert!((c[k] - direct).abs() < 1e-12, "lag {k}: {} vs {direct}", c[k]);
        }
    }
}
