"""Feasibility oracle for issue 43 (tests/identify_md.md, round 4): can any beam of the
diagnosis's model class fit an identified clamped-clamped modal table?

An independent solver, sharing no code or discretisation with the crate: the poles of a
uniform nonlocal Timoshenko beam, clamped at both ends, from the exact transcendental
determinant (no finite elements). The model is the one `beam` states in its docs
(`beam::element::TimoshenkoElement`, `beam::spec`): energies

    T = 1/2 rho A int (w_t^2 + mu w_xt^2) + 1/2 rho I int (th_t^2 + mu th_xt^2),   mu = (e0a)^2
    U = 1/2 E* I int th_x^2 + 1/2 kappa G* A int (w_x - th)^2 + 1/2 N int w_x^2

(Eringen's operator on the translational and the rotary inertia, the paper's (A4) mass
extended to the rotary inertia, as `TimoshenkoElement` documents it; the strong form below is
derived from these energies here, not taken from a reference), E* = E [1 + Delta s/(s + Omega)] multiplying bending
and shear alike (paper eq. 8, `spec::ShearDeformation`), viscous damping c on the
translational inertia with its nonlocal part (`model.rs`: D = (c/rho A) M_translational).
One simplification: the axial force's nonlocal part 1/2 N mu int w_xx^2 is dropped (it raises
the order of the equations). It acts like a change of the bending stiffness by N mu, i.e. a
relative change of omega of about (N L^2/EI)(e0a/L)^2/2 (compression lowers it): measured
against `nanobeam modal` in `validate()`, -1.1e-4 on mode 1 at N L^2/EI = -2.96,
e0a/L = 0.0088, and +1.8e-3 at +7.1, 0.026; without the axial force solver and FE agree to
1e-7 (the FE's discretisation error) in omega and zeta. The fits print |N L^2/EI| (e0a/L)^2
at their optimum.

Dimensionless (EI = rho A = L = 1, time in 1/omega_ref, omega_ref = sqrt(EI/rho A)/L^2):
parameters g = kappa G A L^2/EI, r2 = I/(A L^2), e = e0a/L, n = N L^2/EI, ct = c/(rho A
omega_ref), Delta, Om = Omega/omega_ref. With w, th ~ exp(k x + s t), q = k^2,

    A(q) = (s^2 + ct s)(1 - e^2 q) - (g G + n) q,   C(q) = r2 s^2 (1 - e^2 q) - G q + g G,
    A(q) C(q) + (g G)^2 q = 0   (G = 1 + Delta s/(s + Om)),

a quadratic in q (roots q1, q2). On x in [-1/2, 1/2] the symmetric modes are w = cosh,
th = rho k sinh (rho_j = g G / C(q_j)), the antisymmetric w = sinh, th = rho k cosh; w = th = 0
at x = 1/2 gives, multiplied by C(q1) C(q2) (entire, even in each k_j),

    S(s) = C1 k2 sinh(k2 h) cosh(k1 h) - C2 k1 sinh(k1 h) cosh(k2 h)
    N(s) = C1 sinh(k1 h) cosh(k2 h) / k1 - C2 sinh(k2 h) cosh(k1 h) / k2,     h = 1/2.

Undamped roots: real functions of omega on s = i omega, bracketed on a grid and bisected;
damped poles: complex secant from the undamped root. omega = |s|, zeta = -Re s/|s| (as
`beam::modal_result`). Modes are numbered by increasing omega over both families.

    python3 timoshenko_cc.py validate NANOBEAM     # against `nanobeam modal` (FE, 80 elements)
    python3 timoshenko_cc.py fit MEASURED.yaml NSTART CLASS elastic|damped|both [TOPS]
        # least-squares fits of the lowest 6, 7, ..., M modes (or the comma-separated TOPS) of an
        # identified file, each from 5 informed + NSTART random starts (numpy seed 43) and the
        # previous fit's optimum;
        # CLASS: free, tube, diagnose, diagnose-axial (see `classes`). Prints RMS z, chi^2,
        # the per-mode z of omega (and zeta) and the optimum. Results: tests/identify_md.md.
"""
import json
import subprocess
import sys
import tempfile

