//! What real tubes do (issue 40), diagnosed: data from the independent
//! generator (`tests/independent/mod.rs`, which does not call the project's
//! `beam` module), one set per kind and seed, each diagnosed by the library
//! call at the hidden suite's quick settings. The record of what it measured
//! is `tests/diagnose_catalogue.md`.
//!
//! Base truth (as the hidden suite's): a simply supported (or clamped–clamped)
//! tube, L = 8 nm, d = 1 nm, E = 1 TPa, ρ = 2300 kg/m³, e0a ~ U[0.8, 1.2] nm,
//! one relaxation Δ ~ U[0.3, 0.6], Ω ~ log-U[1e11, 1e12] rad/s; 5 modes;
//! noise 0.3 % on ω and 3 % on ζ (relative, one keyed draw each). The file
//! declares the nominal beam, never the kind.
//!
//! Kinds and what a right verdict is:
//! - `wrong-diameter` (the tube's d is 6–10 % off the declared 1 nm) and
//!   `adsorbate` (+15–30 % mass per length): `section-mismatch`.
//! - `one-end-spring` (κ = kL/EI ~ log-U[1, 10] at x = 0 only) and
//!   `clamped-pinned-as-ss` (clamped at x = 0, the file says simply
//!   supported): `support-rotational-stiffness`, whose class samples each
//!   end's spring apart (a clamp is κ → ∞ at one end).
//! - `string-ss`, `string-cc` (tension 20 N_cr on a simply supported and a
//!   clamped–clamped tube): `axial-force`.
//! - a pair, `spring-and-adsorbate` (the one-end spring and the adsorbate
//!   together): both named, or honestly undecided (the decided causes a
//!   subset of the truth, the truth's model the selection or an alternative).
//! - foreign: `curvature` (a shallow initial curvature, h/d ~ U[0.15, 0.3]),
//!   `crack` (a hinge, κ_c ~ log-U[2, 8], at 0.2–0.8 L), `temperature-gradient`
//!   (EI falling linearly by 30–50 % towards one end), `taper` (the diameter
//!   falling linearly by 10–20 % towards one end, EI ∝ d⁴, ρA ∝ d²; a change
//!   the size of the nominal diameter's own ±10 % uncertainty, issue 40):
//!   `unexplained` where the oracle [`catalogue_fits`] shows the set out of
//!   catalogue, else (a mimic) any verdict that decides no cause.
//!
//! A confident wrong name: a decided cause that is not right for the kind
//! (for a foreign kind, any decided cause) in a diagnosis that says explained.

mod independent;

use std::time::Instant;

use rand::Rng;
use rand_distr::{Distribution, StandardNormal};

use independent::{poles, End, Truth};
use nanobeam::bayes::map::map_estimate;
use nanobeam::bayes::rng::{stream, Purpose};
use nanobeam::bayes::transform::Coordinate;
use nanobeam::bayes::Posterior;
use nanobeam::beam::{BeamSpec, Support};
use nanobeam::calibration::measured::MeasuredFile;
use nanobeam::calibration::{DramSettings, MeasuredData, ModeObservation, ParameterSet};
use nanobeam::diagnose::classes::{model_parameters, ClassParameters};
use nanobeam::diagnose::{diagnose, model_posterior, ppc, DiagnoseSettings, Diagnosis, Model, NominalScales};
use rayon::prelude::*;

/// Relative measurement sds of the hidden suite (§4.2): 0.3 % on ω, 3 % on ζ.
const OMEGA_REL_SD: f64 = 0.003;
const ZETA_REL_SD: f64 = 0.03;
const N_MODES: usize = 5;

#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Clean,
    WrongDiameter,
    Adsorbate,
    OneEndSpring,
    ClampedPinnedAsSs,
    StringSs,
    StringCc,
    Curvature,
    Crack,
    TemperatureGradient,
    Taper,
    SpringAndAdsorbate,
}

