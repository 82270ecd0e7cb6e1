"""Bad input at every entry point gives a clear error naming the problem: never a crash, a
hang, a panic across the Python boundary or a half-written file (issue #6). Complements
test_errors.py (shapes, dtypes, invalid blocks, tolerances) and test_files.py (bad block
files, missing folders)."""

import json
import math
import os
import re
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import penedge

from cli_run import run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
CUBE = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
V, F = CUBE.vertices, CUBE.faces
BOX_NORMALS = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]


# -- arrays ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "vertices",
    [
        np.repeat(V, 2, axis=1)[:, ::2],  # strided columns
        np.repeat(V, 2, axis=0)[::2],  # strided rows
        np.asfortranarray(V),
        V.astype(np.float32),
        V.astype(np.float16),
        V.astype(np.longdouble),
        V.astype(np.int8),
        V.astype(np.uint64),
        V.tolist(),
        tuple(map(tuple, V)),
    ],
    ids=[
        "strided columns",
        "strided rows",
        "fortran",
        "float32",
        "float16",
        "longdouble",
        "int8",
        "uint64",
        "list",
        "tuple",
    ],
)
def test_any_real_array_layout_gives_the_same_block(vertices):
    block = penedge.Block(vertices, F)
    assert np.array_equal(block.vertices, V)
    assert block.volume == 1.0


def test_read_only_arrays_are_accepted():
    vertices = V.copy()
    vertices.flags.writeable = False
    assert penedge.Block(vertices, F).volume == 1.0


@pytest.mark.parametrize(
    ("vertices", "kind"),
    [
        (V.T, "shape"),  # (3, n): the points as columns
        (V.astype(object), "dtype"),  # numbers, but as Python objects
        (np.zeros((8, 3), dtype="datetime64[s]"), "dtype"),
        (np.zeros((8, 3), dtype="timedelta64[s]"), "dtype"),
        (np.zeros((8, 3), dtype=np.complex64), "dtype"),
        (np.array([[b"0", b"0", b"0"]] * 8), "dtype"),
        (np.zeros((8, 3, 1)), "shape"),
        (np.zeros(24), "shape"),
    ],
    ids=["transposed", "object", "datetime", "timedelta", "complex64", "bytes", "3-D", "flat"],
)
def test_unusable_vertex_arrays_raise_input_error(vertices, kind):
    with pytest.raises(penedge.InputError) as info:
        penedge.Block(vertices, F)
    assert info.value.kind == kind
    assert "vertices" in str(info.value)


@pytest.mark.parametrize(
    ("scale", "offset", "what"),
    [
        (1e300, 0.0, "largest coordinate is 1e300"),
        (1e100, 0.0, "largest coordinate is 1e100"),  # the volume's moments would overflow
        (1.0, 1e60, "largest coordinate is 1e60"),
        (1e-60, 0.0, "size is 1.7"),
        (1e-200, 0.0, "size is 1e-200"),  # the diagonal underflows to 0
    ],
)
def test_coordinates_out_of_double_range_are_named(scale, offset, what):
    with pytest.raises(penedge.BlockError) as info:
        penedge.Block(V * scale + offset, F)
    assert info.value.kind == "out_of_range"
    assert what in str(info.value)


def test_the_largest_and_smallest_blocks_in_range_are_valid():
    for scale in (1e49 / 2, 1e-49):
        block = penedge.Block(V * scale, F)
        assert block.volume == pytest.approx(scale**3, rel=1e-12)
        assert np.isfinite(block.centroid).all()


@pytest.mark.parametrize(
    "corners", [([0, 0, 0], [1e300, 1, 1]), ([-1e308] * 3, [1e308] * 3)], ids=["1e300", "1e308"]
)
def test_huge_cuboids_are_refused(corners):
    with pytest.raises(penedge.BlockError) as info:
        penedge.Block.cuboid(*corners)
    assert info.value.kind == "out_of_range"


