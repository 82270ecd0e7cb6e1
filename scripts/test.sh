#!/usr/bin/env bash
# Installs penedge with its test dependencies and runs every check: Rust format, lint and
# tests, then the Python tests (warnings are errors). CI runs exactly this (.ci/run).
set -euo pipefail
cd "$(dirname "$0")/.."

echo "== install (pip builds the Rust extension with maturin)"
python3 -m pip install --quiet --disable-pip-version-check -e '.[test]'
# Debian's chromium + chromium-driver for test_browser.py (apt-get: root and the package
# servers); where they cannot be installed, it says so and that test is skipped.
bash scripts/install-browser.sh --optional

echo "== rust: format, lint, tests"
cargo fmt --all -- --check
cargo clippy --workspace --all-targets --quiet -- -D warnings
cargo test --workspace --quiet
RUSTDOCFLAGS='-D warnings' cargo doc -p penedge --no-deps --quiet

echo "== python: lint, tests"
python3 -m ruff check python tools
python3 -m pytest python/tests -q -W error