impl Kind {
    const ALL: [Kind; 12] = [
        Kind::Clean,
        Kind::WrongDiameter,
        Kind::Adsorbate,
        Kind::OneEndSpring,
        Kind::ClampedPinnedAsSs,
        Kind::StringSs,
        Kind::StringCc,
        Kind::Curvature,
        Kind::Crack,
        Kind::TemperatureGradient,
        Kind::Taper,
        Kind::SpringAndAdsorbate,
    ];

    fn name(self) -> &'static str {
        match self {
            Kind::Clean => "clean",
            Kind::WrongDiameter => "wrong-diameter",
            Kind::Adsorbate => "adsorbate",
            Kind::OneEndSpring => "one-end-spring",
            Kind::ClampedPinnedAsSs => "clamped-pinned-as-ss",
            Kind::StringSs => "string-ss",
            Kind::StringCc => "string-cc",
            Kind::Curvature => "curvature",
            Kind::Crack => "crack",
            Kind::TemperatureGradient => "temperature-gradient",
            Kind::Taper => "taper",
            Kind::SpringAndAdsorbate => "spring-and-adsorbate",
        }
    }

    /// The catalogue causes a right verdict names (empty: `none` for clean data, `unexplained` for a foreign kind).
    fn right(self) -> &'static [&'static str] {
        match self {
            Kind::WrongDiameter | Kind::Adsorbate => &["section-mismatch"],
            Kind::OneEndSpring | Kind::ClampedPinnedAsSs => &["support-rotational-stiffness"],
            Kind::StringSs | Kind::StringCc => &["axial-force"],
            Kind::SpringAndAdsorbate => &["support-rotational-stiffness", "section-mismatch"],
            _ => &[],
        }
    }

    fn foreign(self) -> bool {
        matches!(self, Kind::Curvature | Kind::Crack | Kind::TemperatureGradient | Kind::Taper)
    }
}

/// One generated set: the truth, the file's data, and a line saying what the truth hides.
struct Case {
    kind: Kind,
    seed: u64,
    truth: Truth,
    data: MeasuredData,
    /// The observations before the noise (the truth's ω and ζ, the same sds).
    noise_free: Vec<ModeObservation>,
    what: String,
}

fn log_uniform(rng: &mut impl Rng, lo: f64, hi: f64) -> f64 {
    rng.gen_range(lo.ln()..hi.ln()).exp()
}

