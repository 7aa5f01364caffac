"""Issue 40, item 1: should the base calibration carry the nominal diameter's uncertainty as a prior?

Measured on the paper's Cases 1B and 1C (paper §4.2: data from the N = 1 truth of Table 4, d = 1 nm,
inverted with d0 = 0.97 nm and 1.03 nm). The data here are the truth's three modes without noise
(`nanobeam modal` of the reconstructed Table 4 beam), with the paper's σ (§4.2: Σωω = diag(0.16, 1.75,
5.60) GHz², Σζζ = diag(4.60, 0.51, 0.16)·1e-6), so any bias is the wrong diameter's and not a noise
draw's. Each case is calibrated twice with `nanobeam calibrate`: with d fixed at d0 (the paper's
inversion), and with d sampled under normal(d0, 0.1·d0), the ±10 % a TEM/AFM diameter carries.

    python3 tests/replay/nominal_prior_cases_1b_1c.py NANOBEAM_BINARY

Prints each parameter's mean, sd, 95 % interval and whether it holds the truth. Results:
tests/diagnose_catalogue.md.
"""
import json
import math
import os
import subprocess
import sys
import tempfile

TRUTH_BEAM = """length_nm: 8.1321
diameter_nm: 1.0
youngs_modulus_pa: 1.0e12
density_kg_m3: 2300.0
support: simply-supported
elements: 20
nonlocal_e0a_nm: 1.217
internal_variables: [{ delta: 0.4999, omega_rad_s: 3.9925e11 }]
"""
TRUTH = {"nonlocal_e0a_nm": 1.217, "delta": 0.4999, "omega_rad_s": 3.9925e11, "diameter_nm": 1.0}
SIGMA_OMEGA_GHZ2 = [0.16, 1.75, 5.60]
SIGMA_ZETA_1E6 = [4.60, 0.51, 0.16]


def main():
    nb = sys.argv[1]
    work = tempfile.mkdtemp(prefix="nominal-prior-")
    beam = os.path.join(work, "truth.yaml")
    with open(beam, "w") as f:
        f.write(TRUTH_BEAM)
    out = subprocess.run([nb, "modal", beam, "--modes", "3", "--json"], capture_output=True, text=True, check=True)
    truth = json.loads(out.stdout)["modes"]
    s_om = [math.sqrt(x) * 2e9 * math.pi for x in SIGMA_OMEGA_GHZ2]
    s_ze = [math.sqrt(x * 1e-6) for x in SIGMA_ZETA_1E6]
    modes = "\n".join(
        f"  - {{ mode: {i + 1}, omega_rad_s: {m['omega_rad_s']!r}, omega_sd_rad_s: {s_om[i]!r}, "
        f"zeta: {m['zeta']!r}, zeta_sd: {s_ze[i]!r} }}"
        for i, m in enumerate(truth)
    )
    for d0 in [0.97, 1.03]:
        for free in [False, True]:
            extra = f"\n  diameter_nm: {{ prior: {{ dist: normal, mean: {d0}, sd: {0.1 * d0:.4f} }}, proposal_sd: 0.005 }}"
            path = os.path.join(work, f"case-{d0}-{'free' if free else 'fixed'}.yaml")
            with open(path, "w") as f:
                f.write(f"""beam:
  length_nm: 8.1321
  diameter_nm: {d0}
  youngs_modulus_pa: 1.0e12
  density_kg_m3: 2300.0
  support: simply-supported
  elements: 20
  nonlocal_e0a_nm: 0.5
  internal_variables: [{{ delta: 0.5, omega_rad_s: 1.0e12 }}]
modes:
{modes}
parameters:
  nonlocal_e0a_nm: {{ prior: {{ dist: uniform, lower: 0.0, upper: 2.0 }}, proposal_sd: 0.01 }}
  delta: {{ prior: {{ dist: uniform, lower: 0.0, upper: 1.0 }}, proposal_sd: 0.01 }}
  omega_rad_s: {{ prior: {{ dist: uniform, lower: 0.0, upper: 1.0e13 }}, proposal_sd: 1.0e10 }}{extra if free else ""}
sampler: {{ draws_per_chain: 20000, burn_in: 5000, chains: 4, seed: 102 }}
""")
            s = json.loads(subprocess.run([nb, "calibrate", path, "--json"], capture_output=True, text=True, check=True).stdout)
            print(f"d0 = {d0} nm, d {'sampled' if free else 'fixed'}: ln posterior at MAP {s['log_posterior_map']:.2f}")
            for p in s["parameters"]:
                t = TRUTH[p["name"]]
                lo, hi = p["ci95"]
                print(f"  {p['name']:16s} mean {p['mean']:.5g} sd {p['sd']:.3g} ci95 [{lo:.5g}, {hi:.5g}]"
                      f" truth {t:.5g} held {lo <= t <= hi} z {(p['mean'] - t) / p['sd']:+.1f} rhat {p['rhat']:.3f}")


if __name__ == "__main__":
    main()
