#!/usr/bin/env bash
# Runs the cargo-fuzz targets of fuzz/ one after the other, each for SECONDS (default 60),
# at the lowest CPU priority: scripts/fuzz.sh [SECONDS] [TARGET...] (all targets by default).
# Needs the nightly toolchain and cargo-fuzz (`cargo install cargo-fuzz`). Each target starts
# from its committed seeds (fuzz/seeds/TARGET) and its growing corpus (fuzz/corpus/TARGET);
# a crash, timeout or leak stops the target and is saved under fuzz/artifacts/TARGET. Copy it
# into crates/penedge/tests/fuzz_regressions/TARGET/ to keep it as a regression test
# (docs/fuzzing.md).
set -euo pipefail
cd "$(dirname "$0")/../fuzz"

seconds=60
if [[ $# -gt 0 && $1 =~ ^[0-9]+$ ]]; then
    seconds=$1
    shift
fi
targets=("$@")
if [[ ${#targets[@]} -eq 0 ]]; then
    mapfile -t targets < <(cargo +nightly fuzz list)
fi

nice -n 19 cargo +nightly fuzz build
status=0
for target in "${targets[@]}"; do
    echo "== fuzz $target for $seconds s"
    mkdir -p "corpus/$target" "seeds/$target"
    if ! nice -n 19 cargo +nightly fuzz run "$target" "corpus/$target" "seeds/$target" -- \
        -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1; then
        echo "!! $target found a problem: see fuzz/artifacts/$target"
        status=1
    fi
done
exit $status