/// The set of `kind` and `seed`.
fn generate(kind: Kind, seed: u64) -> Case {
    let mut rng = stream(seed, Purpose::SyntheticCase, [40, kind as u64]);
    let mut t = Truth::simply_supported(8.0, 1.0, 1.0e12, 2300.0);
    t.e0a_nm = rng.gen_range(0.8..1.2);
    t.relaxations = vec![(rng.gen_range(0.3..0.6), log_uniform(&mut rng, 1e11, 1e12))];
    let k_ref = t.ei() / (t.length_nm * 1e-9);
    let mut support = Support::SimplySupported;
    let what = match kind {
        Kind::Clean => String::new(),
        Kind::WrongDiameter => {
            let sign = if rng.gen_range(0..2) == 0 { 1.0 } else { -1.0 };
            t.diameter_nm = 1.0 + sign * rng.gen_range(0.06..0.10);
            format!("d = {:.3} nm (declared 1)", t.diameter_nm)
        }
        Kind::Adsorbate => {
            t.added_mass_fraction = rng.gen_range(0.15..0.30);
            format!("mass/length +{:.1} %", 100.0 * t.added_mass_fraction)
        }
        Kind::OneEndSpring => {
            let kappa = log_uniform(&mut rng, 1.0, 10.0);
            t.ends[0] = End::Pinned { spring_n_m_rad: kappa * k_ref };
            format!("kL/EI = {kappa:.2} at x = 0")
        }
        Kind::ClampedPinnedAsSs => {
            t.ends[0] = End::Clamped;
            "clamped at x = 0".into()
        }
        Kind::StringSs => {
            t.axial_force_n = 20.0 * t.buckling_load_n();
            "N = 20 N_cr".into()
        }
        Kind::StringCc => {
            t.ends = [End::Clamped, End::Clamped];
            support = Support::ClampedClamped;
            t.axial_force_n = 20.0 * t.buckling_load_n();
            "N = 20 N_cr, clamped-clamped".into()
        }
        Kind::Curvature => {
            let h = rng.gen_range(0.15..0.3) * t.diameter_nm;
            let anti = rng.gen_range(0.0..0.5);
            t.curvature = Some((h, anti));
            format!("h = {h:.3} nm, antisymmetric part {anti:.2}")
        }
        Kind::Crack => {
            let x = rng.gen_range(0.2..0.8) * t.length_nm;
            let kappa = log_uniform(&mut rng, 2.0, 8.0);
            t.hinges = vec![(x, kappa * k_ref)];
            format!("hinge kL/EI = {kappa:.2} at {x:.2} nm")
        }
        Kind::TemperatureGradient => {
            t.ei_linear_softening = rng.gen_range(0.3..0.5);
            format!("EI falls by {:.0} % towards x = L", 100.0 * t.ei_linear_softening)
        }
        Kind::SpringAndAdsorbate => {
            let kappa = log_uniform(&mut rng, 1.0, 10.0);
            t.ends[0] = End::Pinned { spring_n_m_rad: kappa * k_ref };
            t.added_mass_fraction = rng.gen_range(0.15..0.30);
            format!("kL/EI = {kappa:.2} at x = 0, mass/length +{:.1} %", 100.0 * t.added_mass_fraction)
        }
        Kind::Taper => {
            t.taper = rng.gen_range(0.1..0.2);
            format!("d falls by {:.1} % towards x = L", 100.0 * t.taper)
        }
    };
    let what = format!(
        "{what}{}e0a {:.3}, Δ {:.3}, Ω {:.3e}",
        if what.is_empty() { "" } else { "; " },
        t.e0a_nm,
        t.relaxations[0].0,
        t.relaxations[0].1
    );
    let noise_free: Vec<ModeObservation> = poles(&t, N_MODES)
        .iter()
        .enumerate()
        .map(|(r, p)| ModeObservation {
            mode: r + 1,
            omega_rad_s: p.omega_rad_s,
            omega_sd_rad_s: OMEGA_REL_SD * p.omega_rad_s,
            zeta: p.zeta,
            zeta_sd: ZETA_REL_SD * p.zeta,
        })
        .collect();
    let mut noise = stream(seed, Purpose::MeasurementNoise, [40, kind as u64]);
    let mut modes = noise_free.clone();
    for m in &mut modes {
        let (e1, e2): (f64, f64) = (StandardNormal.sample(&mut noise), StandardNormal.sample(&mut noise));
        m.omega_rad_s += e1 * m.omega_sd_rad_s;
        m.zeta += e2 * m.zeta_sd;
    }
    let file = MeasuredFile {
        beam: BeamSpec::elastic(8.0, 1.0, 1.0e12, 2300.0, support, 20),
        modes,
        held_out_modes: vec![],
        mode_scans: vec![],
        parameters: None,
        sampler: Some(DramSettings { seed, ..DramSettings::default() }),
    };
    Case {
        kind,
        seed,
        truth: t,
        data: MeasuredData::from_file(file).expect("generated data are valid"),
        noise_free,
        what,
    }
}

