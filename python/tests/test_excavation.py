"""Excavations from Python: tunnels, caverns and shafts removed from block systems, in the
spec and in stages (docs/generation.md, "Excavations"). Volumes worked out by hand."""

import math
from pathlib import Path

import numpy as np
import pytest

import penedge

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def polygon_area(n, r):
    """A regular n-gon inscribed in a circle of radius r."""
    return 0.5 * n * r * r * math.sin(2 * math.pi / n)


def grid(n, size):
    h = size / n
    return penedge.BlockSystem(
        [
            penedge.Block.cuboid([i * h, j * h, k * h], [(i + 1) * h, (j + 1) * h, (k + 1) * h])
            for i in range(n)
            for j in range(n)
            for k in range(n)
        ]
    )


def total(system):
    return float(np.sum(system.arrays().volumes))


def test_a_box_tunnel_through_a_grid_removes_its_section_times_the_width():
    rock = grid(3, 9.0)
    tunnel = {
        "type": "tunnel",
        "profile": "polygon",
        "vertices": [[-1, -0.75], [1, -0.75], [1, 0.75], [-1, 0.75]],
        "start": [4.2, -5, 4.6],
        "trend": 0,
        "length": 30,
    }
    left, report = rock.excavate(tunnel)
    exact = 2 * 1.5 * 9
    assert total(rock) - total(left) == pytest.approx(exact, rel=1e-9)
    assert report["volume_removed"] == pytest.approx(exact, rel=1e-9)
    assert (report["removed_blocks"], report["cut_blocks"]) == (0, 3)
    # Every block stays one block: 27 bodies, some of several parts.
    assert len(set(left.body_ids.tolist())) == 27
    assert len(left) > 27
    assert len(left.internal_faces()["areas"]) > 0


def test_excavating_in_stages():
    rock = grid(2, 10.0)
    shaft = {
        "type": "shaft",
        "profile": "circle",
        "radius": 1,
        "segments": 12,
        "top": [5, 5, 10],
        "depth": 4,
    }
    cavern = {
        "type": "cavern",
        "center": [5, 5, 4],
        "trend": 30,
        "length": 6,
        "width": 3,
        "height": 2,
    }
    one, r1 = rock.excavate(shaft)
    two, r2 = one.excavate(cavern)
    assert r1["volume_removed"] == pytest.approx(polygon_area(12, 1) * 4, rel=1e-9)
    assert r2["volume_removed"] == pytest.approx(6 * 3 * 2, rel=1e-9)  # below the shaft
    assert total(rock) - total(two) == pytest.approx(polygon_area(12, 1) * 4 + 36, rel=1e-9)


def test_the_tunnel_example_generates_with_its_tunnel():
    system, report = penedge.generate(EXAMPLES / "tunnel_circular.toml")
    exact = polygon_area(16, 2) * 10
    assert report["excavated_volume"] == pytest.approx(exact, rel=1e-9)
    assert total(system) == pytest.approx(12 * 10 * 12 - exact, rel=1e-9)
    assert report["blocks"] == len(system)


@pytest.mark.parametrize(
    ("fields", "field", "words"),
    [
        ({"radius": 1, "length": 0}, "excavation.length", "greater than zero"),
        ({"radius": 0, "length": 5}, "excavation.radius", "greater than zero"),
        ({"radius": float("nan"), "length": 5}, "excavation.radius", "finite"),
        ({"radius": 1, "length": 5, "start": [50, 50, 50]}, "excavation", "removes no rock"),
    ],
)
def test_bad_excavations_name_their_field(fields, field, words):
    tunnel = {"type": "tunnel", "profile": "circle", "start": [1, -1, 1], "trend": 0, **fields}
    with pytest.raises(penedge.SpecError, match=words) as e:
        grid(1, 2.0).excavate(tunnel)
    assert e.value.field == field


def test_a_profile_that_crosses_itself_is_refused():
    bow = {
        "type": "shaft",
        "profile": "polygon",
        "vertices": [[0, 0], [1, 1], [1, 0], [0, 1]],
        "top": [1, 1, 2],
        "depth": 1,
    }
    with pytest.raises(penedge.SpecError, match="crosses itself") as e:
        grid(1, 2.0).excavate(bow)
    assert e.value.field == "excavation.vertices"