@pytest.mark.parametrize(
    ("faces", "error", "kind"),
    [
        (np.array(F), None, None),  # an int array is fine
        (np.array(F, dtype=np.uint64), None, None),
        ([[0, 3, 2, 2**40], *F[1:]], penedge.BlockError, "vertex_index_out_of_range"),
        ([[0, 3, 2, 2**64], *F[1:]], penedge.InputError, "faces"),
        ([[0, 3, 2, np.int64(-1)], *F[1:]], penedge.InputError, "faces"),
        (np.array(F, dtype=float), penedge.InputError, "faces"),
        ([[]] * 6, penedge.BlockError, "degenerate_face_list"),
        ([], penedge.BlockError, "too_small"),
        ([F[0]] * 6, penedge.BlockError, "unused_vertex"),
    ],
    ids=[
        "int array",
        "uint64",
        "2**40",
        "2**64",
        "numpy -1",
        "float array",
        "empty",
        "none",
        "same",
    ],
)
def test_face_lists(faces, error, kind):
    if error is None:
        assert penedge.Block(V, faces).volume == 1.0
        return
    with pytest.raises(error) as info:
        penedge.Block(V, faces)
    assert info.value.kind == kind


def test_half_spaces_far_too_many_are_refused_at_once():
    normals = np.random.default_rng(0).normal(size=(2000, 3))
    start = time.perf_counter()
    with pytest.raises(penedge.BlockError) as info:
        penedge.Block.from_planes(normals, np.ones(len(normals)))
    assert time.perf_counter() - start < 1.0  # not O(m^4): 2000 planes would take hours
    assert info.value.kind == "too_many_planes"
    assert "at most 128" in str(info.value)


def test_a_cone_of_128_half_spaces_is_built():
    k = np.arange(127) * 2 * math.pi / 127
    normals = [[0, 0, -1], *np.column_stack([np.cos(k), np.sin(k), np.ones_like(k)]).tolist()]
    block = penedge.Block.from_planes(normals, [0] + [1] * 127)
    assert len(block.vertices) == 128  # the apex and the base polygon


@pytest.mark.parametrize("big", [1e200, 1e-200])
def test_half_space_normals_of_any_length(big):
    normals = np.array(BOX_NORMALS, dtype=float)
    normals[0] *= big  # only the direction counts: the length must neither overflow nor vanish
    block = penedge.Block.from_planes(normals, [big, 0, 1, 0, 1, 0])
    assert block.volume == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("normal", [[1, math.nan, 0], [0, 1, math.inf], [0, 0, 0]])
def test_a_normal_with_any_bad_component_is_degenerate(normal):
    normals = [*BOX_NORMALS[:3], normal, *BOX_NORMALS[4:]]
    with pytest.raises(penedge.BlockError) as info:
        penedge.Block.from_planes(normals, [1, 0, 1, 0, 1, 0])
    assert info.value.kind == "degenerate_plane"
    assert "half-space 3" in str(info.value)


def test_half_spaces_with_huge_offsets_are_out_of_range():
    with pytest.raises(penedge.BlockError) as info:
        penedge.Block.from_planes(BOX_NORMALS, [1e300, 0, 1, 0, 1, 0])
    assert info.value.kind == "out_of_range"


# -- systems --------------------------------------------------------------------------------


def test_an_empty_system_works_everywhere(tmp_path):
    empty = penedge.BlockSystem([])
    found = empty.detect(geometry=True)
    assert len(found) == 0
    assert found.points.shape == (0, 3)
    assert sum(found.counts().values()) == 0
    assert empty.arrays().vertices.shape == (0, 3)
    assert len(penedge.BlockSystem.from_json(empty.to_json())) == 0
    empty.write_json(tmp_path / "e.json")
    assert len(penedge.BlockSystem.read_json(tmp_path / "e.json")) == 0
    for write, name in [
        (empty.write_vtu, "e.vtu"),
        (empty.write_faces_vtu, "f.vtu"),
        (empty.write_csv, "e.csv"),
        (found.write_csv, "c.csv"),
        (found.write_vtp, "c.vtp"),
    ]:
        write(tmp_path / name)
        assert (tmp_path / name).stat().st_size > 0
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        ["e.json", "e.vtu", "f.vtu", "e.csv", "c.csv", "c.vtp"]
    )


