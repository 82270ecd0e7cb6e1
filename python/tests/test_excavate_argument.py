"""``BlockSystem.excavate`` given something other than a dict: a clear InputError naming
``excavation``, never a Rust panic (it was ``PanicException: internal error: entered
unreachable code: a mapping becomes a table``)."""

import pytest

import penedge


@pytest.fixture
def rock():
    return penedge.BlockSystem([penedge.Block.cuboid([0, 0, 0], [1, 1, 1])])


@pytest.mark.parametrize(
    ("value", "kind"),
    [
        ("tunnel", "str"),
        (5, "int"),
        ([1, 2], "list"),
        (3.5, "float"),
        (True, "bool"),
        ((1,), "tuple"),
        (b"tunnel", "bytes"),
        (None, "NoneType"),
    ],
)
def test_excavate_refuses_a_value_that_is_not_a_dict(rock, value, kind):
    with pytest.raises(penedge.InputError) as info:
        rock.excavate(value)
    assert info.value.kind == "type"
    assert str(info.value) == f"excavation must be a dict (a mapping of its fields), got {kind}"


def test_a_bad_value_inside_an_excavation_is_named_under_excavation(rock):
    with pytest.raises(penedge.SpecError) as info:
        rock.excavate({"type": "tunnel", "radius": object()})
    assert info.value.field == "excavation.radius"
