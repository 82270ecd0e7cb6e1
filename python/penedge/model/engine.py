"""The one module that calls the mechanics engine (``penedge.Simulation``, the rigid-block
DEM of docs/mechanics.md): everything else (stages, factor of safety, outputs) talks to an
:class:`Engine`, so a change of the engine's API changes this file only.

An :class:`Engine` is built from a checked :class:`~penedge.model.Setup`; it refuses, before
any step, what the engine cannot do yet (:func:`unsupported`).

The model speaks of blocks, the engine of bodies: a concave block (parts sharing a body id)
is one rigid body of several blocks. The :class:`Engine` translates (docs/models.md,
"Concave blocks"): its arguments and results go per block (a part gets its body's
displacement, velocity and excavation state), the simulation's per body
(``Simulation.block_bodies``). A model of convex blocks has one body per block, in order.
"""

from __future__ import annotations

import contextlib
import copy
import re
from collections.abc import Iterator
from typing import Any

import numpy as np

from penedge.model.check import block_list, partial_body
from penedge.model.fields import ModelError
from penedge.model.schema import JointProperties, Model, Water


class EngineMissingError(Exception):
    """This build of penedge has no mechanics engine (``penedge.Simulation``)."""


def simulation_class() -> Any:
    """``penedge.Simulation``, or :exc:`EngineMissingError`."""
    import penedge

    simulation = getattr(penedge, "Simulation", None)
    if simulation is None:
        raise EngineMissingError(
            "this build of penedge has no mechanics engine (penedge.Simulation, the "
            "rigid-block DEM): the model was read and checked, but it cannot be run"
        )
    return simulation


#: Model features that the engine does not run yet: (field, why). A model using one of
#: them is read and checked, and its run refused with this message before any step.
NOT_SUPPORTED = {
    "residual_tension": "a residual tensile strength is not supported by the engine: a failed "
    "joint holds no tension (contacts that form during the run start failed, and a residual "
    "tension would glue blocks that merely come near each other; docs/mechanics.md)",
}


def has_residual_tension(props: JointProperties) -> bool:
    """Whether `props` asks for a residual tensile strength (the engine has none)."""
    return bool(props.residual_tension)


def unsupported(model: Model) -> list[tuple[str, str]]:
    """The features of `model` the engine cannot run: ``(field, message)`` pairs."""
    found = []
    for i, stage in enumerate(model.stages):
        if stage.kind == "properties" and stage.changes.get("residual_tension"):
            found.append((f"stages[{i}]", NOT_SUPPORTED["residual_tension"]))
    named = {"default": model.default_properties, **model.properties}
    for name, props in named.items():
        if has_residual_tension(props):
            found.append((f"joint_properties.{name}", NOT_SUPPORTED["residual_tension"]))
            break
    return found


def initial_stress_of(setup: Any) -> dict[str, Any] | None:
    """The engine's initial stress field of the model's ``[initial_stress]`` (None if it has
    none): tension positive, ``base + max(0, surface - z) * per_depth`` (docs/models.md).
    An overburden's unit weight is its density times the magnitude of the model's gravity
    (without the seismic load); its surface defaults to the top of the blocks."""
    stress = setup.model.initial_stress
    if stress is None:
        return None
    if stress.kind == "uniform":
        return {"base": list(stress.components), "per_depth": None, "surface": 0.0}
    m = setup.model.mechanics
    density = m.density if stress.density is None else stress.density
    weight = density * float(np.linalg.norm(m.gravity))
    if stress.surface is None:
        surface = float(np.asarray(setup.system.arrays().vertices)[:, 2].max())
    else:
        surface = stress.surface
    kx, ky = stress.k0
    per_depth = [-weight * kx, -weight * ky, -weight, 0.0, 0.0, 0.0]
    return {"base": None, "per_depth": per_depth, "surface": surface}


def refuse_unsupported(model: Model) -> None:
    """Raises a :exc:`ModelError` for the first feature the engine cannot run."""
    for field, message in unsupported(model):
        raise ModelError(field, message)