def test_box_cut_out_of_range_and_planes_that_miss():
    with pytest.raises(penedge.BlockError) as info:
        penedge.BlockSystem.from_box_cut([0, 0, 0], [1e300, 1, 1], [[1, 0, 0]], [0.5])
    assert info.value.kind == "out_of_range"
    assert len(penedge.BlockSystem.from_box_cut([0, 0, 0], [1, 1, 1], [[1, 0, 0]], [1e300])) == 1


def test_an_absurd_thread_count_is_refused_quickly():
    script = textwrap.dedent(
        """
        import penedge
        try:
            penedge.paper_example(1).detect(threads=1_000_000)
        except penedge.InputError as e:
            print("InputError", e.kind)
        """
    )
    try:
        result = subprocess.run(
            [sys.executable, "-c", script], capture_output=True, text=True, timeout=5, check=False
        )
    except subprocess.TimeoutExpired:
        pytest.fail("detect(threads=1_000_000) still runs after 5 s")
    assert result.stdout.startswith("InputError threads"), result.stderr[-500:]


def test_a_cutting_normal_with_a_nan_component_is_degenerate():
    with pytest.raises(penedge.InputError) as info:
        penedge.BlockSystem.from_box_cut([0, 0, 0], [1, 1, 1], [[1, math.nan, 0]], [0.5])
    assert info.value.kind == "degenerate_plane"


# -- block files ----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def block_file_text():
    system, _ = penedge.generate(EXAMPLES / "finite_disc.toml")
    return system.to_json()


@pytest.mark.parametrize("fraction", [0.0, 0.01, 0.3, 0.5, 0.9, 0.999])
def test_a_truncated_block_file_is_a_syntax_error(block_file_text, fraction, tmp_path):
    path = tmp_path / "cut.json"
    path.write_text(block_file_text[: int(len(block_file_text) * fraction)], encoding="utf-8")
    with pytest.raises(penedge.FileFormatError) as info:
        penedge.BlockSystem.read_json(path)
    assert info.value.kind == "syntax"
    assert "cut.json" in str(info.value)


def test_a_system_generated_with_a_coarse_gap_reads_back(tmp_path):
    # Its corner 2.9e-3 from the plane counts as on it (length 1e-2) and stays on the cap;
    # the file used to be refused ("face 6 is not planar") by `penedge detect`.
    spec = {
        **box(),
        "joints": [{"type": "plane", "point": [0.005, 0, 0], "normal": [1, 1, -1]}],
        "options": {"gap": 1e-3},
    }
    system, _ = penedge.generate(spec)
    system.write_json(tmp_path / "blocks.json")
    again = penedge.BlockSystem.read_json(tmp_path / "blocks.json")
    assert np.array_equal(again.arrays().vertices, system.arrays().vertices)
    result = run("detect", "blocks.json", "-o", "c.csv", cwd=tmp_path)
    assert result.returncode == 0, result.stderr


def test_a_binary_block_file_is_a_syntax_error(tmp_path):
    path = tmp_path / "binary.json"
    path.write_bytes(b'{"format": "penedge-blocks", \xff\xfe\x00\x01')
    with pytest.raises(penedge.FileFormatError) as info:
        penedge.BlockSystem.read_json(path)
    assert info.value.kind == "syntax"
    assert "not UTF-8" in str(info.value)
    assert "binary.json" in str(info.value)


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
def test_an_endless_stream_is_an_error_not_a_hang():
    start = time.perf_counter()
    with pytest.raises(penedge.FileFormatError) as info:
        penedge.BlockSystem.read_json("/dev/zero")
    assert "endless stream" in str(info.value)
    with pytest.raises(penedge.SpecError):
        penedge.generate(Path("/dev/zero"))
    assert time.perf_counter() - start < 60


def edited(text, edit):
    """The block file with `edit` applied to its parsed JSON."""
    value = json.loads(text)
    edit(value)
    return json.dumps(value)


def set_key(path, new):
    def edit(value):
        *parents, last = path
        for key in parents:
            value = value[key]
        value[last] = new

    return edit