import numpy as np
from scipy.optimize import brentq, least_squares

H = 0.5


def _quad_roots(s, p):
    g, r2, e, n, ct, dl, om = p
    G = 1.0 + dl * s / (s + om)
    m = s * s + ct * s
    a0, a1 = m, -m * e * e - (g * G + n)
    c0, c1 = r2 * s * s + g * G, -r2 * s * s * e * e - G
    qa, qb, qc = a1 * c1, a0 * c1 + a1 * c0 + (g * G) ** 2, a0 * c0
    disc = np.sqrt(qb * qb - 4 * qa * qc + 0j)
    # numerically stable quadratic roots
    sgn = np.where(np.real(np.conj(qb) * disc) >= 0, 1.0, -1.0)
    t = -0.5 * (qb + sgn * disc)
    qx, qy = t / qa, qc / t
    # a fixed order (q1 the root of larger real part): the characteristic functions are odd
    # under q1 <-> q2, so a label swap would fake a sign change
    swap = np.real(qx) < np.real(qy)
    q1, q2 = np.where(swap, qy, qx), np.where(swap, qx, qy)
    C1 = c0 + c1 * q1
    C2 = c0 + c1 * q2
    return q1, q2, C1, C2


def _scaled(k):
    """(cosh(k h), sinh(k h)/k), both times exp(-|Re k| h): no overflow, positive scale."""
    a = np.abs(np.real(k)) * H
    ep, em = np.exp(k * H - a), np.exp(-k * H - a)
    ch = 0.5 * (ep + em)
    small = np.abs(k * H) < 1e-6
    ks = np.where(small, 1.0, k)
    sh = np.where(small, H * (1 + (k * H) ** 2 / 6) * np.exp(-a), 0.5 * (ep - em) / ks)
    return ch, sh


def det(s, p, family):
    """Scaled characteristic function of the symmetric (family 0) or antisymmetric (1) modes."""
    q1, q2, C1, C2 = _quad_roots(s, p)
    k1, k2 = np.sqrt(q1 + 0j), np.sqrt(q2 + 0j)
    ch1, sh1 = _scaled(k1)
    ch2, sh2 = _scaled(k2)
    if family == 0:
        return C1 * q2 * sh2 * ch1 - C2 * q1 * sh1 * ch2
    return C1 * sh1 * ch2 - C2 * sh2 * ch1


def undamped(p, count):
    """The lowest `count` undamped eigenfrequencies (dimensionless) and their families."""
    pe = (p[0], p[1], p[2], p[3], 0.0, 0.0, 1.0)
    roots = []
    for fam in (0, 1):
        f = lambda w: float(np.real(det(1j * w, pe, fam)))
        found = []
        lo = 0.05
        while len(found) < count and lo < 1e6:
            hi = lo * 1.5
            grid = np.linspace(lo, hi, 400)
            vals = np.real(det(1j * grid, pe, fam))
            idx = np.nonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) < 0)[0]
            for i in idx:
                r = brentq(f, grid[i], grid[i + 1], xtol=1e-15, rtol=1e-15)
                # where q1 = q2 the determinant vanishes identically: not a mode
                q1, q2, _, _ = _quad_roots(1j * r, pe)
                if abs(q1 - q2) < 1e-5 * (abs(q1) + abs(q2)):
                    continue
                found.append(r)
            lo = hi
        roots += [(r, fam) for r in found[:count]]
    roots.sort()
    return roots[:count]


def _det_fam(s, p, fam):
    return np.where(fam == 0, det(s, p, 0), det(s, p, 1))


