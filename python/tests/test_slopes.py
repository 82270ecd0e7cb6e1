"""Slopes and topographic surfaces from Python: the rock left is the exact volume under the
ground (worked out here by trapezoids and triangles), in stages, and bad ground is a
SpecError naming the field."""

import math
from pathlib import Path

import pytest

import penedge

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def rock(size=10.0, n=2):
    """A box of n x n x n cubes."""
    h = size / n
    cubes = [
        penedge.Block.cuboid([i * h, j * h, k * h], [(i + 1) * h, (j + 1) * h, (k + 1) * h])
        for i in range(n)
        for j in range(n)
        for k in range(n)
    ]
    return penedge.BlockSystem(cubes)


def volume(system):
    return float(system.arrays().volumes.sum())


def test_a_benched_slope_leaves_the_area_under_its_profile_times_the_length():
    # Strike North: u is East. Crest at 8 up to x = 3, a face to a bench at 5 (x = 5..6), a
    # face to the toe at 2 from x = 8.
    profile = [[3, 8], [5, 5], [6, 5], [8, 2]]
    area = 3 * 8 + 2 * (8 + 5) / 2 + 1 * 5 + 2 * (5 + 2) / 2 + 2 * 2
    left, report = rock().excavate(
        {"type": "slope", "origin": [0, 0, 0], "trend": 0, "vertices": profile}
    )
    assert volume(left) == pytest.approx(area * 10, rel=1e-12)
    assert report["volume_removed"] == pytest.approx(1000 - area * 10, rel=1e-12)
    # A second stage, one bench deeper: the rock under the lower ground.
    deeper = [[x, v - 1] for x, v in profile]
    second, _ = left.excavate(
        {"type": "slope", "origin": [0, 0, 0], "trend": 0, "vertices": deeper}
    )
    assert volume(second) == pytest.approx((area - 10) * 10, rel=1e-12)


def test_a_topographic_grid_file_and_its_errors(tmp_path):
    # A ramp z = 2 + 0.5 x: 4.5 m of rock on average over 10 x 10.
    lines = ["x,y,z"] + [f"{x},{y},{2 + 0.5 * x}" for y in (0, 10) for x in (0, 5, 10)]
    grid = tmp_path / "ramp.csv"
    grid.write_text("\n".join(lines) + "\n")
    left, _ = rock().excavate({"type": "topography", "file": str(grid)})
    assert volume(left) == pytest.approx(450.0, rel=1e-12)
    holed = tmp_path / "holed.csv"
    holed.write_text("\n".join(lines[:-1]) + "\n")
    with pytest.raises(penedge.SpecError, match="no elevation at x = 10, y = 10") as e:
        rock().excavate({"type": "topography", "file": str(holed)})
    assert e.value.field == "excavation.file"
    with pytest.raises(penedge.SpecError, match="must go one way along u") as e:
        rock().excavate(
            {"type": "slope", "origin": [0, 0, 0], "trend": 0, "vertices": [[0, 5], [4, 5], [3, 1]]}
        )
    assert e.value.field == "excavation.vertices"


def test_the_slope_examples_generate():
    for name in ("slope_profile.toml", "slope_topography.toml"):
        system, report = penedge.generate(EXAMPLES / name)
        assert len(system) > 10
        assert report["excavated_volume"] > 0


def test_a_fine_zig_zag_slope_generates_with_the_volume_under_its_profile():
    # A tester's spec: a 10 m box, one vertical joint set, the ground a wave 5 + 2 sin 3u
    # with every other vertex 1 cm up, 8,000 vertices written to 9 decimals. Its cut makes
    # needle-shaped parts (2.6 m by a few mm in section, 10 m long) glued along the faces,
    # which were refused as overlapping ("body 3: its parts (blocks) 3652 and 3653 overlap").
    n = 8000
    profile = []
    for i in range(n):
        u = i * 10 / (n - 1)
        v = 5 + 2 * math.sin(3 * u) + 0.01 * (i % 2)
        profile.append([float(f"{u:.9f}"), float(f"{v:.9f}")])
    spec = {
        "domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]},
        "joints": [
            {
                "type": "set",
                "name": "v",
                "dip": 90,
                "dip_direction": 90,
                "spacing": 5,
                "origin": [2.5, 0, 0],
            }
        ],
        "excavations": [{"type": "slope", "origin": [0, 0, 0], "trend": 0, "vertices": profile}],
    }
    system, report = penedge.generate(spec)
    # The rock left: the area under the profile (shoelace, down to z = 0 at both ends) times
    # the 10 m along the strike.
    ring = [(0.0, 0.0), *map(tuple, profile), (10.0, 0.0)]
    twice = math.fsum(
        x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(ring, ring[1:] + ring[:1], strict=True)
    )
    rock_volume = abs(twice) / 2 * 10
    assert volume(system) == pytest.approx(rock_volume, rel=1e-9)
    assert report["excavated_volume"] == pytest.approx(1000 - rock_volume, rel=1e-9)
