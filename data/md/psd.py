#!/usr/bin/env python3
"""Welch PSD of a committed MD record and its peaks (needs numpy).

usage: psd.py RECORD.csv.gz SLICE [TAU_PS]
  SLICE   1, 2 or 3: the slice whose y and z columns are averaged as independent segments
  TAU_PS  the Langevin damping time (default 5): sets the segment length
writes RECORD-sliceN.psd.csv (header omega_rad_s,psd_m2_s_per_rad: the one-sided PSD
per rad/s, so that its integral over omega >= 0 is the variance, the record kind
`nanobeam identify` reads) and prints the local maxima that stand above their
surroundings.

Segment length: a Langevin bath of damping time tau gives every line a half-power width
1/tau in omega (1/(2 pi tau) in Hz); the segment is the shortest power of two in samples
whose bin spacing is at most a quarter of that width (T_seg >= 8 pi tau), so that each line
spans four or more bins (identify needs three samples in a half-power band). Hann window, 50 % overlap, mean removed per segment.
"""
import gzip
import math
import sys

import numpy as np


def welch(x, nseg, dt):
    win = np.hanning(nseg)
    step = nseg // 2
    scale = 1.0 / (np.sum(win**2) / dt)  # one-sided density per Hz after doubling
    acc, k = None, 0
    for start in range(0, len(x) - nseg + 1, step):
        s = x[start:start + nseg]
        s = (s - s.mean()) * win
        p = np.abs(np.fft.rfft(s)) ** 2 * scale
        p[1:-1] *= 2.0
        acc = p if acc is None else acc + p
        k += 1
    return np.fft.rfftfreq(nseg, dt), acc / k, k


def main():
    path, slice_no = sys.argv[1], int(sys.argv[2])
    tau = float(sys.argv[3]) * 1e-12 if len(sys.argv) > 3 else 5e-12
    with gzip.open(path, "rt") as f:
        header = f.readline().strip().split(",")
        data = np.loadtxt(f, delimiter=",")
    t = data[:, 0]
    dt = t[1] - t[0]
    cols = [header.index(f"thermal_slice{slice_no}_y_m"), header.index(f"thermal_slice{slice_no}_z_m")]
    nseg = 2 ** math.ceil(math.log2(8 * math.pi * tau / dt))
    if nseg > len(t):
        sys.exit(f"record of {len(t)} samples shorter than one segment ({nseg} samples = {nseg * dt:.3e} s)")
    psd, segments = None, 0
    for c in cols:
        f, p, k = welch(data[:, c], nseg, dt)
        psd = p if psd is None else psd + p
        segments += k
    psd /= len(cols)
    omega = 2 * math.pi * f[1:]
    s_omega = psd[1:] / (2 * math.pi)  # per Hz -> per rad/s
    out = path.replace(".csv.gz", f"-slice{slice_no}.psd.csv")
    with open(out, "w") as o:
        o.write("omega_rad_s,psd_m2_s_per_rad\n")
        for w, s in zip(omega, s_omega):
            o.write(f"{w:.6e},{s:.6e}\n")
    print(f"{path} slice {slice_no}: {len(t)} samples, dt {dt:.2e} s, segment {nseg} samples "
          f"({nseg * dt * 1e12:.1f} ps, bin {1 / (nseg * dt) / 1e9:.2f} GHz), {segments} segments (y and z)")
    # peaks: local maxima of the log-PSD over +-3 bins standing 3x above the minimum within +-10 bins
    ls = np.log10(s_omega)
    for i in range(3, len(ls) - 3):
        if ls[i] == ls[i - 3:i + 4].max():
            lo = ls[max(0, i - 10):i + 11].min()
            if ls[i] - lo > math.log10(3.0) and f[i + 1] < 20e12:
                print(f"  peak {f[i + 1] / 1e9:8.1f} GHz  (omega {omega[i]:.3e} rad/s)  "
                      f"{ls[i] - lo:.2f} decades above its surroundings")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
