"""penedge.Simulation's API: ``system()`` (block order, body ids, sets and unit of the
system the simulation was made of, at the current poses; also after a restart file),
read-only ``gravity``, ``set_velocity`` on a body that is not free, ids that are bools,
unknown joint sets in ``joint``/``bridge``, the dtype of ``contacts()["sub_offsets"]``."""

import json
import tomllib

import numpy as np
import pytest

import penedge

from shapes import rotation_from_quaternion

CUBOID = penedge.Block.cuboid

SPEC = """\
unit = "ft"

[domain]
type = "box"
min = [0, 0, 0]
max = [4, 2, 2]

[[joints]]
type = "plane"
name = "cross"
point = [2, 0, 0]
dip = 90
dip_direction = 90

[[joints]]
type = "plane"
name = "bed"
point = [0, 0, 1]
dip = 0
dip_direction = 0
"""

BRIDGED = """\
[domain]
type = "box"
min = [0, 0, 0]
max = [10, 10, 10]

[[joints]]
type = "polygon"
name = "step"
vertices = [[2, 2, 5], [8, 2, 5], [8, 8, 5], [2, 8, 5]]
bridge = true
"""


def rotation(q):
    """The rotation matrix of a simulation's quaternion ``x, y, z, w``."""
    return rotation_from_quaternion(np.roll(q, 1))  # shapes' helper takes w first


def l_body_system():
    """Block 0 and block 3: an L-shaped body (id 7); block 1 a base, block 2 a cube apart."""
    a = CUBOID([0, 0, 0], [2, 1, 1])
    base = CUBOID([-3, -3, -2], [3, 3, -1])
    far = CUBOID([5, 5, 5], [6, 6, 6])
    b = CUBOID([0, 0, 1], [1, 1, 2])
    return penedge.BlockSystem([a, base, far, b]).with_bodies([7, 1, 2, 7])


def test_system_is_the_blocks_in_their_order_with_their_body_ids_at_the_current_poses():
    system = l_body_system()
    sim = penedge.Simulation(system, density=1000.0)
    assert sim.block_bodies.tolist() == [0, 1, 2, 0]  # the simulation's bodies: 3
    sim.gravity = [0.0, 0.0, 0.0]
    sim.set_joint(kn=1e7, ks=1e7, friction=30.0)  # a time step of 1 ms
    sim.fix([1])
    start = [np.array(sim.positions), np.array(sim.quaternions)]
    sim.set_velocity(0, [0.3, -0.2, 0.1], spin=[0.4, 0.9, -0.7])  # the L tumbles
    sim.set_velocity(2, [0.0, 0.0, 0.5], spin=[0.0, 0.0, 2.0])
    sim.step(400)
    assert sim.time > 0.4
    placed = sim.system()
    assert len(placed) == len(system)
    assert placed.body_ids.tolist() == [7, 1, 2, 7]
    assert placed.internal_faces()["areas"].round(9).tolist() == [1.0]  # the L's glue
    # Each block moved by its body's pose: x -> R R0^T (x - c0) + c, from the input block.
    for k, block in enumerate(system.blocks):
        body = sim.block_bodies[k]
        c0, r0 = start[0][body], rotation(start[1][body])
        c, r = sim.positions[body], rotation(sim.quaternions[body])
        expected = (np.asarray(block.vertices) - c0) @ r0 @ r.T + c
        got = np.asarray(placed.blocks[k].vertices)
        assert got.shape == expected.shape
        assert np.allclose(got, expected, rtol=0, atol=1e-9), k
    # Not the rest poses: the L and the far cube moved and turned.
    for k in (0, 2, 3):
        moved = np.asarray(placed.blocks[k].vertices) - np.asarray(system.blocks[k].vertices)
        assert np.abs(moved).max() > 0.05, k


def test_system_keeps_the_joint_sets_and_the_unit_of_a_generated_system():
    system, _ = penedge.generate(tomllib.loads(SPEC))
    assert system.unit == "ft"
    assert [s["name"] for s in system.sets] == ["cross", "bed"]
    sim = penedge.Simulation(system, density=2500.0)
    bottom = [k for k, b in enumerate(system.blocks) if b.centroid[2] < 1]
    sim.fix(bottom)
    sim.set_joint(kn=1e9, ks=1e9, friction=30.0)
    sim.step(20)
    placed = sim.system()
    assert placed.sets == system.sets
    assert placed.unit == "ft"
    assert placed.body_ids.tolist() == system.body_ids.tolist()
    for a, b in zip(placed.blocks, system.blocks, strict=True):
        assert np.allclose(a.centroid, b.centroid, rtol=0, atol=1e-3)  # settling only
    # A copy keeps them.
    assert sim.copy().system().sets == system.sets


