//! Convergence diagnostics (src/bayes/diagnostics.rs) and posterior summaries
//! (src/bayes/summary.rs): hand-checkable tiny examples computed from the
//! definitions (Vehtari et al. 2021 / ArviZ), and statistical checks on
//! synthetic chains whose true ESS / R̂ are known, with tolerances derived from
//! the sampling distribution of the estimators (comments beside each).

use nanobeam::bayes::diagnostics::{
    autocorrelation, classic_rhat, ess, ess_bulk, ess_tail, integrated_autocorrelation_time, quantile_sorted,
    rank_normalize, rhat, split_chains,
};
use nanobeam::bayes::summary::summarize;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use statrs::distribution::{ChiSquared, ContinuousCDF, Normal};

fn phi_inv(p: f64) -> f64 {
    Normal::new(0.0, 1.0).unwrap().inverse_cdf(p)
}

/// AR(1) chains x_t = φ x_{t−1} + sqrt(1 − φ²) ε_t started in stationarity
/// (x_0 ~ N(0, 1)), so the marginal is N(0, 1) and ρ_k = φ^k,
/// τ = 1 + 2Σφ^k = (1 + φ)/(1 − φ).
fn ar1_chains(phi: f64, chains: usize, draws: usize, seed: u64) -> Vec<Vec<f64>> {
    (0..chains)
        .map(|c| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed * 1000 + c as u64);
            let s = (1.0 - phi * phi).sqrt();
            let mut x: f64 = StandardNormal.sample(&mut rng);
            (0..draws)
                .map(|_| {
                    let e: f64 = StandardNormal.sample(&mut rng);
                    x = phi * x + s * e;
                    x
                })
                .collect()
        })
        .collect()
}

// ------------------------------------------------------------ hand examples

#[test]
fn type7_quantile_matches_numpy_definition() {
    // numpy.quantile([1,2,3,4], q): h = 3q; 0.25 → 1.75, 0.5 → 2.5, 0.975 → 3.925.
    let x = [1.0, 2.0, 3.0, 4.0];
    assert_eq!(quantile_sorted(&x, 0.25), 1.75);
    assert_eq!(quantile_sorted(&x, 0.5), 2.5);
    assert!((quantile_sorted(&x, 0.975) - 3.925).abs() < 1e-15);
    assert_eq!(quantile_sorted(&x, 0.0), 1.0);
    assert_eq!(quantile_sorted(&x, 1.0), 4.0);
}

#[test]
fn rank_normalisation_averages_ties() {
    // [1, 2, 2, 3] → fractional ranks [1, 2.5, 2.5, 4]; S = 4, z = Φ⁻¹((r − 3/8)/4.25):
    // r = 2.5 → Φ⁻¹(0.5) = 0; r = 1 and r = 4 are symmetric: (0.625 + 3.625)/4.25 = 1.
    let z = rank_normalize(&[vec![1.0, 2.0, 2.0, 3.0]]);
    assert_eq!(z[0][1], 0.0);
    assert_eq!(z[0][2], 0.0);
    assert!((z[0][0] - phi_inv(0.625 / 4.25)).abs() < 1e-15);
    assert!((z[0][0] + z[0][3]).abs() < 1e-12);
}

#[test]
fn split_drops_the_middle_draw_of_odd_chains() {
    let s = split_chains(&[vec![1.0, 2.0, 3.0, 4.0, 5.0], vec![6.0, 7.0, 8.0, 9.0, 10.0]]);
    assert_eq!(s, vec![vec![1.0, 2.0], vec![6.0, 7.0], vec![4.0, 5.0], vec![9.0, 10.0]]);
}

/// R̂ of chains of length 2 from the definition: chain variance (ddof 1) of a
/// pair (a, b) is (a − b)²/2; B = n·var(means), n = 2.
fn rhat_of_pairs(pairs: &[(f64, f64)]) -> f64 {
    let m = pairs.len() as f64;
    let means: Vec<f64> = pairs.iter().map(|(a, b)| (a + b) / 2.0).collect();
    let grand = means.iter().sum::<f64>() / m;
    let w = pairs.iter().map(|(a, b)| (a - b).powi(2) / 2.0).sum::<f64>() / m;
    let b = 2.0 * means.iter().map(|x| (x - grand).powi(2)).sum::<f64>() / (m - 1.0);
    ((b / w + 1.0) / 2.0).sqrt()
}

