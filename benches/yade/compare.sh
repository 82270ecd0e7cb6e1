#!/bin/sh
# penedge and YADE Polyhedra on the same settling model, back to back (docs/benchmarks.md,
# "Mechanics"). Usage: benches/yade/compare.sh BLOCKS [YADE_MAX_STEPS]
# Needs a release build of penedge-bench and the Debian package `yade`.
set -e
blocks=${1:-200}
export MAX_STEPS=${2:-100000}
out=${OUT:-/tmp/penedge-mechanics}
mkdir -p "$out"
bench=target/release/penedge-bench
echo "== $(date -u) load: $(cut -d' ' -f1-3 /proc/loadavg)"
$bench mechanics --blocks "$blocks" --samples 4 --max-steps 100000 --export "$out/model-$blocks.txt"
echo "== penedge, the YADE run's $MAX_STEPS steps only: $(date -u) load: $(cut -d' ' -f1-3 /proc/loadavg)"
$bench mechanics --blocks "$blocks" --samples 0 --max-steps "$MAX_STEPS"
echo "== YADE: $(date -u) load: $(cut -d' ' -f1-3 /proc/loadavg)"
OMP_NUM_THREADS=2 yade -n -j2 -x benches/yade/settle.py "$out/model-$blocks.txt" 2>&1 | grep RESULT
echo "== end: $(date -u) load: $(cut -d' ' -f1-3 /proc/loadavg)"
