"""Scalar number arguments: a bool is no number, a relative gap below the rounding is no gap,
and the parts of one body take one rotation however its quaternion is written.

Python counts ``True`` as the int 1 (and numpy's ``np.True_`` converts to 1.0), so every
count, time, density, stiffness or tolerance argument used to take it as 1 or 0. Each is now
an ``InputError`` of kind ``dtype`` naming the argument, as a bool in a list of ids is.
"""

import numpy as np
import pytest

import penedge
from penedge.pictures.scene import build_scene, check_explode


def two_cubes():
    c = penedge.Block.cuboid
    return penedge.BlockSystem([c([0, 0, 0], [1, 1, 1]), c([0, 0, 1], [1, 1, 2])])


def simulation():
    sim = penedge.Simulation(two_cubes())
    sim.fix([0])
    return sim


def notch_system():
    """A U-block of three parts (body 0) and a block in its notch (body 1)."""
    c = penedge.Block.cuboid
    u = [c([0, 0, 0], [3, 1, 1]), c([0, 0, 1], [1, 1, 2]), c([2, 0, 1], [3, 1, 2])]
    return penedge.BlockSystem([*u, c([1, 0, 1], [2, 1, 2])]).with_bodies([0, 0, 0, 1])


def cube_pair():
    c = penedge.Block.cuboid
    return c([0, 0, 0], [1, 1, 1]), c([1, 0, 0], [2, 1, 1])


# (argument name, a call giving it the bool `b`).
CALLS = [
    ("gap", lambda b: penedge.detect_pair(*cube_pair(), gap=b)),
    ("length", lambda b: penedge.detect_pair(*cube_pair(), length=b)),
    ("absolute_gap", lambda b: penedge.detect_pair(*cube_pair(), absolute_gap=b)),
    ("gap", lambda b: penedge.overlap(*cube_pair(), gap=b)),
    ("gap", lambda b: two_cubes().detect(gap=b)),
    ("threads", lambda b: two_cubes().detect(threads=b)),
    ("threads", lambda b: notch_system().detect_bodies(threads=b)),
    ("length", lambda b: notch_system().detect_bodies(length=b)),
    ("gap", lambda b: two_cubes().with_bodies([0, 0], gap=b)),
    ("skin", lambda b: penedge.ContactTracker(two_cubes(), skin=b)),
    ("gap", lambda b: penedge.ContactTracker(two_cubes(), gap=b)),
    ("max_blocks", lambda b: penedge.generate({}, max_blocks=b)),
    ("n", lambda b: penedge.paper_example(b)),
    ("n", lambda b: penedge.paper_table3(b)),
    ("density", lambda b: penedge.Simulation(two_cubes(), density=b)),
    ("gap", lambda b: penedge.Simulation(two_cubes(), gap=b)),
    ("point_width", lambda b: penedge.Simulation(two_cubes(), point_width=b)),
    ("density", lambda b: simulation().set_density(b)),
    ("kn", lambda b: simulation().set_joint(b, 1e9, 30.0)),
    ("friction", lambda b: simulation().set_joint(1e9, 1e9, b)),
    ("residual_friction", lambda b: simulation().set_joint(1e9, 1e9, 30.0, residual_friction=b)),
    ("tension", lambda b: simulation().set_bridge(1e9, 1e9, 30.0, 1e6, b)),
    ("level", lambda b: simulation().set_water(level=b)),
    ("unit_weight", lambda b: simulation().set_water(level=0.5, unit_weight=b)),
    ("pressures[0]", lambda b: simulation().set_water(pressures={0: b})),
    ("surface", lambda b: simulation().set_initial_stress(base=[0.0] * 6, surface=b)),
    ("local", lambda b: simulation().set_damping(local=b)),
    ("viscous", lambda b: simulation().set_damping(viscous=b)),
    ("dt", lambda b: simulation().set_timestep(dt=b)),
    ("safety", lambda b: simulation().set_timestep(safety=b)),
    ("n", lambda b: simulation().step(b)),
    ("t", lambda b: simulation().run_until(b)),
    ("ratio", lambda b: simulation().solve(ratio=b)),
    ("max_steps", lambda b: simulation().solve(max_steps=b)),
    ("fraction", lambda b: simulation().set_update_fraction(b)),
    ("relax_steps", lambda b: simulation().excavate([1], relax_steps=b)),
    ("length", lambda b: simulation().add_bolt([0.5, 0.5, 2], [0, 0, -1], b, 1e8, 1e5)),
    ("stiffness", lambda b: simulation().add_bolt([0.5, 0.5, 2], [0, 0, -1], 1.5, b, 1e5)),
    (
        "shear_capacity",
        lambda b: simulation().add_bolt(
            [0.5, 0.5, 2], [0, 0, -1], 1.5, 1e8, 1e5, shear_stiffness=1e8, shear_capacity=b
        ),
    ),
]