@pytest.mark.parametrize(
    ("edit", "kind", "field", "message"),
    [
        (set_key(["joints", 0, "normal"], [0, 0, 0]), "format", "joints[0].normal", "unit"),
        (set_key(["joints", 0, "normal"], [0, 0, 2]), "format", "joints[0].normal", "unit"),
        (set_key(["joints", 0, "set"], 99), "format", "joints[0].set", "spec entry 99"),
        (set_key(["joints", 0, "id"], 5), "format", "joints[0].id", "in order"),
        (set_key(["joints", 3, "shape", "radius"], -1), "format", "joints[3].shape.radius", "-1"),
        (
            set_key(["joints", 3, "shape"], {"kind": "polygon", "vertices": [[0, 0, 0]]}),
            "format",
            "joints[3].shape.vertices",
            "3 vertices",
        ),
        (set_key(["blocks", 0, "vertices"], "abc"), "syntax", None, 'got the text "abc"'),
        (
            set_key(["blocks", 0, "faces"], [[0, -1, 2]]),
            "syntax",
            None,
            "got the whole number `-1`",
        ),
        (
            set_key(["blocks", 0, "id"], 2**40),
            "syntax",
            None,
            "too large: expected a whole number up to 4294967295",
        ),
        (set_key(["blocks", 0, "extra"], 1), "syntax", None, "unknown field `extra` (a typo?)"),
        (set_key(["version"], 3), "format", "version", "version 3"),
        (set_key(["blocks", 0, "origins"], []), "format", "blocks[0]", "one entry per face"),
    ],
    ids=[
        "zero normal",
        "long normal",
        "no such set",
        "joint id",
        "negative radius",
        "polygon of 1",
        "vertices str",
        "negative index",
        "huge id",
        "unknown key",
        "version",
        "origins",
    ],
)
def test_wrong_fields_are_named(block_file_text, edit, kind, field, message):
    with pytest.raises(penedge.FileFormatError) as info:
        penedge.BlockSystem.from_json(edited(block_file_text, edit))
    assert info.value.kind == kind
    assert info.value.field == field
    assert message in str(info.value)


def test_a_joint_with_a_zero_normal_was_read_and_then_crashed_the_writer(block_file_text):
    # The bug: read_json accepted it, and to_json() panicked ("joint normals are unit vectors").
    text = edited(block_file_text, set_key(["joints", 0, "normal"], [0, 0, 0]))
    with pytest.raises(penedge.FileFormatError):
        penedge.BlockSystem.from_json(text)


@pytest.mark.parametrize(
    "replace",
    [("1.0", "1e400"), ("1.0", "NaN"), ("1.0", "Infinity"), ("1.0", "-"), ('"faces"', '"faces" ')],
    ids=["1e400", "NaN", "Infinity", "lone minus", "whitespace"],
)
def test_numbers_json_does_not_have(block_file_text, replace):
    text = block_file_text.replace(*replace, 1)
    if replace[1] == '"faces" ':
        assert len(penedge.BlockSystem.from_json(text)) > 0  # whitespace is fine
        return
    with pytest.raises(penedge.FileFormatError) as info:
        penedge.BlockSystem.from_json(text)
    assert info.value.kind == "syntax"
    assert "line 1 column" in str(info.value)


@pytest.mark.parametrize("key", ["format", "blocks", "domain"])
def test_deeply_nested_json_is_refused_without_a_stack_overflow(key):
    text = '{"' + key + '": ' + "[" * 100_000 + "]" * 100_000 + "}"
    with pytest.raises(penedge.FileFormatError) as info:
        penedge.BlockSystem.from_json(text)
    assert info.value.kind == "syntax"


def test_from_json_takes_valid_text_only():
    with pytest.raises(penedge.InputError) as info:
        penedge.BlockSystem.from_json('"\ud800"')  # a lone surrogate: not encodable
    assert info.value.kind == "text"
    with pytest.raises(TypeError):
        penedge.BlockSystem.from_json(b"{}")


# -- writing --------------------------------------------------------------------------------

WRITERS = ["write_json", "write_vtu", "write_faces_vtu", "write_csv"]


