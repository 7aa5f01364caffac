"""nanobeam from Python: the paper's Case 1A and a hidden-mass diagnosis.

Run from the repository root after `pip install ./python` (ArviZ optional):

    python docs/python_example.py

Case 1A (paper §4.2): synthetic modal data from the N = 1 beam of Table 4
(reconstructed in paper/reconstructed.yaml, since the text lost the table),
the measurement sds of Σωω = diag(0.16, 1.75, 5.60) GHz² and
Σζζ = diag(4.60, 0.51, 0.16)·10⁻⁶ (§4.2, after eq. 38), and the inverse model
with the nominal diameter equal to the true one; priors, starts and sampler
from paper/specs/case-1a.yaml (its quick sampler, so the script takes seconds).
The noise here is drawn by numpy, so the data (and so the posterior) are a
replicate of Case 1A, not the bytes of `cargo xtask reproduce`.

Hidden mass: data from a beam carrying a point mass that the nominal model
lacks; `diagnose` names the cause.
"""

import math
from pathlib import Path

import numpy as np

import nanobeam

ROOT = Path(__file__).resolve().parents[1]
rec = nanobeam.read_yaml(ROOT / "paper" / "reconstructed.yaml")
spec = nanobeam.read_yaml(ROOT / "paper" / "specs" / "case-1a.yaml")
table_1 = rec["reconstruction"]["table_1"]
fit = rec["reconstruction"]["table_4_fit"]["parameters"]

# --- Case 1A ---------------------------------------------------------------
truth = dict(
    table_1,
    length_nm=fit["length_nm"],
    support="simply-supported",
    elements=20,
    nonlocal_e0a_nm=fit["nonlocal_e0a_nm"],
    internal_variables=[{"delta": fit["delta"], "omega_rad_s": fit["omega_rad_s"]}],
)
exact = nanobeam.modal(truth, 3)["modes"]
# Σ of §4.2: ω variances in GHz² (cyclic GHz, paper/reconstructed.yaml), ζ variances in 1e-6
sd_omega = [2 * math.pi * 1e9 * math.sqrt(v) for v in (0.16, 1.75, 5.60)]
sd_zeta = [math.sqrt(v * 1e-6) for v in (4.60, 0.51, 0.16)]
rng = np.random.default_rng(spec["seed"])
modes = [
    {
        "mode": m["mode"],
        "omega_rad_s": m["omega_rad_s"] + so * rng.standard_normal(),
        "omega_sd_rad_s": so,
        "zeta": m["zeta"] + sz * rng.standard_normal(),
        "zeta_sd": sz,
    }
    for m, so, sz in zip(exact, sd_omega, sd_zeta)
]
inverse_beam = dict(
    table_1,
    diameter_nm=spec["inverse_diameter_nm"],
    support="simply-supported",
    elements=20,
    internal_variables=spec["inverse_internal_variables"],
)
case_1a = {
    "beam": inverse_beam,
    "modes": modes,
    "parameters": spec["parameters"],
    "sampler": spec["quick_sampler"],
}
idata, summary = nanobeam.calibrate(case_1a, return_summary=True)
print("Case 1A posterior (truth in brackets):")
truths = {"nonlocal_e0a_nm": fit["nonlocal_e0a_nm"], "delta": fit["delta"], "omega_rad_s": fit["omega_rad_s"]}
for p in summary["parameters"]:
    print(f"  {p['name']:>16}: mean {p['mean']:.4g}, 95 % CI [{p['ci95'][0]:.4g}, {p['ci95'][1]:.4g}]"
          f"  ({truths[p['name']]:.4g}), R-hat {p['rhat']:.3f}")
try:
    import arviz as az

    print(az.summary(idata, kind="stats"))
    print(az.loo(idata, var_name="omega_rad_s"))
except ImportError:
    print("(ArviZ not installed: idata is a dict of numpy arrays)", list(idata))

# --- a hidden point mass ---------------------------------------------------
nominal = dict(table_1, support="simply-supported", elements=20)
with_mass = dict(
    nominal,
    nonlocal_e0a_nm=1.05,
    internal_variables=[{"delta": 0.45, "omega_rad_s": 3.0e11}],
    point_mass={"mass_kg": 3e-24, "x_nm": 2.5},
)
rng = np.random.default_rng(7)
observed = []
for m in nanobeam.modal(with_mass, 4)["modes"]:
    so, sz = 0.003 * m["omega_rad_s"], 0.03 * m["zeta"]  # the paper's relative sds (§4.2)
    observed.append({"mode": m["mode"], "omega_rad_s": m["omega_rad_s"] + so * rng.standard_normal(),
                     "omega_sd_rad_s": so, "zeta": m["zeta"] + sz * rng.standard_normal(), "zeta_sd": sz})
diagnosis = nanobeam.diagnose({"beam": nominal, "modes": observed, "sampler": {"seed": 11}})
print("hidden mass: misfit detected", diagnosis["misfit_detected"], "- cause", diagnosis["cause"],
      "- explained", diagnosis["explained"])
print("  ln B vs the base model: %.1f" % diagnosis["gain"]["log_bayes_factor"])
for a in diagnosis["alternatives"]:
    print("  alternative:", a["extension"], "(ln B gap %.2f)" % a["log_bayes_factor_gap"])
