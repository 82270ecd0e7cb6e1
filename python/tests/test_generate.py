"""Block generation from Python: every example spec, every way to give a spec, bad specs,
the report, statistics, flat arrays and progress."""

import json
import math
import pickle
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

import penedge
from penedge.pictures import passing_volume

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SPECS = sorted(EXAMPLES.glob("*.toml"))
BOX = {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]}


def spec_dict(name):
    with (EXAMPLES / name).open("rb") as f:
        return tomllib.load(f)


def same_blocks(s, t):
    a, b = s.arrays(), t.arrays()
    for name in ("vertices", "face_offsets", "face_vertices", "face_normals", "volumes"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name


def test_the_examples_folder_has_specs():
    assert len(SPECS) >= 14


@pytest.mark.parametrize("path", SPECS, ids=lambda p: p.stem)
def test_every_example_spec_generates(path):
    system, report = penedge.generate(path)
    assert len(system) == report["blocks"] > 1
    assert report["volume_error"] < 1e-9
    # What the excavations removed counts with the blocks (docs/generation.md, "Excavations").
    kept_and_dropped = report["block_volume"] + report["excavated_volume"]
    if report["slivers"]["policy"] == "drop":
        kept_and_dropped += report["slivers"]["volume"]
    assert kept_and_dropped == pytest.approx(report["domain_volume"], rel=1e-9)
    assert system.volumes.sum() == pytest.approx(report["block_volume"], rel=1e-9)
    entries = spec_dict(path.name)
    assert len(system.sets) == len(entries.get("joints", [])) + len(entries.get("excavations", []))
    assert len(system.domain) == 1
    stats = system.statistics()
    assert stats["count"] == len(np.unique(system.body_ids))  # a concave block's parts: one
    assert stats["min_volume"] <= stats["v10"] <= stats["v50"] <= stats["v90"]


@pytest.mark.parametrize("n", [1, 2, 3])
def test_paper_examples_from_their_specs(n):
    system, _ = penedge.generate(EXAMPLES / f"paper_example_{n}.toml")
    assert system.detect().counts() == penedge.paper_example(n).detect().counts()


def test_a_spec_as_path_text_dict_or_json_gives_the_same_blocks(tmp_path):
    path = EXAMPLES / "joint_set_random.toml"
    reference, _ = penedge.generate(path)
    as_json = tmp_path / "spec.json"
    as_json.write_text(json.dumps(spec_dict(path.name)), encoding="utf-8")
    for spec in (str(path), path.read_text(encoding="utf-8"), spec_dict(path.name), as_json):
        system, _ = penedge.generate(spec)
        same_blocks(system, reference)


def test_a_dict_may_hold_numpy_values_and_none():
    spec = {
        "domain": {"type": "box", "min": np.zeros(3), "max": np.array([10, 10, 10])},
        "joints": [
            {
                "type": "set",
                "dip": np.float64(0),
                "dip_direction": 0,
                "spacing": 2.5,
                "number": np.int64(2),
                "origin": (0, 0, 2.5),
                "name": None,
            },
        ],
    }
    system, report = penedge.generate(spec)
    assert len(system) == 3
    assert report["joint_planes"] == 2
    assert system.sets == [{"name": "joints[0]", "kind": "set"}]
    # np.longdouble stays a longdouble under tolist(): it went round to the nesting limit
    # and was reported as "a list or dict that contains itself".
    spec["domain"]["max"] = np.full(3, 10, dtype=np.longdouble)
    spec["joints"][0]["spacing"] = np.longdouble(2.5)
    again, _ = penedge.generate(spec)
    assert again.to_json() == system.to_json()


def test_report_counts_partial_cuts_by_entry():
    system, report = penedge.generate(EXAMPLES / "finite_disc.toml")
    assert report["partial_cuts_skipped"] == 2
    assert report["partial_cuts_by_entry"] == [0, 2]
    assert [s["name"] for s in system.sets] == ["vertical", "lens"]


def test_report_counts_dropped_slivers():
    _, report = penedge.generate(EXAMPLES / "slivers.toml")
    slivers = report["slivers"]
    assert slivers["policy"] == "drop"
    assert slivers["count"] == 4
    assert slivers["volume"] == pytest.approx(4 * 2.5 * 10 * 0.001, rel=1e-6)
    assert slivers["kept_ids"] == []


def one_plane(**joint):
    return {"domain": dict(BOX), "joints": [{"type": "plane", "point": [5, 5, 5], **joint}]}


def one_set(**joint):
    return {
        "domain": dict(BOX),
        "joints": [{"type": "set", "dip": 0, "dip_direction": 0, "spacing": 2.5, **joint}],
    }


# spec -> (field, kind, part of the message)
BAD_SPECS = {
    "dip 120": (one_plane(dip=120, dip_direction=0), "joints[0].dip", "dip", "got 120"),
    "zero spacing": (one_set(spacing=0), "joints[0].spacing", "not_positive", "got 0"),
    "plane misses": (
        {
            "domain": BOX,
            "joints": [{"type": "plane", "point": [0, 0, 20], "dip": 0, "dip_direction": 0}],
        },
        "joints[0]",
        "misses_domain",
        "misses the domain",
    ),
    "duplicate plane": (
        {"domain": BOX, "joints": [one_plane(dip=0, dip_direction=0)["joints"][0]] * 2},
        "joints[1]",
        "duplicate",
        "same plane as joints[0]",
    ),
    "NaN in a dict": (
        one_plane(dip=math.nan, dip_direction=0),
        "joints[0].dip",
        "not_finite",
        "NaN",
    ),
    "radius on a plane": (
        one_plane(dip=0, dip_direction=0, radius=2),
        "joints[0].radius",
        "not_allowed",
        "not a field of a `plane` entry",
    ),
    "deviation too large": (
        one_set(spacing_deviation=2.5),
        "joints[0].spacing_deviation",
        "deviation_too_large",
        "smaller than the spacing",
    ),
    "bow-tie polygon": (
        {
            "domain": BOX,
            "joints": [
                {"type": "polygon", "vertices": [[0, 0, 5], [10, 10, 5], [10, 0, 5], [0, 10, 5]]}
            ],
        },
        "joints[0].vertices",
        "bad_polygon",
        "not a flat convex polygon",
    ),
    "max below min": (
        {"domain": {"type": "box", "min": [0, 0, 0], "max": [10, 0, 10]}},
        "domain.max",
        "invalid",
        "greater than",
    ),
    "spacing far too small": (
        one_set(spacing=1e-6),
        "joints[0].spacing",
        "too_many_planes",
        "more than the limit",
    ),
    "missing spacing": (
        {"domain": BOX, "joints": [{"type": "set", "dip": 0, "dip_direction": 0}]},
        "joints[0].spacing",
        "missing",
        "missing",
    ),
    "unknown type": (
        {"domain": BOX, "joints": [{"type": "fault"}]},
        "joints[0].type",
        "unknown_type",
        "unknown type `fault`",
    ),
    # a dict's syntax errors name the field, not a line of the TOML text written of it
    "typo": (one_set(dipp=3), "joints[0]", "syntax", "unknown field `dipp` (a typo?)"),
    "text for a number": (one_set(spacing="2.5"), "joints[0].spacing", "syntax", "a number"),
    "both orientations": (
        one_plane(dip=0, dip_direction=0, normal=[0, 0, 1]),
        "joints[0]",
        "orientation",
        "either `normal` or both",
    ),
}


@pytest.mark.parametrize("name", list(BAD_SPECS))
def test_bad_specs_name_the_field(name):
    spec, field, kind, message = BAD_SPECS[name]
    with pytest.raises(penedge.SpecError) as info:
        penedge.generate(spec)
    error = info.value
    assert isinstance(error, ValueError)
    assert error.field.startswith(field), error.field
    assert error.kind == kind, (error.kind, str(error))
    assert message in str(error)
    assert str(error).startswith(error.field)


def test_nan_in_toml_text_names_the_field():
    text = '[domain]\ntype = "box"\nmin = [0, 0, 0]\nmax = [1, 1, nan]\n'
    with pytest.raises(penedge.SpecError) as info:
        penedge.generate(text)
    assert info.value.field == "domain.max"


def test_a_bad_spec_file_is_named_in_the_message(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(
        '[domain]\ntype = "box"\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n\n'
        '[[joints]]\ntype = "plane"\npoint = [0, 0, 0.5]\ndip = 120\ndip_direction = 0\n',
        encoding="utf-8",
    )
    with pytest.raises(penedge.SpecError, match=r"bad\.toml: joints\[0\]\.dip: dip must be"):
        penedge.generate(path)


def test_a_missing_spec_file_raises_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError) as info:
        penedge.generate(tmp_path / "nowhere.toml")
    assert info.value.filename == str(tmp_path / "nowhere.toml")


@pytest.mark.parametrize("spec", [42, None, [1, 2], {"domain": {"type": "box", "min": object()}}])
def test_a_spec_of_another_type_is_refused(spec):
    with pytest.raises(penedge.PenedgeError) as info:
        penedge.generate(spec)
    assert isinstance(info.value, penedge.InputError | penedge.SpecError)


def test_a_cut_error_is_a_block_error_not_a_crash():
    assert issubclass(penedge.SpecError, penedge.PenedgeError)
    assert issubclass(penedge.FileFormatError, ValueError)


def test_progress_is_called_and_ends_with_every_plane():
    calls = []
    system, report = penedge.generate(
        EXAMPLES / "joint_set_random.toml", progress=lambda *a: calls.append(a)
    )
    assert calls, "the last plane is always reported"
    assert calls[-1] == (report["joint_planes"], report["joint_planes"], len(system))
    assert len(calls) <= report["joint_planes"]


def test_an_exception_in_progress_is_raised():
    def fail(done, total, blocks):
        raise RuntimeError(f"stop at {done}")

    with pytest.raises(RuntimeError, match="stop at"):
        penedge.generate(EXAMPLES / "joint_set_random.toml", progress=fail)


def test_an_exception_in_progress_stops_the_run_where_it_is():
    # About 10^5 blocks (0.3 s and more): the callback is first called after 0.1 s, long
    # before the last plane; the run stops there, and the note says how far it got (the
    # run used to go on to the end and raise then).
    calls = []

    def fail(done, total, blocks):
        calls.append(done)
        raise RuntimeError("no more")

    with pytest.raises(RuntimeError, match="no more") as info:
        penedge.generate(EXAMPLES / "three_joint_sets.toml", progress=fail)
    assert len(calls) == 1
    (note,) = info.value.__notes__
    done, total = map(
        int,
        re.fullmatch(r"penedge.generate stopped after (\d+) of (\d+) joint planes", note).groups(),
    )
    assert done == calls[0] < total


def test_an_exception_in_progress_stops_an_excavation_during_its_cuts(tmp_path):
    # A 10 m box in 3 blocks under a ground of 120 x 120 elevations: the excavation makes
    # some 20,000 parts after the last plane. The callback sees them (as the excavation cuts,
    # every 0.1 s, and at the end) and stops the run; it used to see the 3 blocks of the
    # last plane and nothing after (Ctrl-C waited for the end of the excavation).
    n = 120
    xs = np.linspace(-1.0, 11.0, n)
    x, y = np.meshgrid(xs, xs)
    z = 6.0 + 0.3 * np.sin(1.3 * x) * np.cos(0.9 * y) + 0.1 * np.sin(3.1 * x + 2.3 * y)
    ground = tmp_path / "ground.csv"
    rows = "\n".join(
        f"{a:.9f},{b:.9f},{c:.9f}" for a, b, c in zip(x.ravel(), y.ravel(), z.ravel(), strict=True)
    )
    ground.write_text("x,y,z\n" + rows + "\n")
    spec = {
        "domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]},
        "joints": [
            {"type": "set", "dip": 90, "dip_direction": 90, "spacing": 5, "origin": [2.5, 0, 0]}
        ],
        "excavations": [{"type": "topography", "file": str(ground)}],
    }
    calls = []

    def fail(done, total, blocks):
        calls.append((done, total, blocks))
        if blocks > 3:
            raise RuntimeError("no more")

    with pytest.raises(RuntimeError, match="no more") as info:
        penedge.generate(spec, progress=fail)
    assert calls[-1][:2] == (2, 2), calls
    assert calls[-1][2] > 3, calls
    (note,) = info.value.__notes__
    assert note == "penedge.generate stopped after 2 of 2 joint planes"


def three_sets(size, spacing):
    """Three orthogonal sets from the origin: ``(size / spacing)^3`` blocks."""
    joints = [
        {"type": "set", "dip": dip, "dip_direction": direction, "spacing": spacing}
        for dip, direction in ((0, 0), (90, 0), (90, 90))
    ]
    return {"domain": {"type": "box", "min": [0, 0, 0], "max": [size] * 3}, "joints": joints}


def test_a_runaway_spec_is_refused_before_cutting():
    # 10^4 planes a set: 30,000 planes but about 10^12 blocks (the 24 GB run).
    with pytest.raises(penedge.SpecError) as info:
        penedge.generate(three_sets(100, 0.01))
    e = info.value
    assert (e.kind, e.field) == ("too_many_blocks", "joints")
    for words in ("about 1.0e12 blocks", "PB of memory", "larger spacing", "max_blocks"):
        assert words in str(e)


def test_max_blocks_limits_the_run():
    spec = three_sets(10, 2.5)  # 4 x 4 x 4 blocks
    assert len(penedge.generate(spec, max_blocks=64)[0]) == 64
    with pytest.raises(penedge.SpecError, match="the limit is 63 blocks \\(given\\)"):
        penedge.generate(spec, max_blocks=63)
    for bad in (0, -1):
        with pytest.raises(penedge.InputError, match=f"max_blocks must be .* got {bad}"):
            penedge.generate(spec, max_blocks=bad)


def test_the_report_counts_tiny_blocks():
    # z = 5 and z = 5.001 in a 10 m cube: 500, 0.1 and 499.9 m^3; not slivers (thicker than
    # 1e-6 of the domain's size) but 1/4999 of the median block.
    planes = [
        {"type": "plane", "point": [0, 0, z], "dip": 0, "dip_direction": 0} for z in (5, 5.001)
    ]
    _, report = penedge.generate({"domain": BOX, "joints": planes})
    assert report["slivers"]["count"] == 0
    tiny = report["tiny"]
    assert tiny["count"] == 1
    assert tiny["median_volume"] == pytest.approx(499.9)
    assert tiny["threshold"] == pytest.approx(0.4999)
    assert tiny["smallest"] == pytest.approx(0.1)


def test_the_tiny_blocks_median_of_an_even_count_is_the_mean_of_the_middle_two():
    # A 4 x 1 x 1 box cut at x = 1: blocks of 1 and 3, median 2 (it read 3).
    _, report = penedge.generate(
        {
            "domain": {"type": "box", "min": [0, 0, 0], "max": [4, 1, 1]},
            "joints": [{"type": "plane", "point": [1, 0, 0], "normal": [1, 0, 0]}],
        }
    )
    assert report["tiny"]["median_volume"] == pytest.approx(2.0)
    assert report["tiny"]["threshold"] == pytest.approx(2e-3)


def test_statistics_and_volume_curve():
    system, _ = penedge.generate(EXAMPLES / "joint_set_random.toml")
    stats, volumes = system.statistics(), np.sort(system.volumes)
    for x in (10, 50, 90):
        assert stats[f"v{x}"] == passing_volume(volumes, x)
    assert stats["total_volume"] == pytest.approx(volumes.sum())
    curve_v, passing = system.volume_curve()
    assert np.array_equal(curve_v, volumes)
    assert np.all(np.diff(passing) >= 0)
    assert passing[-1] == pytest.approx(1)
    assert penedge.BlockSystem([]).statistics() is None


def test_flat_arrays_rebuild_the_blocks():
    system, _ = penedge.generate(EXAMPLES / "finite_polygon.toml")
    a = system.arrays()
    assert len(a.vertex_offsets) == len(a.face_offsets) == len(system) + 1
    assert len(a.loop_offsets) == len(a.face_block) + 1 == a.face_offsets[-1] + 1
    for i, block in enumerate(system.blocks):
        v0, v1 = a.vertex_offsets[i : i + 2]
        assert np.array_equal(a.vertices[v0:v1], block.vertices)
        f0, f1 = a.face_offsets[i : i + 2]
        assert (a.face_block[f0:f1] == i).all()
        loops = [
            a.face_vertices[a.loop_offsets[f] : a.loop_offsets[f + 1]] - v0 for f in range(f0, f1)
        ]
        assert [loop.tolist() for loop in loops] == block.faces
        assert np.array_equal(a.face_normals[f0:f1], block.face_normals)
    assert np.array_equal(a.volumes, system.volumes)
    assert np.array_equal(a.centroids, system.centroids)
    with pytest.raises(ValueError, match="read-only"):
        a.volumes[0] = 1


def test_face_origins_tell_free_faces_from_joint_faces():
    system, _ = penedge.generate(EXAMPLES / "joint_set_number.toml")
    a = system.arrays()
    boundary, joint = a.face_origin_kind == 1, a.face_origin_kind == 2
    assert (boundary | joint).all()
    assert (a.face_origin_set[joint] == 0).all()  # the one spec entry
    assert set(a.face_origin_index[joint].tolist()) <= set(range(len(system) - 1))
    # the free faces of a box lie in its six planes, with axis normals
    assert np.allclose(np.abs(a.face_normals[boundary]).max(axis=1), 1)


def test_pickle_keeps_the_provenance():
    system, _ = penedge.generate(EXAMPLES / "finite_disc.toml")
    again = pickle.loads(pickle.dumps(system))
    assert again.sets == system.sets
    same_blocks(again, system)
    assert np.array_equal(again.arrays().face_origin_index, system.arrays().face_origin_index)


def test_a_pickled_block_keeps_its_face_origins():
    system, _ = penedge.generate(EXAMPLES / "finite_disc.toml")
    blocks = [pickle.loads(pickle.dumps(b)) for b in system.blocks]
    again, before = penedge.BlockSystem(blocks).arrays(), system.arrays()
    assert (before.face_origin_kind > 0).all()
    for name in ("face_origin_kind", "face_origin_set", "face_origin_index"):
        assert np.array_equal(getattr(again, name), getattr(before, name)), name


def test_restoring_a_block_with_bad_origins_is_an_input_error():
    block = penedge.paper_example(1).blocks[0]
    vertices, faces = block.vertices, block.faces
    n = len(faces)
    with pytest.raises(penedge.InputError, match="code 7"):
        penedge.Block._restore(vertices, faces, [(7, 0, 0)] * n)
    with pytest.raises(penedge.InputError, match="out of range"):
        penedge.Block._restore(vertices, faces, [(2, -5, 0)] * n)
    with pytest.raises(penedge.PenedgeError):
        penedge.Block._restore(vertices, faces, [(0, -1, -1)] * (n + 1))
    # Numbers past any integer type, codes too, and things that are not numbers at all.
    for bad in [(2, 2**70, 0), (2**70, 0, 0), (1, 0, "face"), (1.5, 0, 0)]:
        with pytest.raises(penedge.InputError, match="origin"):
            penedge.Block._restore(vertices, faces, [bad] * n)


def test_a_pickled_block_is_the_same_block_bit_for_bit():
    """Vertices, planes and face origins come back as they were (not refitted), also for
    the pieces of a cut whose caps hold vertices only within the domain's threshold."""
    system, _ = penedge.generate(EXAMPLES / "three_joint_sets.toml")
    blocks = system.blocks[:300]
    again = [pickle.loads(pickle.dumps(b)) for b in blocks]
    for a, b in zip(again, blocks, strict=True):
        assert np.array_equal(a.vertices, b.vertices)
        assert a.faces == b.faces
        assert np.array_equal(a.face_normals, b.face_normals)
    before, after = penedge.BlockSystem(blocks), penedge.BlockSystem(again)
    assert np.array_equal(after.arrays().face_origin_index, before.arrays().face_origin_index)
    found, found_again = before.detect(), after.detect()
    assert np.array_equal(found.pairs, found_again.pairs)
    assert np.array_equal(found.types, found_again.types)


def test_restoring_a_block_with_bad_planes_is_an_error():
    block = penedge.paper_example(1).blocks[0]
    vertices, faces, normals = block.vertices, block.faces, block.face_normals
    n = len(faces)
    origins = [(0, -1, -1)] * n
    points = block.vertices[[face[0] for face in faces]]
    again = penedge.Block._restore(vertices, faces, origins, normals, points, 1e-9)
    assert np.array_equal(again.face_normals, normals)
    with pytest.raises(penedge.InputError, match="normals and"):
        penedge.Block._restore(vertices, faces, origins, normals[:-1], points, 1e-9)
    with pytest.raises(penedge.ToleranceError, match="length"):
        penedge.Block._restore(vertices, faces, origins, normals, points, 0.5)
    with pytest.raises(penedge.BlockError):
        penedge.Block._restore(vertices, faces, origins, -normals, points, 1e-9)


def test_a_block_pickled_without_its_planes_still_loads():
    block = penedge.paper_example(1).blocks[0]
    origins = [(0, -1, -1)] * len(block.faces)
    again = penedge.Block._restore(block.vertices, block.faces, origins)
    assert np.array_equal(again.vertices, block.vertices)
    assert again.faces == block.faces


def test_one_line_toml_text_is_a_spec_not_a_file_name(tmp_path, monkeypatch):
    # a spec on one line has no newline: it was taken for a file name (FileNotFoundError)
    monkeypatch.chdir(tmp_path)
    line = 'domain = { type = "box", min = [0, 0, 0], max = [2, 1, 1] }'
    cut = 'joints = [ { type = "plane", point = [1, 0.5, 0.5], normal = [1, 0, 0] } ]'
    whole, _ = penedge.generate(line)
    halves, _ = penedge.generate(line + "\n" + cut)
    assert (len(whole), len(halves)) == (1, 2)
    # a file whose name holds an `=` is still read as a file
    (tmp_path / "a=b.toml").write_text(line + "\n" + cut)
    from_file, _ = penedge.generate("a=b.toml")
    assert len(from_file) == 2
    # a name that names no file is still a missing file, an `=` in it or not
    for missing in ["nothing.toml", "runs/dip=30.tom"]:
        with pytest.raises(FileNotFoundError):
            penedge.generate(missing)


@pytest.mark.parametrize("name", ["boundary", "bridge of J2", ""])
def test_a_joint_named_as_a_contact_table_label_is_refused(name):
    # The contact table's set_a, set_b give these to domain faces, rock-bridge faces and
    # faces with no origin: a joint of that name made the table ambiguous.
    joints = [
        {"type": "plane", "name": name, "point": [5, 5, 5], "normal": [0, 0, 1]},
        {"type": "plane", "name": "J2", "point": [5, 5, 5], "normal": [1, 0, 0]},
    ]
    with pytest.raises(penedge.SpecError, match=r"joints\[0\]\.name: .*choose another"):
        penedge.generate({"domain": BOX, "joints": joints})