/// The oracle of what the data show: the largest standardised residual of
/// the best base-model fit to the noise-free data (128 prior draws and the
/// truth's own base coordinates screened, Nelder–Mead from the best 3, 600
/// iterations; simplex 5 % of each prior's width, 0.05 in ln x). Below
/// 5 the kind hides in the base model at this noise and no verdict can be
/// asked of it.
fn base_fit_max_z(case: &Case) -> f64 {
    let d = &case.data;
    let scales = NominalScales::of(&d.beam, N_MODES).expect("nominal beam computes");
    let post = model_posterior(&Model::BASE, &ParameterSet::paper_n1(), &d.beam, &case.noise_free, &[], &scales);
    let mut rng = stream(case.seed, Purpose::SyntheticBaseFit, [40, case.kind as u64]);
    let (e0a, (delta, omega)) = (case.truth.e0a_nm, case.truth.relaxations[0]);
    let mut starts = vec![post.from_inner(&[e0a, delta, omega])];
    starts.extend((0..128).map(|_| post.sample_prior(&mut rng)));
    let mut scored: Vec<(f64, Vec<f64>)> = starts.into_iter().map(|u| (post.log_posterior(&u), u)).collect();
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    let sd = simplex_sd(&model_parameters(&Model::BASE, &ParameterSet::paper_n1(), &d.beam, &[], &scales));
    let best = scored
        .iter()
        .take(3)
        .map(|(_, u)| map_estimate(&post, u, &sd, 600))
        .max_by(|a, b| a.log_posterior.total_cmp(&b.log_posterior))
        .expect("starts");
    let Some(fit) = post.inner().predict(&post.to_inner(&best.theta)) else { return f64::INFINITY };
    let obs = post.inner();
    obs.observed().iter().zip(obs.sd()).zip(&fit).map(|((y, sd), f)| ((y - f) / sd).abs()).fold(0.0, f64::max)
}

/// The Nelder–Mead simplex of the oracle fits, per sampling coordinate: 0.05
/// in ln x, else 5 % of the prior's width in its coordinate.
fn simplex_sd(params: &ClassParameters) -> Vec<f64> {
    params
        .set
        .params
        .iter()
        .zip(&params.coordinates)
        .map(|(p, &c)| match c {
            Coordinate::Log => 0.05,
            c => 0.05 * (c.to_u(p.prior.support().1) - c.to_u(p.prior.support().0)),
        })
        .collect()
}

/// The best fit of one catalogue model to a set's noise-free data.
#[derive(Debug, Clone)]
struct CatalogueFit {
    model: String,
    /// The largest |y − ŷ|/σ over the fitted ω and ζ at the fit.
    max_z: f64,
}

/// The |z| of the diagnosis's misfit test: the Šidák per-test level of the
/// family-wise α (1 %) over the 10 fitted observables, 3.29.
fn misfit_z() -> f64 {
    let s = DiagnoseSettings::quick();
    ppc::z_threshold(ppc::sidak_level(s.family_alpha, 2 * N_MODES))
}

