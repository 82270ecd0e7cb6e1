"""Inputs a model file accepted without a word (a tester's findings, 2026-11-29): the clearly
wrong ones are errors naming their field, the plausible but suspicious ones warnings of
``penedge simulate`` and ``--check`` naming theirs (docs/models.md, "Checking before
running", "Warnings"); ``--check`` lists the bolts as it lists the supports."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import penedge.model as pm
from penedge import cli
from penedge.model.fields import ModelError

from cli_run import squeeze

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "models"
PLANAR = (EXAMPLES / "slope_planar.toml").read_text()
# The planar slide without its stages: four blocks, the sliding one (block 3) free.
BASE = PLANAR[: PLANAR.index("[[stages]]")]
SOLVE = '[[stages]]\ntype = "solve"\n'


def bolt(point: str = "[20, 5, 9]", length: float = 6, more: str = "") -> str:
    """A bolt from `point` 20° below the horizontal into the slope (West): from the face at
    (20, 5, 9) it crosses the bedding and ends in the fixed rock below."""
    return (
        f"[[bolts]]\nname = 'b'\npoint = {point}\ntrend = 270\nplunge = 20\nlength = {length}\n"
        f"capacity = 2e6\nstiffness = 1e8\n{more}"
    )


def check(tmp_path: Path, extra: str, *flags: str) -> int:
    """``penedge simulate --check`` on the planar slide with `extra` tables."""
    model = tmp_path / "planar.toml"
    model.write_text(BASE + extra + SOLVE)
    return cli.main(["simulate", str(model), "-o", str(tmp_path / "out"), "--check", *flags])


def warnings_of(tmp_path: Path, capsys: pytest.CaptureFixture[str], extra: str) -> list[str]:
    assert check(tmp_path, extra, "-q") == 0
    err = capsys.readouterr().err
    return [line for line in err.splitlines() if line.startswith("penedge: warning: ")]


# The collar 12.5 m in front of the slope face, the bolt horizontal and 20 m long: 7.5 m of
# it in the rock (the tester's case).
IN_THE_AIR = (
    "[[bolts]]\nname = 'b'\npoint = [30, 5, 12]\ntrend = 270\nplunge = 0\nlength = 20\n"
    "capacity = 2e6\nstiffness = 1e8\n"
)


FREED_LATER = (
    "[[stages]]\ntype = 'boundary'\nregion = {type = 'point', point = [5, 5, 5]}\n"
    "condition = 'free'\n"
)
ON_THE_BACK = (
    "[[support]]\nname = 'back'\nregion = {type = 'point', point = [5, 5, 5]}\n"
    "face = 'west'\npressure = 3e4\n"
)


@pytest.mark.parametrize(
    ("extra", "field", "words", "plausible"),
    [
        (
            IN_THE_AIR,
            "bolts[0].point",
            ["12.5 m outside the rock", "7.5 m of its 20 m", f"{20 / 7.5:.3g}"],
            # on the face, and 5 cm off it (under 1 % of the 6 m)
            [bolt(), bolt(point="[20.05, 5, 9.02]", length=6.05)],
        ),
        (
            bolt(more="rupture_strain = 0.5\n"),
            "bolts[0].rupture_strain = 0.5",
            ["50 %"],
            [bolt(more="rupture_strain = 0.05\n")],
        ),
        (
            ON_THE_BACK,  # block 0, behind the crack, is fixed
            "support[0].region",
            ["'back'", "(0)", "fixed or driven"],
            [
                "[[support]]\nregion = {type = 'all'}\npressure = 3e4\n",
                ON_THE_BACK + FREED_LATER,  # a boundary stage frees the block later
            ],
        ),
        (
            "[initial_stress]\ntype = 'uniform'\nxx = 24085\n",
            "initial_stress is tensile",
            ["+2.408e+04 Pa", "compression is negative"],
            [
                "[initial_stress]\ntype = 'uniform'\nxx = -24085\nzz = -1e4\nzx = 5e3\n",
                "[initial_stress]\ntype = 'overburden'\nsurface = 20\n",
            ],
        ),
        (
            # compressive components, tensile along a diagonal
            "[initial_stress]\ntype = 'uniform'\nxx = -1e6\nyy = -1e6\nzz = -1e6\nxy = 2e6\n",
            "initial_stress is tensile",
            ["+1e+06 Pa"],
            ["[initial_stress]\ntype = 'uniform'\nxx = -1e6\nyy = -1e6\nzz = -1e6\nxy = 5e5\n"],
        ),
        (
            "[water]\ndensity = 1.0\nphreatic = {elevation = 5}\n",
            "water.density = 1 kg/m³",
            ["t/m³"],
            [
                "[water]\nphreatic = {elevation = 5}\n",
                "[water]\ndensity = 1025\npressure = {crack = 1e4}\n",
            ],
        ),
    ],
)
def test_a_suspicious_input_is_warned_of_naming_its_field(
    tmp_path, capsys, extra, field, words, plausible
):
    """The suspicious input is warned of, once, naming its field; the plausible ones of the
    same kind are not."""
    warned = warnings_of(tmp_path, capsys, extra)
    assert len(warned) == 1, warned
    assert warned[0].startswith(f"penedge: warning: {field}"), warned[0]
    for text in words:
        assert text in warned[0], warned[0]
    for other in plausible:
        assert warnings_of(tmp_path, capsys, other) == [], other


def test_the_warnings_come_with_the_run_too(tmp_path, capsys):
    model = tmp_path / "planar.toml"
    model.write_text(BASE + "[water]\ndensity = 1.0\nphreatic = {elevation = 5}\n" + SOLVE)
    out = tmp_path / "out"
    assert cli.main(["simulate", str(model), "-o", str(out), "--no-pictures", "--no-series"]) == 0
    assert "penedge: warning: water.density = 1 kg/m³" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("extra", "field", "words"),
    [
        (bolt(more="rupture_strain = 5\n"), "bolts[0].rupture_strain", "a percent typed?"),
        (bolt(more="rupture_strain = 1\n"), "bolts[0].rupture_strain", "must be below 1"),
        (
            "[initial_stress]\ntype = 'overburden'\nsurface = -10\n",
            "initial_stress.surface",
            "lies below every block (the lowest is at z = 0 m)",
        ),
        # at the lowest vertex: no depth anywhere either
        ("[initial_stress]\ntype = 'overburden'\nsurface = 0\n", "initial_stress.surface", "z = 0"),
    ],
)
def test_a_clearly_wrong_input_is_an_error_naming_its_field(extra, field, words):
    with pytest.raises(ModelError) as raised:
        pm.prepare(BASE + extra + SOLVE)
    assert raised.value.field == field, str(raised.value)
    assert words in str(raised.value)


def test_check_lists_each_bolt_with_the_blocks_it_crosses(tmp_path, capsys):
    extra = bolt() + IN_THE_AIR.replace("name = 'b'", "name = 'long'")
    assert check(tmp_path, extra) == 0
    out = capsys.readouterr().out
    lines = squeeze(out)
    assert (
        "bolt b: 6 m, 6 m in rock, through blocks 3, 2; capacity 2000 kN, stiffness 1e+08 N/m"
        in lines
    )
    assert any(
        line.startswith("bolt long: 20 m, 7.5 m in rock, through blocks 3,") for line in lines
    )
    assert check(tmp_path, extra, "--json") == 0
    listed = json.loads(capsys.readouterr().out)["bolts"]
    assert [b["name"] for b in listed] == ["b", "long"]
    assert listed[0]["blocks"] == [3, 2]
    assert listed[1]["in_rock"] == pytest.approx(7.5, rel=1e-9)
    assert listed[1]["length"] == 20
