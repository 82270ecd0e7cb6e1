"""Systems whose blocks are convex parts of bodies (concave blocks around excavations and
under slopes, pieces held by rock bridges): two parts of one body are one rigid block, so
``BlockSystem.detect``, ``penedge detect`` (counts, contacts.csv) and the contact tracker
never report the glue between them as a contact, and ``penedge generate`` counts and
measures the blocks, not their parts.

References: the same blocks detected as a system without bodies (each block its own body)
with the pairs of one body taken out by the body ids; the parts' volumes summed per body;
a bridged cube worked out by hand (one block, no contact)."""

import csv
import json
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import penedge
from penedge.cli import generate as generate_command
from penedge.pictures.volumes import passing_volume

from cli_run import run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
CONCAVE = ["tunnel_circular", "cavern", "shaft", "slope_topography"]

#: A 10 m cube with a horizontal 4 x 4 m square joint at z = 5 with rock bridges: the joint
#: ends inside the cube, which it cuts through into pieces held by the bridges (one block).
BRIDGED_CUBE = """\
[domain]
type = "box"
min = [0, 0, 0]
max = [10, 10, 10]

[[joints]]
type = "polygon"
name = "square"
vertices = [[3, 3, 5], [7, 3, 5], [7, 7, 5], [3, 7, 5]]
bridge = true
"""


def generated(name):
    system, _ = penedge.generate(EXAMPLES / f"{name}.toml")
    return system


def per_part_less_same_body(system):
    """The contact pairs of `system`'s blocks as blocks of their own, less those of two
    parts of one body of `system`; and the number of pairs taken out."""
    ids = system.body_ids
    plain = system.with_bodies(list(range(len(system))))
    pairs = plain.detect().pairs
    same = ids[pairs[:, 0]] == ids[pairs[:, 1]]
    return pairs[~same], int(same.sum())


@pytest.mark.parametrize("name", CONCAVE)
def test_detect_leaves_out_the_glue_inside_a_block(name):
    system = generated(name)
    assert len(np.unique(system.body_ids)) < len(system)
    expected, same_body = per_part_less_same_body(system)
    assert same_body > 0
    found = system.detect(geometry=True)
    assert found.pairs.tolist() == expected.tolist()
    # The contact tracker reports the same contacts (docs/systems.md, "Time stepping").
    tracker = penedge.ContactTracker(system, skin=0.0)
    assert tracker.contacts.pairs.tolist() == expected.tolist()