/// The oracle of issue 40's item 5: is the set out of catalogue? Every
/// candidate model of the diagnosis (the base, each single cause, each
/// pair) fitted to the noise-free data by its MAP, largest standardised
/// residual at the fit. Starts: 64 prior draws, and per sub-model (the base
/// for a single, each single for a pair) 64 prior draws whose shared
/// parameters (by name) are the sub-model's best fit (the nesting the
/// screening uses, `diagnose::screen`); the best 3 polished by Nelder–Mead,
/// 600 iterations, simplex as [`base_fit_max_z`]'s. A local optimiser can
/// miss a better fit, so a max z here is an upper bound of the catalogue's
/// best: "out of catalogue" may be too kind to the catalogue, "mimic" never is.
/// Sorted best first.
fn catalogue_fits(case: &Case) -> Vec<CatalogueFit> {
    let d = &case.data;
    let scales = NominalScales::of(&d.beam, N_MODES).expect("nominal beam computes");
    let base = ParameterSet::paper_n1();
    let models = Model::candidates(2, d.beam.support, &base);
    let mut best: Vec<(Model, Vec<String>, Vec<f64>, f64)> = Vec::new(); // model, names, u at the fit, max z
    for level in 0..=2 {
        let here: Vec<&Model> = models.iter().filter(|m| m.causes().len() == level).collect();
        let fits: Vec<(Model, Vec<String>, Vec<f64>, f64)> = here
            .par_iter()
            .map(|&m| {
                let post = model_posterior(m, &base, &d.beam, &case.noise_free, &[], &scales);
                let params = model_parameters(m, &base, &d.beam, &[], &scales);
                let names: Vec<String> = params.set.params.iter().map(|p| p.name.clone()).collect();
                let sd = simplex_sd(&params);
                // keyed by (kind, model index among all candidates): [40, kind] is the base-fit oracle's stream
                let index = models.iter().position(|x| x == m).expect("listed") as u64;
                let mut rng = stream(case.seed, Purpose::SyntheticBaseFit, [1000 + case.kind as u64, index]);
                let mut starts: Vec<Vec<f64>> = (0..64).map(|_| post.sample_prior(&mut rng)).collect();
                if level == 0 {
                    let (e0a, (delta, omega)) = (case.truth.e0a_nm, case.truth.relaxations[0]);
                    starts.push(post.from_inner(&[e0a, delta, omega]));
                }
                let subs = best.iter().filter(|(s, ..)| {
                    s.causes().len() + 1 == level && s.causes().iter().all(|c| m.causes().contains(c))
                });
                for (_, sub_names, sub_u, _) in subs {
                    for _ in 0..64 {
                        let mut u = post.sample_prior(&mut rng);
                        for (i, n) in names.iter().enumerate() {
                            if let Some(j) = sub_names.iter().position(|s| s == n) {
                                u[i] = sub_u[j];
                            }
                        }
                        starts.push(u);
                    }
                }
                let mut scored: Vec<(f64, Vec<f64>)> =
                    starts.into_iter().map(|u| (post.log_posterior(&u), u)).collect();
                scored.sort_by(|a, b| b.0.total_cmp(&a.0));
                let fit = scored
                    .iter()
                    .take(3)
                    .map(|(_, u)| map_estimate(&post, u, &sd, 600))
                    .max_by(|a, b| a.log_posterior.total_cmp(&b.log_posterior))
                    .expect("starts");
                let obs = post.inner();
                let max_z = obs.predict(&post.to_inner(&fit.theta)).map_or(f64::INFINITY, |f| {
                    obs.observed()
                        .iter()
                        .zip(obs.sd())
                        .zip(&f)
                        .map(|((y, sd), f)| ((y - f) / sd).abs())
                        .fold(0.0, f64::max)
                });
                (m.clone(), names, fit.theta, max_z)
            })
            .collect();
        best.extend(fits);
    }
    let mut out: Vec<CatalogueFit> =
        best.into_iter().map(|(m, _, _, z)| CatalogueFit { model: m.name(), max_z: z }).collect();
    out.sort_by(|a, b| a.max_z.total_cmp(&b.max_z));
    out
}

/// What a foreign set must come out as, from the oracle's best catalogue
/// fit z* (noise-free). The misfit test flags an observable at |z| ≥ z_t
/// (3.29); noise adds N(0, 1) to the noise-free residual (and the leverage
/// correction only raises |z|), so at z* ≥ z_t + 2.33 the test fires on
/// ≥ 99 % of noise draws whichever model is fitted: **out of catalogue**,
/// `unexplained` is owed. At z* < z_t a catalogue model fits within the
/// threshold: a **mimic** at this amplitude, that no verdict can tell from
/// the catalogue cause; it is owed no decided cause. Between the two the
/// test fires on 50–99 % of noise draws: **grey**, scored as a mimic.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Separable {
    OutOfCatalogue,
    Grey,
    Mimic,
}

fn separable(best_z: f64) -> Separable {
    let zt = misfit_z();
    if best_z >= zt + 2.33 {
        Separable::OutOfCatalogue
    } else if best_z >= zt {
        Separable::Grey
    } else {
        Separable::Mimic
    }
}

/// The selected model's name (`base` for `none`), as alternatives are named.
fn verdict_model(d: &Diagnosis) -> String {
    let names: Vec<&str> = d.causes.iter().map(String::as_str).collect();
    Model::from_name(&names.join("+")).map_or_else(|| "base".into(), |m| m.name())
}

