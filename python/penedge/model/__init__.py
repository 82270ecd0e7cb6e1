"""Model files: a rock mass, its joints and what to do with it, in one TOML file.

A model file extends the generation spec (``[domain]``, ``[[joints]]``, ``[options]``,
docs/generation.md) with the rock's density, joint properties per set, gravity, water,
bolts, boundary conditions, monitoring points and stages; docs/models.md documents every
field. Reading a model checks all of it, with errors naming the field
(:exc:`ModelError`), before any step runs:

>>> import penedge.model as pm
>>> model = pm.parse_model('''
... [domain]
... type = "box"
... min = [0, 0, 0]
... max = [1, 1, 2]
... [[joints]]
... type = "plane"
... name = "bedding"
... point = [0, 0, 1]
... dip = 0
... dip_direction = 0
... [rock]
... density = 2650
... [joint_properties.default]
... kn = 1e9
... ks = 1e8
... friction = 30
... [[boundary]]
... region = {type = "below", z = 1}
... condition = "fixed"
... ''')
>>> model.properties["bedding"].friction, [s.kind for s in model.stages]
(30.0, ['solve'])
>>> setup = pm.prepare(model)
>>> len(setup.system), setup.layout.fixed.tolist()
(2, [True, False])
>>> pm.parse_model('[domain]\\ntype = "box"\\nmin = [0, 0, 0]\\nmax = [1, 1, 1]\\n'
...                '[rock]\\ndensity = -1')
Traceback (most recent call last):
...
penedge.model.fields.ModelError: rock.density: must be greater than 0, got -1
"""

from __future__ import annotations

import contextlib
import os
import tomllib
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from penedge.model.check import Blocks, Layout, resolve
from penedge.model.fields import ModelError
from penedge.model.schema import (
    Bolt,
    Boundary,
    InitialStress,
    JointProperties,
    Mechanics,
    Model,
    Monitor,
    Plane,
    Region,
    Results,
    Seismic,
    Stage,
    Support,
    Water,
    parse,
)

__all__ = [
    "Blocks",
    "Bolt",
    "Boundary",
    "InitialStress",
    "JointProperties",
    "Layout",
    "Mechanics",
    "Model",
    "ModelError",
    "Monitor",
    "Plane",
    "Region",
    "Results",
    "Seismic",
    "Setup",
    "Stage",
    "Support",
    "Water",
    "load_model",
    "naming_file",
    "parse_model",
    "prepare",
    "read_model",
    "simulate",
]


def parse_model(text: str) -> Model:
    """A model from TOML text (a leading byte order mark, which some Windows editors write,
    is skipped, as ``penedge generate`` skips it)."""
    try:
        data = tomllib.loads(text.removeprefix("\ufeff"))
    except tomllib.TOMLDecodeError as e:
        raise ModelError("model", f"not valid TOML: {e}") from None
    return parse(data)


def read_model(path: str | Path) -> Model:
    """A model from a TOML file (``OSError`` when it cannot be read)."""
    path = Path(path)
    data = path.read_bytes()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        # As the generator says it of a spec file (a model saved in another encoding, a
        # degree sign from a Windows editor, a binary file given by mistake).
        raise ModelError(
            "model",
            f"not UTF-8 text (byte {e.start} is not valid UTF-8; a binary file?) (in {path})",
        ) from None
    try:
        return parse_model(text)
    except ModelError as e:
        raise ModelError(e.field, f"{str(e).split(': ', 1)[1]} (in {path})") from None


def load_model(source: str | Path | Mapping[str, Any] | Model) -> Model:
    """A model from a file path, TOML text (anything with a newline), a dict or a
    :class:`Model` (returned as it is)."""
    if isinstance(source, Model):
        return source
    if isinstance(source, Mapping):
        return parse(dict(source))
    if isinstance(source, str) and "\n" in source:
        return parse_model(source)
    return read_model(source)


def file_of(source: Any) -> Path | None:
    """The model file `source` names (:func:`load_model`: a path, or a string without a
    newline), or None for a model given otherwise (TOML text, a dict, a :class:`Model`,
    a :class:`Setup`)."""
    if isinstance(source, str):
        return None if "\n" in source else Path(source)
    if isinstance(source, os.PathLike):
        return Path(source)
    return None


@contextlib.contextmanager
def naming_file(path: str | Path | None) -> Iterator[None]:
    """An error of the model found after reading the file `path` (the checks that need the
    blocks, the generation's, the engine's refusals of the model's values, raised as a
    :exc:`penedge.SpecError`) ends with the file, `` (in model.toml)``, as the errors of
    reading it do (:func:`read_model`); not twice, and not an error of the restart file
    (field ``restart``), which names that file. The error keeps its class, ``field`` and
    ``kind``. Nothing is added where `path` is None."""
    import penedge

    try:
        yield
    except penedge.SpecError as e:
        where = f" (in {path})"
        text = str(e)
        if path is None or text.endswith(where) or getattr(e, "field", None) == "restart":
            raise
        if isinstance(e, ModelError):
            raise ModelError(e.field, text.split(": ", 1)[1] + where) from None
        named = type(e)(text + where)
        for attribute in ("kind", "field"):
            if hasattr(e, attribute):
                setattr(named, attribute, getattr(e, attribute))
        raise named from None


@dataclass
class Setup:
    """A model with its blocks generated and checked: ready to build a simulation."""

    model: Model
    system: Any  # penedge.BlockSystem
    report: dict[str, Any]
    blocks: Blocks
    layout: Layout


def prepare(source: str | Path | Mapping[str, Any] | Model, progress: Any = None) -> Setup:
    """Reads `source` (see :func:`load_model`), generates its blocks and runs every check
    that needs them. Nothing is simulated yet. Given the model's file, every error of the
    model (:exc:`ModelError`, or the generation's :exc:`penedge.SpecError`) ends with it,
    ``(in model.toml)`` (:func:`naming_file`)."""
    import penedge

    with naming_file(file_of(source)):
        model = load_model(source)
        system, report = penedge.generate(model.spec, progress=progress)
        from penedge.model.run import check_excavations

        if len(system) == 0:
            # Before the blocks' arrays are built (they assume some).
            raise ModelError(
                "domain",
                "the model has no blocks (every block was dropped as a sliver or excavated)",
            )
        blocks = Blocks.of(system)
        layout = resolve(model, blocks)
        check_excavations(model, layout.regions, layout.bodies)
    return Setup(model, system, report, blocks, layout)


def simulate(
    source: str | Path | Mapping[str, Any] | Model | Setup,
    progress: Any = None,
    frame: Any = None,
    folder: str | Path | None = None,
    restart: str | Path | None = None,
) -> Any:
    """Reads and checks a model (or takes a :class:`Setup`), runs its stages on the engine
    and returns the :class:`~penedge.model.run.Outcome` (displacements and velocities as
    numpy arrays, the history, the factor of safety if a stage asked for it). ``save``
    stages write into `folder` (default: the current folder); `restart` goes on from a
    restart file one of them wrote (docs/models.md, "Restart"). Given the model's file,
    an error of the model raised before the first step (the engine's refusal of a time
    step included) ends with it, ``(in model.toml)``, as in :func:`prepare`."""
    from penedge.model.engine import Engine
    from penedge.model.run import Runner

    with naming_file(file_of(source)):
        setup = source if isinstance(source, Setup) else prepare(source)
        runner = Runner(
            setup, Engine, progress=progress, frame=frame, folder=folder, restart=restart
        )
    return runner.run()
