#!/usr/bin/env python3
"""Coverage of `nanobeam identify`'s intervals on records of gen.py (needs numpy, pyyaml).

usage: evaluate.py DIR   (DIR holds the identified files m<SEED>.yaml)
A mode whose omega lies more than 20 of its sd from its number's truth is counted as misnumbered
and left out of the coverage; the others give z = (estimate - truth)/sd for omega and zeta."""
import glob, math, sys
import numpy as np
import yaml

F_GHZ = [133.1, 352.5, 651.0, 1006.2, 1400.4, 1823.5, 2253.3, 2699.6, 3145.6, 3590.9, 4040.2]
GAMMA = 2e11
files = sorted(glob.glob(sys.argv[1] + '/m*.yaml'))
zw, zz, misnumbered = [], [], 0
for fn in files:
    for m in yaml.safe_load(open(fn))['modes']:
        w = 2 * math.pi * F_GHZ[m['mode'] - 1] * 1e9
        a = (m['omega_rad_s'] - w) / m['omega_sd_rad_s']
        if abs(a) > 20:
            misnumbered += 1
            continue
        zw.append(a)
        zz.append((m['zeta'] - GAMMA / (2 * w)) / m['zeta_sd'])
print(f'records {len(files)}, modes numbered right {len(zw)}, misnumbered {misnumbered}')
for name, z in [('omega', np.array(zw)), ('zeta', np.array(zz))]:
    print(f'{name:6} 95 % interval covers {np.mean(abs(z) <= 1.96):.3f}, 3 sd {np.mean(abs(z) <= 3):.3f}, '
          f'mean z {z.mean():+.2f}, sd z {z.std():.2f}')
