"""The model file's sections as typed dataclasses, and their parsing from the dict that TOML
gives (every field, its unit and its default: docs/models.md).

Parsing here needs no blocks: it checks types, units, ranges, and that every name a field
refers to (a joint set, a region, a monitor) exists. The checks that need the blocks (a
region that selects no block, a bolt outside the rock) are in :mod:`penedge.model.check`.
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass, field
from typing import Any

from penedge.model.fields import (
    MAX_STEPS,
    ModelError,
    Range,
    Table,
    check_direction,
    check_vector,
)

#: The generation spec's tables, passed unchanged to :func:`penedge.generate` (excavations
#: make concave blocks: docs/models.md, "Concave blocks").
SPEC_TABLES = ("domain", "joints", "excavations", "options")

#: Joint property fields: unit, and whether the default table must give it.
PROPERTY_FIELDS = {
    "kn": "Pa/m",
    "ks": "Pa/m",
    "friction": "degrees",
    "cohesion": "Pa",
    "tension": "Pa",
    "residual_friction": "degrees",
    "residual_cohesion": "Pa",
    "residual_tension": "Pa",
}

#: Domain faces by name: the outward direction they face.
FACE_DIRECTIONS = {
    "bottom": (0.0, 0.0, -1.0),
    "top": (0.0, 0.0, 1.0),
    "west": (-1.0, 0.0, 0.0),
    "east": (1.0, 0.0, 0.0),
    "south": (0.0, -1.0, 0.0),
    "north": (0.0, 1.0, 0.0),
}

STANDARD_GRAVITY = 9.81

#: A factor of safety's finest `tolerance`, relative to its `high`: 1e-5 with the default
#: high = 10 (a bisection of at most about 20 trials), far below what a trial's verdict
#: resolves, far above the floats' spacing (docs/models.md, "Factor of safety").
MIN_RELATIVE_TOLERANCE = 1e-6

# The ranges of the fields whose products the engine computes (masses, weights, contact and
# bolt forces, pressures times areas, the critical time step): wide enough for any rock,
# soil or laboratory model, and far inside what double precision holds, so that a unit or
# an exponent typed wrong (`density = 1e300`, which ran to a NaN ratio and infinite
# displacements with exit status 0) is an error naming its field. docs/models.md, "Ranges".

#: rock.density, water.density, initial_stress.density.
DENSITY = Range(1.0, 1e5, "kg/m³", "air is 1.2 kg/m³; osmium, the densest element, 22,590")
#: kn and ks of joints and rock bridges.
STIFFNESS = Range(
    1e3,
    1e15,
    "Pa/m",
    "1e3 is a thousandth of a loose sand's subgrade modulus; 1e15 ten times intact rock "
    "(E = 100 GPa) over a millimetre",
)
#: The magnitude of mechanics.gravity.
GRAVITY = Range(0.0, 1e4, "m/s²", "1000 g; a geotechnical centrifuge spins at a few hundred g")
#: Pressures and stresses: support, water per set, uniform initial stress, overburden.
STRESS = Range(
    0.0, 1e10, "Pa", "10 GPa: 25 times the strength of the strongest rock, the stress 300 km deep"
)
#: A bolt's axial and dowel stiffness.
BOLT_STIFFNESS = Range(
    0.0, 1e12, "N/m", "EA / length of a steel bar of 1 m² section and 0.2 m length"
)
#: The magnitude of a boundary velocity.
VELOCITY = Range(0.0, 1e3, "m/s", "ten times a rock avalanche's speed")


def attitude_normal(dip: float, dip_direction: float) -> tuple[float, float, float]:
    """The upward unit normal of a plane with `dip` and `dip_direction` (degrees), as in
    docs/generation.md: ``(sin d sin a, sin d cos a, cos d)``."""
    d, a = math.radians(dip), math.radians(dip_direction)
    return (math.sin(d) * math.sin(a), math.sin(d) * math.cos(a), math.cos(d))


@dataclass(frozen=True)
class JointProperties:
    """Mohr-Coulomb joint properties (SI; angles in degrees)."""

    kn: float
    ks: float
    friction: float
    cohesion: float = 0.0
    tension: float = 0.0
    residual_friction: float | None = None  # None: the friction angle
    residual_cohesion: float = 0.0
    residual_tension: float = 0.0

    def reduced(self, factor: float) -> JointProperties:
        """The strength divided by `factor` (strength reduction): tan(friction), cohesion
        and tension, and the residual values likewise; stiffnesses unchanged."""

        def angle(phi: float) -> float:
            return math.degrees(math.atan(math.tan(math.radians(phi)) / factor))

        residual = self.friction if self.residual_friction is None else self.residual_friction
        return JointProperties(
            kn=self.kn,
            ks=self.ks,
            friction=angle(self.friction),
            cohesion=self.cohesion / factor,
            tension=self.tension / factor,
            residual_friction=angle(residual),
            residual_cohesion=self.residual_cohesion / factor,
            residual_tension=self.residual_tension / factor,
        )


@dataclass(frozen=True)
class Mechanics:
    """``[mechanics]`` and ``[rock]``: what every step uses."""

    density: float  # kg/m^3
    gravity: tuple[float, float, float] = (0.0, 0.0, -STANDARD_GRAVITY)  # m/s^2
    damping: float = 0.8  # local (non-viscous) damping coefficient
    time_step: float | None = None  # s; None: automatic
    ratio: float = 1e-5  # equilibrium: maximum unbalanced-force ratio
    max_steps: int = 100_000  # step budget of a `solve`
    gap: float = 1e-3  # relative contact gap of the detection
    point_width: float = 0.2  # width of point and edge contacts / the smaller body's diameter
    mass_scaling: bool = False  # scale the inertia of bodies with a small critical step


@dataclass(frozen=True)
class Plane:
    """A plane through `point` with unit `normal` (upward: its z is >= 0)."""

    point: tuple[float, float, float]
    normal: tuple[float, float, float]

    def height(self, points: Any) -> Any:
        """Signed distance of `points` above the plane (along the upward normal)."""
        import numpy as np

        return (np.asarray(points, dtype=float) - self.point) @ np.asarray(self.normal)


@dataclass(frozen=True)
class InitialStress:
    """``[initial_stress]``: installed before the first stage (compression negative)."""

    kind: str  # "overburden" or "uniform"
    surface: float | None = None  # overburden: z of the ground surface (m); None: domain top
    density: float | None = None  # overburden: kg/m^3; None: the rock's
    k0: tuple[float, float] = (1.0, 1.0)  # overburden: horizontal / vertical (x, y)
    components: tuple[float, ...] = (0.0,) * 6  # uniform: xx, yy, zz, xy, yz, zx (Pa)


@dataclass(frozen=True)
class Water:
    """``[water]``: pressure in the joints, from a phreatic surface and/or per set."""

    density: float = 1000.0  # kg/m^3
    phreatic: Plane | None = None
    pressures: dict[str, float] = field(default_factory=dict)  # set name -> Pa

    def pressure_at(self, points: Any, gravity: float) -> Any:
        """Hydrostatic pressure (Pa) below the phreatic surface at `points`, zero above."""
        import numpy as np

        if self.phreatic is None:
            return np.zeros(len(points))
        # depth below the surface measured vertically: height above the plane / n_z
        depth = -self.phreatic.height(points) / self.phreatic.normal[2]
        return self.density * gravity * np.maximum(depth, 0.0)


@dataclass(frozen=True)
class Bolt:
    """``[[bolts]]``: a fully grouted bolt from `point` along `direction` for `length`."""

    name: str
    point: tuple[float, float, float]  # collar (m)
    direction: tuple[float, float, float]  # unit vector, into the rock
    length: float  # m
    capacity: float  # N, axial capacity (it yields at it)
    stiffness: float  # N/m, axial, of the whole length (EA / length)
    rupture_strain: float | None = None  # axial strain at which it breaks; None: never
    shear_stiffness: float | None = None  # N/m, dowel at each joint crossed; None: axial only
    shear_capacity: float | None = None  # N, the dowel's capacity (with shear_stiffness)

    @property
    def end(self) -> tuple[float, float, float]:
        """The far end of the bolt."""
        p, d = self.point, self.direction
        return (
            p[0] + self.length * d[0],
            p[1] + self.length * d[1],
            p[2] + self.length * d[2],
        )


@dataclass(frozen=True)
class Region:
    """A selection of blocks (``[regions.NAME]``, or inline ``region = {...}``)."""

    name: str
    kind: str  # all, box, below, above, face, point, blocks
    min: tuple[float, float, float] | None = None
    max: tuple[float, float, float] | None = None
    plane: Plane | None = None
    face: str | int | None = None
    part: int = 0
    point: tuple[float, float, float] | None = None
    blocks: tuple[int, ...] = ()


@dataclass(frozen=True)
class Support:
    """``[[support]]``: a pressure on the free faces of the blocks of a region."""

    name: str
    region: str
    pressure: float  # Pa, pushing into the rock
    face: str | int | None = None  # limit to a domain face, or an excavation's walls


@dataclass(frozen=True)
class Seismic:
    """``[seismic]``: pseudo-static body force kh·g horizontal (and kv·g vertical)."""

    coefficient: float  # kh, fraction of g
    azimuth: float  # degrees clockwise from North: where the force pushes
    vertical: float = 0.0  # kv, fraction of g, upward positive


@dataclass(frozen=True)
class Boundary:
    """``[[boundary]]``: a condition on the blocks of a region, applied in order."""

    region: str
    condition: str  # fixed, free, velocity
    velocity: tuple[float, float, float] | None = None  # m/s


@dataclass(frozen=True)
class Monitor:
    """``[[monitors]]``: a block whose displacement and velocity are recorded."""

    name: str
    point: tuple[float, float, float] | None = None
    block: int | None = None


@dataclass(frozen=True)
class Stage:
    """One ``[[stages]]`` entry. `kind` picks which fields are meaningful."""

    name: str
    kind: str  # solve, cycle, time, properties, excavate, boundary, reset, save,
    # factor_of_safety
    ratio: float | None = None  # solve, factor_of_safety
    max_steps: int | None = None  # solve, factor_of_safety
    steps: int | None = None  # cycle
    time: float | None = None  # time
    sets: tuple[str, ...] = ()  # properties, factor_of_safety (empty: every set)
    changes: dict[str, float] = field(default_factory=dict)  # properties
    region: str | None = None  # excavate
    relax_steps: int = 100  # excavate
    file: str | None = None  # save: the restart file (relative: in the results folder)
    boundary: Boundary | None = None  # boundary
    velocity: float = 1e-4  # factor_of_safety: m/s, still moving above this
    # factor_of_safety: m, a trial fails when a free block moved farther (None: 1 % of each
    # block's size, the cube root of its body's volume)
    displacement: float | None = None
    tolerance: float = 0.01  # factor_of_safety
    low: float = 0.1  # factor_of_safety: search range
    high: float = 10.0
    elastic: bool = False  # solve: bonds (cohesion, tension) unbreakable during the stage
    # cycle, time: the local damping of the stage (time: 0 by default, the motion physical;
    # cycle: [mechanics] damping by default)
    damping: float | None = None


@dataclass(frozen=True)
class Results:
    """``[results]``: what is recorded."""

    history_every: int = 10  # steps between history points
    frame_every: int = 0  # steps between ParaView frames (0: the end of each stage only)
    moved: float = 1e-3  # m: a block moved when its displacement exceeds this
    moving: float = 1e-4  # m/s: a block is moving when its speed exceeds this


@dataclass
class Model:
    """A whole model file, parsed and checked (but not yet the checks that need blocks)."""

    spec: dict[str, Any]
    set_names: list[str]
    mechanics: Mechanics
    default_properties: JointProperties
    properties: dict[str, JointProperties]  # every set name -> its properties
    regions: dict[str, Region]
    boundary: list[Boundary]
    monitors: list[Monitor]
    stages: list[Stage]
    results: Results = field(default_factory=Results)
    initial_stress: InitialStress | None = None
    water: Water | None = None
    bolts: list[Bolt] = field(default_factory=list)
    support: list[Support] = field(default_factory=list)
    seismic: Seismic | None = None
    title: str = ""
    #: Rock-bridge properties per joint set name (the sets generated with bridge = true).
    bridges: dict[str, JointProperties] = field(default_factory=dict)

    @property
    def gravity(self) -> tuple[float, float, float]:
        """The body force per unit mass (m/s^2): gravity plus the pseudo-static seismic
        acceleration."""
        g = self.mechanics.gravity
        if self.seismic is None:
            return g
        size = math.sqrt(g[0] ** 2 + g[1] ** 2 + g[2] ** 2)
        s = self.seismic
        a = math.radians(s.azimuth)
        h = s.coefficient * size
        return (
            g[0] + h * math.sin(a),
            g[1] + h * math.cos(a),
            g[2] + s.vertical * size,
        )


# --- parsing ------------------------------------------------------------------------


def parse(data: Any) -> Model:
    """A :class:`Model` from the dict of a model file."""
    top = Table(data, "")
    spec = {key: top.raw(key) for key in SPEC_TABLES if top.has(key)}
    if "domain" not in spec:
        raise ModelError("domain", "missing (this table is required)")
    title = top.text("title", "")
    set_names = joint_names(spec.get("joints", []))
    mechanics = parse_mechanics(top.table("rock"), top.table("mechanics"))
    properties_table = top.table("joint_properties")
    default, properties = parse_properties(properties_table, set_names)
    bridges = parse_bridges(properties_table, spec.get("joints", []), set_names, properties)
    regions = parse_regions(top.table("regions"))
    model = Model(
        spec=spec,
        set_names=set_names,
        mechanics=mechanics,
        default_properties=default,
        properties=properties,
        regions=regions,
        boundary=[parse_boundary(t, regions) for t in top.tables("boundary")],
        monitors=parse_monitors(top.tables("monitors")),
        stages=[],
        results=parse_results(top.table("results")) if top.has("results") else Results(),
        title=title,
        bridges=bridges,
    )
    if top.has("initial_stress"):
        model.initial_stress = parse_initial_stress(top.table("initial_stress"))
    if top.has("water"):
        model.water = parse_water(top.table("water"), set_names)
    model.bolts = parse_bolts(top.tables("bolts"))
    model.support = [parse_support(t, regions) for t in top.tables("support")]
    if top.has("seismic"):
        model.seismic = parse_seismic(top.table("seismic"))
    model.stages = parse_stages(
        top.tables("stages"), set_names, regions, mechanics, model.results.moving
    )
    top.done()
    return model


def joint_names(joints: Any) -> list[str]:
    """The name of each spec entry (``joints[i]`` when it has none), as generation names
    them; the keys of ``[joint_properties]`` and ``[water.pressure]``."""
    if not isinstance(joints, list):
        return []  # generation names the error
    names = []
    for i, joint in enumerate(joints):
        name = joint.get("name") if isinstance(joint, dict) else None
        names.append(name if isinstance(name, str) else f"joints[{i}]")
    seen: dict[str, int] = {}
    for i, name in enumerate(names):
        if name in seen:
            raise ModelError(
                f"joints[{i}].name",
                f"{name!r} is also the name of joints[{seen[name]}]; joint properties "
                "and water pressures refer to sets by name, so names must differ",
            )
        if name == "default":
            raise ModelError(
                f"joints[{i}].name", "'default' names the default joint properties; rename it"
            )
        seen[name] = i
    return names


def parse_mechanics(rock: Table, t: Table) -> Mechanics:
    density = DENSITY.check(rock.field("density"), rock.number("density", required=True, above=0))
    rock.done()
    gravity = t.vector("gravity", (0.0, 0.0, -STANDARD_GRAVITY))
    GRAVITY.check(t.field("gravity"), math.hypot(*gravity))
    time_step = t.optional_number("time_step", above=0)
    mechanics = Mechanics(
        density=density,
        gravity=(gravity[0], gravity[1], gravity[2]),
        damping=t.number("damping", 0.8, at_least=0, below=1),
        time_step=time_step,
        ratio=t.number("ratio", 1e-5, above=0, below=1),
        max_steps=t.integer("max_steps", 100_000, minimum=1, maximum=MAX_STEPS),
        gap=t.number("gap", 1e-3, above=0, below=0.01),
        point_width=t.number("point_width", 0.2, above=0, at_most=1),
        mass_scaling=t.boolean("mass_scaling", False),
    )
    t.done()
    return mechanics


def parse_property_values(
    t: Table, base: JointProperties | None, also: tuple[str, ...] = ()
) -> dict[str, float]:
    """The property fields given in `t` (all of kn, ks, friction when `base` is None); the
    keys `also` are left to the caller."""
    values: dict[str, float] = {}
    for key in PROPERTY_FIELDS:
        if key in ("kn", "ks"):
            bounds: dict[str, float] = {"above": 0}
        elif key in ("friction", "residual_friction"):
            bounds = {"at_least": 0, "below": 90}
        else:
            bounds = {"at_least": 0}
        required = base is None and key in ("kn", "ks", "friction")
        if required or t.has(key):
            values[key] = t.number(key, required=True, **bounds)
            if key in ("kn", "ks"):
                STIFFNESS.check(t.field(key), values[key])
    t.done(also)
    return values


def merge(base: JointProperties, values: dict[str, float]) -> JointProperties:
    """`base` with `values` replacing its fields."""
    fields = {**base.__dict__, **values}
    return JointProperties(**fields)


def parse_properties(
    t: Table, set_names: list[str]
) -> tuple[JointProperties, dict[str, JointProperties]]:
    if not t.has("default"):
        raise ModelError(
            t.field("default"), "missing: give at least kn, ks and friction for every joint"
        )
    default = JointProperties(**parse_property_values(t.table("default"), None, ("bridge",)))
    properties = {}
    for name in set_names:
        if t.has(name):
            values = parse_property_values(t.table(name), default, ("bridge",))
            properties[name] = merge(default, values)
        else:
            properties[name] = default
    for key in t.data:
        if key not in t.read:
            raise ModelError(t.field(str(key)), unknown_set(str(key), set_names))
    return default, properties


#: Rock-bridge fields: the intact rock's strength must be given; kn and ks default to the
#: set's joint stiffness, the residual cohesion to 0 (a brittle bridge).
BRIDGE_FIELDS = ("kn", "ks", "friction", "cohesion", "tension", "residual_cohesion")

#: The bridge fields that may be left out.
OPTIONAL_BRIDGE_FIELDS = ("kn", "ks", "residual_cohesion")


def parse_bridge_values(t: Table) -> dict[str, float]:
    """The fields of a ``bridge`` table (friction, cohesion and tension required)."""
    values: dict[str, float] = {}
    for key in BRIDGE_FIELDS:
        if key in ("kn", "ks"):
            bounds: dict[str, float] = {"above": 0}
        elif key == "friction":
            bounds = {"at_least": 0, "below": 90}
        else:
            bounds = {"at_least": 0}
        if key not in OPTIONAL_BRIDGE_FIELDS or t.has(key):
            values[key] = t.number(key, required=True, **bounds)
            if key in ("kn", "ks"):
                STIFFNESS.check(t.field(key), values[key])
    if values.get("residual_cohesion", 0.0) > values["cohesion"]:
        raise ModelError(
            t.field("residual_cohesion"),
            f"{values['residual_cohesion']} is above the cohesion ({values['cohesion']}): "
            "a bridge loses strength when it breaks, it gains none",
        )
    t.done()
    return values


def parse_bridges(
    t: Table, joints: Any, set_names: list[str], properties: dict[str, JointProperties]
) -> dict[str, JointProperties]:
    """``[joint_properties.<set>.bridge]`` (else ``[joint_properties.default.bridge]``) for
    each joint generated with ``bridge = true``: the intact rock's properties of its rock
    bridges (docs/models.md, "Rock bridges"); kn and ks default to the set's joints'."""
    entries = joints if isinstance(joints, list) else []
    bridged = {
        name
        for name, j in zip(set_names, entries, strict=False)
        if isinstance(j, dict) and j.get("bridge") is True
    }

    def bridge_table(key: str) -> Table | None:
        owner = Table(t.data.get(key, {}), t.field(key))
        return owner.table("bridge") if owner.has("bridge") else None

    default_table = bridge_table("default")
    default_values = parse_bridge_values(default_table) if default_table is not None else None
    bridges = {}
    for i, name in enumerate(set_names):
        own = bridge_table(name)
        if own is not None and name not in bridged:
            raise ModelError(
                own.path, f"joints[{i}] ({name!r}) has no rock bridges: give it bridge = true"
            )
        values = parse_bridge_values(own) if own is not None else default_values
        if name in bridged and values is None:
            raise ModelError(
                t.field(f"{name}.bridge"),
                f"missing: joints[{i}] has bridge = true; give the intact rock's friction, "
                "cohesion and tension here or in [joint_properties.default.bridge]",
            )
        if values is not None and name in bridged:
            joint = properties[name]
            bridges[name] = JointProperties(**{"kn": joint.kn, "ks": joint.ks, **values})
    return bridges


def unknown_set(name: str, set_names: list[str]) -> str:
    """The message for a reference to a joint set that does not exist."""
    known = ", ".join(set_names) if set_names else "none: the model has no [[joints]]"
    return f"no joint set is named {name!r} (the sets are: {known})"


def parse_plane(t: Table, horizontal_key: str) -> Plane:
    """A plane from `horizontal_key` (an elevation: a horizontal plane), or `point` with
    `normal` or `dip` + `dip_direction`."""
    if t.has(horizontal_key):
        z = t.number(horizontal_key, required=True)
        for key in ("point", "normal", "dip", "dip_direction"):
            if t.has(key):
                raise ModelError(
                    t.field(key), f"give either {horizontal_key} or a point and an orientation"
                )
        return Plane((0.0, 0.0, z), (0.0, 0.0, 1.0))
    point = t.vector("point")
    if t.has("normal"):
        if t.has("dip") or t.has("dip_direction"):
            raise ModelError(t.field("normal"), "give either normal or dip + dip_direction")
        normal = check_direction(t.field("normal"), t.raw("normal"))
    else:
        dip = t.number("dip", required=True, at_least=0, at_most=90)
        normal = attitude_normal(dip, t.number("dip_direction", required=True))
    if normal[2] < 0:
        normal = (-normal[0], -normal[1], -normal[2])
    return Plane(point, normal)


REGION_KINDS = ("all", "box", "below", "above", "face", "point", "blocks")


def parse_face(t: Table, key: str) -> str | int:
    """A domain face: a name (``bottom``, ``east``, ...) or an index into the domain's
    faces."""
    value = t.raw(key)
    if isinstance(value, str):
        return t.text(key, choices=tuple(FACE_DIRECTIONS))
    if value is None:
        raise t.missing(key)
    return t.integer(key)


def parse_region(t: Table, name: str) -> Region:
    kind = t.text("type", choices=REGION_KINDS)
    region = Region(name=name, kind=kind)
    if kind == "box":
        lo, hi = t.vector("min"), t.vector("max")
        if any(h <= lo_ for lo_, h in zip(lo, hi, strict=True)):
            raise ModelError(t.field("max"), "must be greater than min in every coordinate")
        region = Region(name, kind, min=(lo[0], lo[1], lo[2]), max=(hi[0], hi[1], hi[2]))
    elif kind in ("below", "above"):
        region = Region(name, kind, plane=parse_plane(t, "z"))
    elif kind == "face":
        region = Region(name, kind, face=parse_face(t, "face"), part=t.integer("part", 0))
    elif kind == "point":
        p = t.vector("point")
        region = Region(name, kind, point=(p[0], p[1], p[2]))
    elif kind == "blocks":
        ids = t.raw("ids")
        if not isinstance(ids, list) or not ids:
            raise ModelError(t.field("ids"), "must be a non-empty list of block ids")
        for i, v in enumerate(ids):
            if isinstance(v, bool) or not isinstance(v, int) or v < 0:
                raise ModelError(f"{t.field('ids')}[{i}]", f"must be a block id >= 0, got {v!r}")
        region = Region(name, kind, blocks=tuple(ids))
    t.done()
    return region


def parse_regions(t: Table) -> dict[str, Region]:
    """``[regions]``: any name TOML takes (``zone.1`` quoted: ``[regions."zone.1"]``) but an
    empty one or one with ``[`` or ``]``, which are kept for the inline regions (named by
    their place in the file: ``boundary[0].region``, see :func:`region_ref`)."""
    for name in t.data:
        if not str(name).strip() or "[" in str(name) or "]" in str(name):
            raise ModelError(
                t.field(str(name)),
                "a region name must not be empty nor hold [ or ] (an inline region is named "
                "by its place in the file, as boundary[0].region)",
            )
    regions = {str(name): parse_region(t.table(str(name)), str(name)) for name in list(t.data)}
    t.done()
    return regions


def named_regions(regions: dict[str, Region]) -> list[str]:
    """The names from ``[regions]`` in `regions` (which also holds the inline regions read
    so far, under their paths: ``boundary[0].region``)."""
    return [name for name in regions if "[" not in name]


def region_ref(t: Table, key: str, regions: dict[str, Region], required: bool = True) -> str:
    """The name of the region a field refers to: a name from ``[regions]``, or an inline
    table (added to `regions` under the field's path)."""
    value = t.raw(key)
    field_path = t.field(key)
    if value is None:
        if required:
            raise t.missing(key)
        return ""
    if isinstance(value, str):
        named = named_regions(regions)
        if value not in named:
            known = ", ".join(named) if named else "none: the model has no [regions]"
            raise ModelError(field_path, f"no region is named {value!r} (the regions are: {known})")
        return value
    region = parse_region(Table(value, field_path), field_path)
    regions[field_path] = region
    return field_path


def parse_boundary(t: Table, regions: dict[str, Region]) -> Boundary:
    region = region_ref(t, "region", regions)
    condition = t.text("condition", choices=("fixed", "free", "velocity"))
    velocity = None
    if condition == "velocity":
        v = t.vector("velocity")
        VELOCITY.check(t.field("velocity"), math.hypot(*v))
        velocity = (v[0], v[1], v[2])
    elif t.has("velocity"):
        raise ModelError(
            t.field("velocity"), f'only with condition = "velocity", not {condition!r}'
        )
    t.done()
    return Boundary(region, condition, velocity)


def parse_monitors(tables: list[Table]) -> list[Monitor]:
    monitors = []
    names: set[str] = set()
    for i, t in enumerate(tables):
        name = t.text("name", f"monitors[{i}]")
        if name in names:
            raise ModelError(t.field("name"), f"{name!r} names another monitor too")
        names.add(name)
        if t.has("point") == t.has("block"):
            raise ModelError(t.path, "give either point (the block containing it) or block (an id)")
        if t.has("point"):
            p = t.vector("point")
            monitors.append(Monitor(name, point=(p[0], p[1], p[2])))
        else:
            monitors.append(Monitor(name, block=t.integer("block")))
        t.done()
    return monitors


def parse_results(t: Table) -> Results:
    results = Results(
        history_every=t.integer("history_every", 10, minimum=1),
        frame_every=t.integer("frame_every", 0),
        moved=t.number("moved", 1e-3, above=0),
        moving=t.number("moving", 1e-4, above=0),
    )
    t.done()
    return results


def parse_initial_stress(t: Table) -> InitialStress:
    kind = t.text("type", choices=("overburden", "uniform"))
    if kind == "overburden":
        k0 = t.number("k0", 1.0, at_least=0) if t.has("k0") else None
        kx = t.optional_number("k0_x", at_least=0)
        ky = t.optional_number("k0_y", at_least=0)
        if k0 is not None and (kx is not None or ky is not None):
            raise ModelError(t.field("k0"), "give either k0 or k0_x and k0_y")
        base = 1.0 if k0 is None else k0
        stress = InitialStress(
            kind,
            surface=t.optional_number("surface"),
            density=optional_density(t),
            k0=(base if kx is None else kx, base if ky is None else ky),
        )
    else:
        keys = ("xx", "yy", "zz", "xy", "yz", "zx")
        components = tuple(STRESS.check(t.field(k), t.number(k, 0.0), True) for k in keys)
        stress = InitialStress(kind, components=components)
    t.done()
    return stress


def optional_density(t: Table) -> float | None:
    """The table's ``density`` (kg/m³) when given."""
    if not t.has("density"):
        return None
    return DENSITY.check(t.field("density"), t.number("density", required=True, above=0))


PHREATIC_FORMS = (
    "a table: {elevation = Z} (a horizontal water table), "
    "{point = [x, y, z], dip = D, dip_direction = A} (an inclined plane, dip < 90), "
    "or {points = [[x, y, z], [x, y, z], [x, y, z]]} (the plane through three points)"
)


def parse_phreatic(value: Any, path: str) -> Plane:
    """A phreatic surface: a non-vertical plane, in one of the forms of
    :data:`PHREATIC_FORMS`."""
    import numpy as np

    if not isinstance(value, dict):
        raise ModelError(path, f"must be {PHREATIC_FORMS}")
    t = Table(value, path)
    forms = [k for k in ("elevation", "points", "point") if k in value]
    if len(forms) != 1:
        found = " and ".join(forms) if forms else "none of elevation, point, points"
        raise ModelError(path, f"found {found}; it must be {PHREATIC_FORMS}")
    if forms[0] == "points":
        points = t.raw("points")
        if not isinstance(points, list) or len(points) != 3:
            raise ModelError(t.field("points"), "must be three points [[x, y, z], ...]")
        p = np.array([check_vector(f"{t.field('points')}[{i}]", q) for i, q in enumerate(points)])
        n = np.cross(p[1] - p[0], p[2] - p[0])
        scale = max(float(np.ptp(p, axis=0).max()), 1e-300)
        if np.linalg.norm(n) <= 1e-9 * scale**2:
            raise ModelError(t.field("points"), "the three points are on one line: no plane")
        n = n / np.linalg.norm(n)
        plane = Plane(tuple(p[0]), tuple(n if n[2] >= 0 else -n))  # type: ignore[arg-type]
    else:
        plane = parse_plane(t, "elevation")
    t.done()
    if plane.normal[2] < 1e-6:
        raise ModelError(path, "a phreatic surface cannot be vertical (dip must be below 90)")
    return plane


def parse_water(t: Table, set_names: list[str]) -> Water:
    density = DENSITY.check(t.field("density"), t.number("density", 1000.0, above=0))
    phreatic = parse_phreatic(t.raw("phreatic"), t.field("phreatic")) if t.has("phreatic") else None
    pressures: dict[str, float] = {}
    if t.has("pressure"):
        p = t.table("pressure")
        for name in list(p.data):
            if name not in set_names:
                raise ModelError(p.field(str(name)), unknown_set(str(name), set_names))
            value = p.number(str(name), required=True, at_least=0)
            pressures[str(name)] = STRESS.check(p.field(str(name)), value)
    if phreatic is None and not pressures:
        raise ModelError(
            t.path,
            "give a phreatic surface ([water.phreatic]) or pressures per set ([water.pressure])",
        )
    t.done()
    return Water(density, phreatic, pressures)


def parse_bolts(tables: list[Table]) -> list[Bolt]:
    bolts = []
    for i, t in enumerate(tables):
        point = t.vector("point")
        if t.has("direction"):
            for key in ("trend", "plunge"):
                if t.has(key):
                    raise ModelError(t.field(key), "give either direction or trend + plunge")
            direction = check_direction(t.field("direction"), t.raw("direction"))
        else:
            # trend: azimuth clockwise from North; plunge: degrees below the horizontal
            trend = t.number("trend", required=True)
            plunge = t.number("plunge", required=True, at_least=-90, at_most=90)
            tr, pl = math.radians(trend), math.radians(plunge)
            direction = (math.cos(pl) * math.sin(tr), math.cos(pl) * math.cos(tr), -math.sin(pl))
        bolts.append(
            Bolt(
                name=t.text("name", f"bolts[{i}]"),
                point=(point[0], point[1], point[2]),
                direction=direction,
                length=t.number("length", required=True, above=0),
                capacity=t.number("capacity", required=True, above=0),
                stiffness=BOLT_STIFFNESS.check(
                    t.field("stiffness"), t.number("stiffness", required=True, above=0)
                ),
                rupture_strain=rupture_strain(t),
                **parse_dowel(t),
            )
        )
        t.done()
    return bolts


def rupture_strain(t: Table) -> float | None:
    """A bolt's ``rupture_strain``, above 0 and below 1: a strain of 1 doubles the bolt's
    length, which no bolt survives (a percent typed: 5 for 5 %; one above 0.2 is warned
    of, penedge.model.run.input_warnings)."""
    strain = t.optional_number("rupture_strain", above=0)
    if strain is not None and strain >= 1:
        raise ModelError(
            t.field("rupture_strain"),
            f"must be below 1 (a strain: 0.05 is 5 %), got {strain:g}: a strain of {strain:g} "
            f"stretches the bolt to {1 + strain:g} times its length; a percent typed?",
        )
    return strain


def parse_dowel(t: Table) -> dict[str, float | None]:
    """A bolt's optional dowel: ``shear_stiffness`` and ``shear_capacity``, both or neither."""
    stiffness = t.optional_number("shear_stiffness", above=0)
    if stiffness is not None:
        BOLT_STIFFNESS.check(t.field("shear_stiffness"), stiffness)
    capacity = t.optional_number("shear_capacity", above=0)
    if (stiffness is None) != (capacity is None):
        missing = "shear_capacity" if capacity is None else "shear_stiffness"
        raise ModelError(t.field(missing), "a dowel needs both shear_stiffness and shear_capacity")
    return {"shear_stiffness": stiffness, "shear_capacity": capacity}


def parse_support(t: Table, regions: dict[str, Region]) -> Support:
    index = t.path
    support = Support(
        name=t.text("name", index),
        region=region_ref(t, "region", regions),
        pressure=STRESS.check(t.field("pressure"), t.number("pressure", required=True, above=0)),
        face=parse_support_face(t) if t.has("face") else None,
    )
    t.done()
    return support


def parse_support_face(t: Table) -> str | int:
    """A support's ``face``: a domain face (a name or an index) or an excavation (its name,
    or ``excavations[i]``), resolved with the blocks (check.support_faces)."""
    if isinstance(t.raw("face"), str):
        return t.text("face")
    return parse_face(t, "face")


def parse_seismic(t: Table) -> Seismic:
    seismic = Seismic(
        coefficient=t.number("coefficient", required=True, at_least=0, below=1),
        azimuth=t.number("azimuth", required=True),
        vertical=t.number("vertical", 0.0, above=-1, below=1),
    )
    t.done()
    return seismic


STAGE_KINDS = (
    "solve",
    "cycle",
    "time",
    "properties",
    "excavate",
    "boundary",
    "reset",
    "save",
    "factor_of_safety",
)


def stage_sets(t: Table, set_names: list[str]) -> tuple[str, ...]:
    """``sets = [...]``: names of joint sets (empty: every set)."""
    if not t.has("sets"):
        return ()
    value = t.raw("sets")
    if not isinstance(value, list) or not value:
        raise ModelError(t.field("sets"), "must be a non-empty list of joint set names")
    for i, name in enumerate(value):
        if name not in set_names:
            raise ModelError(f"{t.field('sets')}[{i}]", unknown_set(str(name), set_names))
    return tuple(value)


def parse_stage(
    t: Table,
    set_names: list[str],
    regions: dict[str, Region],
    mechanics: Mechanics,
    moving: float,
) -> Stage:
    kind = t.text("type", choices=STAGE_KINDS)
    name = t.text("name", t.path)
    if kind == "solve":
        stage = Stage(
            name,
            kind,
            ratio=t.number("ratio", mechanics.ratio, above=0, below=1),
            max_steps=t.integer("max_steps", mechanics.max_steps, minimum=1, maximum=MAX_STEPS),
            elastic=t.boolean("elastic", False),
        )
    elif kind == "cycle":
        stage = Stage(
            name,
            kind,
            steps=t.integer("steps", minimum=1, maximum=MAX_STEPS),
            damping=t.number("damping", mechanics.damping, at_least=0, below=1),
        )
    elif kind == "time":
        # Model time is physical time: undamped unless the stage says otherwise (local
        # damping takes 0.8 of the unbalanced force away: a block sliding on a plane moved
        # a sixth of its distance).
        stage = Stage(
            name,
            kind,
            time=t.number("time", required=True, above=0),
            damping=t.number("damping", 0.0, at_least=0, below=1),
        )
    elif kind == "properties":
        sets = stage_sets(t, set_names)
        refuse_unknown(t, ("type", "name", "sets", *PROPERTY_FIELDS))
        changes = {k: t.raw(k) for k in PROPERTY_FIELDS if k in t.data}
        if not changes:
            raise ModelError(t.path, f"changes nothing: give some of {', '.join(PROPERTY_FIELDS)}")
        sub = Table({k: v for k, v in t.data.items() if k in PROPERTY_FIELDS}, t.path)
        stage = Stage(name, kind, sets=sets, changes=parse_property_values(sub, any_base()))
        t.read.update(PROPERTY_FIELDS)
    elif kind == "excavate":
        stage = Stage(
            name,
            kind,
            region=region_ref(t, "region", regions),
            relax_steps=t.integer("relax_steps", 100, minimum=1, maximum=MAX_STEPS),
        )
    elif kind == "boundary":
        boundary = parse_boundary(
            Table(
                {k: v for k, v in t.data.items() if k in ("region", "condition", "velocity")},
                t.path,
            ),
            regions,
        )
        t.read.update(("region", "condition", "velocity"))
        stage = Stage(name, kind, boundary=boundary)
    elif kind == "reset":
        stage = Stage(name, kind)
    elif kind == "save":
        stage = Stage(name, kind, file=parse_save_file(t))
    else:
        stage = Stage(
            name,
            kind,
            sets=stage_sets(t, set_names),
            ratio=t.number("ratio", mechanics.ratio, above=0, below=1),
            max_steps=t.integer("max_steps", mechanics.max_steps, minimum=1, maximum=MAX_STEPS),
            velocity=t.number("velocity", moving, above=0),
            displacement=t.optional_number("displacement", above=0),
            tolerance=t.number("tolerance", 0.01, above=0),
            low=t.number("low", 0.1, above=0),
            high=t.number("high", 10.0, above=0),
        )
        if stage.high <= stage.low:
            raise ModelError(t.field("high"), f"must be greater than low ({stage.low:g})")
        finest = MIN_RELATIVE_TOLERANCE * stage.high
        if stage.tolerance < finest:
            raise ModelError(
                t.field("tolerance"),
                f"must be at least {MIN_RELATIVE_TOLERANCE:g} x high ({finest:g} here), got "
                f"{stage.tolerance:g}: the trials' verdict does not tell factors of safety "
                "apart so finely (the bisection would take trials to no purpose, and below "
                "the floats' spacing could never end)",
            )
    t.done()
    return stage


def refuse_unknown(t: Table, known: tuple[str, ...]) -> None:
    """Refuses a key of `t` that is not one of `known`, naming it and the known key it looks
    like a typo of (``stages[0].frction``: before "changes nothing" of a properties stage
    whose only change is misspelt)."""
    for key in map(str, t.data):
        if key not in known:
            close = difflib.get_close_matches(key, known, 1)
            typo = f" ({close[0]!r} is a field here: a typo?)" if close else ""
            raise ModelError(
                t.field(key), f"unknown field{typo}; this table takes {', '.join(known)}"
            )


def parse_save_file(t: Table) -> str:
    """A save stage's ``file``: a non-empty path (a restart file, docs/models.md)."""
    file = t.text("file")
    if not file.strip() or file.endswith(("/", "\\")):
        raise ModelError(t.field("file"), f"must be a file name or path, got {file!r}")
    return file


def any_base() -> JointProperties:
    """A placeholder base, so that a properties stage may give any subset of fields."""
    return JointProperties(kn=1.0, ks=1.0, friction=0.0)


def parse_stages(
    tables: list[Table],
    set_names: list[str],
    regions: dict[str, Region],
    mechanics: Mechanics,
    moving: float,
) -> list[Stage]:
    if not tables:
        return [Stage("stages[0]", "solve", ratio=mechanics.ratio, max_steps=mechanics.max_steps)]
    return [parse_stage(t, set_names, regions, mechanics, moving) for t in tables]
