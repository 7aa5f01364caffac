#!/bin/sh
# Run the MD cases of data/md one after another: ./run.sh CASE [CASE ...]
# CASE is one of cc7 cl7 cc11 cl11 (support, nominal free length in nm) or cc7nve. Outputs go to
# data/md/work/ (ignored by git); convert.py turns them into the committed records.
# Each LAMMPS process is serial and runs under nice: the machine is shared.
# NPROD / NNVE in the environment override the case's production lengths (steps), e.g. to
# fit a time budget; the provenance of each record states the length actually run.
set -eu
cd "$(dirname "$0")"
mkdir -p work
LMP=${LMP:-lmp}
for case in "$@"; do
  # case: support  total_cells  seed  nprod  nnve   (steps of 1 fs)
  case $case in
    cc7)  set -- cc 33 4711 600000 300000 ;;
    cl7)  set -- cl 31 4721 500000 0 ;;
    cc11) set -- cc 49 4731 450000 0 ;;
    cl11) set -- cl 47 4741 400000 0 ;;
    # cc7 again with another seed: 20 ps in the bath, then an NVE production (undamped lines)
    cc7nve) set -- cc 33 4751 20000 120000 ;;
    *) echo "unknown case $case (cc7 cl7 cc11 cl11 cc7nve)" >&2; exit 2 ;;
  esac
  printf 'support %s\ncells %s\nseed %s\nnequil 30000\nnprod %s\nnnve %s\nevery 20\ntau 5.0\n' \
    "$1" "$2" "$3" "${NPROD:-$4}" "${NNVE:-$5}" > "work/$case.params"
  python3 make_tube.py 5 "$2" 1.42 "work/$case.data" > "work/$case.geometry"
  nice -n 10 "$LMP" -in in.tube -log "work/$case.log" -screen none \
    -var data "work/$case.data" -var cells "$2" -var support "$1" -var seed "$3" \
    -var nequil 30000 -var nprod "${NPROD:-$4}" -var nnve "${NNVE:-$5}" -var every 20 -var tau 5.0 \
    -var out "work/$case"
done
