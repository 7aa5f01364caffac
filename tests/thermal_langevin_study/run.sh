#!/bin/bash
# usage: tests/thermal_langevin_study/run.sh NANOBEAM OUTDIR SEEDS...   (from the repository root)
# Generates each seed's record with gen.py, identifies it with the cc11 beam file, then evaluates.
set -euo pipefail
bin=$1 out=$2; shift 2
here=$(dirname "$0")
mkdir -p "$out"
for s in "$@"; do
  python3 "$here/gen.py" "$s" "$out/r$s.csv"
  "$bin" identify --beam data/md/tube-cc11.yaml "$out/r$s.csv" --out "$out/m$s.yaml" 2> "$out/e$s.txt" || echo "seed $s: exit $?"
done
python3 "$here/evaluate.py" "$out"