#[test]
fn rank_rhat_tiny_example_by_hand() {
    // Chains A = [1,2,3,4], B = [5,6,7,8]. Split: {1,2}, {5,6}, {3,4}, {7,8};
    // 8 distinct values → ranks = values, z_k = Φ⁻¹((k − 3/8)/8.25).
    let z = |r: f64| phi_inv((r - 0.375) / 8.25);
    let bulk = rhat_of_pairs(&[(z(1.0), z(2.0)), (z(5.0), z(6.0)), (z(3.0), z(4.0)), (z(7.0), z(8.0))]);
    // Folded about the median 4.5: A → [3.5, 2.5, 1.5, 0.5], B → [0.5, 1.5, 2.5, 3.5].
    // Split: {3.5, 2.5}, {0.5, 1.5}, {1.5, 0.5}, {2.5, 3.5}; every value appears twice,
    // so average ranks are 0.5 → 1.5, 1.5 → 3.5, 2.5 → 5.5, 3.5 → 7.5.
    let tail = rhat_of_pairs(&[(z(7.5), z(5.5)), (z(1.5), z(3.5)), (z(3.5), z(1.5)), (z(5.5), z(7.5))]);
    let expected = bulk.max(tail);
    let got = rhat(&[vec![1.0, 2.0, 3.0, 4.0], vec![5.0, 6.0, 7.0, 8.0]]);
    assert!((got - expected).abs() < 1e-12, "{got} vs {expected} (bulk {bulk}, tail {tail})");
    assert!(got > 2.0, "two non-overlapping chains: R̂ = {got}");
}

#[test]
fn ess_tiny_examples_by_hand() {
    // (1) Antithetic x = [1,−1,1,−1,1,−1,1,−1]: ĉ0 = 1, ĉ1 = −7/8; W = 8/7, var⁺ = 1,
    // ρ̂1 = 1 − (8/7 + 7/8) = −57/56; ρ̂0 + ρ̂1 < 0 so the Geyer loop never runs,
    // t_max = −1, τ̂ = −1 + ρ̂0 = 0 → capped at 1/log10(8): ESS = 8·log10(8).
    let alt: Vec<f64> = (0..8).map(|i| if i % 2 == 0 { 1.0 } else { -1.0 }).collect();
    assert!((ess(&[alt]) - 8.0 * 8f64.log10()).abs() < 1e-12);

    // (2) x = [0,0,0,0,1,1,1,1]: ĉ_t = (8 − 3t)/32 for t ≤ 4; W = 2/7, var⁺ = 1/4,
    // ρ̂_t = −1/7 + 4ĉ_t: ρ̂1 = 27/56, ρ̂2 = 3/28, ρ̂3 = −15/56.
    // Loop at t = 1: ρ̂2 + ρ̂3 < 0 → stop, t_max = 1; ρ̂2 > 0 is kept as the last term:
    // τ̂ = −1 + 2(1 + 27/56) + 3/28 = 29/14, ESS = 8·14/29 = 112/29.
    let step = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
    let got_step = ess(std::slice::from_ref(&step));
    assert!((got_step - 112.0 / 29.0).abs() < 1e-12, "{got_step}");

    // (3) Two chains: `step` and `step + 10`. Same ĉ_t per chain (ĉ4 = −4/32,
    // ĉ5 = −3/32: all pairs at lag ≥ 4 straddle the step); W = 2/7;
    // var⁺ = (7/8)W + var(0.5, 10.5) = 1/4 + 50. ρ̂_t = 1 − (W − ĉ_t)/var⁺ decreases
    // with t and stays positive: the loop runs for t = 1, 3 (t + 3 < 8), storing
    // ρ̂1..ρ̂5; t_max = 3, the monotone step changes nothing,
    // τ̂ = −1 + 2(ρ̂0 + ρ̂1 + ρ̂2 + ρ̂3) + ρ̂4, ESS = 16/τ̂.
    let c = [8.0, 5.0, 2.0, -1.0, -4.0].map(|v| v / 32.0);
    let w = 2.0 / 7.0;
    let var_plus = 0.25 + 50.0;
    let mut rho: Vec<f64> = c.iter().map(|ct| 1.0 - (w - ct) / var_plus).collect();
    rho[0] = 1.0; // ρ̂_0 ≡ 1 by definition (Stan/ArviZ), not 1 − (W − ĉ_0)/var⁺.
    let tau = -1.0 + 2.0 * (rho[0] + rho[1] + rho[2] + rho[3]) + rho[4];
    let shifted: Vec<f64> = step.iter().map(|v| v + 10.0).collect();
    let got = ess(&[step, shifted]);
    assert!((got - 16.0 / tau).abs() < 1e-10, "{got} vs {}", 16.0 / tau);
}