@pytest.mark.parametrize("writer", WRITERS)
def test_writing_under_a_file_fails_and_leaves_nothing(writer, tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(NotADirectoryError):
        getattr(penedge.paper_example(1), writer)(tmp_path / "file" / "out")
    assert [p.name for p in tmp_path.iterdir()] == ["file"]


@pytest.mark.parametrize("writer", WRITERS)
def test_writing_over_a_folder_fails_and_leaves_it_alone(writer, tmp_path):
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "keep").write_text("x")
    with pytest.raises(IsADirectoryError):
        getattr(penedge.paper_example(1), writer)(tmp_path / "out")
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # no temporary file left
    assert [p.name for p in (tmp_path / "out").iterdir()] == ["keep"]


@pytest.mark.parametrize("writer", ["write_csv", "write_vtp"])
def test_contact_writers_over_a_folder(writer, tmp_path):
    found = penedge.paper_example(1).detect(geometry=True)
    (tmp_path / "out").mkdir()
    with pytest.raises(IsADirectoryError):
        getattr(found, writer)(tmp_path / "out")
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root ignores permissions")
def test_writing_into_a_read_only_folder_keeps_the_old_file(tmp_path):
    folder = tmp_path / "ro"
    folder.mkdir()
    (folder / "blocks.json").write_text("old")
    folder.chmod(0o555)
    try:
        with pytest.raises(PermissionError):
            penedge.paper_example(1).write_json(folder / "blocks.json")
        assert (folder / "blocks.json").read_text() == "old"
        assert [p.name for p in folder.iterdir()] == ["blocks.json"]
    finally:
        folder.chmod(0o755)


