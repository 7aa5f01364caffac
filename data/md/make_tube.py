#!/usr/bin/env python3
"""Write a LAMMPS data file of an armchair (n,n) carbon nanotube along x.

Standard library only. The tube is built by rolling a graphene sheet: in the
unrolled sheet the circumference runs along the armchair direction (period
3*a_cc per hexagon) and the axis along the zigzag direction (period
sqrt(3)*a_cc, two atom rows per period). Row 0 holds atoms at arc positions
3k*a_cc + {0, a_cc}; row 1, shifted by half a period along the axis, holds
3k*a_cc + {1.5, 2.5}*a_cc. The geometry is nominal: the LAMMPS input
minimises it with the potential before anything is frozen.

usage: make_tube.py N_CHIRAL N_CELLS A_CC_ANGSTROM OUT.data
prints: the atom count, the tube length (A) and the mean diameter (A).
"""
import math
import sys


def tube(n, cells, acc):
    circ = 3.0 * n * acc
    radius = circ / (2.0 * math.pi)
    period = math.sqrt(3.0) * acc
    atoms = []
    for c in range(cells):
        for row, offsets in ((0, (0.0, 1.0)), (1, (1.5, 2.5))):
            x = c * period + row * period / 2.0
            for k in range(n):
                for o in offsets:
                    phi = 2.0 * math.pi * (3.0 * k + o) * acc / circ
                    atoms.append((x, radius * math.cos(phi), radius * math.sin(phi)))
    return atoms, radius


def main():
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    n, cells, acc, out = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), sys.argv[4]
    atoms, radius = tube(n, cells, acc)
    xs = [a[0] for a in atoms]
    pad = 20.0  # box margin (A): far more than any thermal deflection of these tubes
    with open(out, "w") as f:
        f.write(f"({n},{n}) carbon nanotube, {cells} cells, a_cc = {acc} A, axis x\n\n")
        f.write(f"{len(atoms)} atoms\n1 atom types\n\n")
        f.write(f"{min(xs) - pad} {max(xs) + pad} xlo xhi\n")
        f.write(f"{-radius - pad} {radius + pad} ylo yhi\n")
        f.write(f"{-radius - pad} {radius + pad} zlo zhi\n\n")
        f.write("Masses\n\n1 12.011\n\nAtoms # atomic\n\n")
        for i, (x, y, z) in enumerate(atoms, start=1):
            f.write(f"{i} 1 {x:.6f} {y:.6f} {z:.6f}\n")
    print(len(atoms), max(xs) - min(xs), 2.0 * radius)


if __name__ == "__main__":
    main()