#[test]
fn invalid_input_gives_nan_and_constant_gives_draw_count() {
    assert!(rhat(&[vec![1.0, 2.0, 3.0, 4.0], vec![1.0, 2.0, 3.0]]).is_nan());
    assert!(ess_bulk(&[vec![1.0, f64::NAN, 3.0, 4.0]]).is_nan());
    assert!(rhat(&[vec![1.0, 2.0, 3.0]]).is_nan());
    assert!(ess_tail(&[]).is_nan());
    assert_eq!(ess(&[vec![2.0; 10], vec![2.0; 10]]), 20.0);
}

// ------------------------------------------------------------ statistical checks

#[test]
fn iid_normal_chains_converge() {
    let (m, n_draw) = (4, 5000);
    let chains = ar1_chains(0.0, m, n_draw, 1);
    let s = (m * n_draw) as f64;
    // R̂: split chains n = 2500, M' = 8. For iid normal draws (after the rank
    // transform, still ≈ iid normal) B/W ~ F(M'−1, M'(n−1)) ≈ χ²₇/7 and
    // R̂² = (n − 1)/n + (B/W)/n, so R̂ ∈ [sqrt((n−1)/n), sqrt((n − 1 + q)/n)] with
    // q the 1 − 1e-6 quantile of χ²₇/7 (each of bulk/folded fails w.p. 1e-6).
    let n = (n_draw / 2) as f64;
    let q = ChiSquared::new(7.0).unwrap().inverse_cdf(1.0 - 1e-6) / 7.0;
    let r = rhat(&chains);
    eprintln!("iid: R̂ = {r}, band [{}, {}]", ((n - 1.0) / n).sqrt(), ((n - 1.0 + q) / n).sqrt());
    assert!(r >= ((n - 1.0) / n).sqrt() && r <= ((n - 1.0 + q) / n).sqrt());
    assert!(r < 1.01);
    // ESS: τ̂ − 1 = 2Σρ̂_t over the lags Geyer keeps. For iid draws each ρ̂_t has
    // sd 1/√S (Bartlett) and each pair Γ_k is positive w.p. ≈ 1/2, so more than
    // K = 15 pairs are kept w.p. ≈ 2⁻¹⁵; with ≤ 2K + 1 = 31 lags, 4σ gives
    // |τ̂ − 1| ≤ 2·4·√31/√S = δ, and ESS/S ∈ [1/(1 + δ), 1/(1 − δ)].
    let delta = 8.0 * 31f64.sqrt() / s.sqrt();
    for (what, e) in [("bulk", ess_bulk(&chains)), ("tail", ess_tail(&chains)), ("plain", ess(&chains))] {
        eprintln!("iid: ESS {what} = {e} of {s} (band ±{delta:.3} in τ)");
        assert!(e >= s / (1.0 + delta) && e <= s / (1.0 - delta), "{what} ESS {e}");
    }
}