def test_a_killed_writer_never_leaves_a_half_written_file(tmp_path):
    """A process killed while it writes leaves the previous complete file or the new one."""
    target = tmp_path / "blocks.json"
    script = textwrap.dedent(
        f"""
        import penedge, sys
        system, _ = penedge.generate({str(EXAMPLES / "three_joint_sets.toml")!r})
        system.write_json({str(target)!r})
        print(len(system), flush=True)
        while True:
            system.write_json({str(target)!r})
        """
    )
    child = subprocess.Popen(
        [sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        count = int(child.stdout.readline())
        size = target.stat().st_size
        for delay in (0.01, 0.037, 0.05, 0.11, 0.2):
            time.sleep(delay)
            os.kill(child.pid, signal.SIGSTOP)  # freeze it mid-write, then look
            assert target.stat().st_size == size
            assert len(penedge.BlockSystem.read_json(target)) == count
            os.kill(child.pid, signal.SIGCONT)
    finally:
        child.kill()
        child.wait()
        child.stdout.close()
        child.stderr.close()
    assert len(penedge.BlockSystem.read_json(target)) == count
    others = [p.name for p in tmp_path.iterdir() if p != target]
    assert all(name.startswith(".blocks.json.") and name.endswith(".tmp") for name in others)


# -- generation specs -----------------------------------------------------------------------


def test_a_syntax_error_is_one_short_line_even_on_a_huge_line():
    text = "[domain]\ntype = 'box'\nmin = [0, 0, 0]\nmax = [1, 1, 1" + ", 1" * 100_000 + "\n"
    with pytest.raises(penedge.SpecError) as info:
        penedge.generate(text)
    message = str(info.value)
    assert info.value.kind == "syntax"
    assert "\n" not in message
    assert len(message) < 400
    assert message.startswith("spec: line 4, column ")


def test_a_binary_spec_file_is_a_syntax_error(tmp_path):
    path = tmp_path / "spec.toml"
    path.write_bytes(b"[domain]\ntype = \xff\xfe")
    with pytest.raises(penedge.SpecError) as info:
        penedge.generate(path)
    assert info.value.kind == "syntax"
    assert "not UTF-8" in str(info.value)


def two_sets():
    return {
        "domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]},
        "joints": [
            {"type": "set", "dip": 30, "dip_direction": 10, "spacing": 5},
            {"type": "set", "dip": 60, "dip_direction": 100, "spacing": 5},
        ],
        "options": {"gap": 1e-3},
    }


@pytest.mark.parametrize(
    ("edit", "field", "message"),
    [
        (lambda s: s["joints"][1].update(spasing=5), "joints[1]", "unknown field `spasing`"),
        (lambda s: s["joints"][1].update(dip="steep"), "joints[1].dip", 'got the text "steep"'),
        (lambda s: s["joints"][0].update(extent={"r": 1}), "joints[0]", "unknown field `extent`"),
        (lambda s: s["options"].update(gapp=1), "options", "unknown field `gapp`"),
        (lambda s: s.update(foo=1), "spec", "unknown field `foo`"),
        (lambda s: s["domain"].update(max="x"), "domain.max", 'got the text "x"'),
        (lambda s: s["domain"].pop("type"), "domain", "the field `type` is missing"),
        (lambda s: s.pop("domain"), "spec", "the field `domain` is missing"),
    ],
    ids=[
        "typo in a set",
        "text for a number",
        "unknown table",
        "typo in options",
        "typo",
        "max",
        "no type",
        "no domain",
    ],
)
def test_an_error_in_a_dict_spec_names_its_field_not_a_line_of_text_never_written(
    edit, field, message
):
    # a dict spec is parsed from TOML text written of it: its line numbers point nowhere
    spec = two_sets()
    edit(spec)
    with pytest.raises(penedge.SpecError) as info:
        penedge.generate(spec)
    assert info.value.field == field, str(info.value)
    assert str(info.value).startswith(f"{field}: {message}")
    assert not re.search(r"line \d+, column", str(info.value))


@pytest.mark.parametrize(
    ("excavation", "field", "message"),
    [
        ({"type": "tunnel", "radus": 1}, "excavation", "unknown field `radus`"),
        ({"type": "tunnel", "radius": "big"}, "excavation.radius", 'got the text "big"'),
        ({"radius": 1}, "excavation", "the field `type` is missing"),
    ],
    ids=["typo", "text for a number", "no type"],
)
def test_an_error_in_an_excavation_dict_names_its_field(excavation, field, message):
    system = penedge.BlockSystem([penedge.Block.cuboid([0, 0, 0], [10, 10, 10])])
    with pytest.raises(penedge.SpecError) as info:
        system.excavate(excavation)
    assert info.value.field == field, str(info.value)
    assert str(info.value).startswith(f"{field}: {message}")
    assert not re.search(r"line \d+, column", str(info.value))


def box(**domain):
    return {"domain": {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1], **domain}}


@pytest.mark.parametrize(
    ("spec", "kind", "field", "message"),
    [
        (box(max=[1e300, 1, 1]), "domain", "domain", "largest coordinate is 1e300"),
        (
            {
                "domain": {
                    "type": "halfspaces",
                    "normals": np.random.default_rng(0).normal(size=(500, 3)),
                    "offsets": np.ones(500),
                }
            },
            "domain",
            "domain",
            "at most 128",
        ),
        (
            {**box(), "joints": [{"type": "set", "dip": 1e300, "dip_direction": 0, "spacing": 1}]},
            "dip",
            "joints[0].dip",
            "got 1e300",  # not 301 digits
        ),
        (
            {**box(), "joints": [{"type": "set", "dip": 0, "dip_direction": 0, "spacing": 1e-300}]},
            "too_many_planes",
            "joints[0].spacing",
            "more than the limit",
        ),
        (
            {**box(), "joints": [{"type": "set", "dip": 0, "dip_direction": 0, "spacing": 1e30}]},
            "misses_domain",
            "joints[0]",
            "misses the domain",
        ),
        (
            {
                **box(),
                "joints": [
                    {
                        "type": "set",
                        "dip": 0,
                        "dip_direction": 0,
                        "spacing": 0.1,
                        "origin": [0, 0, 1e300],
                    }
                ],
            },
            "origin_far",
            "joints[0].origin",
            "put the origin near the domain",
        ),
        (
            {
                **box(),
                "joints": [
                    {"type": "disc", "center": [0.5] * 3, "normal": [0, 0, 1], "radius": math.inf}
                ],
            },
            "not_finite",
            "joints[0].radius",
            "inf",
        ),
        (
            {**box(), "joints": [{"type": "polygon", "vertices": [[0, 0, 0.5]] * 1000}]},
            "bad_polygon",
            "joints[0].vertices",
            "area is zero",
        ),
        (
            {
                **box(),
                "joints": [
                    {"type": "set", "dip": 0, "dip_direction": 0, "spacing": 1, "number": 2**63 - 1}
                ],
            },
            "too_many_planes",
            "joints[0].number",
            "would make 9223372036854775807 planes, more than the limit of 1000000",
        ),
    ],
    ids=[
        "huge box",
        "500 half-spaces",
        "huge dip",
        "tiny spacing",
        "huge spacing",
        "far origin",
        "infinite radius",
        "polygon of one point",
        "huge number",
    ],
)
def test_bad_specs_are_named_quickly(spec, kind, field, message):
    start = time.perf_counter()
    with pytest.raises(penedge.SpecError) as info:
        penedge.generate(spec)
    assert time.perf_counter() - start < 5.0
    assert (info.value.kind, info.value.field) == (kind, field), str(info.value)
    assert message in str(info.value)


@pytest.mark.parametrize("shape", ["cycle", "deep"])
def test_a_self_referencing_or_deep_dict_spec_is_an_error_not_a_crash(shape, tmp_path):
    make = {
        "cycle": "x = []; x.append(x)",
        "deep": "x = [0]; exec('for _ in range(100_000): x = [x]')",
    }[shape]
    script = "\n".join(
        [
            "import penedge",
            make,
            "try:",
            '    penedge.generate({"domain": {"type": "box", "min": x, "max": [1, 1, 1]}})',
            "except penedge.SpecError as e:",
            '    print("SpecError", e.field)',
        ]
    )
    result = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120, check=False
    )
    assert result.returncode == 0, f"exit {result.returncode}: {result.stderr[-500:]}"
    assert result.stdout.startswith("SpecError domain.min")


