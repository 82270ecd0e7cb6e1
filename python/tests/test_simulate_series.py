"""The ParaView series of ``penedge simulate`` (docs/models.md, "Results"): the sub-contacts'
water force and the bolt elements, written from a real simulation and read back (with the
standard library's XML parser). References computed here: the water force of a face under a
water table, and each element's force over its elongation, its stiffness."""

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import penedge
from penedge import cli
from penedge.model.series import Series

STIFFNESS = 1e7  # the bolt's, N/m
EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"


def bolted_cube_under_water():
    """A free 1 m cube on a fixed base, a water table 2 m above the base's top, and a 1.5 m
    bolt down from the cube's top into the base."""
    base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    sim = penedge.Simulation(penedge.BlockSystem([base, cube]), density=2500.0)
    sim.fix([0])
    sim.set_joint(kn=1e9, ks=1e9, friction=30.0)
    sim.set_water(level=2.0)
    sim.add_bolt([0, 0, 1], [0, 0, -1], 1.5, stiffness=STIFFNESS, capacity=1e6)
    assert sim.solve()["converged"]
    return sim


def read(path):
    """The data arrays of a VTK XML file, by name, as float arrays; and its piece."""
    root = ET.parse(path).getroot()
    arrays = {a.get("Name"): np.array(a.text.split(), dtype=float) for a in root.iter("DataArray")}
    return arrays, root.find(".//Piece")


def listed(index):
    return [d.get("file") for d in ET.parse(index).getroot().iter("DataSet")]


def test_the_series_shows_the_water_forces_and_the_bolts(tmp_path):
    sim = bolted_cube_under_water()
    contacts, bolts = sim.contacts(), sim.bolts()
    series = Series(tmp_path, speed=1e-4)
    n = len(sim.positions)
    for time in (0.0, 1.0):
        series.write(time, sim.system(), np.zeros((n, 3)), sim.velocities, contacts, bolts=bolts)
    assert listed(series.contacts_index) == ["subcontacts_000000.vtp", "subcontacts_000001.vtp"]
    assert listed(series.bolts_index) == ["bolts_000000.vtp", "bolts_000001.vtp"]

    subs, _ = read(tmp_path / "subcontacts_000001.vtp")
    offsets = contacts["sub_offsets"].astype(np.int64)
    per_sub = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
    assert np.array_equal(subs["contact"], per_sub)
    # The one face-face contact carries the pressure at its depth below the table (2 m, less
    # the cube's settlement) over its 1 m2; the others none.
    face = contacts["types"] == penedge.FACE_FACE
    assert face.sum() == 1
    depth = 2.0 - contacts["points"][per_sub == np.flatnonzero(face)[0], 2].mean()
    assert depth == pytest.approx(2.0, abs=1e-4)
    expected = np.where(face, 9810.0 * depth * 1.0, 0.0)[per_sub]
    assert subs["water_force"] == pytest.approx(expected, rel=1e-8)

    lines, piece = read(tmp_path / "bolts_000001.vtp")
    k = len(bolts["bolt"])
    assert k >= 1
    assert piece.get("NumberOfLines") == str(k)
    assert lines["connectivity"].tolist() == list(range(2 * k))
    assert lines["offsets"].tolist() == list(range(2, 2 * k + 1, 2))
    points = lines["points"].reshape(-1, 2, 3)
    assert points[:, 0] == pytest.approx(bolts["starts"])
    assert points[:, 1] == pytest.approx(bolts["ends"])
    assert lines["bolt"].tolist() == [0] * k
    assert lines["state"].tolist() == [0] * k  # elastic: force = stiffness x elongation
    assert lines["force"] == pytest.approx(STIFFNESS * lines["elongation"], rel=1e-6)
    assert lines["rest_length"].sum() == pytest.approx(1.5)
    assert lines["shear_force"].reshape(-1, 3) == pytest.approx(np.zeros((k, 3)))


def test_a_frame_without_bolts_writes_no_bolt_series(tmp_path):
    system = penedge.BlockSystem([penedge.Block.cuboid([0, 0, 0], [1, 1, 1])])
    series = Series(tmp_path, speed=1e-4)
    series.write(0.0, system, np.zeros((1, 3)), np.zeros((1, 3)))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blocks.pvd", "blocks_000000.vtu"]


def test_penedge_simulate_writes_the_bolt_series_of_a_bolted_model(tmp_path):
    out = tmp_path / "out"
    model = EXAMPLES / "tunnel_roof_bolt.toml"
    assert cli.main(["simulate", str(model), "-o", str(out), "-q", "--no-pictures"]) == 0
    frames = listed(out / "series" / "blocks.pvd")
    bolt_frames = listed(out / "series" / "bolts.pvd")
    assert len(bolt_frames) == len(frames) >= 2
    lines, _ = read(out / "series" / bolt_frames[-1])
    # The one bolt holds the roof wedge: in tension, elastic, stretched by force / stiffness.
    assert lines["bolt"].tolist() == [0]
    assert lines["state"].tolist() == [0]
    assert lines["force"][0] > 0
    # its one element spans the whole bolt, so its stiffness is the file's (50e6 N/m)
    assert lines["rest_length"].tolist() == [5.0]
    assert lines["force"][0] == pytest.approx(50e6 * lines["elongation"][0], rel=1e-6)