#[test]
fn ar1_ess_matches_theory() {
    // True ESS = S/τ, τ = (1 + φ)/(1 − φ). Var(τ̂)/τ² ≈ 2(2M + 1)/S for a window of
    // M lags (Madras & Sokal 1988); Geyer's initial sequence stops where the pair
    // sums reach the noise level (for φ = 0.9 at ≈ 2-4τ), so M ≤ max(5τ, 10) and
    // the 4σ relative tolerance is 4·sqrt(2(2M + 1)/S).
    let (m, n_draw) = (4, 20_000);
    let s = (m * n_draw) as f64;
    for (k, phi) in [0.5, 0.9, -0.3].into_iter().enumerate() {
        let chains = ar1_chains(phi, m, n_draw, 10 + k as u64);
        let tau = (1.0 + phi) / (1.0 - phi);
        let window = (5.0 * tau).max(10.0);
        let tol = 4.0 * (2.0 * (2.0 * window + 1.0) / s).sqrt();
        let expected = s / tau;
        let t0 = std::time::Instant::now();
        let (plain, bulk, tail, r) = (ess(&chains), ess_bulk(&chains), ess_tail(&chains), rhat(&chains));
        eprintln!(
            "AR(1) φ = {phi}: expected {expected:.0}, ess {plain:.0}, bulk {bulk:.0}, tail {tail:.0}, R̂ {r:.5} ({:?} for all four)",
            t0.elapsed()
        );
        // The rank transform of an N(0,1) AR(1) chain is ≈ the identity, so bulk ESS
        // has the same target; tail ESS (indicator chains) has a different one and is
        // only checked below.
        for (what, e) in [("plain", plain), ("bulk", bulk)] {
            assert!((e / expected - 1.0).abs() <= tol, "φ = {phi}: {what} ESS {e} vs {expected} (tol {tol})");
        }
        // The indicator of a Gaussian AR(1) chain is at most as autocorrelated as
        // the chain: |corr(f(x_0), g(x_k))| ≤ |ρ_k| = |φ|^k (the maximal correlation
        // of a bivariate normal is |ρ|, Lancaster 1957), so its τ is at most
        // (1 + |φ|)/(1 − |φ|) and its ESS at least S(1 − |φ|)/(1 + |φ|), up to the
        // same estimation tolerance.
        let tail_floor = s * (1.0 - phi.abs()) / (1.0 + phi.abs());
        assert!(tail >= tail_floor * (1.0 - tol), "φ = {phi}: tail ESS {tail} vs floor {tail_floor}");
        assert!(r < 1.01, "stationary chains: R̂ {r}");
    }
}

#[test]
fn integrated_autocorrelation_time_of_ar1() {
    // One chain of N = 100 000, φ = 0.9 (τ = 19); Sokal's window M ≈ 5τ, so the 4σ
    // relative tolerance is 4·sqrt(2(2M + 1)/N) ≈ 0.25; window truncation bias
    // 2φ^M/(1 − φ) ≈ 1e-3 is negligible.
    let x = &ar1_chains(0.9, 1, 100_000, 3)[0];
    let tau = integrated_autocorrelation_time(x);
    let tol = 4.0 * (2.0 * (2.0 * 95.0 + 1.0) / 1e5f64).sqrt();
    eprintln!("IAT: {tau} vs 19 (tol {tol})");
    assert!((tau / 19.0 - 1.0).abs() <= tol);
    // iid: τ = 1; window M ≈ 5 lags → 4·sqrt(2·11/N).
    let y = &ar1_chains(0.0, 1, 100_000, 4)[0];
    let tau0 = integrated_autocorrelation_time(y);
    assert!((tau0 - 1.0).abs() <= 4.0 * (22.0 / 1e5f64).sqrt(), "{tau0}");
}

#[test]
fn autocorrelation_of_ar1_follows_phi_power_k() {
    // Bartlett: Var(ρ̂_k) ≈ (1/N)[(1 + φ²)(1 − φ^{2k})/(1 − φ²) − 2kφ^{2k}] for AR(1).
    let phi: f64 = 0.5;
    let n = 100_000;
    let x = &ar1_chains(phi, 1, n, 5)[0];
    let rho = autocorrelation(x, 5);
    assert_eq!(rho.len(), 6);
    assert_eq!(rho[0], 1.0);
    #[allow(clippy::needless_range_loop)] // k is the lag in the formula, not just an index
    for k in 1..=5 {
        let p2k = phi.powi(2 * k as i32);
        let var = ((1.0 + phi * phi) * (1.0 - p2k) / (1.0 - phi * phi) - 2.0 * k as f64 * p2k) / n as f64;
        assert!((rho[k] - phi.powi(k as i32)).abs() <= 4.0 * var.sqrt(), "lag {k}: {}", rho[k]);
    }
}