@pytest.mark.parametrize("name", ["tunnel_circular", "cavern"])
def test_the_detect_command_counts_blocks_and_their_contacts(tmp_path, name):
    made = run("generate", EXAMPLES / f"{name}.toml", "-o", "b.json", "-q", cwd=tmp_path)
    assert made.returncode == 0, made.stderr
    system = penedge.BlockSystem.read_json(tmp_path / "b.json")
    expected, _ = per_part_less_same_body(system)
    bodies = len(np.unique(system.body_ids))
    result = run("detect", "b.json", "-o", "c.csv", "--json", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert (summary["bodies"], summary["blocks"]) == (bodies, len(system))
    assert summary["contacts"] == len(expected)
    with (tmp_path / "c.csv").open(newline="") as handle:
        rows = [(int(r["block_a"]), int(r["block_b"])) for r in csv.DictReader(handle)]
    assert rows == [tuple(p) for p in expected.tolist()]
    text = run("detect", "b.json", cwd=tmp_path)
    first = text.stdout.splitlines()[0]
    assert first.startswith(
        f"b.json: {bodies} blocks ({len(system)} convex parts), {len(expected)} contacts"
    )


def test_a_cube_held_by_rock_bridges_is_one_block_without_contacts(tmp_path):
    (tmp_path / "cube.toml").write_text(BRIDGED_CUBE)
    made = run("generate", "cube.toml", "-o", "b.json", "--json", cwd=tmp_path)
    assert made.returncode == 0, made.stderr
    summary = json.loads(made.stdout)
    system = penedge.BlockSystem.read_json(tmp_path / "b.json")
    assert len(system) > 1  # cut through into pieces
    assert (summary["bodies"], summary["blocks"]) == (1, len(system))
    assert summary["statistics"]["count"] == 1
    assert summary["statistics"]["min_volume"] == pytest.approx(1000.0)
    found = run("detect", "b.json", "-o", "c.csv", cwd=tmp_path)
    assert found.returncode == 0, found.stderr
    assert found.stdout.startswith(f"b.json: 1 block ({len(system)} convex parts), 0 contacts")
    assert (tmp_path / "c.csv").read_text().count("\n") == 1  # the header only
    assert len(system.detect()) == 0
    assert len(system.detect_bodies()) == 0
    # The pieces do touch: as blocks of their own they would be contacts.
    assert per_part_less_same_body(system)[1] > 0


@pytest.mark.parametrize("name", ["cavern", "tunnel_circular"])
def test_statistics_are_per_block_with_its_parts_summed(tmp_path, name):
    system = generated(name)
    ids, volumes = system.body_ids, system.volumes
    blocks = np.array([volumes[ids == b].sum() for b in np.unique(ids)])
    assert len(blocks) < len(system)
    stats = system.statistics()
    assert stats["count"] == len(blocks)
    assert stats["min_volume"] == pytest.approx(blocks.min())
    assert stats["max_volume"] == pytest.approx(blocks.max())
    assert stats["total_volume"] == pytest.approx(volumes.sum())
    for percent in (10, 50, 90):
        assert stats[f"v{percent}"] == pytest.approx(passing_volume(blocks, percent))
    curve, passing = system.volume_curve()
    assert curve.tolist() == pytest.approx(np.sort(blocks).tolist())
    assert passing[-1] == pytest.approx(1.0)
    mass = system.body_mass_properties()["volumes"]
    assert np.sort(blocks) == pytest.approx(np.sort(mass))
    result = run("generate", EXAMPLES / f"{name}.toml", cwd=tmp_path)
    first = result.stdout.splitlines()[0]
    assert f": {len(blocks)} blocks ({len(system)} convex parts) in " in first
    assert f"(min {blocks.min():.4g}, max {blocks.max():.4g})" in result.stdout


def test_a_system_of_convex_blocks_counts_as_before(tmp_path):
    system = penedge.paper_example(3)
    stats = system.statistics()
    assert stats["count"] == len(system) == 26
    assert stats["min_volume"] == pytest.approx(system.volumes.min())
    made = run("generate", EXAMPLES / "paper_example_3.toml", "-o", "b.json", cwd=tmp_path)
    assert ": 26 blocks in " in made.stdout.splitlines()[0]
    assert "convex part" not in made.stdout
    found = run("detect", "b.json", cwd=tmp_path)
    assert found.stdout.startswith("b.json: 26 blocks, 325 contacts")


def test_detect_help_names_every_column_of_the_contact_table(tmp_path):
    made = run("generate", EXAMPLES / "plane_dip.toml", "-o", "b.json", "-q", cwd=tmp_path)
    assert made.returncode == 0
    assert run("detect", "b.json", "-o", "c.csv", "-q", cwd=tmp_path).returncode == 0
    header = (tmp_path / "c.csv").read_text().splitlines()[0].split(",")
    help_text = " ".join(run("detect", "--help", cwd=tmp_path).stdout.split())
    missing = [column for column in header if column not in help_text]
    assert missing == []


@pytest.mark.parametrize(
    "spec",
    [
        {"domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]}},
        {
            "domain": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]},
            "unit": "m",
            "options": {"min_volume": 0.001},
        },
    ],
)
def test_detect_names_a_json_spec(tmp_path, spec):
    (tmp_path / "spec.json").write_text(json.dumps(spec))
    assert run("generate", "spec.json", "-q", cwd=tmp_path).returncode == 0  # a valid spec
    result = run("detect", "spec.json", cwd=tmp_path)
    assert result.returncode == 1
    assert (
        "penedge: error: spec.json: this looks like a joint spec (JSON), not a block file: "
        "run `penedge generate` on it first" in result.stderr
    )
    # Any other JSON object that is no block file keeps its message.
    (tmp_path / "other.json").write_text(json.dumps({"domain": 1, "colour": "red"}))
    other = run("detect", "other.json", cwd=tmp_path)
    assert "no `format` field" in other.stderr