def poles(p, count, steps=10):
    """(omega, zeta) dimensionless of the lowest `count` modes of the damped beam: each
    undamped root followed as the damping (c, Delta) grows from 0 to its value in `steps`
    steps (so a root is never exchanged for a neighbour's), by a secant iteration on all modes
    at once."""
    g, r2, e, n, ct, dl, om = p
    und = undamped(p, count)
    w0 = np.array([w for w, _ in und])
    fam = np.array([f for _, f in und])
    s = 1j * w0
    prev = s.copy()
    for j in range(1, steps + 1):
        a = j / steps
        pj = (g, r2, e, n, a * ct, a * dl, om)
        guess = s + (s - prev) if j > 1 else s
        prev = s.copy()
        s0, s1 = guess * (1 + 1e-4), guess.copy()
        f0, f1 = _det_fam(s0, pj, fam), _det_fam(s1, pj, fam)
        for _ in range(40):
            denom = f1 - f0
            ok = (denom != 0) & (np.abs(s1 - s0) > 1e-14 * np.abs(s1))
            if not ok.any():
                break
            s2 = np.where(ok, s1 - f1 * (s1 - s0) / np.where(ok, denom, 1.0), s1)
            s0, f0 = s1, f1
            s1 = s2
            f1 = _det_fam(s1, pj, fam)
        s = s1
    r = np.abs(s)
    return list(zip(r, -s.real / r))


# ---- physical units ---------------------------------------------------------------------------


def dimensionless(beam):
    """Dimensionless parameters and omega_ref of a beam given in the crate's YAML fields."""
    L = beam["length_nm"] * 1e-9
    d = beam["diameter_nm"] * 1e-9
    t = beam["wall_nm"] * 1e-9
    A = np.pi * d * t
    I = np.pi * d * t * (d * d + t * t) / 8
    E, rho = beam["youngs_modulus_pa"], beam["density_kg_m3"]
    EI, rA = E * I, rho * A
    wref = np.sqrt(EI / rA) / L**2
    kG_E = beam["kappa"] / (2 * (1 + beam["nu"]))
    g = kG_E * A * L * L / I
    r2 = I / (A * L * L)
    p = (g, r2, beam["e0a_nm"] * 1e-9 / L, beam["axial_n"] * L * L / EI, beam["c"] / (rA * wref),
         beam["delta"], beam["Omega"] / wref)
    return p, wref


def validate(binary):
    """Compare with `nanobeam modal` (the crate's FE) on beams of the class."""
    cases = [
        dict(kappa=0.52, nu=0.2, e0a_nm=0.0, axial_n=0.0, c=0.0, delta=0.0, Omega=1e12),
        dict(kappa=0.65, nu=0.2, e0a_nm=0.1, axial_n=-0.83e-9, c=3.2e-4, delta=0.28, Omega=1.06e12),
        dict(kappa=0.40, nu=0.3, e0a_nm=0.3, axial_n=2e-9, c=1e-4, delta=1.0, Omega=5e12),
        # the last two without the axial force: what is left is the FE's discretisation error
        dict(kappa=0.65, nu=0.2, e0a_nm=0.1, axial_n=0.0, c=3.2e-4, delta=0.28, Omega=1.06e12),
        dict(kappa=0.40, nu=0.3, e0a_nm=0.3, axial_n=0.0, c=1e-4, delta=1.0, Omega=5e12),
    ]
    worst = 0.0
    for c in cases:
        beam = dict(length_nm=11.403, diameter_nm=0.678, wall_nm=0.34, youngs_modulus_pa=7e11,
                    density_kg_m3=2213.0, **c)
        y = f"""length_nm: 11.403
diameter_nm: 0.678
section: {{ tube: {{ wall_nm: 0.34 }} }}
youngs_modulus_pa: 7.0e11
density_kg_m3: 2213
support: clamped-clamped
elements: 80
nonlocal_e0a_nm: {c['e0a_nm']}
viscous_damping_n_s_m2: {c['c']}
axial_force_n: {c['axial_n']}
internal_variables: [{{ delta: {c['delta']}, omega_rad_s: {c['Omega']} }}]
shear_deformation: {{ poisson_ratio: {c['nu']}, shear_coefficient: {c['kappa']} }}
"""
        with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as fh:
            fh.write(y)
        res = json.loads(subprocess.run([binary, "modal", fh.name, "--modes", "12", "--json"],
                                        capture_output=True, text=True, check=True).stdout)
        fe = [(m["omega_rad_s"], m["zeta"]) for m in res["modes"]]
        p, wref = dimensionless(beam)
        ex = poles(p, 12)
        print(f"case {c}")
        for i, ((wf, zf), (we, ze)) in enumerate(zip(fe, ex)):
            dw = (wf - we * wref) / (we * wref)
            dz = (zf - ze) / ze if ze > 0 else zf - ze
            worst = max(worst, abs(dw))
            print(f"  mode {i+1:2d}  FE {wf:.6e} {zf:.5f}  exact {we*wref:.6e} {ze:.5f}  rel dw {dw:+.2e}  rel dzeta {dz:+.2e}")
    print(f"worst relative omega difference {worst:.2e}")