def test_system_gives_the_pieces_of_a_bridged_body_their_own_ids():
    system, _ = penedge.generate(tomllib.loads(BRIDGED))
    system = system.with_bodies([3] * len(system))  # one body, of id 3: not the pieces' ids
    sim = penedge.Simulation(system)
    ids = system.body_ids.tolist()
    pieces = sim.block_bodies.tolist()
    assert len(set(pieces)) > len(set(ids))  # the bridges hold pieces of one body
    # The rule of the docstring, computed here: the piece of a body's first block keeps
    # its id, the others numbered on from the largest id, in the order of first block.
    expected, first, fresh = {}, {}, max(ids) + 1
    for body, piece in zip(ids, pieces, strict=True):
        if piece not in expected:
            if first.setdefault(body, piece) == piece:
                expected[piece] = body
            else:
                expected[piece], fresh = fresh, fresh + 1
    assert sim.system().body_ids.tolist() == [expected[p] for p in pieces]
    assert sim.system().sets == system.sets


def test_a_loaded_simulation_has_its_blocks_in_their_order(tmp_path):
    system = l_body_system()
    sim = penedge.Simulation(system)
    sim.fix([1])
    sim.step(5)
    sim.save(tmp_path / "state.json")
    loaded = penedge.Simulation.load(tmp_path / "state.json")
    placed, again = sim.system(), loaded.system()
    # The file keeps the block order and the system's ids (since 2026-11-29).
    assert again.body_ids.tolist() == placed.body_ids.tolist() == [7, 1, 2, 7]
    assert loaded.block_bodies.tolist() == [0, 1, 2, 0]
    for a, b in zip(placed.blocks, again.blocks, strict=True):
        assert np.array_equal(a.vertices, b.vertices)


def test_a_loaded_simulation_keeps_the_joint_sets_and_the_unit(tmp_path):
    system, _ = penedge.generate(tomllib.loads(SPEC))
    sim = penedge.Simulation(system, density=2500.0)
    sim.fix([k for k, b in enumerate(system.blocks) if b.centroid[2] < 1])
    sim.set_joint(kn=1e9, ks=1e9, friction=30.0)
    sim.step(5)
    path = tmp_path / "state.json"
    sim.save(path)
    loaded = penedge.Simulation.load(path).system()
    original = sim.system()
    assert [s["name"] for s in original.sets] == ["cross", "bed"]
    assert loaded.sets == original.sets == system.sets
    assert loaded.unit == original.unit == "ft"
    assert loaded.body_ids.tolist() == original.body_ids.tolist()
    # With the joint table the faces name: a block file of it reads back.
    again = penedge.BlockSystem.from_json(loaded.to_json())
    assert again.sets == system.sets
    assert again.unit == "ft"
    # A file written before restart files kept them: no sets, no unit, and the
    # simulation's bodies as the ids.
    state = json.loads(path.read_text())
    del state["system"]
    older = tmp_path / "older.json"
    older.write_text(json.dumps(state))
    old = penedge.Simulation.load(older)
    assert old.system().sets == []
    assert old.system().unit is None
    assert old.system().body_ids.tolist() == old.block_bodies.tolist()


def test_gravity_is_read_only_as_the_state_arrays():
    sim = penedge.Simulation(penedge.BlockSystem([CUBOID([0, 0, 0], [1, 1, 1])]))
    with pytest.raises(ValueError, match="read-only"):
        sim.gravity[2] = 0.0
    assert sim.gravity.tolist() == [0.0, 0.0, -9.81]
    sim.gravity = [0.0, 0.0, -1.0]  # set as a whole
    assert sim.gravity.tolist() == [0.0, 0.0, -1.0]


def two_cubes():
    base = CUBOID([-2, -2, -1], [2, 2, 0])
    cube = CUBOID([-0.5, -0.5, 0], [0.5, 0.5, 1])
    far = CUBOID([5, 5, 5], [6, 6, 6])
    return penedge.Simulation(penedge.BlockSystem([base, cube, far]))