CALL_IDS = [f"{name}-{i}" for i, (name, _) in enumerate(CALLS)]


@pytest.mark.parametrize("value", [True, False, np.True_, np.False_, np.array(True)], ids=repr)
@pytest.mark.parametrize(("name", "call"), CALLS, ids=CALL_IDS)
def test_a_bool_is_no_number(name, call, value):
    with pytest.raises(penedge.InputError, match=r"must be (a real number|an integer)") as e:
        call(value)
    assert e.value.kind == "dtype"
    assert str(e.value).startswith(f"{name} must be ")
    assert f"got the bool {value}" in str(e.value)


def test_the_numbers_themselves_are_still_taken():
    # The checks refuse bools only: ints, floats and numpy scalars pass as before.
    sim = simulation()
    sim.set_joint(np.int64(1_000_000_000), 1e9, np.float32(30.0))
    sim.set_density(np.float64(2500.0))
    sim.step(np.int64(2))
    sim.solve(ratio=1e-3, max_steps=np.uint8(3))
    assert sim.steps == 5
    assert len(two_cubes().detect(threads=np.int16(1), gap=0)) == 1
    assert penedge.paper_example(np.int64(1)) is not None


def test_a_time_in_a_series_is_no_bool(tmp_path):
    system = two_cubes()
    series = penedge.TimeSeries(tmp_path / "series")
    with pytest.raises(penedge.InputError, match=r"^time must be a real number, got the bool True"):
        series.write_step(True, system)
    with pytest.raises(penedge.InputError, match="the time of dataset 1 must be a real number"):
        penedge.write_pvd(tmp_path / "a.pvd", [(0.0, "a.vtu"), (np.True_, "b.vtu")])


def test_the_pictures_take_no_bool_for_a_number():
    with pytest.raises(ValueError, match="explode must be a number, got the bool True"):
        check_explode(True)
    with pytest.raises(ValueError, match="max_blocks must be a whole number, got the bool"):
        build_scene(two_cubes(), 0.0, np.True_)
    assert check_explode(np.float64(0.25)) == 0.25


@pytest.mark.parametrize("gap", [1e-300, 5e-324, 1e-16, 3.5e-15])
def test_a_relative_gap_below_the_rounding_is_refused_everywhere(gap):
    a, b = cube_pair()
    calls = [
        lambda: penedge.detect_pair(a, b, gap=gap),
        lambda: penedge.overlap(a, b, gap=gap),
        lambda: two_cubes().detect(gap=gap),
        lambda: penedge.ContactTracker(two_cubes(), gap=gap),
        lambda: penedge.Simulation(two_cubes(), gap=gap),
    ]
    for call in calls:
        with pytest.raises(penedge.ToleranceError, match="`gap` must be 0 or at least") as e:
            call()
        assert e.value.kind == "gap_below_rounding"
    # 0 (the rounding floor alone) and the bound itself are taken by the detection.
    bound = 16 * np.finfo(float).eps
    for gap in (0.0, bound):
        assert penedge.detect_pair(a, b, gap=gap).outcome == "face-face"


@pytest.mark.parametrize("scale", [-1.0, 3.0, -2.5, 1e-3, 1e200, -1e-300])
def test_parts_of_one_body_take_one_rotation_as_any_quaternion_of_it(scale):
    system = notch_system()
    q = np.array([0.1, -0.2, 0.3, 0.9])
    q /= np.linalg.norm(q)
    translations = np.tile([0.5, -0.25, 2.0], (4, 1))
    expected = penedge.ContactTracker(system, skin=0.1)
    expected.update(np.tile(q, (4, 1)), translations)
    tracker = penedge.ContactTracker(system, skin=0.1)
    rotations = np.tile(q, (4, 1))
    rotations[1] *= scale  # a part of body 0: the same rotation, another quaternion
    rotations[2] *= -1.0
    tracker.update(rotations, translations)
    got, want = tracker.body_contacts, expected.body_contacts
    assert len(want) == 3
    assert got.bodies.tolist() == want.bodies.tolist()
    assert got.types.tolist() == want.types.tolist()
    assert got.areas.tolist() == want.areas.tolist()
    assert got.normals.tolist() == want.normals.tolist()
    # Another rotation (by 1e-9 rad about z) is another pose, refused as before.
    turn = np.array([0.0, 0.0, np.sin(0.5e-9), np.cos(0.5e-9)])
    x1, y1, z1, w1 = q
    x2, y2, z2, w2 = turn
    turned = [
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
    ]
    rotations[2] = turned
    with pytest.raises(penedge.InputError, match="parts of body 0"):
        tracker.update(rotations, translations)
