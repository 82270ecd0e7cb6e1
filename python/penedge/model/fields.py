"""Reading one table of a model file: typed fields, units checked, every error naming the
field by its path in the file (``stages[2].steps``), unknown fields refused.

A :class:`Table` wraps the dict that TOML (or JSON, or the caller) gave for one table; each
``table.number("density", ...)`` marks the key as read, and :meth:`Table.done` refuses the
keys nobody read, listing the ones the table takes.
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from penedge._core import SpecError

#: The largest whole number a model field takes (:meth:`Table.integer`).
MAX_WHOLE = 10**15

#: The most steps one stage may take: a ``cycle``'s `steps`, a ``solve``'s or a factor of
#: safety's `max_steps` (per trial), an ``excavate``'s `relax_steps`, a ``time`` stage's
#: time over the time step (docs/models.md, "How long a run is").
MAX_STEPS = 10**8

#: Why :data:`MAX_STEPS`, for the errors that refuse more.
MAX_STEPS_WHY = (
    "the most steps a stage may take: hours to days of computing, and a history of "
    "gigabytes; a longer run is several stages, on purpose (docs/models.md, "
    '"How long a run is")'
)


class ModelError(SpecError):
    """A model file that cannot be run: ``field: what is wrong`` (also a
    :exc:`penedge.SpecError`, hence a ``ValueError``). `field` is the path of the bad field in
    the file (``joint_properties.J1.friction``, ``stages[2].region``)."""

    def __init__(self, field: str, message: str) -> None:
        super().__init__(f"{field}: {message}")
        self.field = field
        self.kind = "model"


def _describe(value: Any) -> str:
    if isinstance(value, bool):
        return f"a boolean ({str(value).lower()})"
    if isinstance(value, str):
        return f"the text {value!r}"
    if isinstance(value, Mapping):
        return "a table"
    if isinstance(value, list | tuple):
        return f"a list of {len(value)}"
    return repr(value)


class Table:
    """One table of the model file, read field by field.

    Parameters
    ----------
    data : mapping
        The table's keys and values.
    path : str
        Its path in the file (``""`` for the top level), prefixed to every error.
    """

    def __init__(self, data: Any, path: str) -> None:
        if not isinstance(data, Mapping):
            raise ModelError(path or "model", f"must be a table, got {_describe(data)}")
        self.data = data
        self.path = path
        self.read: set[str] = set()

    def field(self, key: str) -> str:
        """The path of `key` in the file."""
        return f"{self.path}.{key}" if self.path else key

    def has(self, key: str) -> bool:
        """Whether `key` is given (and marks it read)."""
        self.read.add(key)
        return key in self.data

    def raw(self, key: str, default: Any = None) -> Any:
        """The value as given, or `default`."""
        self.read.add(key)
        return self.data.get(key, default)

    def need(self, key: str) -> Any:
        """The value of a required key."""
        self.read.add(key)
        if key not in self.data:
            raise self.missing(key)
        return self.data[key]

    def missing(self, key: str) -> ModelError:
        """The error of a required `key` that is not given (naming a key given instead
        that looks like a typo of it)."""
        close = difflib.get_close_matches(key, [str(k) for k in self.data if k not in self.read], 1)
        typo = f"; {close[0]!r} is given: a typo?" if close else ""
        return ModelError(self.field(key), f"missing (this field is required{typo})")

    def number(
        self,
        key: str,
        default: float | None = None,
        *,
        required: bool = False,
        above: float | None = None,
        at_least: float | None = None,
        below: float | None = None,
        at_most: float | None = None,
    ) -> float:
        """A finite number, within the bounds given (`above` / `below` strict)."""
        value = self.need(key) if required else self.raw(key, default)
        if value is None:
            raise self.missing(key)
        return check_number(self.field(key), value, above, at_least, below, at_most)

    def optional_number(self, key: str, **bounds: float) -> float | None:
        """A number when given, else None."""
        return self.number(key, **bounds) if self.has(key) else None

    def integer(
        self, key: str, default: int | None = None, *, minimum: int = 0, maximum: int = MAX_WHOLE
    ) -> int:
        """A whole number from `minimum` to `maximum` (by default 10^15: more steps or items
        than any run takes, and within what the engine's counters hold)."""
        value = self.raw(key, default)
        field = self.field(key)
        if value is None:
            raise self.missing(key)
        if isinstance(value, bool) or not isinstance(value, int):
            if isinstance(value, float) and value.is_integer():
                value = int(value)
            else:
                raise ModelError(field, f"must be a whole number, got {_describe(value)}")
        if value < minimum:
            raise ModelError(field, f"must be at least {minimum}, got {value}")
        if value > maximum:
            why = f" ({MAX_STEPS_WHY})" if maximum == MAX_STEPS else ""
            raise ModelError(field, f"must be at most {maximum:.0e}, got {value:.3g}{why}")
        return value

    def text(self, key: str, default: str | None = None, choices: Sequence[str] = ()) -> str:
        """A string, one of `choices` when given."""
        value = self.raw(key, default)
        field = self.field(key)
        if value is None:
            raise self.missing(key)
        if not isinstance(value, str):
            raise ModelError(field, f"must be a text, got {_describe(value)}")
        if choices and value not in choices:
            raise ModelError(
                field, f"unknown value {value!r}, expected one of {', '.join(choices)}"
            )
        return value

    def boolean(self, key: str, default: bool) -> bool:
        """True or false."""
        value = self.raw(key, default)
        if not isinstance(value, bool):
            raise ModelError(self.field(key), f"must be true or false, got {_describe(value)}")
        return value

    def vector(self, key: str, default: Sequence[float] | None = None) -> tuple[float, ...]:
        """Three finite numbers."""
        value = self.raw(key, default)
        if value is None:
            raise self.missing(key)
        return check_vector(self.field(key), value)

    def table(self, key: str) -> Table:
        """A sub-table (an empty one when absent)."""
        return Table(self.raw(key, {}), self.field(key))

    def tables(self, key: str) -> list[Table]:
        """A list of tables (``[[key]]``), empty when absent."""
        value = self.raw(key, [])
        field = self.field(key)
        if not isinstance(value, list):
            raise ModelError(field, f"must be a list of tables ([[{key}]]), got {_describe(value)}")
        return [Table(item, f"{field}[{i}]") for i, item in enumerate(value)]

    def done(self, also: Sequence[str] = ()) -> None:
        """Refuses the keys that were not read (a typo, or a field this table does not
        take), naming the ones it does take."""
        for key in self.data:
            if key not in self.read and key not in also:
                known = ", ".join(sorted(self.read | set(also)))
                hint = f"; this table takes {known}" if known else ""
                raise ModelError(self.field(str(key)), f"unknown field{hint}")


def check_number(
    field: str,
    value: Any,
    above: float | None = None,
    at_least: float | None = None,
    below: float | None = None,
    at_most: float | None = None,
) -> float:
    """`value` as a finite float within the bounds, or a :exc:`ModelError` naming `field`."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ModelError(field, f"must be a number, got {_describe(value)}")
    try:
        value = float(value)
    except OverflowError:
        # A whole number of hundreds of digits: beyond any float.
        raise ModelError(field, "must be a finite number, got a number too large") from None
    if not math.isfinite(value):
        raise ModelError(field, f"must be a finite number, got {value}")
    if above is not None and not value > above:
        raise ModelError(field, f"must be greater than {above:g}, got {value:g}")
    if at_least is not None and not value >= at_least:
        raise ModelError(field, f"must be at least {at_least:g}, got {value:g}")
    if below is not None and not value < below:
        raise ModelError(field, f"must be less than {below:g}, got {value:g}")
    if at_most is not None and not value <= at_most:
        raise ModelError(field, f"must be at most {at_most:g}, got {value:g}")
    return value


@dataclass(frozen=True)
class Range:
    """The values a field takes beyond its sign: `low` to `high` `unit` (the magnitude
    with `magnitude`), for the fields whose products the engine computes (masses, forces,
    the critical time step; docs/models.md, "Ranges"). `why` says what the bounds are
    (physically generous: a value outside is a unit or an exponent typed wrong)."""

    low: float
    high: float
    unit: str
    why: str

    def check(self, field: str, value: float, magnitude: bool = False, what: str = "") -> float:
        """`value` (a finite float), or a :exc:`ModelError` naming `field` and the range;
        `what` starts the message (the value's name when it is not the field's own)."""
        size = abs(value) if magnitude else value
        if not self.low <= size <= self.high:
            what = what or ("its magnitude " if magnitude else "")
            span = (
                f"at most {self.high:g} {self.unit}"
                if self.low == 0
                else f"{self.low:g} to {self.high:g} {self.unit}"
            )
            raise ModelError(
                field,
                f"{what}{size:g} {self.unit} is outside the range a model takes, {span} "
                f"({self.why}): a unit or an exponent typed wrong?",
            )
        return value


def check_vector(field: str, value: Any) -> tuple[float, float, float]:
    """Three finite numbers ``[x, y, z]``."""
    if not isinstance(value, list | tuple) or len(value) != 3:
        raise ModelError(field, f"must be three numbers [x, y, z], got {_describe(value)}")
    x, y, z = (check_number(f"{field}[{i}]", v) for i, v in enumerate(value))
    return (x, y, z)


def check_direction(field: str, value: Any) -> tuple[float, float, float]:
    """A non-zero vector, returned as a unit vector."""
    x, y, z = check_vector(field, value)
    norm = math.sqrt(x * x + y * y + z * z)
    if not norm > 0:
        raise ModelError(field, "must be a non-zero vector")
    return (x / norm, y / norm, z / norm)


def point_text(point: Any) -> str:
    """``(20, 5, 5)``: a point for a message."""
    return "(" + ", ".join(f"{float(v):.6g}" for v in point) + ")"