/// The column of the confusion matrix.
fn verdict(d: &Diagnosis) -> String {
    if d.cause == "multiple" {
        d.causes.join("+")
    } else {
        d.cause.clone()
    }
}

#[derive(Default, Debug)]
struct Tally {
    cases: usize,
    right: usize,
    confident_wrong: usize,
}

/// Is `d` right for `kind`: `none` on clean data; on a foreign kind
/// `unexplained` when the oracle shows the set out of catalogue, else no
/// decided cause (`separable`); else explained with exactly the right
/// causes named. A set whose base-fit max z is below 5 (`visible` false)
/// hides in the base model at this noise: `none` is right for it too.
fn is_right(kind: Kind, d: &Diagnosis, visible: bool, sep: Option<Separable>) -> bool {
    if !visible && d.cause == "none" {
        return true;
    }
    match kind {
        Kind::Clean => d.cause == "none",
        k if k.foreign() => match sep {
            Some(Separable::OutOfCatalogue) | None => d.cause == "unexplained",
            Some(_) => d.cause == "unexplained" || d.decided_causes.is_empty(),
        },
        k => {
            let named = d.explained
                && d.causes.len() == k.right().len()
                && k.right().iter().all(|c| d.causes.iter().any(|n| n == c));
            // a pair: named, or honestly undecided (issue 40, item 6): the
            // decided causes a subset of the truth and the truth's model the
            // selection or an alternative
            let truth = Model::from_name(&k.right().join("+")).expect("class names").name();
            let listed = verdict_model(d) == truth || d.alternatives.iter().any(|a| a.extension == truth);
            named
                || (k.right().len() == 2
                    && d.explained
                    && listed
                    && d.decided_causes.iter().all(|c| k.right().contains(&c.as_str())))
        }
    }
}

/// A decided cause that is not right for `kind`, in a diagnosis that says explained.
fn confident_wrong(kind: Kind, d: &Diagnosis) -> bool {
    d.explained && d.decided_causes.iter().any(|c| !kind.right().contains(&c.as_str()))
}

/// Diagnoses every (kind, seed), one at a time (each diagnosis is parallel
/// inside), prints one line per case and the confusion, and counts.
fn tally(cases: &[(Kind, u64)]) -> Tally {
    let settings = DiagnoseSettings::quick();
    let mut t = Tally::default();
    let mut rows = Vec::new();
    for &(kind, seed) in cases {
        let case = generate(kind, seed);
        let z = base_fit_max_z(&case);
        // the oracle, for foreign kinds only (the catalogue's own kinds are in it by construction)
        let fits = if kind.foreign() { catalogue_fits(&case) } else { vec![] };
        let sep = fits.first().map(|f| separable(f.max_z));
        let oracle = fits.iter().take(3).map(|f| format!("{} {:.2}", f.model, f.max_z)).collect::<Vec<_>>();
        let t0 = Instant::now();
        let d = diagnose(&case.data, &settings).expect("valid generated data");
        let secs = t0.elapsed().as_secs_f64();
        let (right, wrong) = (is_right(kind, &d, z >= 5.0, sep), confident_wrong(kind, &d));
        // the selected model's end springs, in κ = kL/EI (posterior mean ± sd)
        let k_ref = case.truth.ei() / (case.truth.length_nm * 1e-9);
        let springs: Vec<String> = d
            .candidates
            .iter()
            .filter(|c| c.extension == verdict(&d) || c.causes == d.causes)
            .take(1)
            .flat_map(|c| c.posterior.iter())
            .filter(|(n, _)| n.starts_with("support_rotational_stiffness"))
            .map(|(n, s)| format!("{n} κ {:.3} ± {:.3}", s.mean / k_ref, s.sd / k_ref))
            .collect();
        t.cases += 1;
        t.right += usize::from(right);
        t.confident_wrong += usize::from(wrong);
        let line = format!(
            "{:22} seed {seed:3} [{}] base-fit max z {z:6.1}; oracle {sep:?} (best catalogue fits, max z: {oracle:?}) → \
             {} (explained {}, decided {:?}, alternatives {:?}, lnB {:.1}) right {right} confident-wrong {wrong}; springs \
             {springs:?}; {} models, {} forward solves, {secs:.0} s",
            kind.name(),
            case.what,
            verdict(&d),
            d.explained,
            d.decided_causes,
            d.alternatives.iter().map(|a| &a.extension).collect::<Vec<_>>(),
            d.gain.log_bayes_factor,
            d.candidates.len(),
            d.candidates.iter().map(|c| c.forward_evaluations).sum::<u64>(),
        );
        eprintln!("{line}");
        rows.push((kind.name(), verdict(&d), line));
    }
    println!("\nconfusion (truth → verdict)");
    for (k, v, line) in &rows {
        println!("  {k:22} → {v:40}\n      {line}");
    }
    println!("right {}/{}, confident wrong {}", t.right, t.cases, t.confident_wrong);
    t
}

