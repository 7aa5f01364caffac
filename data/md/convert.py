#!/usr/bin/env python3
"""Turn one LAMMPS run of run.sh into a committed record: CASE.ENSEMBLE.csv.gz and
CASE.ENSEMBLE.provenance.yaml. Standard library only.

usage: convert.py CASE ENSEMBLE     (e.g. convert.py cc7 langevin)
reads work/CASE.log, work/CASE.ENSEMBLE.ave (fix ave/time, slice centres of mass in A),
work/CASE.ENSEMBLE.force (1000-step means of the clamps' axial forces in eV/A).

The CSV has the header time_s,thermal_slice1_y_m,…,thermal_slice3_z_m (the thermal-motion
record `nanobeam identify` reads):
the transverse centre-of-mass coordinates of three one-cell slices (20 atoms) in metres,
sampled every `every` steps; the slices' positions along the tube are in the provenance.
A run stopped before its planned end gives a shorter record: only complete lines are kept
and the provenance states the length actually recorded.
"""
import gzip
import math
import re
import sys

EV_PER_A_IN_N = 1.602176634e-9  # 1 eV/A in newtons (CODATA 2018 elementary charge)
AMU_KG = 1.66053906660e-27  # CODATA 2018
CARBON_AMU = 12.011  # the data file's mass (IUPAC standard atomic weight)
TIMESTEP_PS = 0.001  # in.tube: timestep 0.001 (metal units, ps)


def log_values(path):
    text = open(path).read()
    version = text.splitlines()[0].strip()
    geo = re.search(r"^GEOMETRY (.*)$", text, re.M).group(1).split()
    counts = re.search(r"^COUNTS (.*)$", text, re.M).group(1).split()
    geo = {geo[i]: float(geo[i + 1]) for i in range(0, len(geo), 2)}
    counts = {counts[i]: int(counts[i + 1]) for i in range(0, len(counts), 2)}
    return version, geo, counts