# ---- the feasibility fits ---------------------------------------------------------------------


def read_modes(path):
    import re
    txt = open(path).read()
    modes = []
    for blk in re.split(r"(?m)^- mode: ", txt.split("modes:\n", 1)[1].split("held_out_modes:")[0])[1:]:
        num = int(blk.split("\n", 1)[0])
        get = lambda k: float(re.search(rf"{k}: ([-0-9.eE+]+)", blk).group(1))
        modes.append((num, get("omega_rad_s"), get("omega_sd_rad_s"), get("zeta"), get("zeta_sd")))
    return modes


# parameter vector u: ln wref, ln g, ln r2, e, n, ct, Delta, ln Om (Om = Omega/wref). The `free`
# class's ct <= 2 lies below cc11's bath (ct about 5); `diagnose-viscous` has the diagnosis's range.
LO = np.array([np.log(1e9), np.log(0.5), np.log(1e-5), 0.0, -30.0, 0.0, 0.0, np.log(1e-3)])
HI = np.array([np.log(1e13), np.log(1e5), np.log(1e-1), 0.1, 60.0, 2.0, 5.0, np.log(1e4)])


def model(u, count, damped=True):
    wref = np.exp(u[0])
    p = (np.exp(u[1]), np.exp(u[2]), u[3], u[4], u[5] if damped else 0.0, u[6] if damped else 0.0,
         np.exp(u[7]))
    if damped:
        pl = poles(p, count)
    else:
        pl = [(w, 0.0) for w, _ in undamped(p, count)]
    if len(pl) < count:
        return None
    return np.array([w * wref for w, _ in pl]), np.array([z for _, z in pl])


def residuals(u, data, damped):
    count = max(m[0] for m in data)
    r = model(u, count, damped)
    if r is None:
        return np.full(len(data) * (2 if damped else 1), 1e3)
    w, z = r
    out = [(w[m[0] - 1] - m[1]) / m[2] for m in data]
    if damped:
        out += [(z[m[0] - 1] - m[3]) / m[4] for m in data]
    return np.array(out)


def fit(data, damped, starts, rng, extra=(), cls=None):
    """Multi-start least squares over the free parameters of the class `cls` (see `CLASSES`);
    returns the best full parameter vector and its cost."""
    lo, hi, fixed = cls["bounds"] if cls else (LO, HI, {})
    free = np.array([i for i in (range(8) if damped else range(5)) if i not in fixed])
    best = None
    for u0 in list(extra) + list(starts(rng)):
        u0 = np.clip(u0, lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo))
        for i, v in fixed.items():
            u0[i] = v

        def res(v, u0=u0):
            u = u0.copy()
            u[free] = v
            return residuals(u, data, damped)
        try:
            r = least_squares(res, u0[free], bounds=(lo[free], hi[free]), x_scale="jac",
                              diff_step=1e-7, max_nfev=300)
        except (ValueError, FloatingPointError):
            continue
        u = u0.copy()
        u[free] = r.x
        if best is None or r.cost < best[1]:
            best = (u, r.cost)
    return best


NOMINAL = dict(length_nm=11.403, diameter_nm=0.678, wall_nm=0.34, youngs_modulus_pa=1e12,
               density_kg_m3=2213.0, kappa=0.52, nu=0.2, e0a_nm=0.0, axial_n=0.0, c=0.0, delta=0.0,
               Omega=1e12)