#[test]
fn shifted_chain_means_are_detected() {
    // 4 iid N(0,1) chains of 2000, one shifted by δ = 1. Split (8 chains, 2 shifted):
    // var of the chain means ≈ δ²·(2·6)/(8·7) = 0.214δ²; after the rank transform
    // W and the between-chain spread shrink by about the same factor, so
    // R̂ ≈ sqrt(1 + 0.214δ²) ≈ 1.10. Require half that excess.
    let mut chains = ar1_chains(0.0, 4, 2000, 6);
    for x in chains[3].iter_mut() {
        *x += 1.0;
    }
    let r = rhat(&chains);
    eprintln!("shifted: R̂ = {r}");
    assert!(r > 1.05, "{r}");
}

#[test]
fn different_chain_scales_are_detected_by_folding() {
    // Same location, one chain with sd 3: the bulk R̂ (rank-normalised split
    // draws) sees no shift of the means, but the folded draws |x − median| have
    // means ≈ 0.80 vs 2.39 (E|X| = σ√(2/π)): the folded R̂ is large.
    let mut chains = ar1_chains(0.0, 4, 2000, 7);
    for x in chains[0].iter_mut() {
        *x *= 3.0;
    }
    let bulk_only = classic_rhat(&rank_normalize(&split_chains(&chains)));
    let r = rhat(&chains);
    eprintln!("scale mismatch: bulk R̂ = {bulk_only}, rank R̂ = {r}");
    // Chain means in z-space all have mean 0 by symmetry; the wide chain's mean has
    // ≈ 2× the variance, which keeps B/W at the χ² level: 1.01 is ≫ 4σ for n = 1000.
    assert!(bulk_only < 1.01);
    assert!(r > 1.1);
}

#[test]
fn drifting_single_chain_is_detected_by_splitting() {
    // One chain whose mean drifts linearly from −1 to 1: the halves have means ∓0.5,
    // so var(means) = 0.5 (ddof 1), and within-half variance 1 + 1/12 (unit noise
    // plus a linear ramp of range 1): R̂ ≈ sqrt(1 + 0.5/1.083) ≈ 1.21 ≫ 1.01 even
    // with a single chain. Require a quarter of the excess.
    let mut chain = ar1_chains(0.0, 1, 4000, 8).remove(0);
    let n = chain.len() as f64;
    for (i, x) in chain.iter_mut().enumerate() {
        *x += -1.0 + 2.0 * i as f64 / n;
    }
    assert!(rhat(&[chain]) > 1.05);
}

// ------------------------------------------------------------ summaries

