"""scripts/install-browser.sh where the browser cannot be installed: scripts/test.sh passes
``--optional``, so that the rest of the tests run and the browser test is skipped with a
message, instead of the whole run failing."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "install-browser.sh"
BASH = shutil.which("bash")


def install_browser(tmp_path, *args):
    """Runs the script as a non-root user with no chromium on the PATH (a stub `id` says
    uid 1000; the PATH holds nothing else)."""
    stub = tmp_path / "id"
    stub.write_text("#!/bin/sh\necho 1000\n")
    stub.chmod(0o755)
    return subprocess.run(
        [BASH, str(SCRIPT), *args],
        capture_output=True,
        text=True,
        env={"PATH": str(tmp_path)},
        check=False,
    )


@pytest.mark.skipif(BASH is None, reason="no bash")
def test_optional_install_says_the_browser_test_is_skipped_and_succeeds(tmp_path):
    done = install_browser(tmp_path, "--optional")
    assert done.returncode == 0, done.stderr
    assert "not root" in done.stderr
    assert "test_browser.py) will be skipped" in done.stderr


@pytest.mark.skipif(BASH is None, reason="no bash")
def test_required_install_fails_with_the_reason(tmp_path):
    done = install_browser(tmp_path)
    assert done.returncode == 1
    assert "sudo apt-get install chromium chromium-driver" in done.stderr
    assert "skipped" not in done.stderr


def test_test_script_installs_the_browser_optionally():
    text = (SCRIPT.parent / "test.sh").read_text()
    assert "bash scripts/install-browser.sh --optional" in text
