"""Input that the bindings and files took without a clear error: a tracker pose moving a
block out of double precision's range, blocks far from the origin, joint names that the
contact table cannot tell apart, a unit's name of any length, whole numbers beyond 64 bits;
and the contact table's body columns for concave blocks.

References: the core's checked move (``Block.translated``) for the tracker's range, the
system's ``body_ids`` for the body columns, the limits named in the messages."""

import csv
import json
import re

import numpy as np
import pytest

import penedge

IDENTITY = [0.0, 0.0, 0.0, 1.0]


def cube_grid():
    """Four unit cubes in a row along x, touching."""
    return penedge.BlockSystem([penedge.Block.cuboid([i, 0, 0], [i + 1, 1, 1]) for i in range(4)])


@pytest.mark.parametrize("far", [1e300, -1e300, 1e14])
def test_a_tracker_pose_out_of_range_is_an_input_error_naming_the_block(far):
    system = cube_grid()
    tracker = penedge.ContactTracker(system, skin=0.1)
    before = tracker.contacts.pairs.tolist()
    rotations = np.tile(IDENTITY, (4, 1))
    translations = np.zeros((4, 3))
    translations[2, 1] = far
    with pytest.raises(penedge.InputError, match=r"^pose 2 moves block 2 too far") as info:
        tracker.update(rotations, translations)
    assert "1e50" in str(info.value)
    # The checked move of the block refuses it too, and the tracker is unchanged.
    with pytest.raises(penedge.BlockError):
        system[2].translated([0, far, 0])
    assert tracker.contacts.pairs.tolist() == before
    # Nearer, the block is placed: it has left its neighbours.
    translations[2, 1] = 1e13
    tracker.update(rotations, translations)
    system[2].translated([0, 1e13, 0])
    assert tracker.contacts.pairs.tolist() == [[0, 1]]


def test_vertices_rounded_together_far_away_say_the_coordinates_are_too_large():
    with pytest.raises(penedge.BlockError) as info:
        penedge.Block.cuboid([1e15] * 3, [1e15 + 1] * 3)
    assert info.value.kind == "repeated_vertex"
    message = str(info.value)
    for part in ("up to 1e15 in magnitude", "too large for double precision", "1.73e0 across"):
        assert part in message, message
    # Near the origin a vertex given twice is only that.
    vertices = np.array(
        [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [1, 1, 1]]
    )
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    with pytest.raises(penedge.BlockError, match=r"^vertices 6 and 7 are at the same position$"):
        penedge.Block(vertices, faces)


def test_distances_in_block_messages_have_three_digits():
    vertices = np.array(
        [
            [0, 0, 0],
            [1, 0, 0],
            [1, 1, 0],
            [0, 1, 0],
            [0, 0, 1],
            [1, 0, 1],
            [1, 1, 1 + 1e-3 / 3],
            [0, 1, 1],
        ]
    )
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    with pytest.raises(penedge.BlockError) as info:
        penedge.Block(vertices, faces)
    numbers = re.findall(r"\d\.\d+e-?\d+", str(info.value))
    assert numbers, str(info.value)
    assert all(len(n.split("e")[0]) <= 4 for n in numbers), str(info.value)