# -- command line ---------------------------------------------------------------------------


@pytest.fixture
def files(tmp_path):
    """A folder with a good block file and bad inputs of every kind."""
    good = penedge.paper_example(1)
    good.write_json(tmp_path / "blocks.json")
    text = (tmp_path / "blocks.json").read_text()
    (tmp_path / "truncated.json").write_text(text[: len(text) // 2])
    (tmp_path / "binary.json").write_bytes(bytes(range(256)))
    (tmp_path / "empty.json").write_text("")
    (tmp_path / "folder.json").mkdir()
    (tmp_path / "broken_block.json").write_text(text.replace('"faces":[[', '"faces":[[0,0,', 1))
    (tmp_path / "huge.toml").write_text("[domain]\ntype='box'\nmin=[0,0,0]\nmax=[1e300,1,1]\n")
    (tmp_path / "binary.toml").write_bytes(b"\xff\xfe[domain]")
    (tmp_path / "many.toml").write_text(
        "[domain]\ntype='box'\nmin=[0,0,0]\nmax=[1,1,1]\n"
        "[[joints]]\ntype='set'\ndip=10\ndip_direction=0\nspacing=1e-9\n"
    )
    long_line = "[domain]\ntype='box'\nmin=[0,0,0]\nmax=[1,1,1" + ",1" * 50_000 + "\n"
    (tmp_path / "long.toml").write_text(long_line)
    return tmp_path


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["detect", "truncated.json"], "truncated.json: the file ends in the middle of"),
        (["detect", "binary.json"], "binary.json: not UTF-8 text"),
        (["detect", "empty.json"], "empty.json: the file is empty"),
        (["detect", "folder.json"], "folder.json: Is a directory"),
        (["detect", "broken_block.json"], "broken_block.json: domain[0]: face 0 is not a polygon"),
        (["generate", "huge.toml", "-o", "out.json"], "domain: invalid domain: the block's"),
        (["generate", "binary.toml", "-o", "out.json"], "binary.toml: spec: not UTF-8 text"),
        (["generate", "many.toml", "-o", "out.json"], "joints[0].spacing: would make"),
        (["generate", "long.toml", "-o", "out.json"], "long.toml: spec: line 4, column"),
        (["detect", "blocks.json", "-o", "blocks.json/c.csv"], "cannot write blocks.json/c.csv"),
        (["detect", "/dev/zero"], "/dev/zero: not a regular file"),
    ],
)
def test_command_line_errors_are_one_line_and_write_nothing(files, args, message):
    before = {p.name: p.read_bytes() for p in files.iterdir() if p.is_file()}
    result = run(*args, cwd=files)
    assert result.returncode == 1, result.stderr
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr[:2000]
    assert lines[0].startswith("penedge: error: ")
    assert message in lines[0]
    assert len(lines[0]) < 500
    assert result.stdout == ""
    after = {p.name: p.read_bytes() for p in files.iterdir() if p.is_file()}
    assert after == before  # no output, not even a temporary file


