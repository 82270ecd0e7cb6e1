#!/usr/bin/env bash
# Installs what the browser test (python/tests/test_browser.py) needs: Debian's headless
# Chromium and its WebDriver (packages chromium and chromium-driver), and the Python
# package selenium. Idempotent: when both are there it only checks, in well under a second.
# apt-get needs root (CI and the development machines run as root); no prompts.
set -euo pipefail

have_browser() {
    command -v chromium >/dev/null 2>&1 && command -v chromedriver >/dev/null 2>&1
}

if have_browser; then
    echo "install-browser: chromium and chromedriver are installed"
else
    if [ "$(id -u)" -ne 0 ]; then
        echo "install-browser: chromium or chromedriver is missing and this is not root;" >&2
        echo "  run: sudo apt-get install chromium chromium-driver" >&2
        exit 1
    fi
    echo "install-browser: apt-get install chromium chromium-driver"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends chromium chromium-driver >/dev/null
    have_browser || { echo "install-browser: chromium still missing after apt-get" >&2; exit 1; }
fi

PYTHON="${PYTHON:-python3}"
if "$PYTHON" -c "import selenium" >/dev/null 2>&1; then
    echo "install-browser: selenium is installed"
else
    echo "install-browser: pip install selenium"
    "$PYTHON" -m pip install --quiet --disable-pip-version-check "selenium>=4.11"
fi