def classes(beam):
    """The model classes of the fits, as (lower bounds, upper bounds, fixed entries) of u:
    - free: every group free over wide bounds (LO, HI): the section's shape free, so the
      rotary inertia r2 apart from the shear stiffness g;
    - tube: the nominal tube's r2 = (d^2 + t^2)/(8 L^2), everything else as `free`;
    - diagnose: the diagnosis's shear-deformation + section-mismatch over the base model
      (`diagnose::classes`): r2 nominal, kappa in [0.3, 1] at nu = 0.2 (so g in
      [0.3, 1]/2.4/r2), the stiffness-to-mass factor f in [2/3, 3/2] (omega_ref in
      sqrt(f) times the nominal), e0a in [0, 2] nm, Delta in [0, 1], Omega in (0, 1e13] rad/s,
      no axial force, no viscous damping;
    - diagnose-axial: `diagnose` with the axial-force class's N/N_cr in [-0.5, 100]
      (N_cr = 4 pi^2 EI/L^2 of the nominal beam) as a third cause;
    - diagnose-viscous: `diagnose` with viscous-damping's C as a third cause (three causes:
      more than the diagnosis's search holds, `diagnose::search`)."""
    p, wref = dimensionless(beam)
    L = beam["length_nm"]
    r2 = p[1]
    out = {"free": (LO.copy(), HI.copy(), {})}
    out["tube"] = (LO.copy(), HI.copy(), {2: np.log(r2)})
    lo, hi = LO.copy(), HI.copy()
    lo[0], hi[0] = np.log(wref * np.sqrt(2 / 3)), np.log(wref * np.sqrt(1.5))
    lo[1], hi[1] = np.log(0.3 / 2.4 / r2), np.log(1.0 / 2.4 / r2)
    lo[3], hi[3] = 0.0, 2.0 / L
    lo[6], hi[6] = 0.0, 1.0
    lo[7], hi[7] = np.log(1e6 / wref), np.log(1e13 / wref)
    out["diagnose"] = (lo, hi, {2: np.log(r2), 4: 0.0, 5: 0.0})
    lo2, hi2 = lo.copy(), hi.copy()
    # n = N L^2/EI with EI = f EI_nominal: the widest range over f in [2/3, 3/2]
    lo2[4], hi2[4] = -0.5 * 4 * np.pi**2 * 1.5, 100 * 4 * np.pi**2 * 1.5
    out["diagnose-axial"] = (lo2, hi2, {2: np.log(r2), 5: 0.0})
    lo3, hi3 = lo.copy(), hi.copy()
    # viscous-damping's prior C in 2 rho A omega_1^0 [1e-4, 0.3], omega_1^0 = 22.373 omega_ref of
    # the nominal (clamped-clamped Euler-Bernoulli, beta_1 = 4.730); in ct = C/(rho A omega_ref)
    # the widest range over omega_ref in sqrt([2/3, 3/2]) times the nominal
    lo3[5], hi3[5] = 2 * 22.373 * 1e-4 / np.sqrt(1.5), 2 * 22.373 * 0.3 / np.sqrt(2 / 3)
    out["diagnose-viscous"] = (lo3, hi3, {2: np.log(r2), 4: 0.0})
    return {k: {"bounds": v} for k, v in out.items()}


