"""Slopes and topographic surfaces from Python: the rock left is the exact volume under the
ground (worked out here by trapezoids and triangles), in stages, and bad ground is a
SpecError naming the field."""

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