def test_set_velocity_of_a_body_that_is_not_free_is_an_error_naming_it():
    sim = two_cubes()
    sim.fix([0])
    with pytest.raises(penedge.MechanicsError, match=r"body 0 is fixed") as e:
        sim.set_velocity(0, [0.0, 0.0, 1.0])
    assert e.value.kind == "not_free"
    sim.prescribe(1, [0.0, 0.0, 0.01])
    with pytest.raises(penedge.MechanicsError, match=r"body 1 moves at a prescribed") as e:
        sim.set_velocity(1, [1.0, 0.0, 0.0])
    assert e.value.kind == "not_free"
    assert sim.velocities[1].tolist() == [0.0, 0.0, 0.01]
    sim.set_velocity(2, [1.0, 0.0, 0.0])  # a free body's
    assert sim.velocities[2].tolist() == [1.0, 0.0, 0.0]
    sim.free([1])  # freed, it takes one
    sim.set_velocity(1, [1.0, 0.0, 0.0])
    assert sim.velocities[1].tolist() == [1.0, 0.0, 0.0]
    with pytest.raises(penedge.MechanicsError) as e:  # an unknown body: the core's error
        sim.set_velocity(9, [1.0, 0.0, 0.0])
    assert e.value.kind == "unknown_body"


@pytest.mark.parametrize(
    "call",
    [
        lambda sim: sim.set_velocity(True, [0, 0, 1]),
        lambda sim: sim.prescribe(True, [0, 0, 1]),
        lambda sim: sim.apply_force(True, [0, 0, 1]),
        lambda sim: sim.apply_moment(True, [0, 0, 1]),
        lambda sim: sim.set_velocity(np.True_, [0, 0, 1]),
        lambda sim: sim.joint(set=False),
        lambda sim: sim.bridge(False),
        lambda sim: sim.set_joint(1e9, 1e9, 30.0, set=True),
        lambda sim: sim.set_bridge(1e9, 1e9, 30.0, 1e6, 1e5, set=True),
        lambda sim: sim.set_water(pressures={True: 1e3}),
    ],
)
def test_a_bool_is_not_an_id(call):
    system = penedge.BlockSystem.from_box_cut([0, 0, 0], [3, 1, 1], [[1, 0, 0]] * 2, [1, 2])
    sim = penedge.Simulation(system)  # bodies 0, 1 and 2, joint sets 0 and 1
    with pytest.raises(penedge.InputError, match="bool") as e:
        call(sim)
    assert e.value.kind == "dtype"
    with pytest.raises(penedge.InputError, match="bool"):  # as the lists of ids
        sim.fix([True])


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda sim: sim.set_velocity(1.0, [0, 0, 1]), "id"),
        (lambda sim: sim.set_velocity(np.array([1]), [0, 0, 1]), "id"),
        (lambda sim: sim.apply_force(np.float64(1), [0, 0, 1]), "id"),
        (lambda sim: sim.set_joint(1e9, 1e9, 30.0, set=1.0), "set"),
    ],
)
def test_a_float_or_an_array_is_not_an_id(call, name):
    # A bare TypeError ("'float' object cannot be interpreted as an integer") named nothing.
    system = penedge.BlockSystem.from_box_cut([0, 0, 0], [3, 1, 1], [[1, 0, 0]] * 2, [1, 2])
    sim = penedge.Simulation(system)
    with pytest.raises(penedge.InputError, match=rf"{name} must be an integer, got the ") as e:
        call(sim)
    assert e.value.kind == "dtype"


def test_joint_and_bridge_of_an_unknown_set_are_the_setters_error():
    system = penedge.BlockSystem.from_box_cut([0, 0, 0], [3, 1, 1], [[1, 0, 0]] * 2, [1, 2])
    sim = penedge.Simulation(system)  # joint sets 0 and 1
    sim.set_joint(kn=2e9, ks=2e9, friction=35.0, set=0)
    assert sim.joint(set=0)["kn"] == 2e9
    assert sim.joint(set=1) == sim.joint()  # a set without its own: the default
    assert sim.bridge(1)["friction"] == 45.0
    for call in (
        lambda: sim.joint(set=99),
        lambda: sim.bridge(99),
        lambda: sim.set_joint(kn=1e9, ks=1e9, friction=30.0, set=99),
    ):
        with pytest.raises(penedge.MechanicsError, match="no joint set 99") as e:
            call()
        assert e.value.kind == "unknown_set"


def test_sub_offsets_are_int64_as_point_offsets():
    sim = two_cubes()
    sim.fix([0, 2])
    sim.set_joint(kn=1e9, ks=1e9, friction=30.0)
    sim.step(3)
    c = sim.contacts()
    assert c["sub_offsets"].dtype == np.int64
    assert (c["sub_offsets"][:-1] + np.arange(len(c["types"]))).dtype == np.int64
    found = sim.system().detect(gap=1e-3, geometry=True)
    assert found.point_offsets.dtype == c["sub_offsets"].dtype


