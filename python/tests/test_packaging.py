"""What ``pip show penedge`` and the package metadata say: name, summary, version, author,
licence (with its file), and no placeholder URL anywhere in the package manifests."""

from __future__ import annotations

import re
from importlib import metadata
from pathlib import Path

import penedge

ROOT = Path(__file__).resolve().parents[2]
MANIFESTS = [
    "pyproject.toml",
    "Cargo.toml",
    *(f"crates/{c}/Cargo.toml" for c in ("penedge", "penedge-py", "penedge-bench")),
]


def test_metadata_is_complete():
    meta = metadata.metadata("penedge")
    assert meta["Name"] == "penedge"
    assert meta["Version"] == penedge.__version__
    assert "penetration-edge" in meta["Summary"]
    assert meta.get("Author") or meta.get("Author-email")
    assert meta.get("License-Expression") == "MIT" or meta.get("License") == "MIT"
    assert "LICENSE" in (meta.get_all("License-File") or [])
    assert "numpy>=1.24" in (meta.get_all("Requires-Dist") or [])


def test_the_licence_file_is_the_declared_mit_licence():
    text = (ROOT / "LICENSE").read_text()
    assert text.startswith("MIT License")
    assert "Permission is hereby granted, free of charge" in text
    assert re.search(r'^license = "MIT"$', (ROOT / "pyproject.toml").read_text(), re.M)
    assert re.search(r'^license = "MIT"$', (ROOT / "Cargo.toml").read_text(), re.M)


def test_no_placeholder_urls():
    for name in MANIFESTS:
        text = (ROOT / name).read_text()
        assert ".invalid" not in text, name
        assert "example.com" not in text, name