def test_quiet_detect_prints_no_warning(tmp_path):
    cube = penedge.Block.cuboid
    penedge.BlockSystem([cube([0, 0, 0], [1, 1, 1]), cube([0.5, 0, 0], [2, 1, 1])]).write_json(
        tmp_path / "overlap.json"
    )
    quiet = run("detect", "overlap.json", "-o", "c.csv", "-q", cwd=tmp_path)
    assert (quiet.returncode, quiet.stdout, quiet.stderr) == (0, "", "")
    assert (tmp_path / "c.csv").exists()
    loud = run("detect", "overlap.json", cwd=tmp_path)
    assert "warning: 1 pair of blocks overlap" in loud.stderr


@pytest.mark.parametrize("limit", [2**63 - 1, 2**63, 2**64 + 5, 10**30])
def test_a_huge_block_limit_is_no_limit(tmp_path, limit):
    result = run("generate", EXAMPLES / "plane_dip.toml", "--max-blocks", limit, cwd=tmp_path)
    assert (result.returncode, result.stderr) == (0, "")
    assert generate_command.block_count(str(limit)) == min(limit, 2**63 - 1)


def test_a_block_limit_is_still_checked(tmp_path):
    result = run("generate", EXAMPLES / "plane_dip.toml", "--max-blocks", "0", cwd=tmp_path)
    assert result.returncode == 2
    assert "must be 1 or more" in result.stderr


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="needs /proc")
def test_generate_writes_every_output_or_none(tmp_path):
    args = ("generate", EXAMPLES / "plane_dip.toml", "-o", "ok.json", "--vtu", "ok.vtu")
    result = run(*args, "--csv", "/proc/x.csv", cwd=tmp_path)
    assert result.returncode == 1
    assert "cannot write /proc/x.csv" in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # no output, no temporary file
    assert run(*args, "--csv", "ok.csv", "-q", cwd=tmp_path).returncode == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ok.csv", "ok.json", "ok.vtu"]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="needs /proc")
def test_detect_writes_both_outputs_or_neither(tmp_path):
    made = run("generate", EXAMPLES / "plane_dip.toml", "-o", "b.json", "-q", cwd=tmp_path)
    assert made.returncode == 0
    result = run("detect", "b.json", "-o", "c.csv", "--vtp", "/proc/c.vtp", cwd=tmp_path)
    assert result.returncode == 1
    assert "cannot write /proc/c.vtp" in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.json"]


def test_the_glue_inside_a_bridged_block_is_no_bare_face():
    # The faces of the crack inside the bridged cube are joint faces covered by glue, not
    # faces an excavation left bare (penedge.model's supports push on bare faces).
    from penedge.model.check import Blocks, bare_faces

    system, _ = penedge.generate(tomllib.loads(BRIDGED_CUBE))
    joint = np.asarray(system.arrays().face_origin_kind) == 2
    assert joint.any()  # the crack's faces, of the square joint
    assert len(bare_faces(Blocks.of(system), []).faces) == 0


def test_a_write_failing_after_the_work_leaves_no_output_and_names_the_output(
    tmp_path, monkeypatch, capsys
):
    # the checks before the work pass; the block table's writer then fails: the block file
    # already written to its temporary file is not published, and the error names the table
    import errno

    from penedge.cli import main

    def full(self, path):
        raise OSError(errno.ENOSPC, "No space left on device", str(path))

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(penedge.BlockSystem, "write_csv", full)
    status = main(["generate", str(EXAMPLES / "plane_dip.toml"), "-o", "ok.json", "--csv", "t.csv"])
    assert status == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == []  # no output, no temporary file
    assert capsys.readouterr().err.strip() == "penedge: error: t.csv: No space left on device"


def test_show_counts_bodies_and_draws_their_volumes(tmp_path):
    from penedge.pictures.volumes import _volumes

    system = generated("cavern")
    bodies = np.unique(system.body_ids, return_inverse=True)[1]
    expected = np.sort(np.bincount(bodies, weights=system.volumes))
    assert len(expected) < len(system)  # a concave system
    assert _volumes(system).tolist() == expected.tolist()
    system.write_json(tmp_path / "b.json")
    result = run("show", "b.json", "--json", "--no-picture", "--stats-png", "v.png", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    summary = json.loads(result.stdout)
    assert (summary["blocks"], summary["bodies"]) == (len(system), len(expected))