def starts_for(nstart):
    def gen(rng):
        # the nominal Timoshenko tube (E = 1 TPa, t = 0.34 nm, kappa = 0.52, nu = 0.2) and cc7's
        # posterior (E = 0.68 TPa, kappa = 0.65, e0a = 0.027 nm, delta = 0.28, Omega = 1.06e12)
        # in these units, then random points over the box (uniform in u)
        wref0 = 4.38e10
        yield np.array([np.log(wref0), np.log(0.217 * 1.39e19 * (11.403e-9) ** 2), np.log(1 / (1.39e19 * (11.403e-9) ** 2)),
                        0.0, -2.0, 0.04, 0.3, np.log(1.06e12 / wref0)])
        yield np.array([np.log(wref0 * 0.82), np.log(0.27 * 1.39e19 * (11.403e-9) ** 2), np.log(1 / (1.39e19 * (11.403e-9) ** 2)),
                        0.0024, -3.0, 0.04, 0.28, np.log(1.06e12 / wref0 / 0.82)])
        # the diagnosis's shear-deformation + section-mismatch posterior mean on cc11's modes 1-8
        # (E = 0.689 TPa, kappa = 0.754, e0a = 0.094 nm, Delta = 0.211, Omega = 9.95e11 rad/s),
        # with and without the bath's viscous damping (c = 3.2e-4 kg/(m s): ct = 5.1)
        w = wref0 * np.sqrt(0.689)
        for ct in (0.0, 5.1):
            yield np.array([np.log(w), np.log(0.754 / 2.4 / 5.53e-4), np.log(5.53e-4), 0.094 / 11.403, 0.0,
                            ct, 0.211, np.log(9.95e11 / w)])
        # the elastic optimum of class `diagnose` on modes 1-11 (f = 0.814, kappa = 0.81,
        # e0a = 0.112 nm) with the bath's damping and a weak relaxation
        w = 3.955e10
        yield np.array([np.log(w), np.log(610.1), np.log(5.53e-4), 0.009836, 0.0, 5.1, 0.02, np.log(1e12 / w)])
        for _ in range(nstart):
            u = LO + (HI - LO) * rng.random(len(LO))
            # frequency scale near the data's (a start 100x off wastes the search)
            u[0] = np.log(wref0) + rng.uniform(-1.0, 1.0)
            yield u
    return gen


def describe(u, data, damped):
    z = residuals(u, data, damped)
    wref = np.exp(u[0])
    n = len(data)
    zw, zz = z[:n], z[n:]
    par = dict(omega_ref=wref, g=np.exp(u[1]), r2=np.exp(u[2]), e0a_over_L=u[3], NL2_over_EI=u[4],
               c_tilde=u[5], delta=u[6], Omega_rad_s=np.exp(u[7]) * wref)
    return z, zw, zz, par


def main_fit(path, nstart, cls_name, which, tops=None):
    modes = read_modes(path)
    rng = np.random.default_rng(43)
    M = len(modes)
    cls = classes(NOMINAL)[cls_name]
    for damped in which:
        print(f"=== class {cls_name}: "
              f"{'omega and zeta, damped model' if damped else 'omega only, elastic model'}")
        prev = []
        for top in tops or range(min(6, M), M + 1):
            data = [m for m in modes if m[0] <= top]
            u, _ = fit(data, damped, starts_for(nstart), rng, extra=prev, cls=cls)
            prev = [u]
            z, zw, zz, par = describe(u, data, damped)
            rms = np.sqrt(np.mean(z**2))
            nfree = len([i for i in (range(8) if damped else range(5)) if i not in cls["bounds"][2]])
            print(f"modes 1-{top}: RMS z {rms:.2f}  chi2 {np.sum(z**2):.1f} on {len(z)} obs, "
                  f"{len(z) - nfree} dof")
            print("   omega z: " + " ".join(f"{v:+.1f}" for v in zw))
            if damped:
                print("   zeta  z: " + " ".join(f"{v:+.1f}" for v in zz))
            print("   " + " ".join(f"{k}={v:.4g}" for k, v in par.items())
                  + f"  kappaG/E={par['g'] * par['r2']:.4g}"
                  + f"  |n| e^2 = {abs(par['NL2_over_EI']) * par['e0a_over_L'] ** 2:.2e}")
            sys.stdout.flush()


if __name__ == "__main__":
    if sys.argv[1] == "validate":
        validate(sys.argv[2])
    elif sys.argv[1] == "fit":
        # fit MEASURED NSTART CLASS elastic|damped|both
        which = {"elastic": (False,), "damped": (True,), "both": (False, True)}[sys.argv[5]]
        tops = [int(v) for v in sys.argv[6].split(",")] if len(sys.argv) > 6 else None
        main_fit(sys.argv[2], int(sys.argv[3]), sys.argv[4], which, tops)