def two_planes(names):
    joints = []
    for name, z in zip(names, (3, 6), strict=True):
        joint = {"type": "plane", "point": [0, 0, z], "dip": 0, "dip_direction": 0}
        if name is not None:
            joint["name"] = name
        joints.append(joint)
    return {"domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]}, "joints": joints}


@pytest.mark.parametrize(
    ("names", "words"),
    [
        (["J1", "J1"], '"J1" is already that of joints[0]'),
        (["J1", "J2|J3"], '"J2|J3" holds `|`'),
        (["joints[1]", None], "already that of joints[0]"),
    ],
)
def test_a_spec_refuses_a_name_twice_or_with_the_separator(names, words):
    with pytest.raises(penedge.SpecError) as info:
        penedge.generate(two_planes(names))
    assert info.value.field == "joints[1].name"
    assert words in str(info.value)


def written_file(tmp_path, change):
    system, _ = penedge.generate(two_planes(["A", "B"]))
    path = tmp_path / "b.json"
    system.write_json(path)
    data = json.loads(path.read_text())
    change(data)
    path.write_text(json.dumps(data))
    return path


@pytest.mark.parametrize(
    ("change", "field"),
    [
        (lambda d: d["sets"][1].update(name="A"), "sets[1].name"),
        (lambda d: d["sets"][0].update(name="A|B"), "sets[0].name"),
        (lambda d: d.update(unit="f" * 17), "unit"),
        (lambda d: d.update(unit="x" * 1_000_000), "unit"),
        (lambda d: d.update(unit="m\n"), None),
        (lambda d: d.update(unit="m\x07"), "unit"),
    ],
)
def test_a_block_file_refuses_bad_set_names_and_unit_names(tmp_path, change, field):
    path = written_file(tmp_path, change)
    if field is None:  # trimmed, as the spec's unit
        assert penedge.BlockSystem.read_json(path).unit == "m"
        return
    with pytest.raises(penedge.FileFormatError) as info:
        penedge.BlockSystem.read_json(path)
    assert info.value.field == field
    assert len(str(info.value)) < 300 + len(str(path))


def test_the_contact_table_has_the_bodies_of_the_blocks(tmp_path):
    c = penedge.Block.cuboid
    u = [c([0, 0, 0], [3, 1, 1]), c([0, 0, 1], [1, 1, 2]), c([2, 0, 1], [3, 1, 2])]
    blocks = [*u, c([1, 0, 1], [2, 1, 2])]
    for system, glued in (
        (penedge.BlockSystem(blocks).with_bodies([0, 0, 0, 1]), True),
        (penedge.BlockSystem(blocks), False),
    ):
        path = tmp_path / "c.csv"
        system.detect(geometry=True).write_csv(path)
        with path.open(newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
        assert list(rows[0])[-4:] == ["set_a", "set_b", "body_a", "body_b"]
        ids = system.body_ids
        for row in rows:
            for block, body in (("block_a", "body_a"), ("block_b", "body_b")):
                assert int(row[body]) == ids[int(row[block])]
        # The U-block's parts name their body, not themselves; convex blocks themselves.
        differ = any(row[f"body_{s}"] != row[f"block_{s}"] for row in rows for s in "ab")
        assert differ == glued


SPEC = {"domain": {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1]}, "joints": []}


@pytest.mark.parametrize(
    "big",
    [2**63, 2**64 + 5, -(2**63) - 1, 10**5000],
    ids=["2**63", "2**64+5", "-2**63-1", "10**5000"],
)
def test_max_blocks_beyond_64_bits_is_an_input_error_naming_it(big):
    with pytest.raises(
        penedge.InputError, match=r"^max_blocks must be .*9223372036854775807"
    ) as info:
        penedge.generate(SPEC, max_blocks=big)
    assert info.value.kind == "out_of_range"
    assert len(str(info.value)) < 200
    assert len(penedge.generate(SPEC, max_blocks=2**63 - 1)[0]) == 1


def simulation():
    base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    return penedge.Simulation(penedge.BlockSystem([base, cube]))


BIG = 2**64
WHOLE_ARGUMENTS = {
    "step": (lambda big: simulation().step(big), "^n must be"),
    "solve": (lambda big: simulation().solve(max_steps=big), "^max_steps must be"),
    "excavate": (lambda big: simulation().excavate([1], relax_steps=big), "^relax_steps must be"),
    "set_joint": (
        lambda big: simulation().set_joint(kn=1e9, ks=1e9, friction=30.0, set=big),
        "^set must be",
    ),
    "bridge": (lambda big: simulation().bridge(big), "^set must be"),
    "joint": (lambda big: simulation().joint(set=big), "^set must be"),
    "set_water": (
        lambda big: simulation().set_water(pressures={big: 1.0}),
        "^a set of pressures must be",
    ),
    "set_velocity": (lambda big: simulation().set_velocity(big, [0, 0, 0]), "^id must be"),
    "apply_force": (lambda big: simulation().apply_force(big, [0, 0, 1]), "^id must be"),
    "paper_example": (lambda big: penedge.paper_example(big), "examples are 1, 2 and 3"),
    "threads": (lambda big: penedge.paper_example(1).detect(threads=big), "^threads must be"),
}


@pytest.mark.parametrize("name", WHOLE_ARGUMENTS)
@pytest.mark.parametrize("sign", [1, -1])
def test_a_whole_number_beyond_64_bits_is_named_not_a_bare_overflow(name, sign):
    call, message = WHOLE_ARGUMENTS[name]
    with pytest.raises(penedge.InputError, match=message) as info:
        call(sign * BIG)
    assert str(sign * BIG) in str(info.value)


@pytest.mark.parametrize("big", [2**63, -(2**64)])
def test_an_index_beyond_64_bits_is_an_index_error_as_a_lists(big):
    system = penedge.paper_example(1)
    with pytest.raises(IndexError, match=f"block index {big} out of range for 8 blocks"):
        system[big]
    found = system.detect(geometry=True)
    with pytest.raises(IndexError, match=f"contact index {big} out of range"):
        found.points_of(big)
    assert np.array_equal(system[-1].vertices, system[7].vertices)