# -- mechanics ------------------------------------------------------------------------------


def test_a_simulation_of_no_blocks_is_refused_when_made():
    with pytest.raises(penedge.MechanicsError, match="the block system has no blocks"):
        penedge.Simulation(penedge.BlockSystem([]))


NEGATIVE_ARGUMENTS = {
    "fix": (lambda sim: sim.fix([-1]), r"ids\[0\] is -1"),
    "free": (lambda sim: sim.free([1, -2]), r"ids\[1\] is -2"),
    "set_density": (lambda sim: sim.set_density(2000.0, ids=[-1]), r"ids\[0\] is -1"),
    "excavate": (lambda sim: sim.excavate([-1]), r"ids\[0\] is -1"),
    "relax_steps": (lambda sim: sim.excavate([1], relax_steps=-1), "relax_steps .*-1"),
    "step": (lambda sim: sim.step(-1), "^n must be .*got -1"),
    "solve": (lambda sim: sim.solve(max_steps=-1), "max_steps .*got -1"),
    "set_joint": (
        lambda sim: sim.set_joint(kn=1e9, ks=1e9, friction=30.0, set=-1),
        "^set must be .*got -1",
    ),
    "set_bridge": (
        lambda sim: sim.set_bridge(kn=1e9, ks=1e9, friction=30.0, cohesion=0, tension=0, set=-1),
        "^set must be .*got -1",
    ),
    "joint": (lambda sim: sim.joint(set=-1), "^set must be .*got -1"),
    "bridge": (lambda sim: sim.bridge(-1), "^set must be .*got -1"),
    "set_water": (lambda sim: sim.set_water(pressures={-1: 1.0}), "pressures .*got -1"),
    "set_velocity": (lambda sim: sim.set_velocity(-1, [0, 0, 0]), "^id must be .*got -1"),
    "prescribe": (lambda sim: sim.prescribe(-1, [0, 0, 0]), "^id must be .*got -1"),
    "apply_force": (lambda sim: sim.apply_force(-1, [0, 0, 1]), "^id must be .*got -1"),
    "apply_moment": (lambda sim: sim.apply_moment(-1, [0, 0, 1]), "^id must be .*got -1"),
}


@pytest.mark.parametrize("name", NEGATIVE_ARGUMENTS)
def test_a_negative_count_or_id_is_named_not_a_bare_overflow(name):
    call, message = NEGATIVE_ARGUMENTS[name]
    base = penedge.Block.cuboid([-2, -2, -1], [2, 2, 0])
    cube = penedge.Block.cuboid([-0.5, -0.5, 0], [0.5, 0.5, 1])
    sim = penedge.Simulation(penedge.BlockSystem([base, cube]))
    with pytest.raises(penedge.InputError, match=message) as e:
        call(sim)
    assert e.value.kind == "negative"
    assert sim.steps == 0
    assert not sim.fixed.any()


def test_a_block_moved_out_of_range_is_refused():
    # the moved copy was not checked: vertices collapsed at 1e17 (volume still 1), inf at 1e308
    cube = penedge.Block.cuboid([0, 0, 0], [1, 1, 1])
    for offset in ([1e17, 0, 0], [1.7e308, 0, 0]):
        with pytest.raises(penedge.BlockError):
            cube.translated(offset).translated(offset)
    with pytest.raises(penedge.BlockError):
        cube.rotated([0, 0, 1, 0], about=[1e300, 0, 0])
    # in range: the same block as before, bit for bit
    moved = cube.translated([1e6, 0, 0])
    assert moved.aabb.tolist() == [[1e6, 0.0, 0.0], [1e6 + 1, 1.0, 1.0]]