/// Seed 500 of every kind; `NANOBEAM_CATALOGUE_SEEDS=500,501` (a developer's aid) runs others.
fn all_cases() -> Vec<(Kind, u64)> {
    let seeds: Vec<u64> = std::env::var("NANOBEAM_CATALOGUE_SEEDS").map_or(vec![500], |v| {
        v.split(',').map(|s| s.trim().parse().expect("NANOBEAM_CATALOGUE_SEEDS: comma-separated seeds")).collect()
    });
    Kind::ALL.iter().flat_map(|&k| seeds.iter().map(move |&s| (k, s))).collect()
}

/// Every kind of the catalogue record (`NANOBEAM_CATALOGUE_KINDS=crack,adsorbate` keeps some): no confident wrong
/// name, every set right (issue 40's targets: singles ≥ 95 %, foreign 100 %
/// `unexplained`, clean 100 % `none`, confident wrong 0).
#[test]
#[ignore = "issue 40's study: every kind, one diagnosis each per seed (5-15 min per seed on 2 cores), beyond CI's \
            budget; run with `NANOBEAM_CATALOGUE_SEEDS=500,501 cargo test --test diagnose_catalogue -- --ignored \
            --nocapture`; what it measured is in tests/diagnose_catalogue.md"]
fn every_kind_is_named_right_and_nothing_is_named_wrong_with_confidence() {
    let only: Option<Vec<String>> =
        std::env::var("NANOBEAM_CATALOGUE_KINDS").ok().map(|v| v.split(',').map(|s| s.trim().to_string()).collect());
    let cases: Vec<(Kind, u64)> = all_cases()
        .into_iter()
        .filter(|(k, _)| only.as_ref().is_none_or(|o| o.iter().any(|n| n == k.name())))
        .collect();
    let t = tally(&cases);
    assert_eq!(t.confident_wrong, 0, "a confident wrong name");
    assert_eq!(t.right, t.cases, "right {}/{}", t.right, t.cases);
}

/// The generated sets are what they say: every kind but the clean one moves
/// some observable ≥ 5 sd away from the best base-model fit (the hidden
/// suite's visibility rule), and the clean sets leave the base fit within
/// the noise (< 5 sd).
#[test]
#[ignore = "the oracle fits the base model to every set (about a minute on 2 cores); run with the catalogue"]
fn every_kind_is_visible_against_the_base_model() {
    let mut hidden = Vec::new();
    for (kind, seed) in all_cases() {
        let case = generate(kind, seed);
        let z = base_fit_max_z(&case);
        println!("{:22} seed {seed} [{}]: base-fit max z {z:.1}", kind.name(), case.what);
        if (kind == Kind::Clean) != (z < 5.0) {
            hidden.push(format!("{} seed {seed}: {z:.1}", kind.name()));
        }
    }
    assert!(hidden.is_empty(), "clean sets must fit (< 5 sd), every other set must not: {hidden:?}");
}

