#!/usr/bin/env python3
"""Independent generator of thermal-motion records like data/md/cc11.langevin.csv.gz (needs numpy, scipy).

A clamped-clamped tube in a Langevin bath: each of eleven lines (cc11's identified frequencies,
tests/identify_md.md round 3) and each plane (y, z) has a modal coordinate, the exact discretisation
of a damped oscillator q'' + gamma q' + w_k^2 q = white noise (natural frequency w_k, gamma = 1/tau =
2e11 1/s, the bath's; transition matrix expm(A dt), innovation covariance S - E S E^T, started
stationary), variance proportional to 1/w_k^2 (equipartition). The column of slice s and one plane
is sum_k phi_k(x_s) q_k(t), phi the clamped-clamped Euler-Bernoulli shapes, at the record's three
slices; the slices see the same coordinates, the planes independent ones. 12 618 samples of 20 fs,
plus a white floor far below the lines. Truth: omega_k = 2 pi f_k, zeta_k = gamma/(2 omega_k).

usage: gen.py SEED OUT.csv"""
import sys, math
import numpy as np
from scipy.linalg import expm
f_ghz = [133.1, 352.5, 651.0, 1006.2, 1400.4, 1823.5, 2253.3, 2699.6, 3145.6, 3590.9, 4040.2]
dt, n = 2e-14, 12618
L = 11.4029e-9
xs = np.array([5.701, 3.421, 1.710]) * 1e-9
bl = [4.730040745, 7.853204624, 10.99560784, 14.13716549, 17.27875966] + [(2*k+1)*math.pi/2 for k in range(6, 12)]
def phi(k, x):
    b = bl[k] / L
    s = (math.cosh(bl[k]) - math.cos(bl[k])) / (math.sinh(bl[k]) - math.sin(bl[k]))
    y = np.cosh(b*x) - np.cos(b*x) - s*(np.sinh(b*x) - np.sin(b*x))
    return y
def gen(seed, nm=len(f_ghz), tau=5e-12):
    rng = np.random.default_rng(seed)
    g = 1.0 / tau
    cols = np.zeros((6, n))
    for k in range(nm):
        w = 2*math.pi*f_ghz[k]*1e9
        varq = (1.5e-11 * (2*math.pi*133.1e9) / w) ** 2
        A = np.array([[0.0, 1.0], [-w*w, -g]])
        E = expm(A*dt)
        S = np.diag([varq, w*w*varq])
        Q = S - E @ S @ E.T
        C = np.linalg.cholesky(Q)
        for plane in range(2):
            z = np.linalg.cholesky(S) @ rng.standard_normal(2)
            q = np.empty(n)
            noise = rng.standard_normal((n, 2)) @ C.T
            for i in range(n):
                q[i] = z[0]
                z = E @ z + noise[i]
            for s in range(3):
                cols[2*s+plane] += phi(k, xs[s]) * q
    cols += 1e-14 * rng.standard_normal(cols.shape)
    return cols
if __name__=="__main__":
    seed, out = int(sys.argv[1]), sys.argv[2]
    cols=gen(seed)
    with open(out, "w") as o:
        o.write("time_s,thermal_slice1_y_m,thermal_slice1_z_m,thermal_slice2_y_m,thermal_slice2_z_m,thermal_slice3_y_m,thermal_slice3_z_m\n")
        for i in range(n):
            o.write("%.6e," % (i*dt) + ",".join("%.5e" % cols[c, i] for c in range(6)) + "\n")