@contextlib.contextmanager
def time_step_field() -> Iterator[None]:
    """The engine's refusal of the time step (``[mechanics] time_step`` above the critical
    one, when the engine is built or after a stage that stiffened a joint) as an error
    naming the field that set it, ``mechanics.time_step``."""
    import penedge

    try:
        yield
    except penedge.MechanicsError as e:
        if getattr(e, "kind", None) != "time_step":
            raise
        raise ModelError(
            "mechanics.time_step",
            f"{e}: lower it, or leave it out for the automatic step (a fraction of the "
            "critical one, which stiffer joints and bolts lower)",
        ) from e


class Engine:
    """A simulation of a checked model: the engine set up with the model's density,
    gravity (with the seismic load), damping, joint properties per set and boundary
    conditions.

    Parameters
    ----------
    setup : penedge.model.Setup
        The model with its blocks.
    """

    def __init__(self, setup: Any) -> None:
        refuse_unsupported(setup.model)
        simulation = simulation_class()
        model = setup.model
        m = model.mechanics
        self.setup = setup
        self.sim = simulation(setup.system, density=m.density, gap=m.gap, point_width=m.point_width)
        #: Per block, its body: the row of the simulation's arrays (the parts of a concave
        #: block share one).
        self.body = np.asarray(self.sim.block_bodies, dtype=np.int64)
        self.sim.gravity = list(model.gravity)
        self.sim.set_damping(local=m.damping)
        self.set_ids = {name: i for i, name in enumerate(model.set_names)}
        self.properties = dict(model.properties)
        self.default = model.default_properties
        self.apply_properties(self.properties)
        if model.water is not None:
            self.apply_water(model.water)
        layout = setup.layout
        self.apply_boundary(layout.fixed, layout.velocity)
        if layout.support_forces is not None:
            self.apply_support(layout.support_forces, layout.support_moments)
        self.bolt_names = self.apply_bolts(model.bolts)
        stress = initial_stress_of(setup)
        if stress is not None:
            self.sim.set_initial_stress(**stress)
        #: ``[mechanics] mass_scaling``: rescaled from the stiffness and supports of the
        #: moment, here and after every change of them (:meth:`rescale`); after an
        #: excavation the simulation rescales by itself (its free bodies changed).
        self.mass_scaling = m.mass_scaling
        self.rescale()
        if m.time_step is not None:
            # Last: checked against the critical step, which the bolts' stiffness lowers.
            with time_step_field():
                self.sim.set_timestep(dt=m.time_step)

    def rescale(self) -> None:
        """Under ``[mechanics] mass_scaling``, scales the inertia (not the weight) of every
        free body whose critical step is below the free bodies' median up to that median
        (docs/mechanics.md, "Mass scaling"), for the joints' stiffness and the supports as
        they are now; nothing without it, or while no body is free."""
        if not getattr(self, "mass_scaling", False):
            return  # off, or the engine is still being built (scaled once at its end)
        import penedge

        try:
            self.sim.set_mass_scaling(True)
        except penedge.MechanicsError as e:
            if getattr(e, "kind", None) != "no_free_body":
                raise

    @property
    def concave(self) -> bool:
        """Whether some body has several blocks (a concave block)."""
        return len(self.sim) != len(self.body)

    def per_body(self, values: np.ndarray) -> np.ndarray:
        """Per-block rows (n, k) summed per body."""
        values = np.asarray(values, dtype=float)
        return np.stack(
            [np.bincount(self.body, values[:, k], len(self.sim)) for k in range(values.shape[1])],
            axis=1,
        )

    def apply_support(self, forces: np.ndarray, moments: np.ndarray | None) -> None:
        """The support pressures (per block: a force on its centroid and a moment about it)
        as constant forces on the bodies' centroids and, where their resultant misses the
        centroid, constant moments about it. A concave block takes the sum of its parts'
        forces, and their moments about its own centroid: each part's moment plus its force's
        moment about the body's centroid (the arm from there to the part's centroid)."""
        forces = np.asarray(forces, dtype=float)
        moments = np.zeros_like(forces) if moments is None else np.asarray(moments, dtype=float)
        if self.concave:
            arm = self.setup.blocks.centroids - self.positions()
            arm[np.bincount(self.body)[self.body] == 1] = 0.0  # a convex block's own centroid
            moments = moments + np.cross(arm, forces)
            forces, moments = self.per_body(forces), self.per_body(moments)
        for i in np.flatnonzero(np.abs(forces).sum(axis=1)):
            self.sim.apply_force(int(i), forces[i].tolist())
        for i in np.flatnonzero(np.abs(moments).sum(axis=1)):
            self.sim.apply_moment(int(i), moments[i].tolist())

    def apply_bolts(self, bolts: list[Any]) -> list[str]:
        """Installs the model's ``[[bolts]]`` (in order: bolt ``i`` is engine bolt ``i``);
        their names. An engine refusal (a bolt outside the rock) names the bolt's field."""
        import penedge

        for i, bolt in enumerate(bolts):
            try:
                self.sim.add_bolt(
                    bolt.point,
                    bolt.direction,
                    bolt.length,
                    bolt.stiffness,
                    bolt.capacity,
                    rupture_strain=bolt.rupture_strain,
                    shear_stiffness=bolt.shear_stiffness,
                    shear_capacity=bolt.shear_capacity,
                )
            except penedge.MechanicsError as e:
                raise ModelError(f"bolts[{i}]", self.with_blocks(str(e))) from e
        return [bolt.name for bolt in bolts]

    def with_blocks(self, message: str) -> str:
        """An engine message that names a body (``(body 10)``: the engine's row) with the
        blocks it is made of, the ids a model's user knows; and one that names two
        (``bodies 3 and 7 overlap``, a penetration) with theirs, when some body is not the
        block of its own id (a concave block, or pieces that rock bridges hold: else body
        ``i`` is block ``i`` and the message is left as it is)."""
        found = re.search(r"\(body (\d+)\)", message)
        if found is not None:
            body = int(found[1])
            message = message.replace(found[0], f"(body {body}: {self.blocks_of(body)})")
        pair = re.match(r"bodies (\d+) and (\d+) ", message)
        if pair is not None and not np.array_equal(self.body, np.arange(len(self.body))):
            a, b = int(pair[1]), int(pair[2])
            named = f"bodies {a} and {b} ({self.blocks_of(a)}; {self.blocks_of(b)}) "
            message = named + message[pair.end() :]
        return message

    def blocks_of(self, body: int) -> str:
        """The blocks of engine body `body`, as a message names them."""
        blocks = np.flatnonzero(self.body == body)
        if len(blocks) == 1:
            return f"block {blocks[0]}"
        return f"the concave block made of blocks {block_list(blocks)}"

    # --- set-up ---------------------------------------------------------------------

    def joint(self, props: JointProperties) -> dict[str, float]:
        """The engine's joint model of `props`."""
        if has_residual_tension(props):
            raise ModelError("joint_properties", NOT_SUPPORTED["residual_tension"])
        return {
            "kn": props.kn,
            "ks": props.ks,
            "friction": props.friction,
            "cohesion": props.cohesion,
            "tension": props.tension,
            "residual_friction": props.residual_friction,
            "residual_cohesion": props.residual_cohesion,
        }

    def apply_water(self, water: Water) -> None:
        """The water in the joints: the phreatic surface (pressure per depth ``ρw g``, g the
        magnitude of the model's static gravity, before any seismic load) and the pressures
        per set by the sets' engine ids."""
        surface: dict[str, Any] = {}
        g = float(np.linalg.norm(self.setup.model.mechanics.gravity))
        if water.phreatic is not None and g > 0:  # without gravity, no hydrostatic pressure
            surface = {
                "point": list(water.phreatic.point),
                "normal": list(water.phreatic.normal),
                "unit_weight": water.density * g,
            }
        self.sim.set_water(
            **surface, pressures={self.set_ids[name]: p for name, p in water.pressures.items()}
        )

    def apply_properties(self, properties: dict[str, JointProperties], factor: float = 1.0) -> None:
        """Joint properties per set name (the default stays for contacts of no set), and the
        rock bridges' of those sets, their strength divided by `factor` (strength reduction)."""
        self.sim.set_joint(**self.joint(self.default), set=None)
        for name, props in properties.items():
            self.properties[name] = props
            self.sim.set_joint(**self.joint(props), set=self.set_ids[name])
            bridge = self.setup.model.bridges.get(name)
            if bridge is not None:
                reduced = bridge if factor == 1.0 else bridge.reduced(factor)
                self.sim.set_bridge(**self.joint(reduced), set=self.set_ids[name])
        self.rescale()  # a stiffer joint lowers the critical steps

    def set_damping(self, local: float) -> float:
        """Sets the local damping (a ``cycle`` or ``time`` stage's); returns the one it
        replaces, for the runner to set back after the stage."""
        previous = float(self.sim.damping[0])
        self.sim.set_damping(local=local, viscous=float(self.sim.damping[1]))
        return previous

    #: The cohesion and tensile strength (Pa) of an elastic solve: no bond fails.
    UNBREAKABLE = 1e30

    def set_elastic(self, on: bool) -> None:
        """With `on`, every joint and bridge model **with a bond** (cohesion or tension > 0)
        gets an unbreakable one (cohesion and tension :attr:`UNBREAKABLE`; friction and
        stiffness kept): a ``solve`` stage with ``elastic = true`` reaches the initial
        equilibrium without the bonds failing under the sudden load of gravity (3DEC's advice:
        equilibrium with high strength first). A model without a bond keeps its strength: made
        unbreakable, a joint of friction only (an open tension crack) would hold the blocks in
        tension, an equilibrium the model does not have, released at once when the stage ends
        (docs/mechanics.md, "Rock bridges"). Off: the model's properties again."""
        if not on:
            self.apply_properties(dict(self.properties))
            return

        def strong(props: JointProperties) -> dict[str, float]:
            engine = self.joint(props)
            if props.cohesion > 0 or props.tension > 0:
                engine.update(cohesion=self.UNBREAKABLE, tension=self.UNBREAKABLE)
            return engine

        self.sim.set_joint(**strong(self.default), set=None)
        for name, props in self.properties.items():
            self.sim.set_joint(**strong(props), set=self.set_ids[name])
            bridge = self.setup.model.bridges.get(name)
            if bridge is not None:
                self.sim.set_bridge(**strong(bridge), set=self.set_ids[name])

    def apply_boundary(self, fixed: np.ndarray, velocity: np.ndarray) -> None:
        """Fixes, frees or drives every body as the per-block masks say (excavated bodies
        stay out). The parts of a concave block must be given one condition (the model's
        conditions hold whole bodies: :func:`penedge.model.check.apply_boundary`); parts
        that disagree are a :exc:`ModelError` naming the body and its blocks."""
        fixed, velocity = self.body_conditions(np.asarray(fixed, bool), np.asarray(velocity))
        present = ~np.asarray(self.sim.removed, dtype=bool)
        driven = ~np.isnan(velocity[:, 0]) & present
        fixed = fixed & present
        free = ~fixed & ~driven & present
        if fixed.any():
            self.sim.fix(np.flatnonzero(fixed).tolist())
        if free.any():
            self.sim.free(np.flatnonzero(free).tolist())
        for i in np.flatnonzero(driven):
            self.sim.prescribe(int(i), velocity[i].tolist())
        self.rescale()  # the free bodies, and so their median, may have changed

    def body_conditions(
        self, fixed: np.ndarray, velocity: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Per-block fixity and prescribed velocity (NaN: none) as per-body ones; an error
        when the parts of one body disagree."""
        if not self.concave:
            return fixed, velocity
        first = np.full(len(self.sim), len(self.body))
        np.minimum.at(first, self.body, np.arange(len(self.body)))
        same_fixed = fixed == fixed[first][self.body]
        theirs = velocity[first][self.body]
        same_velocity = ((velocity == theirs) | (np.isnan(velocity) & np.isnan(theirs))).all(1)
        wrong = np.flatnonzero(~(same_fixed & same_velocity))
        if len(wrong):
            k = int(wrong[0])
            body = int(self.body[k])
            j = int(first[body])
            parts = ", ".join(map(str, np.flatnonzero(self.body == body).tolist()))

            def condition(i: int) -> str:
                if fixed[i]:
                    return "fixed"
                if np.isnan(velocity[i, 0]):
                    return "free"
                return "velocity ({:g}, {:g}, {:g})".format(*velocity[i])

            raise ModelError(
                "boundary",
                f"blocks {j} and {k} are parts of one concave block (body {body}: blocks "
                f"{parts}) but are given different conditions, {condition(j)} and "
                f"{condition(k)}: a concave block is one rigid body; give its parts one "
                "condition",
            )
        return fixed[first], velocity[first]

    def copy(self) -> Engine:
        """An independent copy (state, contacts and shear histories included).

        Raises
        ------
        NotImplementedError
            The engine cannot copy a simulation (the runner then replays the stages)."""
        if not hasattr(self.sim, "copy"):
            raise NotImplementedError("penedge.Simulation has no copy()")
        twin = copy.copy(self)
        twin.sim = self.sim.copy()
        twin.properties = dict(self.properties)
        return twin

    # --- excavation and restart (docs/models.md, "Excavation" and "Restart") --------

    def removed(self) -> np.ndarray:
        """Which blocks were excavated (their body was), (n,) bool."""
        removed = getattr(self.sim, "removed", None)
        n = len(self.setup.blocks)
        return np.zeros(n, bool) if removed is None else np.array(removed, dtype=bool)[self.body]

    def excavate(self, mask: np.ndarray, relax_steps: int) -> np.ndarray:
        """Removes the blocks of `mask` not removed yet, whole bodies only (a `mask` that
        holds some parts of a concave block and not the others is a :exc:`ModelError`);
        their forces on the rest relax over `relax_steps` steps (the steps the caller takes
        next). The block ids removed. Under ``[mechanics] mass_scaling`` the simulation
        computes its factors again from the free blocks that stay (docs/mechanics.md, "Mass
        scaling"): the excavated ones no longer count in the median."""
        split = partial_body(mask, self.body)
        if split is not None:
            raise ModelError("excavate", split)
        ids = np.flatnonzero(mask & ~self.removed())
        if len(ids):
            bodies = np.unique(self.body[ids])
            self.sim.excavate(bodies.tolist(), relax_steps=relax_steps)
        return ids

    def save(self, path: Any, note: str) -> None:
        """Writes the engine's state to the restart file `path`, with `note`."""
        self.sim.save(str(path), note=note)

    def restore(self, path: Any) -> str | None:
        """Replaces the simulation by the one of the restart file `path` (which must have
        this model's blocks); its note."""
        sim = simulation_class().load(str(path))
        n = len(self.sim)
        if len(sim) != n:
            what = "bodies" if self.concave else "blocks"
            raise ModelError(
                "restart",
                f"{path} holds {len(sim)} {what}, the model {n}: it was saved from another model",
            )
        self.sim = sim
        if getattr(self, "mass_scaling", False) and not getattr(sim, "mass_scaling", True):
            # A file from before restart files kept the switch, that scaled no body (read
            # as off): on, as the model says (the runner checks it against the file's note).
            self.rescale()
        note: str | None = sim.note
        return note

    # --- stepping -------------------------------------------------------------------

    def cycle(self, steps: int) -> None:
        """`steps` steps."""
        with time_step_field():
            self.sim.step(steps)

    @property
    def timestep(self) -> float:
        """The time step (s)."""
        with time_step_field():
            return float(self.sim.timestep)

    # --- state ----------------------------------------------------------------------

    @property
    def steps(self) -> int:
        """Steps taken."""
        return int(self.sim.steps)

    @property
    def time(self) -> float:
        """Model time (s)."""
        return float(self.sim.time)

    @property
    def ratio(self) -> float:
        """The unbalanced-force ratio."""
        return float(self.sim.unbalanced_ratio)

    def positions(self) -> np.ndarray:
        """Per block, its body's centroid now, (n, 3): a convex block's centroid; the
        parts of a concave block share their body's (so their displacements are the
        body's)."""
        return np.array(self.sim.positions, dtype=float)[self.body]

    #: A body whose contact forces sum to less than this share of its weight is held by
    #: nothing (falling freely: blocks falling together touch with forces of rounding size).
    HELD_SHARE = 1e-3

    def held(self) -> np.ndarray:
        """Per block, whether its body's contact (and bolt) forces at the last step are at
        least :attr:`HELD_SHARE` of its weight, (n,) bool: a body held by nothing (falling
        freely, or before any step) is not."""
        forces = np.linalg.norm(np.array(self.sim.contact_forces, dtype=float), axis=1)
        weights = np.asarray(self.sim.masses, dtype=float) * float(
            np.linalg.norm(np.asarray(self.sim.gravity, dtype=float))
        )
        return (forces >= self.HELD_SHARE * weights)[self.body]

    def rotations(self) -> np.ndarray:
        """Per block, its body's orientation now, a unit quaternion ``x, y, z, w`` (n, 4)."""
        return np.array(self.sim.quaternions, dtype=float)[self.body]

    def velocities(self) -> np.ndarray:
        """Per block, its body's velocity (of the centroid) now, (n, 3)."""
        return np.array(self.sim.velocities, dtype=float)[self.body]

    def kinetic_energy(self) -> float:
        """Total kinetic energy of the blocks (J)."""
        return float(self.sim.kinetic_energy())

    def system(self) -> Any:
        """The blocks at their current poses, as a :class:`penedge.BlockSystem`, in the
        model's block order with their body ids (a picture draws a concave block as one):
        ``Simulation.system()``."""
        placed = self.sim.system()
        if np.array_equal(self.sim.block_bodies, self.body):
            return placed
        # A restart file from before 2026-11-28 keeps no block order (its simulation's
        # block_bodies go part by part, body by body): the model's order from the parts'.
        import penedge

        order = np.argsort(self.body, kind="stable")  # the blocks in the parts' order
        row = np.empty_like(order)
        row[order] = np.arange(len(order))
        parts = placed.blocks
        system = penedge.BlockSystem([parts[r] for r in row.tolist()])
        return system.with_bodies(self.body.tolist())

    def bolts(self) -> list[dict[str, Any]]:
        """Per bolt: its name, its largest axial force now (N, tension > 0; over its
        elements), its largest elongation (m) and its state: ``"elastic"``, ``"yielding"``
        (an element at its capacity), ``"broken"`` (an element broke) or ``"excavated"`` (every
        element was anchored in excavated rock: force and elongation 0)."""
        if not self.bolt_names:
            return []
        data = self.sim.bolts()
        out = []
        for i, name in enumerate(self.bolt_names):
            mine = data["bolt"] == i
            states = data["states"][mine]
            forces = data["forces"][mine]
            if not mine.any():
                # Every element was anchored in excavated rock: the bolt no longer acts.
                out.append({"name": name, "force": 0.0, "elongation": 0.0, "state": "excavated"})
                continue
            state = (
                "broken"
                if (states == 2).any()
                else "yielding"
                if (states == 1).any()
                else "elastic"
            )
            out.append(
                {
                    "name": name,
                    "force": float(forces[np.argmax(np.abs(forces))]),
                    "elongation": float(data["elongations"][mine].max()),
                    "state": state,
                }
            )
        return out

    def contacts(self) -> Any:
        """The contacts now, for the ParaView series (None when the engine gives none)."""
        return self.sim.contacts()

    def bolt_elements(self) -> Any:
        """The bolt elements now (``Simulation.bolts()``), for the ParaView series; None for
        a model without bolts."""
        return self.sim.bolts() if self.bolt_names else None