/// Issue 40's item 5, measured first: for every foreign kind and seed
/// (`NANOBEAM_CATALOGUE_SEEDS`, default 500), the best fit of every
/// catalogue model to the noise-free data ([`catalogue_fits`]) and what the
/// set is owed ([`separable`]). It asserts nothing about the catalogue (a
/// mimic is a fact of the amplitude, not a failure); it asserts that every
/// candidate (29 on a simply supported beam) was fitted to a finite
/// residual, so no model is missing from the "no model fits" claim.
#[test]
#[ignore = "28 MAP fits per set, 1-3 min on 2 cores per set; run with the catalogue, the record is tests/diagnose_catalogue.md"]
fn every_foreign_set_is_out_of_catalogue_or_a_declared_mimic() {
    println!("misfit test |z| threshold {:.3}; out of catalogue at best max z >= {:.3}", misfit_z(), misfit_z() + 2.33);
    for (kind, seed) in all_cases().into_iter().filter(|(k, _)| k.foreign()) {
        let case = generate(kind, seed);
        let t0 = Instant::now();
        let fits = catalogue_fits(&case);
        let base = fits.iter().find(|f| f.model == "base").expect("the base is a candidate").max_z;
        let z = base_fit_max_z(&case);
        println!(
            "{:22} seed {seed} [{}]: base-fit max z {z:.2} (oracle's base {base:.2}); {:?}; best: {}; {:.0} s",
            kind.name(),
            case.what,
            separable(fits[0].max_z),
            fits.iter().take(6).map(|f| format!("{} {:.2}", f.model, f.max_z)).collect::<Vec<_>>().join(", "),
            t0.elapsed().as_secs_f64()
        );
        assert_eq!(fits.len(), 29, "{} seed {seed}: every candidate of a simply supported beam", kind.name());
        assert!(
            fits.iter().all(|f| f.max_z.is_finite()),
            "{} seed {seed}: a model not evaluable: {fits:?}",
            kind.name()
        );
    }
}

/// A tube 7 % thinner than declared (wrong-diameter seed 500, d = 0.929 nm)
/// is named `section-mismatch`, and nothing is decided wrongly. Before the
/// class it was named `viscous-damping`, decided and explained (a confident
/// wrong name; tests/diagnose_catalogue.md).
#[test]
fn a_wrong_diameter_is_named_section_mismatch() {
    let t = tally(&[(Kind::WrongDiameter, 500)]);
    assert_eq!(t.confident_wrong, 0, "a confident wrong name");
    assert_eq!(t.right, 1, "wrong-diameter seed 500 not named section-mismatch");
}

/// A tension of 20 N_cr (the string regime) is named `axial-force`, on a
/// simply supported and on a clamped–clamped tube (issue 40, item 3; seed
/// 500 of each, the independent generator). Before the prior reached the
/// string regime (U[−0.5, 2] N_cr) neither could be fitted by the class.
#[test]
fn a_string_regime_tension_is_named_axial_force() {
    let t = tally(&[(Kind::StringSs, 500), (Kind::StringCc, 500)]);
    assert_eq!(t.confident_wrong, 0, "a confident wrong name");
    assert_eq!(t.right, 2, "a 20 N_cr tension not named axial-force");
}

/// A rotational spring at one end only, and a clamped–pinned tube declared
/// simply supported, are named `support-rotational-stiffness`, the class
/// whose two end springs are sampled apart (issue 40, item 2; seed 500 of
/// each, the independent generator). Before per-end springs the one-end
/// spring was named with every cause undecided and the clamped–pinned beam
/// came out `unexplained` (tests/diagnose_catalogue.md).
#[test]
fn a_one_end_spring_and_a_clamped_end_are_named_the_per_end_spring() {
    let t = tally(&[(Kind::OneEndSpring, 500), (Kind::ClampedPinnedAsSs, 500)]);
    assert_eq!(t.confident_wrong, 0, "a confident wrong name");
    assert_eq!(t.right, 2, "not named support-rotational-stiffness");
}
