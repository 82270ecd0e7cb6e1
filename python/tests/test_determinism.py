"""Determinism from Python: the same contacts for any number of threads and any block order.

``BlockSystem.detect`` has no thread-count argument; rayon's global pool reads
``RAYON_NUM_THREADS`` when it starts, so each thread count runs in a fresh interpreter.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

import penedge

SPEC = {
    "domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]},
    "joints": [
        {"type": "set", "dip": 35, "dip_direction": 40, "spacing": 1.6, "origin": [0.3, 0.7, 0.1]},
        {"type": "set", "dip": 75, "dip_direction": 150, "spacing": 1.4, "origin": [1, 2, 3]},
        {"type": "set", "dip": 85, "dip_direction": 260, "spacing": 1.5, "origin": [2, 1, 0.5]},
    ],
}

# Prints a digest of everything detect returns (contacts, features, penetrating pairs and
# the geometry, bit for bit) for the paper's Example 3 and the jointed system above.
SCRIPT = f"""
import hashlib
import penedge
spec = {SPEC!r}
digest = hashlib.sha256()
for system in (penedge.paper_example(3), penedge.generate(spec)[0]):
    found = system.detect(geometry=True)
    for name in ("pairs", "types", "feature_kinds", "feature_ids", "penetrating",
                 "normals", "distances", "areas", "point_offsets", "points"):
        digest.update(getattr(found, name).tobytes())
print(len(system), len(found), digest.hexdigest())
"""


def run_with_threads(threads: int) -> str:
    env = {**os.environ, "RAYON_NUM_THREADS": str(threads)}
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT], env=env, capture_output=True, text=True, check=True
    )
    return done.stdout.strip()


def test_any_number_of_threads_gives_identical_output():
    one = run_with_threads(1)
    blocks, contacts, _ = one.split()
    assert int(blocks) > 100
    assert int(contacts) > 300
    for threads in (2, 4):
        assert run_with_threads(threads) == one, f"{threads} threads"


def renumbered(found: penedge.SystemContacts, order: np.ndarray):
    """The contacts of a permuted system (block k is block order[k] of the original) in the
    original ids, sorted: pairs, types, feature kinds and ids (smaller id first)."""
    pairs = order[found.pairs]
    flip = pairs[:, 0] > pairs[:, 1]
    kinds, ids = found.feature_kinds.copy(), found.feature_ids.copy()
    pairs[flip] = pairs[flip][:, ::-1]
    kinds[flip] = kinds[flip][:, ::-1]
    ids[flip] = ids[flip][:, ::-1]
    sort = np.lexsort((pairs[:, 1], pairs[:, 0]))
    penetrating = np.sort(order[found.penetrating], axis=1)
    penetrating = penetrating[np.lexsort((penetrating[:, 1], penetrating[:, 0]))]
    return pairs[sort], found.types[sort], kinds[sort], ids[sort], penetrating


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_any_order_of_the_blocks_gives_the_same_contacts(seed):
    system, _ = penedge.generate(SPEC)
    blocks = system.blocks
    expected = system.detect()
    order = np.random.default_rng(seed).permutation(len(blocks))
    permuted = penedge.BlockSystem([blocks[i] for i in order])
    got = renumbered(permuted.detect(), order)
    want = (
        expected.pairs,
        expected.types,
        expected.feature_kinds,
        expected.feature_ids,
        expected.penetrating.reshape(-1, 2),
    )
    names = ("pairs", "types", "kinds", "ids", "penetrating")
    for name, g, w in zip(names, got, want, strict=True):
        assert np.array_equal(g, w), name