def test_every_body_id_array_is_int64_as_the_systems_pairs():
    # Mixed integer kinds do not mix in numpy: uint64 with int64 becomes float64 (ids 2^53 and
    # up lose digits), and uint32 pairs cannot be compared with a detection's int64 ones in one
    # array without a cast. Every id the simulation hands out is int64, as BlockSystem's.
    sim = two_cubes()
    sim.fix([0])
    sim.set_joint(kn=1e9, ks=1e9, friction=30.0)
    sim.add_bolt([0, 0, 0.5], [0, 0, -1], 1.0, stiffness=1e7, capacity=1e5)
    sim.step(3)
    found = sim.system().detect(gap=1e-3, geometry=True)
    arrays = {
        "contacts pairs": sim.contacts()["pairs"],
        "bolts bolt": sim.bolts()["bolt"],
        "bolts pairs": sim.bolts()["pairs"],
        "block_bodies": sim.block_bodies,
    }
    report = sim.excavate([2])
    arrays |= {"excavate removed": report["removed"], "excavate loaded": report["loaded"]}
    for name, ids in arrays.items():
        assert ids.dtype == found.pairs.dtype == np.int64, name
    assert report["removed"].tolist() == [2]
    assert sim.contacts()["pairs"].tolist() == [[0, 1]] == found.pairs.tolist()
    assert sim.bolts()["pairs"].tolist() == [[1, 0]]  # from the cube down into the base


@pytest.mark.parametrize(
    "call",
    [
        lambda sim: sim.fix([0, True]),
        lambda sim: sim.excavate([2, True]),
        lambda sim: sim.set_density(2000.0, (np.int64(0), np.True_)),
    ],
)
def test_a_bool_in_a_list_of_ids_is_refused_not_read_as_0_or_1(call):
    # numpy makes [0, True] the int64 array [0, 1]: body 1 was fixed, excavated or changed.
    sim = two_cubes()
    with pytest.raises(penedge.InputError, match=r"ids\[1\] must be an integer, got the bool"):
        call(sim)
    assert not sim.fixed.any()
    assert not sim.removed.any()
    with pytest.raises(penedge.InputError, match="body_ids"):
        penedge.BlockSystem([CUBOID([0, 0, 0], [1, 1, 1])] * 1).with_bodies([False])


def test_a_large_unsigned_id_is_named_as_given():
    sim = two_cubes()
    with pytest.raises(penedge.MechanicsError, match="18446744073709551615"):
        sim.fix(np.array([2**64 - 1], dtype=np.uint64))


@pytest.mark.parametrize(
    ("base", "problem"),
    [
        (np.array([1, 2, 3, 0, 0, 0], dtype=complex), "real numbers"),
        (np.array([True, False, False, False, False, False]), "real numbers"),
        (np.zeros((1, 6)), "shape"),
        (np.zeros((3, 3)), "shape"),
        (np.float64(1.0), "shape"),
    ],
)
def test_an_initial_stress_that_is_not_six_real_numbers_is_named(base, problem):
    # Complex values were cut to their real part, bools read as 1 and 0 Pa, and wrong
    # shapes raised a bare ValueError or TypeError naming no argument.
    sim = two_cubes()
    with pytest.raises(penedge.InputError, match=rf"base.*{problem}|{problem}.*base") as e:
        sim.set_initial_stress(base=base)
    assert "base" in str(e.value)
    with pytest.raises(penedge.InputError, match="per_depth"):
        sim.set_initial_stress(per_depth=base)
    sim.set_initial_stress(base=np.arange(6.0), per_depth=(0, 0, 1e4, 0, 0, 0))  # fine


def test_a_masked_array_with_masked_values_is_refused_not_read_under_the_mask():
    # np.asarray drops the mask: the box went up to z = 99 and gravity to -1e6.
    hidden = np.ma.masked_array([1.0, 1.0, 99.0], mask=[0, 0, 1])
    with pytest.raises(penedge.InputError, match="hi has masked values") as e:
        CUBOID([0, 0, 0], hidden)
    assert e.value.kind == "masked"
    sim = two_cubes()
    with pytest.raises(penedge.InputError, match="gravity has masked values"):
        sim.gravity = np.ma.masked_array([0.0, 0.0, -1e6], mask=[0, 0, 1])
    assert sim.gravity.tolist() == [0.0, 0.0, -9.81]
    # No value masked: read as it is.
    box = CUBOID([0, 0, 0], np.ma.masked_array([1.0, 2.0, 3.0], mask=False))
    assert box.volume == pytest.approx(6.0)
