#!/bin/sh
# Time to the same settled state, penedge and YADE Polyhedra, back to back (docs/benchmarks.md,
# "Mechanics", "Time to equilibrium"). Usage: benches/yade/settle_time.sh BLOCKS SPEED
# Settled: the fastest free block slower than SPEED (m/s) after one has been faster than 1 mm/s
# (or the unbalanced-force ratio below 1e-5, whichever comes first). 2 threads each.
# Needs a release build of penedge-bench and the Debian package `yade`.
set -e
blocks=${1:-100}
speed=${2:-1e-4}
out=${OUT:-/tmp/penedge-mechanics}
mkdir -p "$out"
bench=target/release/penedge-bench
echo "== penedge: $(date -u) load: $(cut -d' ' -f1-3 /proc/loadavg)"
$bench mechanics --blocks "$blocks" --samples 0 --max-steps 100000 --speed "$speed" \
    --threads 2 --export "$out/model-$blocks-settle.txt"
echo "== YADE: $(date -u) load: $(cut -d' ' -f1-3 /proc/loadavg)"
OMP_NUM_THREADS=2 MAX_STEPS=${MAX_STEPS:-100000} yade -n -j2 -x benches/yade/settle.py \
    "$out/model-$blocks-settle.txt" 2>&1 | grep RESULT
echo "== end: $(date -u) load: $(cut -d' ' -f1-3 /proc/loadavg)"