#[test]
fn summary_by_hand_and_json_keys() {
    // a = 1..10 over 2 chains; b = 3 − 2a; c = a² (positive but not linear in a).
    let draws = |r: std::ops::Range<i32>| -> Vec<Vec<f64>> {
        r.map(|i| {
            let a = i as f64;
            vec![a, 3.0 - 2.0 * a, a * a]
        })
        .collect()
    };
    let chains = vec![draws(1..6), draws(6..11)];
    let names: Vec<String> = ["a_nm", "b_nm", "c_nm2"].iter().map(|s| s.to_string()).collect();
    let s = summarize(&names, &chains).with_map(&[5.0, -7.0, 25.0]);
    let a = &s.parameters[0];
    // mean 5.5; var(1..10, ddof 1) = 10·11/12 = 55/6; type-7 quantiles over
    // sorted 1..10: h = 9·0.025 = 0.225 → 1.225, h = 9·0.975 = 8.775 → 9.775.
    assert!((a.mean - 5.5).abs() < 1e-14);
    assert!((a.sd - (55.0f64 / 6.0).sqrt()).abs() < 1e-14);
    assert!((a.cv - (55.0f64 / 6.0).sqrt() / 5.5).abs() < 1e-14);
    assert!((a.ci95[0] - 1.225).abs() < 1e-14 && (a.ci95[1] - 9.775).abs() < 1e-14);
    let b = &s.parameters[1];
    assert!((b.mean + 8.0).abs() < 1e-14 && (b.sd - 2.0 * a.sd).abs() < 1e-13);
    assert!((b.ci95[0] + 16.55).abs() < 1e-13 && (b.ci95[1] - 0.55).abs() < 1e-13);
    assert!((b.cv - b.sd / 8.0).abs() < 1e-14);
    // corr(a, 3 − 2a) = −1; corr(a, a²) over 1..10 from the definition.
    assert!((s.correlation[0][1] + 1.0).abs() < 1e-14);
    assert_eq!(s.correlation[0][0], 1.0);
    let xs: Vec<f64> = (1..=10).map(|i| i as f64).collect();
    let ys: Vec<f64> = xs.iter().map(|x| x * x).collect();
    let (mx, my) = (5.5, 38.5);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    let syy: f64 = ys.iter().map(|y| (y - my).powi(2)).sum();
    assert!((s.correlation[0][2] - sxy / (sxx * syy).sqrt()).abs() < 1e-14);
    assert_eq!(s.correlation[2][0], s.correlation[0][2]);
    // Two chains that do not overlap in a: R̂ flags it.
    assert!(a.rhat > 1.5);

    let json = serde_json::to_value(&s.parameters[0]).unwrap();
    let mut keys: Vec<&str> = json.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    keys.sort();
    assert_eq!(keys, ["ci95", "cov", "ess_bulk", "ess_tail", "map", "mean", "name", "rhat", "sd"]);
    assert_eq!(json["map"], 5.0);
    assert_eq!(json["ci95"].as_array().unwrap().len(), 2);
}

#[test]
fn summary_is_invariant_to_parameter_scale() {
    // Ω ~ 1e12 next to Δ ~ 0.5: rescaling a parameter by 1e12 rescales mean/sd/CI
    // by 1e12 and leaves cv, correlations, R̂ and ESS unchanged (rank-based
    // diagnostics see the same ranks; relative round-off ~1e-15).
    let base = ar1_chains(0.7, 3, 3000, 9);
    let other = ar1_chains(0.2, 3, 3000, 19);
    let mk = |scale: f64| -> Vec<Vec<Vec<f64>>> {
        base.iter()
            .zip(&other)
            .map(|(c, o)| c.iter().zip(o).map(|(x, y)| vec![scale * (3.0 + x), 0.5 + 0.1 * (x + y)]).collect())
            .collect()
    };
    let names = vec!["omega_rad_s".to_string(), "delta".to_string()];
    let s1 = summarize(&names, &mk(1.0));
    let s2 = summarize(&names, &mk(1e12));
    let (p1, p2) = (&s1.parameters[0], &s2.parameters[0]);
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    assert!(rel(p2.mean, 1e12 * p1.mean) < 1e-14);
    assert!(rel(p2.sd, 1e12 * p1.sd) < 1e-12);
    assert!(rel(p2.cv, p1.cv) < 1e-12);
    assert!(rel(p2.ci95[0], 1e12 * p1.ci95[0]) < 1e-14 && rel(p2.ci95[1], 1e12 * p1.ci95[1]) < 1e-14);
    assert!(rel(p2.rhat, p1.rhat) < 1e-12 && rel(p2.ess_bulk, p1.ess_bulk) < 1e-12);
    assert!(rel(p2.ess_tail, p1.ess_tail) < 1e-12);
    assert!((s2.correlation[0][1] - s1.correlation[0][1]).abs() < 1e-12);
    // corr(x, 0.1(x + y)) for independent unit-variance x, y is 1/√2; the sample
    // value has sd ≈ (1 − ρ²)/√ESS ≈ 0.5/√1600 with ESS ≥ 9000·(1 − 0.7)/(1 + 0.7).
    assert!((s1.correlation[0][1] - 0.5f64.sqrt()).abs() < 4.0 * 0.5 / 1600f64.sqrt());
}