def read_ave(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                continue
            parts = line.split()
            if len(parts) != 7:
                continue  # a line cut by a stopped run
            try:
                rows.append([int(parts[0])] + [float(v) for v in parts[1:]])
            except ValueError:
                continue
    return rows


def mean_se(values, batches=10):
    """Mean and its standard error from batch means (the 1000-step block means are correlated)."""
    n = len(values)
    mean = sum(values) / n
    b = max(2, min(batches, n))
    size = n // b
    means = [sum(values[i * size:(i + 1) * size]) / size for i in range(b)]
    var = sum((m - mean) ** 2 for m in means) / (b - 1)
    return mean, math.sqrt(var / b)


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    case, ens = sys.argv[1], sys.argv[2]
    version, geo, counts = log_values(f"work/{case}.log")
    # the LAMMPS log does not echo -var values: run.sh writes them to work/CASE.params
    var = dict(line.split() for line in open(f"work/{case}.params") if line.strip())
    every = int(var["every"])
    rows = read_ave(f"work/{case}.{ens}.ave")
    dt_s = every * TIMESTEP_PS * 1e-12
    with gzip.GzipFile(f"{case}.{ens}.csv.gz", "wb", mtime=0) as gz:
        out = ["time_s,thermal_slice1_y_m,thermal_slice1_z_m,thermal_slice2_y_m,thermal_slice2_z_m,thermal_slice3_y_m,thermal_slice3_z_m\n"]
        for r in rows:
            t = r[0] * TIMESTEP_PS * 1e-12
            out.append("%.6e," % t + ",".join("%.5e" % (v * 1e-10) for v in r[1:]) + "\n")
        gz.write("".join(out).encode())
    blocks = []
    with open(f"work/{case}.{ens}.force") as f:
        for line in f:
            if line.startswith("#"):
                continue
            p = line.split()
            if len(p) == 4:
                blocks.append([float(v) for v in p[1:]])
    support = "clamped-clamped" if counts["clampR"] > 0 else "clamped-free"
    if support == "clamped-clamped":
        tension = [(fl - fr) / 2.0 * EV_PER_A_IN_N for fl, fr, _ in blocks]
    else:
        tension = [fl * EV_PER_A_IN_N for fl, _, _ in blocks]
    n_mean, n_se = mean_se(tension)
    t_mean, t_se = mean_se([b[2] for b in blocks])
    period_m = geo["period_A"] * 1e-10
    mu = 20 * CARBON_AMU * AMU_KG / period_m  # 4n = 20 atoms per axial period of a (5,5) tube
    tau_s = float(var["tau"]) * 1e-12
    x0 = geo["x0_A"]
    with open(f"{case}.{ens}.provenance.yaml", "w") as p:
        w = p.write
        w(f"# provenance of {case}.{ens}.csv.gz, written by convert.py from the LAMMPS log\n")
        w(f"record: {case}.{ens}.csv.gz\n")
        w("columns: time_s, then thermal_slice{1,2,3}_{y,z}_m: transverse centre-of-mass coordinates (m) of each slice\n")
        w("tube: {chirality: '(5,5)', atoms: %d, clamped_atoms: %d, mobile_atoms: %d}\n"
          % (counts["all"], counts["clampL"] + counts["clampR"], counts["mobile"]))
        w(f"support: {support}\n")
        w("clamps: the first two unit cells (4 atom rows, 40 atoms) at each clamped end, frozen after a free relaxation\n")
        w(f"free_length_nm: {geo['L_A'] / 10:.4f}   # inner face of one clamp to the other's (or to the free end's last row)\n")
        w(f"axial_period_nm: {geo['period_A'] / 10:.5f}   # relaxed unit-cell length (LB Tersoff, 0 K)\n")
        w("mean_diameter_nm: 0.678   # nominal, a_cc = 0.142 nm rolled; relaxed value not measured\n")
        w("slices_x_nm: [%s]   # slice centres from the low-x clamp's inner face; each one unit cell, 20 atoms\n"
          % ", ".join("%.3f" % (geo[f"slice{i}_A"] / 10) for i in (1, 2, 3)))
        w("potential: {file: C.LB2010.tersoff, pair_style: tersoff, source: 'L. Lindsay and D. A. Broido, "
          "Phys. Rev. B 81, 205441 (2010), optimized Tersoff'}\n")
        w(f"lammps: '{version}, Debian package lammps 20220106.git7586adbb6a+ds1-2+b2, serial'\n")
        w("timestep_fs: 1.0\n")
        w("temperature_k: 300\n")
        w(f"measured_temperature_k: {{mean: {t_mean:.2f}, standard_error: {t_se:.2f}}}   # mobile atoms\n")
        w("seeds: {velocities: %s, thermalisation_bath: %d, production_bath: %d}\n"
          % (var["seed"], int(var["seed"]) + 1, int(var["seed"]) + 2))
        w("thermalisation: {steps: %s, ensemble: 'Langevin, damp 1 ps', initial_velocities_k: 600}\n" % var["nequil"])
        if ens == "langevin":
            w("production: {ensemble: 'NVE + Langevin (fix langevin on mobile atoms)', damp_ps: %s}\n" % var["tau"])
            w("bath_mass_per_length_kg_m: %.5e   # 20 carbon atoms per axial period\n" % mu)
            w("bath_viscous_damping_kg_m_s: %.5e   # c = (mass per length)/tau: the drag -m v/tau of every atom\n"
              % (mu / tau_s))
        else:
            w("production: {ensemble: NVE, follows the Langevin production}\n")
        w(f"planned_steps: {var['nprod'] if ens == 'langevin' else var['nnve']}\n")
        w(f"recorded_samples: {len(rows)}\n")
        w(f"sample_interval_s: {dt_s:.3e}\n")
        w(f"record_length_s: {len(rows) * dt_s:.4e}\n")
        w("clamp_axial_force_n: {mean: %.4e, standard_error: %.1e, blocks_1000_steps: %d}   # tension > 0\n"
          % (n_mean, n_se, len(blocks)))
    print(f"{case}.{ens}: {len(rows)} samples, {len(rows) * dt_s * 1e9:.3f} ns, N = {n_mean:.3e} +- {n_se:.1e} N, "
          f"T = {t_mean:.1f} K")


if __name__ == "__main__":
    main()
