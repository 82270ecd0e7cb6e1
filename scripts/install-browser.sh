#!/usr/bin/env bash
# Installs what the browser test (python/tests/test_browser.py) needs: Debian's headless
# Chromium and its WebDriver (packages chromium and chromium-driver), and the Python
# package selenium. Idempotent: when both are there it only checks, in well under a second.
# apt-get needs root and the system's package servers (CI and the development machines run
# as root); no prompts.
#
# --optional (what scripts/test.sh passes): where they cannot be installed (not root, no
# apt-get, no network), say so, say that the browser test will be skipped, and exit 0, so
# that the rest of the tests still run. Without it, that is an error (exit 1).
set -euo pipefail

optional=0
if [ "${1:-}" = "--optional" ]; then
    optional=1
fi

# Stops with the reason: a note and exit 0 when --optional, an error otherwise.
cannot() {
    if [ "$optional" -eq 1 ]; then
        echo "install-browser: $1" >&2
        echo "install-browser: the browser test (python/tests/test_browser.py) will be skipped" >&2
        exit 0
    fi
    echo "install-browser: $1" >&2
    exit 1
}

have_browser() {
    command -v chromium >/dev/null 2>&1 && command -v chromedriver >/dev/null 2>&1
}

if have_browser; then
    echo "install-browser: chromium and chromedriver are installed"
else
    if [ "$(id -u)" -ne 0 ]; then
        cannot "chromium or chromedriver is missing and this is not root; to install them: sudo apt-get install chromium chromium-driver"
    fi
    command -v apt-get >/dev/null 2>&1 ||
        cannot "chromium or chromedriver is missing and there is no apt-get to install them"
    echo "install-browser: apt-get install chromium chromium-driver"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq || cannot "apt-get update failed (no package servers?)"
    apt-get install -y -qq --no-install-recommends chromium chromium-driver >/dev/null ||
        cannot "apt-get install chromium chromium-driver failed"
    have_browser || cannot "chromium still missing after apt-get"
fi

PYTHON="${PYTHON:-python3}"
if "$PYTHON" -c "import selenium" >/dev/null 2>&1; then
    echo "install-browser: selenium is installed"
else
    echo "install-browser: pip install selenium"
    "$PYTHON" -m pip install --quiet --disable-pip-version-check "selenium>=4.11" ||
        cannot "pip install selenium failed"
fi
