"""cc7 variants of issue 69 defect 3 (tests/invariance.md): the record's displacements x 1e10,
x 1e150 and + 3e-11 m, every value written with repr (the shortest round-trip form), times as
written. Usage: python3 invariance_variants.py data/md/cc7.langevin.csv.gz OUT_DIR, then
nanobeam identify OUT_DIR/cc7.x1e10.csv --beam data/md/tube-cc7.yaml --json (and the others)."""
import csv
import gzip
import sys

src, out = sys.argv[1], sys.argv[2]
rows = list(csv.reader(gzip.open(src, "rt")))
head, body = rows[0], rows[1:]
for name, f in [("x1e10", lambda v: v * 1e10), ("x1e150", lambda v: v * 1e150), ("p3e-11", lambda v: v + 3e-11)]:
    with open(f"{out}/cc7.{name}.csv", "w") as o:
        o.write(",".join(head) + "\n")
        for r in body:
            o.write(r[0] + "," + ",".join(repr(f(float(v))) for v in r[1:]) + "\n")
