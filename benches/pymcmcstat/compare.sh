#!/bin/sh
# One-thread comparison of `nanobeam calibrate` with pymcmcstat on the same data
# (see README.md). Usage: benches/pymcmcstat/compare.sh [PYTHON] [RUNS]
# PYTHON: a python with numpy<2, scipy<1.12, pymcmcstat, pyyaml (default: python3).
set -e
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
py=${1:-python3}
runs=${2:-3}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# The binary a user runs: `cargo build --release` / `cargo install --path .`
# ([profile.release] in Cargo.toml). The dev profile of the test suite has
# debug assertions and overflow checks; NANOBEAM_PROFILE=dev measures it.
profile=${NANOBEAM_PROFILE:-release}
case $profile in
  release) (cd "$root" && cargo build --quiet --release --bin nanobeam); bin="$root/target/release/nanobeam" ;;
  dev) (cd "$root" && cargo build --quiet --bin nanobeam); bin="$root/target/debug/nanobeam" ;;
  *) echo "NANOBEAM_PROFILE: '$profile' is not one of release, dev" >&2; exit 2 ;;
esac
echo "nanobeam binary: $bin ($profile profile)"
# Wall seconds of a command (stdout discarded) to the millisecond, from
# GNU date's nanosecond clock: /usr/bin/time's %e resolves 0.01 s, 9 % of a
# ~0.11 s nanobeam run, which is coarser than the margin being measured.
wall() {
  t0=$(date +%s%N)
  "$@" > /dev/null
  t1=$(date +%s%N)
  echo "$(( (t1 - t0) / 1000000 ))" | awk '{ printf "%.3f", $1 / 1000 }'
}
draws=80000   # 4 chains x 20 000 draws (measured.yaml)
export RAYON_NUM_THREADS=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 MKL_NUM_THREADS=1
echo "load before: $(uptime)"
for i in $(seq "$runs"); do
  rm -rf "$out/nb"
  t=$(wall taskset -c 0 "$bin" calibrate "$here/measured.yaml" --out "$out/nb" --json)
  echo "nanobeam   run $i: $t s wall = $(echo "$t * 1000000 / $draws" | bc -l | cut -c1-6) us/draw"
done
for i in $(seq "$runs"); do
  t=$(wall taskset -c 0 "$py" "$here/calibrate.py" "$here/measured.yaml" "$out/py")
  echo "pymcmcstat run $i: $t s wall = $(echo "$t * 1000000 / $draws" | bc -l | cut -c1-6) us/draw"
done
echo "load after: $(uptime)"
