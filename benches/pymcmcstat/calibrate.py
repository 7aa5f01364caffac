"""The pymcmcstat side of the issue-15 comparison: the same calibration as
`nanobeam calibrate benches/pymcmcstat/measured.yaml` (same data, priors,
proposal sd, 4 chains x 20 000 DRAM draws with 2 stages), with the paper's
beam written as vectorised numpy/scipy: Hermite cubic elements (A4, A6) of
the nonlocal Euler-Bernoulli beam, the lowest eigenvalues of
K phi = lambda (M0 + (e0a/L)^2 M1) phi by LAPACK (scipy.linalg.eigh, subset),
the poles of each modal family (s^2 + lambda G(s) = 0, G of eq. 9 with N = 1)
as eigenvalues of stacked companion matrices, omega = |s| (34),
zeta = -Re s/|s| (35), and a Gaussian likelihood (sum of squares / sd^2).

Run (one thread): see README.md. Writes chains.csv and summary.json to OUT.
"""
import json
import os
import sys
import time

import numpy as np
import scipy.linalg
import yaml
from pymcmcstat.MCMC import MCMC

T_START = time.perf_counter()


def element_matrices(h):
    k = np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                  [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]]) / h**3
    m0 = np.array([[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                   [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]]) * h / 420
    m1 = np.array([[36, 3 * h, -36, 3 * h], [3 * h, 4 * h * h, -3 * h, -h * h],
                   [-36, -3 * h, 36, -3 * h], [3 * h, -h * h, -3 * h, 4 * h * h]]) / (30 * h)
    return k, m0, m1


def assemble(elements, support):
    """Unit (x/L) matrices of the mesh with the support DOFs removed."""
    h = 1.0 / elements
    ke, m0e, m1e = element_matrices(h)
    n = 2 * (elements + 1)
    k, m0, m1 = (np.zeros((n, n)) for _ in range(3))
    for e in range(elements):
        s = slice(2 * e, 2 * e + 4)
        k[s, s] += ke
        m0[s, s] += m0e
        m1[s, s] += m1e
    removed = {"simply-supported": [0, n - 2], "clamped-clamped": [0, 1, n - 2, n - 1],
               "clamped-free": [0, 1], "clamped-pinned": [0, 1, n - 2]}[support]
    keep = [i for i in range(n) if i not in removed]
    return k[np.ix_(keep, keep)], m0[np.ix_(keep, keep)], m1[np.ix_(keep, keep)]


def numbers_as_floats(v):
    """PyYAML (YAML 1.1) reads 1.0e12 as a string: convert every numeric string."""
    if isinstance(v, dict):
        return {k: numbers_as_floats(x) for k, x in v.items()}
    if isinstance(v, list):
        return [numbers_as_floats(x) for x in v]
    if isinstance(v, str):
        try:
            return float(v)
        except ValueError:
            return v
    return v


def main(measured_path, out_dir):
    with open(measured_path) as f:
        data = numbers_as_floats(yaml.safe_load(f))
    beam = data["beam"]
    modes = data["modes"]
    params = data["parameters"]
    sampler = data["sampler"]
    names = list(params)
    assert names == ["nonlocal_e0a_nm", "delta", "omega_rad_s"], names
    L = beam["length_nm"] * 1e-9
    d = beam["diameter_nm"] * 1e-9
    area, inertia = np.pi * d * d / 4, np.pi * d**4 / 64
    ei, rho_a = beam["youngs_modulus_pa"] * inertia, beam["density_kg_m3"] * area
    omega_ref = np.sqrt(ei / rho_a) / L**2
    k, m0, m1 = assemble(int(beam["elements"]), beam["support"])
    numbers = np.array([m["mode"] for m in modes])
    top = int(numbers.max())
    y = np.concatenate([[m["omega_rad_s"] for m in modes], [m["zeta"] for m in modes]])
    sd = np.concatenate([[m["omega_sd_rad_s"] for m in modes], [m["zeta_sd"] for m in modes]])

    def forward(theta):
        e_tilde = theta[0] / beam["length_nm"]
        lam = scipy.linalg.eigh(k, m0 + e_tilde**2 * m1, eigvals_only=True,
                                subset_by_index=[0, top - 1], driver="gvx")[numbers - 1]
        om = theta[2] / omega_ref
        # (s^2 + lam)(s + om) + lam*delta*s = s^3 + om s^2 + lam(1+delta) s + lam om
        comp = np.zeros((lam.size, 3, 3))
        comp[:, 0, :] = -np.stack([np.full_like(lam, om), lam * (1 + theta[1]), lam * om], axis=1)
        comp[:, 1, 0] = comp[:, 2, 1] = 1.0
        roots = np.linalg.eigvals(comp)
        s = roots[np.arange(lam.size), np.argmax(roots.imag, axis=1)]
        if np.any(s.imag <= 0):
            return None
        r = np.abs(s)
        return np.concatenate([r * omega_ref, -s.real / r])

    def sos(theta, _data):
        pred = forward(theta)
        if pred is None:
            return np.inf
        return np.sum(((y - pred) / sd) ** 2)

    chains = []
    start = [1.0, 0.5, 1.0e12]
    for c in range(int(sampler["chains"])):
        np.random.seed(int(sampler["seed"]) + c)
        mc = MCMC()
        mc.data.add_data_set(x=np.zeros(1), y=y)
        for i, name in enumerate(names):
            prior = params[name]["prior"]
            mc.parameters.add_model_parameter(name=name, theta0=start[i], minimum=prior["lower"],
                                              maximum=prior["upper"])
        mc.model_settings.define_model_settings(sos_function=sos)
        qcov = np.diag([params[n]["proposal_sd"] ** 2 for n in names])
        # 2 DR stages with the second covariance 0.1 x the first (drscale is on sd)
        mc.simulation_options.define_simulation_options(
            nsimu=int(sampler["draws_per_chain"]), method="dram", ntry=2, drscale=np.array([np.sqrt(10.0)]),
            qcov=qcov, adaptint=100, waitbar=False, verbosity=0, updatesigma=False)
        mc.run_simulation()
        chains.append(mc.simulation_results.results["chain"])
    os.makedirs(out_dir, exist_ok=True)
    burn = int(sampler["burn_in"])
    with open(os.path.join(out_dir, "chains.csv"), "w") as f:
        f.write("chain,draw," + ",".join(names) + "\n")
        for c, ch in enumerate(chains):
            for i, row in enumerate(ch):
                f.write(f"{c},{i}," + ",".join(repr(float(v)) for v in row) + "\n")
    kept = np.concatenate([ch[burn:] for ch in chains])
    summary = {n: {"mean": float(kept[:, i].mean()), "sd": float(kept[:, i].std(ddof=1))} for i, n in enumerate(names)}
    draws = sum(len(ch) for ch in chains)
    summary["_timing"] = {"draws": draws, "seconds_in_python": time.perf_counter() - T_START}
    with open(os.path.join(out_dir, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
    print(json.dumps(summary))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
